//! In-place reordering of a family's particle arrays by the cell order of the
//! neighbour search: every array follows the cycles of one permutation, with one mark
//! bit per particle as the only extra memory.

/// `v[k] = v_old[order[k]]` for all k, in place, by walking each cycle of `order` once
/// with one element held aside; `scratch` holds a bitset (resized here).
pub fn cycle_apply<T: Copy>(v: &mut [T], order: &[u32], scratch: &mut PermuteScratch) {
    let done = &mut scratch.done;
    debug_assert_eq!(v.len(), order.len());
    done.clear();
    done.resize(order.len().div_ceil(64), 0);
    for start in 0..order.len() {
        if done[start / 64] & (1 << (start % 64)) != 0 {
            continue;
        }
        let held = v[start];
        let mut k = start;
        loop {
            done[k / 64] |= 1 << (k % 64);
            let from = order[k] as usize;
            if from == start {
                v[k] = held;
                break;
            }
            v[k] = v[from];
            k = from;
        }
    }
}

/// Reusable scratch for a family's `permute` ([`FineParticles::permute`](crate::fine::state::FineParticles::permute)): one mark bit per particle.
#[derive(Clone, Default, Debug)]
pub struct PermuteScratch {
    done: Vec<u64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The in-place cycle walk equals a gathered copy, for a permutation with cycles of
    /// many lengths (and fixed points).
    #[test]
    fn in_place_permutation_equals_a_gathered_copy() {
        let n = 1000u32;
        let mut order: Vec<u32> = (0..n).collect();
        let mut x = 12345u64;
        for k in (1..n as usize).rev() {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            if k % 7 != 0 {
                order.swap(k, (x >> 33) as usize % (k + 1));
            }
        }
        let v: Vec<u64> = (0..n as u64).map(|i| i * i + 3).collect();
        let want: Vec<u64> = order.iter().map(|&o| v[o as usize]).collect();
        let mut got = v.clone();
        let mut done = PermuteScratch::default();
        cycle_apply(&mut got, &order, &mut done);
        assert_eq!(got, want);
    }
}

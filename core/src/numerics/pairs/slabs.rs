//! Two-phase schedule of the symmetric pair sweeps.
//!
//! The fine–fine lists hold each pair once, under its lower index, and a neighbour of
//! a particle in slab s lies in slab s or s + 1 ([`neighbors`](crate::numerics::neighbors)). A
//! sweep that evaluates each pair once and adds its two halves to both particles
//! therefore writes, for the particles of slab s, only into slabs s and s + 1. The
//! even slabs run first and the odd ones second: within a phase the slabs' windows
//! (own slab and the next) do not overlap, so they run in parallel without locks, and
//! every particle receives its pair terms in an order fixed by the slabs (the
//! preceding slab's, then its own slab's in index order), never by the threads.
//! Results are bitwise identical at any thread count.

/// Call `task(s, window, base)` for every slab s with entries, where `window` is
/// `acc[start[s]..start[min(s + 2, ns)]]` (the slab and the next one) and
/// `base = start[s]` is the index of the window's first entry. `start` holds the
/// `ns + 1` slab boundaries; `acc` one entry per particle or per cluster of particles
/// ([`clusters`](crate::numerics::pairs::clusters)). A range of slabs runs on the calling thread
/// below `serial` entries.
pub fn two_phase_in<T, F>(start: &[u32], acc: &mut [T], serial: usize, task: &F)
where
    T: Send,
    F: Fn(usize, &mut [T], usize) + Sync,
{
    let ns = start.len().saturating_sub(1);
    debug_assert_eq!(start.last().map_or(0, |&e| e as usize), acc.len());
    for first in 0..2.min(ns) {
        let lo = start[first] as usize;
        let tasks = (ns - first).div_ceil(2);
        run(start, &mut acc[lo..], (lo, serial), first, tasks, task);
    }
}

/// Slabs `first, first + 2, …` (`tasks` of them) on `acc`, which begins at particle
/// `base` and reaches at least to the end of the last slab's window.
fn run<T, F>(
    start: &[u32],
    acc: &mut [T],
    (base, serial): (usize, usize),
    first: usize,
    tasks: usize,
    task: &F,
) where
    T: Send,
    F: Fn(usize, &mut [T], usize) + Sync,
{
    let ns = start.len() - 1;
    let last = first + 2 * (tasks - 1);
    let end = start[(last + 2).min(ns)] as usize;
    let own = |s: usize| (start[s + 1] - start[s]) as usize;
    if tasks == 1 || end - base <= serial {
        for s in (first..=last).step_by(2).filter(|&s| own(s) > 0) {
            let (a, b) = (start[s] as usize, start[(s + 2).min(ns)] as usize);
            task(s, &mut acc[a - base..b - base], a);
        }
        return;
    }
    // split where the particles of the range are halved (at least one slab a side)
    let middle = (start[first] as usize + start[last + 1] as usize) / 2;
    let mut k = (1..tasks)
        .find(|&k| start[first + 2 * k] as usize >= middle)
        .unwrap_or(tasks - 1);
    k = k.clamp(1, tasks - 1);
    let second = first + 2 * k;
    let cut = start[second] as usize - base;
    let (left, right) = acc.split_at_mut(cut);
    rayon::join(
        || run(start, left, (base, serial), first, k, task),
        || run(start, right, (base + cut, serial), second, tasks - k, task),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Every slab with particles runs once, on its own window; the even slabs before
    /// the odd ones.
    #[test]
    fn every_slab_once_with_its_window() {
        let start = [0u32, 3, 3, 700, 900, 1500, 1501, 2600, 2600];
        let mut acc = vec![0usize; 2600];
        let calls = AtomicUsize::new(0);
        let odd_seen = AtomicUsize::new(0);
        two_phase_in(&start, &mut acc, 512, &|s, w: &mut [usize], base| {
            calls.fetch_add(1, Ordering::SeqCst);
            assert_eq!(base, start[s] as usize);
            assert_eq!(w.len(), (start[(s + 2).min(8)] - start[s]) as usize);
            if s % 2 == 1 {
                odd_seen.fetch_add(1, Ordering::SeqCst);
            } else {
                assert_eq!(odd_seen.load(Ordering::SeqCst), 0, "odd slab before even");
            }
            for (k, x) in w.iter_mut().enumerate() {
                // owners of a window's second slab add, the own slab's entries count
                if k < (start[s + 1] - start[s]) as usize {
                    *x += 1;
                }
            }
        });
        // slabs 1 and 7 are empty
        assert_eq!(calls.load(Ordering::SeqCst), 6);
        assert!(acc.iter().all(|&x| x == 1));
    }
}

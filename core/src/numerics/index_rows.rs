//! Index invariants of stored lists: compressed rows and index bounds. A restored
//! state's lists are checked with these before any step reads them
//! ([`crate::run::restore`]), so that lists forged or corrupted in a state are refused
//! with a message instead of read out of range.

/// Whether `off` are the offsets of `rows` compressed rows over `len` entries: `rows
/// + 1` offsets, ascending, from 0 to `len`.
pub fn rows(off: &[u32], rows: usize, len: usize) -> bool {
    off.len() == rows + 1 && off[0] == 0 && off[rows] as usize == len && ascending(off)
}

/// Whether `v` never decreases.
pub fn ascending(v: &[u32]) -> bool {
    v.windows(2).all(|w| w[0] <= w[1])
}

/// Whether every index of `idx` is below `n`.
pub fn below(idx: &[u32], n: usize) -> bool {
    idx.iter().all(|&i| (i as usize) < n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_need_every_offset_in_order() {
        assert!(rows(&[0, 2, 2, 5], 3, 5));
        assert!(rows(&[0], 0, 0));
        assert!(!rows(&[0, 2, 2, 5], 3, 6), "last offset is the length");
        assert!(!rows(&[0, 3, 2, 5], 3, 5), "descending");
        assert!(!rows(&[1, 2, 2, 5], 3, 5), "first offset is 0");
        assert!(!rows(&[0, 2, 5], 3, 5), "one offset per row and one more");
        assert!(!rows(&[], 0, 0));
        assert!(below(&[0, 4, 2], 5) && !below(&[0, 5], 5));
    }
}

//! A deterministic test pattern for the particle channel: every record of every frame
//! is a hash of (frame, index, word), so a subscriber in any language can check what
//! it received bit for bit without the publisher's data. `docs/ipc.md` gives the same
//! formula in numpy.

use crate::payload::ParticleRecord;
use crate::publisher::FrameInfo;

/// Coarse-grain records at the end of every pattern frame.
pub const PATTERN_COARSE: usize = 7;

/// Word `w` (0..14, in layout order) of record `i` in frame `k`, as raw bits.
#[inline(always)]
pub fn pattern_word(k: u64, i: usize, w: u32) -> u32 {
    let h = (i as u32)
        .wrapping_mul(2_654_435_761)
        .wrapping_add((k as u32).wrapping_mul(40_503))
        .wrapping_add(w.wrapping_mul(97));
    if !(8..11).contains(&w) {
        // a finite float in [0.5, 2) with a random sign and mantissa
        (h & 0x807F_FFFF) | 0x3F00_0000
    } else {
        h
    }
}

/// Record `i` of pattern frame `k`.
pub fn pattern_record(k: u64, i: usize) -> ParticleRecord {
    let f = |w| f32::from_bits(pattern_word(k, i, w));
    ParticleRecord {
        position: [f(0), f(1), f(2)],
        velocity: [f(3), f(4), f(5)],
        pressure: f(6),
        plastic_strain: f(7),
        id: pattern_word(k, i, 8),
        group: pattern_word(k, i, 9),
        family: pattern_word(k, i, 10),
        pore_pressure: f(11),
        excess_pore_pressure: f(12),
        porosity: f(13),
    }
}

/// Header data of pattern frame `k` with `n` records.
pub fn pattern_info(k: u64, n: usize) -> FrameInfo {
    FrameInfo {
        time: k as f64 * 0.5,
        step: k * 10,
        fine_count: n - PATTERN_COARSE.min(n),
        coarse_count: PATTERN_COARSE.min(n),
        water_count: 0,
        dimension: 3,
    }
}

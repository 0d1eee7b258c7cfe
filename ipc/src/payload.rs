//! The payload of the particle channel: a [`FrameHeader`] (iceoryx2 user header) and a
//! slice of [`ParticleRecord`]s. Both are `#[repr(C)]` with explicit type names, so
//! subscribers in other languages (Python `ctypes`, C) declare the same layout; see
//! `docs/ipc.md`. Change either layout only together with [`SCHEMA_VERSION`].

use iceoryx2::prelude::ZeroCopySend;

/// Layout version of [`FrameHeader`] and [`ParticleRecord`], also a service attribute.
pub const SCHEMA_VERSION: u32 = 4;

/// One particle: 56 bytes, fine particles first, then coarse-grain particles, then
/// water; the one particle record of granmix
/// ([`granmix_core::run::sample::ParticleRecord`]), its family in `family`.
pub use granmix_core::run::sample::{ParticleRecord, FAMILY_COARSE, FAMILY_FINE, FAMILY_WATER};

/// Per-frame header: 56 bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[type_name("granmix::FrameHeader")]
#[repr(C)]
pub struct FrameHeader {
    /// Simulation time (s).
    pub time: f64,
    /// Fine solver steps taken so far.
    pub step: u64,
    /// Frame number of this publisher, from 0; a gap means frames were dropped.
    pub sequence: u64,
    /// Wall clock when the frame was sent (ns since the Unix epoch), for latency.
    pub sent_unix_ns: u64,
    /// Fine particles: records `0..fine_count`.
    pub fine_count: u32,
    /// Coarse-grain particles: records `fine_count..fine_count + coarse_count`.
    pub coarse_count: u32,
    /// Scene dimension (2 or 3).
    pub dimension: u32,
    /// [`SCHEMA_VERSION`] of the publisher.
    pub schema_version: u32,
    /// Water particles: the records after the coarse ones.
    pub water_count: u32,
    /// Zero (keeps the header a multiple of 8 bytes).
    pub reserved: u32,
}

impl FrameHeader {
    /// Records in the frame.
    pub fn count(&self) -> usize {
        self.fine_count as usize + self.coarse_count as usize + self.water_count as usize
    }
}

/// The records as raw bytes (for recording and checksums); safe: the record is plain
/// `#[repr(C)]` data without padding (checked by a test).
pub fn record_bytes(records: &[ParticleRecord]) -> Vec<u8> {
    let mut out = Vec::with_capacity(std::mem::size_of_val(records));
    for r in records {
        append_record(&mut out, r);
    }
    out
}

/// Append one record's bytes (native little-endian layout, as in shared memory).
#[inline(always)]
pub fn append_record(out: &mut Vec<u8>, r: &ParticleRecord) {
    for x in r.position.iter().chain(&r.velocity) {
        out.extend_from_slice(&x.to_le_bytes());
    }
    out.extend_from_slice(&r.pressure.to_le_bytes());
    out.extend_from_slice(&r.plastic_strain.to_le_bytes());
    out.extend_from_slice(&r.id.to_le_bytes());
    out.extend_from_slice(&r.group.to_le_bytes());
    out.extend_from_slice(&r.family.to_le_bytes());
    out.extend_from_slice(&r.pore_pressure.to_le_bytes());
    out.extend_from_slice(&r.excess_pore_pressure.to_le_bytes());
    out.extend_from_slice(&r.porosity.to_le_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{align_of, size_of};

    #[test]
    fn layouts_have_no_padding() {
        assert_eq!(size_of::<ParticleRecord>(), 56);
        assert_eq!(align_of::<ParticleRecord>(), 4);
        assert_eq!(size_of::<FrameHeader>(), 56);
        assert_eq!(align_of::<FrameHeader>(), 8);
        let r = ParticleRecord {
            position: [1.0, 2.0, 3.0],
            velocity: [4.0, 5.0, 6.0],
            pressure: 7.0,
            plastic_strain: 8.0,
            id: 9,
            group: 10,
            family: FAMILY_WATER,
            pore_pressure: 11.0,
            excess_pore_pressure: 12.0,
            porosity: 0.25,
        };
        let b = record_bytes(&[r]);
        assert_eq!(b.len(), 56);
        assert_eq!(&b[36..40], &10u32.to_le_bytes());
        assert_eq!(&b[40..44], &2u32.to_le_bytes());
        assert_eq!(&b[44..48], &11f32.to_le_bytes());
        assert_eq!(&b[48..52], &12f32.to_le_bytes());
        assert_eq!(&b[52..56], &0.25f32.to_le_bytes());
    }
}

//! The envelope of a serialised FMU state (`fmi2SerializeFMUstate`): a header that says
//! what the bytes are and whose they are, and a checksum over everything.
//!
//! Layout (integers little-endian):
//!
//! | bytes | field |
//! |---|---|
//! | 8 | magic `GRANMIX\x1a` |
//! | 2 | format version ([`VERSION`]) |
//! | 1 | model kind: 1 granular scene, 2 structural partner |
//! | 1 | payload encoding: 0 raw, 1 deflate |
//! | 1 + n | GUID of the FMU: length n, then its ASCII bytes |
//! | 1 | the instance's state-machine state ([`State`] bit; version 3 on) |
//! | 2 + m | why it is in the error state: length m, then UTF-8 (empty otherwise; version 3 on) |
//! | 8 | payload length as stored |
//! | 8 | payload length once decoded |
//! | … | payload |
//! | 4 | CRC-32 (IEEE) of every byte before it |
//!
//! [`open`] checks, in order: the magic (else "not a granmix FMU state"), the checksum
//! (a flipped byte anywhere after the magic), the version, the kind, the GUID (a state
//! of another FMU), then the lengths. Version 2 states (before the instance's state was
//! carried) are still read: their place follows from the payload.

use crate::state::{Place, State};
use flate2::read::DeflateDecoder;
use flate2::write::DeflateEncoder;
use flate2::Compression;
use std::io::{Read, Write};

/// First bytes of every serialised state.
pub const MAGIC: [u8; 8] = *b"GRANMIX\x1a";
/// Format version written. Version 2 (without the instance's state) is read too;
/// version 1 (a replay list) is no longer read.
pub const VERSION: u16 = 3;
/// The oldest version read.
const OLDEST: u16 = 2;
/// Longest error-state message kept in a state (bytes).
const FAILURE_MAX: usize = u16::MAX as usize;

/// Which model a state belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum ModelKind {
    Granular = 1,
    Structure = 2,
}

impl ModelKind {
    fn name(byte: u8) -> &'static str {
        match byte {
            1 => "a granular scene",
            2 => "a structural partner",
            _ => "an unknown model kind",
        }
    }
}

/// How the payload is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Encoding {
    Raw = 0,
    Deflate = 1,
}

/// A state envelope that cannot be written, or bytes that are not a state of this FMU.
/// Messages say what was expected and what was found.
#[derive(Debug, thiserror::Error)]
pub enum EnvelopeError {
    /// Compressing the payload failed.
    #[error("compressing the state: {0}")]
    Compress(std::io::Error),
    #[error("GUID longer than 255 bytes")]
    GuidTooLong,
    /// The bytes do not start with [`MAGIC`].
    #[error("not a granmix FMU state: the {len} bytes do not start with the granmix state tag")]
    NotAState { len: usize },
    /// Fewer bytes than the fixed part of the header.
    #[error("serialised state truncated: {len} bytes, the header alone takes {header}")]
    Short { len: usize, header: usize },
    /// A read at byte `at` runs past the end of the `len` bytes (the header or a
    /// payload read by [`crate::model::bytes::Reader`]).
    #[error("serialised state truncated at byte {at} of {len}")]
    Truncated { at: usize, len: usize },
    /// The checksum does not match: a byte changed after the tag.
    #[error(
        "serialised state corrupted: CRC-32 {crc:08x} of its {len} bytes differs from the \
         stored {stored:08x}"
    )]
    Corrupted { crc: u32, len: usize, stored: u32 },
    #[error(
        "serialised state of format version {version}; this FMU reads versions {OLDEST} \
         to {VERSION}"
    )]
    Version { version: u16 },
    /// A state-machine byte that is no state.
    #[error("serialised state: instance state byte {0} is not a state")]
    Place(u8),
    /// A state of another kind of model (the byte of [`ModelKind`]).
    #[error(
        "serialised state of {}, not of {}",
        ModelKind::name(*found),
        ModelKind::name(*wanted as u8)
    )]
    Kind { found: u8, wanted: ModelKind },
    #[error("serialised state with unknown payload encoding {0}")]
    Encoding(u8),
    /// A state of the FMU with GUID `found`.
    #[error("serialised state of another FMU (GUID {found}); this FMU's GUID is {guid}")]
    OtherFmu { found: String, guid: String },
    #[error("serialised state: header gives a payload of {stored} bytes, {follow} follow")]
    StoredLength { stored: u64, follow: usize },
    #[error("serialised state: raw payload of {stored} bytes said to decode to {decoded}")]
    RawLength { stored: u64, decoded: u64 },
    /// A decoded length no deflated payload of this size can give.
    #[error("serialised state: {stored} deflated bytes said to give {decoded}")]
    DeflatedLength { stored: u64, decoded: u64 },
    #[error("serialised state: decompressing: {0}")]
    Decompress(std::io::Error),
    #[error("serialised state: payload decoded to {got} bytes, the header says {decoded}")]
    DecodedLength { got: usize, decoded: u64 },
}

/// What [`open`] finds in an envelope.
#[derive(Debug)]
pub struct Opened {
    /// The decoded payload.
    pub payload: Vec<u8>,
    /// The instance's place in the state machine (None in a version 2 state).
    pub place: Option<Place>,
}

/// Wrap `payload`, taken at `place` of the state machine, in the envelope.
pub fn seal(
    kind: ModelKind,
    guid: &str,
    encoding: Encoding,
    place: &Place,
    payload: &[u8],
) -> Result<Vec<u8>, EnvelopeError> {
    let stored = match encoding {
        Encoding::Raw => None,
        Encoding::Deflate => {
            let mut e =
                DeflateEncoder::new(Vec::with_capacity(payload.len() / 2), Compression::fast());
            e.write_all(payload)
                .and_then(|_| e.finish())
                .map(Some)
                .map_err(EnvelopeError::Compress)?
        }
    };
    let body = stored.as_deref().unwrap_or(payload);
    let guid = guid.as_bytes();
    let glen = u8::try_from(guid.len()).map_err(|_| EnvelopeError::GuidTooLong)?;
    let mut out = Vec::with_capacity(body.len() + guid.len() + 40);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.push(kind as u8);
    out.push(encoding as u8);
    out.push(glen);
    out.extend_from_slice(guid);
    out.push(place.state as u8);
    let failure = place.failure.as_deref().unwrap_or("");
    let mut cut = failure.len().min(FAILURE_MAX);
    while !failure.is_char_boundary(cut) {
        cut -= 1;
    }
    out.extend_from_slice(&(cut as u16).to_le_bytes());
    out.extend_from_slice(&failure.as_bytes()[..cut]);
    out.extend_from_slice(&(body.len() as u64).to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(body);
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    Ok(out)
}

/// Check the envelope of `bytes` for a state of `kind` of the FMU `guid`, and return the
/// decoded payload and the instance's place.
pub fn open(bytes: &[u8], kind: ModelKind, guid: &str) -> Result<Opened, EnvelopeError> {
    let n = bytes.len();
    let data = checked(bytes)?;
    let mut r = Cursor {
        data,
        at: MAGIC.len(),
        len: n,
    };
    let version = u16::from_le_bytes(r.take(2)?.try_into().expect("2 bytes"));
    if !(OLDEST..=VERSION).contains(&version) {
        return Err(EnvelopeError::Version { version });
    }
    let k = r.take(1)?[0];
    if k != kind as u8 {
        return Err(EnvelopeError::Kind {
            found: k,
            wanted: kind,
        });
    }
    let encoding = match r.take(1)?[0] {
        0 => Encoding::Raw,
        1 => Encoding::Deflate,
        e => return Err(EnvelopeError::Encoding(e)),
    };
    let glen = r.take(1)?[0] as usize;
    let g = String::from_utf8_lossy(r.take(glen)?).into_owned();
    if g != guid {
        return Err(EnvelopeError::OtherFmu {
            found: g,
            guid: guid.to_string(),
        });
    }
    let place = if version >= 3 { Some(r.place()?) } else { None };
    let stored = u64::from_le_bytes(r.take(8)?.try_into().expect("8 bytes"));
    let decoded = u64::from_le_bytes(r.take(8)?.try_into().expect("8 bytes"));
    let body = &data[r.at..];
    if stored != body.len() as u64 {
        return Err(EnvelopeError::StoredLength {
            stored,
            follow: body.len(),
        });
    }
    let payload = decode(encoding, body, (stored, decoded))?;
    Ok(Opened { payload, place })
}

/// The bytes of an envelope before its checksum, once its magic, its length (at
/// least the fixed fields) and its CRC-32 are checked.
fn checked(bytes: &[u8]) -> Result<&[u8], EnvelopeError> {
    let n = bytes.len();
    if n < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
        return Err(EnvelopeError::NotAState { len: n });
    }
    const FIXED: usize = 8 + 2 + 1 + 1 + 1 + 8 + 8 + 4;
    if n < FIXED {
        return Err(EnvelopeError::Short {
            len: n,
            header: FIXED,
        });
    }
    let (data, tail) = bytes.split_at(n - 4);
    let stored_crc = u32::from_le_bytes(tail.try_into().expect("4 bytes"));
    let crc = crc32fast::hash(data);
    if crc != stored_crc {
        return Err(EnvelopeError::Corrupted {
            crc,
            len: data.len(),
            stored: stored_crc,
        });
    }
    Ok(data)
}

/// The header fields of an envelope read in order: its checked bytes, the next byte
/// to read and the whole envelope's length (for the error of a truncated field).
struct Cursor<'a> {
    data: &'a [u8],
    at: usize,
    len: usize,
}

impl<'a> Cursor<'a> {
    /// The next `k` bytes.
    fn take(&mut self, k: usize) -> Result<&'a [u8], EnvelopeError> {
        let at = self.at;
        let s = self
            .data
            .get(at..at + k)
            .ok_or(EnvelopeError::Truncated { at, len: self.len })?;
        self.at += k;
        Ok(s)
    }

    /// The instance's place (version 3 on): its state bit, then its failure message.
    fn place(&mut self) -> Result<Place, EnvelopeError> {
        let b = self.take(1)?[0];
        let state = State::from_bit(b).ok_or(EnvelopeError::Place(b))?;
        let m = u16::from_le_bytes(self.take(2)?.try_into().expect("2 bytes")) as usize;
        let failure = String::from_utf8_lossy(self.take(m)?).into_owned();
        Ok(Place {
            state,
            failure: (!failure.is_empty()).then_some(failure),
        })
    }
}

/// The payload of `body`, stored in `encoding`, checked against its stored and
/// decoded lengths; a deflated payload's claimed length is bounded by its stored one
/// before anything is allocated.
fn decode(
    encoding: Encoding,
    body: &[u8],
    (stored, decoded): (u64, u64),
) -> Result<Vec<u8>, EnvelopeError> {
    Ok(match encoding {
        Encoding::Raw if decoded != stored => {
            return Err(EnvelopeError::RawLength { stored, decoded })
        }
        Encoding::Raw => body.to_vec(),
        Encoding::Deflate => {
            let cap = usize::try_from(decoded)
                .ok()
                .filter(|&c| c / 1100 <= body.len() + 1)
                .ok_or(EnvelopeError::DeflatedLength { stored, decoded })?;
            let mut out = Vec::with_capacity(cap);
            DeflateDecoder::new(body)
                .take(decoded + 1)
                .read_to_end(&mut out)
                .map_err(EnvelopeError::Decompress)?;
            if out.len() as u64 != decoded {
                return Err(EnvelopeError::DecodedLength {
                    got: out.len(),
                    decoded,
                });
            }
            out
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: &str = "{00000000-0000-0000-0000-000000000001}";
    const STEP: Place = Place {
        state: State::StepMode,
        failure: None,
    };

    #[test]
    fn round_trip_in_both_encodings() {
        let payload: Vec<u8> = (0..5000u32).flat_map(|i| (i * 7).to_le_bytes()).collect();
        for e in [Encoding::Raw, Encoding::Deflate] {
            let b = seal(ModelKind::Granular, G, e, &STEP, &payload).unwrap();
            let o = open(&b, ModelKind::Granular, G).unwrap();
            assert_eq!(o.payload, payload);
            assert_eq!(o.place, Some(STEP));
        }
    }

    #[test]
    fn every_flipped_byte_is_refused() {
        let payload: Vec<u8> = (0..300u32).flat_map(|i| i.to_le_bytes()).collect();
        let b = seal(ModelKind::Granular, G, Encoding::Deflate, &STEP, &payload).unwrap();
        for i in 0..b.len() {
            for bit in [0x01u8, 0x80] {
                let mut c = b.clone();
                c[i] ^= bit;
                let e = open(&c, ModelKind::Granular, G).unwrap_err().to_string();
                let want = if i < MAGIC.len() {
                    "not a granmix FMU state"
                } else {
                    "corrupted"
                };
                assert!(e.contains(want), "byte {i}: {e}");
            }
        }
    }

    #[test]
    fn garbage_other_kind_and_other_fmu_say_so() {
        let b = seal(ModelKind::Granular, G, Encoding::Raw, &STEP, b"abc").unwrap();
        let message = |b: &[u8], kind, guid: &str| match open(b, kind, guid) {
            Ok(_) => panic!("opened"),
            Err(e) => e.to_string(),
        };
        let e = message(b"hello, this is not a state", ModelKind::Granular, G);
        assert!(e.starts_with("not a granmix FMU state"), "{e}");
        let e = message(&b, ModelKind::Structure, G);
        assert!(
            e.contains("of a granular scene, not of a structural partner"),
            "{e}"
        );
        let other = G.replace('1', "2");
        let e = message(&b, ModelKind::Granular, &other);
        assert!(e.contains("another FMU") && e.contains(G), "{e}");
        let e = message(&b[..b.len() - 1], ModelKind::Granular, G);
        assert!(e.contains("corrupted"), "{e}");
    }

    #[test]
    fn the_error_state_and_its_cause_travel_with_the_state() {
        let place = Place {
            state: State::Error,
            failure: Some("fmi2DoStep: numerical blow-up at step 3 — ü".to_string()),
        };
        let b = seal(ModelKind::Granular, G, Encoding::Deflate, &place, b"xyz").unwrap();
        let o = open(&b, ModelKind::Granular, G).unwrap();
        assert_eq!((o.payload.as_slice(), o.place), (&b"xyz"[..], Some(place)));
        // a message longer than the field is cut at a character boundary
        let long = Place {
            state: State::Error,
            failure: Some("é".repeat(40_000)),
        };
        let b = seal(ModelKind::Granular, G, Encoding::Raw, &long, b"").unwrap();
        let f = open(&b, ModelKind::Granular, G)
            .unwrap()
            .place
            .unwrap()
            .failure;
        assert_eq!(f.unwrap().len(), FAILURE_MAX - 1);
    }

    #[test]
    fn version_2_states_still_open_without_a_place() {
        let b = seal(ModelKind::Granular, G, Encoding::Raw, &STEP, b"abc").unwrap();
        // the version 2 layout: no state byte and no message
        let at = MAGIC.len() + 2 + 1 + 1 + 1 + G.len();
        let mut old = b[..at].to_vec();
        old[8..10].copy_from_slice(&2u16.to_le_bytes());
        old.extend_from_slice(&b[at + 3..b.len() - 4]);
        let crc = crc32fast::hash(&old);
        old.extend_from_slice(&crc.to_le_bytes());
        let o = open(&old, ModelKind::Granular, G).unwrap();
        assert_eq!((o.payload.as_slice(), o.place), (&b"abc"[..], None));
    }
}

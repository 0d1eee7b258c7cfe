//! Forged serialised states never bring an instance down: 10⁴ states made from valid
//! ones (payload bytes changed, inserted or cut and the envelope sealed again with its
//! checksum recomputed; header fields changed with the checksum recomputed; truncations;
//! oversize lengths) are given to `fmi2DeSerializeFMUstate` and `fmi2SetFMUstate`, and
//! those taken in are stepped. No call may return fmi2Fatal, every refusal leaves the
//! instance as it was, and after each case the valid state restores and steps bitwise as
//! before. `FORGED_TRACE=1` prints every case's outcome and time.

use granmix_fmu::envelope::{self, Encoding, ModelKind, MAGIC};
use granmix_fmu::ffi::{LocalError, LocalInstance};
use granmix_fmu::state::{Place, State};
use std::path::{Path, PathBuf};

const FATAL: i32 = fmi_sys::fmi2::fmi2Status_fmi2Fatal as i32;

/// A small deterministic generator (splitmix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../models/scenes")
        .join(name)
}

/// How a case ended.
#[derive(Default, Debug)]
struct Tally {
    refused: usize,
    stepped: usize,
    step_refused: usize,
    step_failed: usize,
    internal: usize,
    examples: Vec<String>,
}

fn status_of(e: &LocalError) -> Option<i32> {
    match e {
        LocalError::Status { status, .. } => Some(*status as i32),
        _ => None,
    }
}

/// The GUID written into every state of the instance (read back from a valid one).
fn guid_of(bytes: &[u8]) -> String {
    let at = MAGIC.len() + 2 + 1 + 1;
    let n = bytes[at] as usize;
    String::from_utf8(bytes[at + 1..at + 1 + n].to_vec()).unwrap()
}

/// One forged state from `valid` (whose decoded payload is `payload`).
fn forge(rng: &mut Rng, valid: &[u8], payload: &[u8], guid: &str) -> Vec<u8> {
    let step = Place {
        state: State::StepMode,
        failure: None,
    };
    let seal = |p: &[u8]| envelope::seal(ModelKind::Granular, guid, Encoding::Deflate, &step, p);
    let mut p = payload.to_vec();
    match rng.below(10) {
        // a few payload bytes changed (most of the cases)
        0..=4 => {
            for _ in 0..1 + rng.below(4) {
                let i = rng.below(p.len());
                p[i] = match rng.below(4) {
                    0 => p[i] ^ (1 << rng.below(8)),
                    1 => 0xff,
                    2 => 0,
                    _ => rng.next() as u8,
                };
            }
            seal(&p).unwrap()
        }
        // payload cut or grown
        5 => {
            p.truncate(rng.below(p.len()));
            seal(&p).unwrap()
        }
        6 => {
            let at = rng.below(p.len());
            let extra: Vec<u8> = (0..1 + rng.below(16)).map(|_| rng.next() as u8).collect();
            p.splice(at..at, extra);
            seal(&p).unwrap()
        }
        // a header byte changed and the checksum recomputed (place, lengths, version…)
        7 => {
            let mut b = valid.to_vec();
            let header = MAGIC.len() + 2 + 3 + guid.len() + 1 + 2 + 16;
            let i = MAGIC.len() + rng.below(header - MAGIC.len());
            b[i] = rng.next() as u8;
            let n = b.len() - 4;
            let crc = crc32fast::hash(&b[..n]);
            b[n..].copy_from_slice(&crc.to_le_bytes());
            b
        }
        // an oversize decoded length (a deflate bomb's header), checksum recomputed
        8 => {
            let mut b = valid.to_vec();
            let at = MAGIC.len() + 2 + 3 + guid.len() + 1 + 2 + 8;
            let big: u64 =
                [u64::MAX, 1 << 40, 200_000_000, payload.len() as u64 * 2000][rng.below(4)];
            b[at..at + 8].copy_from_slice(&big.to_le_bytes());
            let n = b.len() - 4;
            let crc = crc32fast::hash(&b[..n]);
            b[n..].copy_from_slice(&crc.to_le_bytes());
            b
        }
        // the whole blob truncated (its checksum then fails)
        _ => valid[..rng.below(valid.len())].to_vec(),
    }
}

/// Run `cases` forged states against an instance of `scene` (with `sets`), after
/// `steps` communication steps of `h`.
fn fuzz(scene_file: &str, sets: &[&str], steps: usize, h: f64, cases: usize, seed: u64) -> Tally {
    let dir = tempdir(scene_file);
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let guid = granmix_fmu::package::write_resources(&scene(scene_file), &sets, &dir).unwrap();
    let mut inst = LocalInstance::new("forged", &guid, &dir).unwrap();
    let mut t = 0.0;
    for _ in 0..steps {
        inst.do_step(t, h).unwrap();
        t += h;
    }
    let valid = inst.state_bytes().unwrap();
    assert_eq!(guid_of(&valid), guid);
    let payload = envelope::open(&valid, ModelKind::Granular, &guid)
        .unwrap()
        .payload;
    // the valid state's next step, for the bitwise check after each case
    let expected = {
        inst.do_step(t, h).unwrap();
        inst.state_bytes().unwrap()
    };
    inst.restore(&valid).unwrap();
    let mut rng = Rng(seed);
    let mut tally = Tally::default();
    for case in 0..cases {
        let forged = forge(&mut rng, &valid, &payload, &guid);
        let clock = std::time::Instant::now();
        let taken = inst.restore(&forged);
        if std::env::var("FORGED_TRACE").is_ok() {
            eprintln!(
                "case {case}: {:?} {:.1} ms",
                taken.as_ref().err(),
                clock.elapsed().as_secs_f64() * 1e3
            );
        }
        match &taken {
            Err(e) => {
                assert_ne!(status_of(e), Some(FATAL), "case {case}: restore: {e}");
                tally.refused += 1;
            }
            Ok(()) => {
                tally.stepped += 1;
                let now = inst.time().unwrap_or(t);
                let clock = std::time::Instant::now();
                let stepped = inst.do_step(now, h);
                if std::env::var("FORGED_TRACE").is_ok() {
                    eprintln!(
                        "  step {:?} {:.1} ms {:?}",
                        stepped.as_ref().err(),
                        clock.elapsed().as_secs_f64() * 1e3,
                        inst.failure()
                    );
                }
                if let Err(e) = stepped {
                    assert_ne!(status_of(&e), Some(FATAL), "case {case}: step: {e}");
                    match inst.failure() {
                        Some(f) if f.contains("internal error") => {
                            tally.internal += 1;
                            if tally.examples.len() < 5 {
                                tally.examples.push(f);
                            }
                        }
                        Some(_) => tally.step_failed += 1,
                        None => tally.step_refused += 1,
                    }
                }
            }
        }
        // a refused state left the instance as it was; one taken in is replaced by the
        // valid state, whatever it did
        if taken.is_ok() {
            inst.restore(&valid).unwrap();
        }
        if case % 997 == 0 {
            let now = inst.time().unwrap();
            assert_eq!(now, t, "case {case}: restored time");
            inst.do_step(t, h).unwrap();
            assert!(
                inst.state_bytes().unwrap() == expected,
                "case {case}: the valid state no longer steps bitwise"
            );
            inst.restore(&valid).unwrap();
        }
    }
    drop(inst);
    let _ = std::fs::remove_dir_all(&dir);
    tally
}

fn tempdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "granmix-forged-{}-{}",
        tag.trim_end_matches(".toml"),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn report(name: &str, t: &Tally) {
    eprintln!(
        "{name}: {} refused at restore, {} taken in ({} steps refused, {} failed, {} \
         internal errors)",
        t.refused, t.stepped, t.step_refused, t.step_failed, t.internal
    );
    for e in &t.examples {
        eprintln!("  {e}");
    }
}

#[test]
fn forged_states_of_a_layer_against_a_barrier_never_fatal() {
    let t = fuzz("fmu_barrier_2d.toml", &[], 5, 1e-3, 6000, 0x5eed_0001);
    report("fmu_barrier_2d", &t);
    assert_eq!(t.refused + t.stepped, 6000);
    // the checks refuse what would fail inside the solver: no forgery gets as far as
    // the panic guard (those taken in changed values within their ranges)
    assert!(t.refused > 3000 && t.internal == 0, "{t:?}");
}

#[test]
fn forged_states_of_a_body_in_water_never_fatal() {
    let t = fuzz(
        "disc_resting_in_water.toml",
        &["simulation.dp=0.01"],
        3,
        1e-3,
        4000,
        0x5eed_0002,
    );
    report("disc_resting_in_water", &t);
    assert_eq!(t.refused + t.stepped, 4000);
    assert!(t.refused > 2000 && t.internal == 0, "{t:?}");
}

//! No suction from dry soil (issue 26): a barrier pulled away from a layer at rest
//! receives no pulling load from a cohesionless soil, and from a cohesive one at most the
//! soil's tensile strength, the apex c cot φ of its Drucker–Prager cone (seed 000
//! Eqs. 4–6), per unit area of contact. fmu_barrier_2d at its own dp = 10 mm: a layer
//! H = 0.1 m high from the K0 geostatic stress, the barrier driven as the FMU drives it.

use granmix_core::run::simulation::Simulation;
use granmix_tests::load;

/// fmu_barrier_2d with `set`, settled against the fixed barrier for 20 ms.
fn at_rest(set: &[&str]) -> Simulation<2> {
    let loaded = load("fmu_barrier_2d.toml", set);
    let mut sim = Simulation::<2>::new(&loaded.scene).unwrap_or_else(|e| panic!("{e:?}"));
    sim.advance_to(0.02).expect("settles");
    sim
}

/// Horizontal load on the barrier in the last step (N/m; + pushes it away from the soil).
fn load_x(sim: &Simulation<2>) -> f64 {
    sim.stepper.step_loads[0].force[0]
}

/// Smallest distance between a fine particle and a dummy particle of the barrier.
fn gap(sim: &Simulation<2>) -> f64 {
    let w = &sim.world.walls;
    let object = w.barriers[0].object as u16;
    let mut g = f64::INFINITY;
    for (q, _) in w.pos.iter().zip(&w.object).filter(|(_, &o)| o == object) {
        for p in &sim.world.fine.pos {
            g = g.min((p - q).norm());
        }
    }
    g
}

/// The barrier's speed away from the soil (m/s) at time t (s) since the pull began.
type Speed = Box<dyn Fn(f64) -> f64>;

/// One pull: every step's load, the gap after it, and the time.
struct Pull {
    loads: Vec<(f64, f64, f64)>,
}

/// Pull the barrier away from the soil (+x) with speed `v(t)` from the settled state
/// for `duration` seconds, or until the gap has exceeded the kernel support for 20
/// steps.
fn pull(mut sim: Simulation<2>, v: impl Fn(f64) -> f64, duration: f64) -> Pull {
    let cut = sim.stepper.kernel.cutoff;
    let t0 = sim.time();
    let mut loads = Vec::new();
    let mut clear = 0;
    while sim.time() < t0 + duration && clear < 20 {
        let t = sim.time() - t0;
        sim.drive_barrier(0, [v(t), 0.0, 0.0])
            .expect("driven barrier");
        sim.step(1e-3).expect("no blow-up");
        let g = gap(&sim);
        if g > cut {
            clear += 1;
        }
        loads.push((sim.time() - t0, load_x(&sim), g));
    }
    Pull { loads }
}

fn report(name: &str, p: &Pull) {
    let min = p.loads.iter().map(|x| x.1).fold(f64::INFINITY, f64::min);
    eprintln!(
        "{name}: {} steps, first {:.4} N/m, min {:.6e} N/m, last gap {:.4} m",
        p.loads.len(),
        p.loads[0].1,
        min,
        p.loads.last().unwrap().2
    );
}

/// A cohesionless layer: at 0.1, 1 and 5 m/s and at 10 m/s² the load never pulls by
/// more than 1e-9 of the load at rest (round-off of a sum of ~10³ pair terms of that
/// size), and once the gap exceeds the kernel support 2h it is exactly zero.
#[test]
fn dry_soil_never_pulls_a_receding_barrier() {
    let rest = at_rest(&[]);
    let f0 = load_x(&rest);
    assert!(f0 > 20.0, "at-rest load {f0} N/m");
    let cut = rest.stepper.kernel.cutoff;
    let cases: [(&str, Speed, f64, bool); 4] = [
        ("0.1 m/s", Box::new(|_| 0.1), 0.05, false),
        ("1 m/s", Box::new(|_| 1.0), 0.05, true),
        ("5 m/s", Box::new(|_| 5.0), 0.05, true),
        ("10 m/s²", Box::new(|t| 10.0 * t), 0.04, false),
    ];
    for (name, v, duration, leaves) in cases {
        let p = pull(rest.clone(), v, duration);
        report(name, &p);
        for &(t, f, g) in &p.loads {
            assert!(
                f >= -1e-9 * f0,
                "{name}: pulling load {f:.6e} N/m at t = {t:.5} s (at rest {f0:.3} N/m)"
            );
            if g > cut {
                assert_eq!(f, 0.0, "{name}: load {f:e} N/m with a gap {g:.4} m > 2h");
            }
        }
        if leaves {
            assert!(
                p.loads.last().unwrap().2 > cut,
                "{name}: the barrier should leave the soil"
            );
        }
    }
}

/// A cohesive layer (c = 1 kPa, φ = 30°) pulled at 1 m/s: the barrier is held back,
/// by at most the apex stress σ_t = c cot φ = 1.73 kPa over the contact height H = 0.1 m
/// (+5 %: the discrete wall sum of a layer cut off at its top and toe).
#[test]
fn cohesive_soil_pulls_at_most_its_tensile_strength() {
    let c = 1000.0;
    let sigma_t = c / 30f64.to_radians().tan();
    let bound = sigma_t * 0.1;
    let rest = at_rest(&["materials[0].cohesion=1000"]);
    let p = pull(rest, |_| 1.0, 0.01);
    report("cohesive 1 m/s", &p);
    let most = p.loads.iter().map(|x| -x.1).fold(0.0, f64::max);
    eprintln!("cohesive: largest pull {most:.3} N/m against σ_t H = {bound:.3} N/m");
    for &(t, f, _) in &p.loads {
        assert!(
            -f <= 1.05 * bound,
            "pull {:.3} N/m at t = {t:.5} s beyond σ_t H = {bound:.3} N/m",
            -f
        );
    }
    assert!(
        most >= 0.5 * bound,
        "a cohesive soil should hold the barrier back: largest pull {most:.3} N/m"
    );
}

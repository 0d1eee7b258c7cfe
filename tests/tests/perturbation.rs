//! `simulation.perturbation`: an ensemble member's start is the unperturbed one with
//! every soil and water particle moved by exactly ε dp, and nothing else moved; the
//! seed alone decides the directions.

use granmix_core::AnySimulation;
use granmix_tests::load;

type Start = (Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<f64>>);

/// Fine, water and coarse positions at t = 0.
fn start(set: &[&str]) -> Start {
    let loaded = load("debris_flow_saturated.toml", set);
    let AnySimulation::D2(sim) = AnySimulation::new(&loaded).unwrap() else {
        panic!("a 2D scene")
    };
    let w = &sim.world;
    let pos = |v: &[granmix_core::numerics::math::Vect<2>]| {
        v.iter().map(|p| p.as_slice().to_vec()).collect()
    };
    (
        pos(&w.fine.pos),
        pos(&w.water.particles.pos),
        pos(&w.coarse.particles.pos),
    )
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn each_particle_moves_by_epsilon_dp_and_the_seed_decides_where() {
    let dp = 0.02; // the bundled scene's
    let plain = start(&[]);
    let eps = 1e-4;
    let a = start(&[
        "simulation.perturbation.seed=3",
        "simulation.perturbation.amplitude=1e-4",
    ]);
    assert!(!plain.0.is_empty() && !plain.1.is_empty() && !plain.2.is_empty());
    for (family, p, q) in [("soil", &plain.0, &a.0), ("water", &plain.1, &a.1)] {
        assert_eq!(p.len(), q.len(), "{family}: the same particles");
        for (x, y) in p.iter().zip(q) {
            let d = distance(x, y);
            // positions of order 1 m: round-off 1e-16 m against ε dp = 2e-6 m
            assert!(
                (d - eps * dp).abs() < 1e-12,
                "{family}: moved {d} m, not {}",
                eps * dp
            );
        }
    }
    assert_eq!(plain.2, a.2, "the boulders keep their places");
    let again = start(&[
        "simulation.perturbation.seed=3",
        "simulation.perturbation.amplitude=1e-4",
    ]);
    assert_eq!(a, again, "the same seed: bitwise the same start");
    let other = start(&[
        "simulation.perturbation.seed=4",
        "simulation.perturbation.amplitude=1e-4",
    ]);
    let same = a.0.iter().zip(&other.0).filter(|(x, y)| x == y).count();
    assert_eq!(same, 0, "another seed moves every particle elsewhere");
}

//! VALIDATION.md §7: colliding rubber rings (TLSPH, seed 000 §7.2). Total momentum is
//! conserved to round-off (1e-10 of one ring's momentum), the total energy (kinetic +
//! strain + contact springs) never increases, and the rings bounce apart keeping
//! their shape (no hourglass modes).

use granmix_tests::run;

#[test]
fn rubber_rings_conserve_momentum_and_never_gain_energy() {
    // dp = 1 mm (4.4 k particles) instead of 0.5 mm
    let (samples, end, sim) = run("rubber_rings.toml", &["simulation.dp=0.001"]);
    assert!(
        !matches!(end, granmix_core::run::runner::RunEnd::Blowup(_)),
        "{end:?}"
    );
    let first = &samples[0];
    let ring_p = first.bodies[0].velocity[0].abs() * first.coarse_kinetic_energy
        / first.bodies[0].velocity[0].powi(2); // = M_ring |v| (both rings alike)
    let energy = |s: &granmix_core::run::simulation::Sample| {
        s.coarse_kinetic_energy + s.strain_energy + s.contact_energy
    };
    let e0 = energy(first);
    let mut prev = e0;
    let mut touched = false;
    for s in &samples {
        let dp: f64 = (0..2)
            .map(|k| (s.momentum[k] - first.momentum[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            dp < 1e-10 * ring_p,
            "t = {}: momentum drift {dp:e} vs ring momentum {ring_p:e}",
            s.time
        );
        let e = energy(s);
        assert!(
            e <= prev * (1.0 + 1e-9),
            "t = {}: energy grew from {prev} to {e} J/m",
            s.time
        );
        prev = e;
        touched |= s.bodies[0].contacts > 0;
    }
    assert!(touched, "the rings never met");
    let last = samples.last().unwrap();
    assert!(
        last.bodies[0].velocity[0] < 0.0 && last.bodies[1].velocity[0] > 0.0,
        "rings did not bounce apart: {:?} {:?}",
        last.bodies[0].velocity,
        last.bodies[1].velocity
    );
    assert!(energy(last) < e0, "no dissipation at all");
    // shape: no hourglass zig-zag, clumping or tearing — every particle keeps its
    // nearest neighbour (same ring) between 0.7 dp and 1.3 dp
    let f = sim.frame();
    let dp = 0.001;
    for b in 0..2u32 {
        let pts: Vec<[f32; 3]> = f
            .coarse
            .iter()
            .filter(|p| p.group == b)
            .map(|p| p.position)
            .collect();
        for (i, p) in pts.iter().enumerate() {
            let nn = pts
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, q)| (((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)) as f64).sqrt())
                .fold(f64::INFINITY, f64::min);
            assert!(
                nn > 0.7 * dp && nn < 1.3 * dp,
                "ring {b}: particle {i} has its nearest neighbour at {nn:e} m"
            );
        }
    }
}

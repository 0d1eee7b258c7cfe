//! The same scene gives bitwise-identical results on 1 and 2 threads.

use granmix_core::AnySimulation;
use granmix_tests::load;

fn run_with_threads(threads: usize, scene: &str, set: &[&str], steps: usize) -> Vec<u64> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let loaded = load(scene, set);
        let mut sim = AnySimulation::new(&loaded).unwrap();
        for _ in 0..steps {
            sim.step(f64::INFINITY).unwrap();
        }
        let f = sim.frame();
        let s = sim.sample();
        let mut bits: Vec<u64> = f
            .fine
            .iter()
            .flat_map(|p| p.position.iter().map(|x| x.to_bits() as u64))
            .collect();
        bits.extend(
            f.stress
                .iter()
                .flat_map(|p| p.iter().map(|x| x.to_bits() as u64)),
        );
        bits.extend(f.fine.iter().map(|p| p.id as u64));
        bits.extend(f.awake.iter().map(|&a| a as u64));
        bits.extend(
            f.coarse
                .iter()
                .flat_map(|p| p.position.iter().map(|x| x.to_bits() as u64)),
        );
        bits.extend(
            s.bodies
                .iter()
                .flat_map(|b| b.force.iter().chain(&b.velocity).map(|x| x.to_bits())),
        );
        bits.push(s.kinetic_energy.to_bits());
        bits.extend(f.water.iter().flat_map(|p| {
            p.position
                .iter()
                .chain(&p.velocity)
                .map(|x| x.to_bits() as u64)
                .chain([p.id as u64])
        }));
        if let Some(w) = &s.water {
            bits.extend(w.momentum.iter().map(|x| x.to_bits()));
        }
        bits.extend(
            s.barriers
                .iter()
                .flat_map(|b| b.force.iter().map(|x| x.to_bits())),
        );
        bits
    })
}

#[test]
fn bitwise_identical_across_thread_counts() {
    for (scene, set, steps) in [
        ("granular_barrier_2d.toml", vec!["simulation.dp=0.005"], 600),
        ("column_collapse_3d.toml", vec!["simulation.dp=0.02"], 200),
        // fine–coarse coupling, multi-rate sub-steps, TLSPH
        ("impact_crater.toml", vec!["simulation.dp=0.008"], 150),
        // resting grains asleep (a short window so that some fall asleep), woken
        (
            "impact_crater.toml",
            vec![
                "simulation.dp=0.008",
                "numerics.sleep=true",
                "numerics.sleep_steps=10",
                "numerics.sleep_speed=0.05",
            ],
            150,
        ),
        // rigid bodies with contacts
        ("blocks_impact.toml", vec!["simulation.dp=0.005"], 400),
        // water on walls and a rigid body
        ("boulder_in_water.toml", vec!["simulation.dp=0.01"], 200),
        // 3D water
        ("dam_break_3d.toml", vec!["simulation.dp=0.0057"], 150),
        // water across a periodic seam
        ("poiseuille_2d.toml", vec!["simulation.dp=0.00125"], 300),
        // soil across a periodic seam, μ(I), the Riemann jump reconstructed
        ("bagnold_incline.toml", vec!["simulation.dp=2.5e-4"], 400),
        // soil and water: seepage, buoyancy, a permeable sieve
        ("seepage_column.toml", vec![], 300),
    ] {
        let a = run_with_threads(1, scene, &set, steps);
        let b = run_with_threads(2, scene, &set, steps);
        assert_eq!(a.len(), b.len());
        let diff = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert_eq!(
            diff, 0,
            "{scene}: {diff} values differ between 1 and 2 threads"
        );
    }
}

//! A seeded perturbation of the start (`simulation.perturbation`): every soil and water
//! particle moved by ε dp in a direction drawn from the seed. An ensemble's members
//! differ by their seed alone, so each is reproducible and can be rerun by itself
//! (docs/sweeps.md, *Ensembles*).
//!
//! The direction of particle i is a function of (seed, family, i) only (a counter-based
//! draw: SplitMix64 of the three), so it does not depend on the thread count or on the
//! order in which particles are visited. Coarse bodies, walls and barriers keep their
//! places: an elastic body's particles are its reference configuration.

use crate::numerics::math::{Real, Vect};
use crate::numerics::periodic::Wrap;

/// The family a particle belongs to, mixed into its draw so that soil particle i and
/// water particle i move independently.
#[derive(Clone, Copy)]
pub enum Family {
    Soil = 1,
    Water = 2,
}

/// SplitMix64's finaliser (Steele, Lea & Flood, "Fast splittable pseudorandom number
/// generators", OOPSLA 2014): a bijection of u64 whose outputs pass BigCrush as a
/// counter-based generator.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The k-th uniform number in [0, 1) of particle `i` of `family` under `seed`.
fn uniform(seed: u64, family: Family, i: usize, k: u64) -> Real {
    let key = mix(mix(seed) ^ ((family as u64) << 60) ^ mix(i as u64)) ^ k;
    // the top 53 bits: every value a multiple of 2^-53
    (mix(key) >> 11) as Real * (1.0 / (1u64 << 53) as Real)
}

/// A unit vector drawn uniformly over the circle (2D) or the sphere (3D).
fn direction<const D: usize>(seed: u64, family: Family, i: usize) -> Vect<D> {
    let tau = std::f64::consts::TAU;
    let a = tau * uniform(seed, family, i, 0);
    let mut n = Vect::<D>::zeros();
    if D == 2 {
        (n[0], n[1]) = (a.cos(), a.sin());
    } else {
        // Archimedes: z uniform on [−1, 1] gives a uniform point on the sphere
        let z = 2.0 * uniform(seed, family, i, 1) - 1.0;
        let r = (1.0 - z * z).max(0.0).sqrt();
        (n[0], n[1], n[2]) = (r * a.cos(), r * a.sin(), z);
    }
    n
}

/// Move every position of `pos` by `distance` along its drawn direction, wrapped into
/// the period if there is one.
pub fn displace<const D: usize>(
    pos: &mut [Vect<D>],
    seed: u64,
    family: Family,
    distance: Real,
    periodic: Wrap,
) {
    for (i, x) in pos.iter_mut().enumerate() {
        *x += direction::<D>(seed, family, i) * distance;
        if let Some(p) = periodic {
            p.wrap_point(x);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_particle_moves_by_the_stated_distance() {
        let mut p = vec![Vect::<3>::new(0.1, 0.2, 0.3); 1000];
        displace(&mut p, 7, Family::Soil, 1e-3, None);
        for x in &p {
            let d = (x - Vect::<3>::new(0.1, 0.2, 0.3)).norm();
            assert!((d - 1e-3).abs() < 1e-15, "{d}");
        }
    }

    #[test]
    fn directions_are_uniform_and_the_seed_decides_them() {
        // the mean of 10^4 unit vectors uniform on the sphere is 0 within 3/sqrt(3 n)
        let n = 10_000;
        let mean: Vect<3> = (0..n)
            .map(|i| direction::<3>(1, Family::Water, i))
            .sum::<Vect<3>>()
            / n as Real;
        assert!(mean.norm() < 3.0 / (3.0 * n as Real).sqrt(), "{mean:?}");
        // ⟨z²⟩ = 1/3 on the sphere
        let zz: Real = (0..n)
            .map(|i| direction::<3>(1, Family::Water, i)[2].powi(2))
            .sum::<Real>()
            / n as Real;
        assert!((zz - 1.0 / 3.0).abs() < 0.01, "{zz}");
        let same = direction::<2>(5, Family::Soil, 3);
        assert_eq!(same, direction::<2>(5, Family::Soil, 3));
        assert_ne!(same, direction::<2>(6, Family::Soil, 3));
        assert_ne!(same, direction::<2>(5, Family::Water, 3));
        assert_ne!(same, direction::<2>(5, Family::Soil, 4));
    }
}

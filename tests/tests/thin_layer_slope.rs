//! Basal friction of a thin layer against the infinite-slope limit of a cohesionless
//! soil (Mohr–Coulomb): a layer on a rough floor inclined at θ stays at rest when
//! θ < φ and slides when θ > φ, with acceleration g (sin θ − tan φ cos θ) once the
//! whole layer slips on its base (Coulomb). The answer must not depend on how many particles
//! thick the layer is. The floor is tilted by tilting gravity.
//!
//! With seed 000's mirror (`numerics.wall_stress = "mirrored"`) the wall gives a
//! particle lying on it only the shear at the particle's centre, half the basal shear
//! of a one-particle-thick layer, and such a layer slides at θ = 20° on a φ = 30°
//! soil. The default extrapolates the stress to the wall as Eq. (35) extrapolates
//! the pressure.

use granmix_tests::run_text;

const DP: f64 = 0.005;
const LEN: f64 = 0.6;
const RHO: f64 = 2600.0;
const G: f64 = 9.81;

/// Down-slope speed at each output time in the middle of a layer `layers` particles
/// thick, as probes at a quarter, half and three quarters of its length read it (the
/// layer's free ends slump locally).
fn slide(theta: f64, phi: f64, layers: usize, wall_stress: &str) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    run_text(
        &layer_scene(theta, phi, layers, wall_stress),
        "thin_layer.toml",
        |x| {
            let v = x.probes.iter().map(|p| p.1.velocity[0]).sum::<f64>() / 3.0;
            out.push((x.time, v));
        },
    );
    out
}

/// A layer `layers` particles thick on a floor inclined at θ (gravity tilted), with
/// velocity probes at a quarter, half and three quarters of its length.
fn layer_scene(theta: f64, phi: f64, layers: usize, wall_stress: &str) -> String {
    let (s, c) = theta.to_radians().sin_cos();
    let height = layers as f64 * DP;
    format!(
        r#"
[simulation]
dimension = 2
gravity = [{gx}, {gy}]
gravity_ramp = 0.1
end_time = 0.6
dp = {DP}
output_interval = 0.05

[numerics]
wall_stress = "{wall_stress}"

[[materials]]
name = "sand"
density = {RHO}
youngs_modulus = 5.98e6
poisson_ratio = 0.3
friction_angle = {phi}

[[regions]]
name = "layer"
material = "sand"
shape = {{ type = "box", min = [0.0, 0.0], max = [{LEN}, {height}] }}

[[barriers]]
name = "floor"
shape = {{ type = "box", min = [-0.1, -0.025], max = [1.5, 0.0] }}
reference_point = [0.0, 0.0]

[[probes]]
name = "a"
position = [{q1}, {mid}]

[[probes]]
name = "b"
position = [{q2}, {mid}]

[[probes]]
name = "c"
position = [{q3}, {mid}]
"#,
        q1 = 0.25 * LEN,
        q2 = 0.5 * LEN,
        q3 = 0.75 * LEN,
        mid = 0.5 * height,
        gx = G * s,
        gy = -G * c,
    )
}

fn speed_at(v: &[(f64, f64)], t: f64) -> f64 {
    v.iter()
        .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
        .unwrap()
        .1
}

#[test]
fn thin_layers_rest_below_friction_angle_whatever_their_thickness() {
    for layers in [1, 2, 4] {
        let v = slide(20.0, 30.0, layers, "extrapolated");
        let late = v
            .iter()
            .filter(|x| x.0 >= 0.3)
            .map(|x| x.1.abs())
            .fold(0.0, f64::max);
        assert!(
            late < 1e-3,
            "a layer {layers} particle(s) thick slides at {late:.4} m/s on a 20° slope (φ = 30°)"
        );
    }
    // seed 000's mirror: the one-particle layer slides
    let v = slide(20.0, 30.0, 1, "mirrored");
    let late = speed_at(&v, 0.6);
    assert!(
        late > 0.1,
        "mirrored wall stress: one-particle layer at {late:.3} m/s"
    );
}

/// Above φ the layer slips on its base. Drucker–Prager's plane-strain fit (Eq. 6)
/// mobilises at least Coulomb's tan φ there (measured: 0.76–0.98 of Coulomb's
/// acceleration for one to four particles), while the mirror's half basal shear lets
/// a one-particle layer gain 1.9 times it, two 1.45 times, four 1.2 times.
#[test]
fn thin_layers_slide_above_friction_angle_no_faster_than_coulomb() {
    let (theta, phi) = (20.0f64, 15.0f64);
    let (s, c) = theta.to_radians().sin_cos();
    let coulomb = G * (s - phi.to_radians().tan() * c);
    for layers in [1, 2, 4] {
        let v = slide(theta, phi, layers, "extrapolated");
        // after the gravity ramp (0.1 s)
        let a = (speed_at(&v, 0.45) - speed_at(&v, 0.15)) / 0.3;
        assert!(
            (0.6..=1.1).contains(&(a / coulomb)),
            "a layer {layers} particle(s) thick slides at {a:.3} m/s² on a {theta}° slope \
             (φ = {phi}°), Coulomb: {coulomb:.3} m/s²"
        );
    }
}

/// A resting layer carries its own weight and no more (issue 41): the normal stress at
/// its base is ρ g h cos θ. The base value is the bottom row's mean σ_nn (its centre
/// lies dp/2 above the floor) plus the weight of the half particle below its centre,
/// over the middle half of the layer (its free ends slump). A layer squeezed by the
/// transients of its loading, or one whose particles' volumes grew, carries more.
#[test]
fn resting_thin_layers_carry_their_weight_at_the_base() {
    let (theta, phi) = (20.0f64, 30.0);
    let cos = theta.to_radians().cos();
    for layers in [1, 2, 4] {
        let text = layer_scene(theta, phi, layers, "extrapolated");
        let sim = run_text(&text, "thin_layer.toml", |_| {});
        let f = sim.frame();
        let (mut sum, mut n) = (0.0, 0);
        for (p, s) in f.fine.iter().zip(&f.stress) {
            let [x, y, _] = p.position.map(f64::from);
            if y < DP && (0.25 * LEN..0.75 * LEN).contains(&x) {
                sum -= f64::from(s[1]);
                n += 1;
            }
        }
        assert!(n > 0, "no particle in the bottom row");
        let base = sum / n as f64 + RHO * G * cos * 0.5 * DP;
        let expected = RHO * G * cos * layers as f64 * DP;
        assert!(
            (base / expected - 1.0).abs() < 0.10,
            "a layer {layers} particle(s) thick on a {theta}° slope: base pressure {base:.1} Pa, \
             ρ g h cos θ = {expected:.1} Pa"
        );
    }
}

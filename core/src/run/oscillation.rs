//! Period and decay of a sampled damped oscillation, e.g. the horizontal momentum of
//! a sloshing tank (`standing_wave_2d.toml`): the bench's standing wave and the tests
//! read the water scheme's dissipation with it.

use crate::numerics::math::Real;

/// A damped oscillation A e^{−γt} sin(2πt/T + φ) as read from its samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oscillation {
    /// Period T (s).
    pub period: Real,
    /// Decay rate γ of the amplitude (1/s).
    pub gamma: Real,
    /// Extrema the decay was fitted on.
    pub half_periods: usize,
}

impl Oscillation {
    /// The log decrement per period, γ T.
    pub fn decrement(&self) -> Real {
        self.gamma * self.period
    }
}

/// Period and decay of a damped oscillation (t, p) starting near a zero: the period is
/// twice the mean spacing of its zero crossings (least squares over their index), γ
/// the slope of ln |p| at its extremum between each pair of crossings (parabola through
/// the largest sample and its neighbours).
pub fn damped(p: &[(Real, Real)]) -> Option<Oscillation> {
    // zero crossings, linearly interpolated (the start at p = 0 is not one)
    let mut zeros = Vec::new();
    for w in p.windows(2) {
        let ((t0, a), (t1, b)) = (w[0], w[1]);
        if a != 0.0 && a.signum() != b.signum() {
            zeros.push(t0 + a / (a - b) * (t1 - t0));
        }
    }
    // the extrema: from the start to the first crossing, and between crossings
    let mut bounds = vec![p.first()?.0];
    bounds.extend(&zeros);
    let mut peaks = Vec::new();
    for b in bounds.windows(2) {
        let idx: Vec<usize> = (0..p.len())
            .filter(|&i| p[i].0 > b[0] && p[i].0 < b[1])
            .collect();
        let Some(&i) = idx
            .iter()
            .max_by(|&&i, &&j| p[i].1.abs().total_cmp(&p[j].1.abs()))
        else {
            continue; // two crossings within one sample: no extremum between them
        };
        if i == 0 || i + 1 >= p.len() {
            continue;
        }
        let (a, m, c) = (p[i - 1].1.abs(), p[i].1.abs(), p[i + 1].1.abs());
        let den = a - 2.0 * m + c;
        let off = if den < 0.0 { 0.5 * (a - c) / den } else { 0.0 };
        let dt = 0.5 * (p[i + 1].0 - p[i - 1].0);
        peaks.push((p[i].0 + off * dt, m - 0.25 * (a - c) * off));
    }
    if peaks.len() < 2 || zeros.len() < 2 {
        return None;
    }
    let half = slope(
        &zeros
            .iter()
            .enumerate()
            .map(|(n, t)| (n as Real, *t))
            .collect::<Vec<_>>(),
    );
    let decay = slope(&peaks.iter().map(|(t, a)| (*t, a.ln())).collect::<Vec<_>>());
    Some(Oscillation {
        period: 2.0 * half,
        gamma: -decay,
        half_periods: peaks.len(),
    })
}

/// Least-squares slope of y against x.
fn slope(xy: &[(Real, Real)]) -> Real {
    let n = xy.len() as Real;
    let (mx, my) = (
        xy.iter().map(|p| p.0).sum::<Real>() / n,
        xy.iter().map(|p| p.1).sum::<Real>() / n,
    );
    let sxy: f64 = xy.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fit recovers the period and decay of a sampled e^{−γt} sin(ωt), with an
    /// incoherent jitter on top.
    #[test]
    fn fit_recovers_a_damped_sine() {
        let (w, g) = (5.3, 0.4);
        let p: Vec<(Real, Real)> = (0..400)
            .map(|i| {
                let t = 0.01 * i as Real;
                let jitter = 1e-3 * ((i * 7919 % 101) as Real / 50.0 - 1.0);
                (t, 10.0 * (-g * t).exp() * (w * t).sin() + jitter)
            })
            .collect();
        let f = damped(&p).expect("a fit");
        let t = 2.0 * std::f64::consts::PI / w;
        assert!((f.period / t - 1.0).abs() < 1e-3, "{f:?}");
        assert!((f.gamma / g - 1.0).abs() < 1e-2, "{f:?}");
        assert_eq!(f.half_periods, 6);
    }
}

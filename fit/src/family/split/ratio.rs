//! Backscatter family (the paper's §3.2): the backward integral from the foot of
//! the perpendicular, as a ratio to the whole forward integral,
//!
//!   `∫₀^{θ1} e^{−κ(sec θ + tan θ)} dθ / ∫₀^{π/2} e^{−κ(sec θ − tan θ)} dθ ≈ f(θ1) e^{−g(θ1) κ^{h(θ1)}}`,
//!
//! with `f, g, h` cubic in `θ1` (the paper's matrix; its third row is `h`, printed `d`).
//!
//! The fit minimises the least-squares relative error of `A` (the exact forward
//! part plus the ratio's backward part) over points drawn from the `thin` and
//! `dense` domains: the backward part's error counts in proportion to its share of
//! the glow. For fixed `g, h` the coefficients of `f` solve a linear least-squares
//! problem (SVD); `g, h` are moved by Nelder–Mead, starting from the paper's values.

use airlight_truth::domains::Domain;
use super::phase_exp::sec_plus_tan;
use super::segments::exact_forward;
use crate::lsq::{self, Outcome};
use airlight_truth::quad::gauss_kronrod;
use nalgebra::{DMatrix, DVector};
use std::f64::consts::FRAC_PI_2;

/// Cubic coefficients (`θ³, θ², θ, 1`) of `f`, `g` and `h`.
#[derive(Debug, Clone, PartialEq)]
pub struct Ratio {
    /// Amplitude.
    pub f: [f64; 4],
    /// Decay rate.
    pub g: [f64; 4],
    /// Exponent of κ.
    pub h: [f64; 4],
}

fn cubic(c: &[f64; 4], x: f64) -> f64 {
    ((c[0] * x + c[1]) * x + c[2]) * x + c[3]
}

impl Ratio {
    /// The paper's matrix, as printed.
    pub fn paper() -> Ratio {
        Ratio {
            f: [-0.0394, 0.1065, 0.5774, 0.0058],
            g: [-0.1299, 0.4204, 0.3811, 0.5993],
            h: [0.0171, -0.1586, -0.0424, 1.0879],
        }
    }

    /// The approximate ratio at `(θ1, κ)`; `κ^h` is 0 at κ = 0.
    pub fn eval(&self, theta1: f64, kappa: f64) -> f64 {
        cubic(&self.f, theta1) * self.decay(theta1, kappa)
    }

    fn decay(&self, theta1: f64, kappa: f64) -> f64 {
        let k = if kappa == 0.0 { 0.0 } else { kappa.powf(cubic(&self.h, theta1)) };
        (-cubic(&self.g, theta1) * k).exp()
    }
}

/// `∫_lo^hi e^{−κ(sec θ + tan θ)} dθ` for `0 ≤ lo ≤ hi ≤ π/2`, by adaptive quadrature.
pub fn exact_backward(kappa: f64, lo: f64, hi: f64) -> f64 {
    let f = |th: f64| {
        if th >= FRAC_PI_2 {
            if kappa == 0.0 {
                1.0
            } else {
                0.0
            }
        } else {
            (-kappa * sec_plus_tan(th)).exp()
        }
    };
    // Breakpoints where the integrand turns over to its e^{−2κ/(π/2 − θ)} tail.
    let mut cuts = vec![lo];
    for k in 1..40 {
        let c = FRAC_PI_2 - 0.5f64.powi(k);
        if c > lo && c < hi {
            cuts.push(c);
        }
    }
    cuts.push(hi);
    gauss_kronrod(f, &cuts, 1e-13, 400).value
}

/// One target of the ratio fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RatioSample {
    /// `κ = T = τ sin γ`.
    pub kappa: f64,
    /// Upper angle of the backward part.
    pub theta1: f64,
    /// Exact backward integral `∫₀^{θ1}`.
    pub backward: f64,
    /// Exact whole forward integral `∫₀^{π/2}` (the ratio's denominator).
    pub forward: f64,
    /// Exact forward part of the same point, `∫₀^{π/2 − γ}` (0 at γ = π/2): with the
    /// backward part it makes up `A` (up to a common factor), whose relative error
    /// the fit minimises.
    pub forward_part: f64,
}

/// Targets at κ = 0 (no extinction, where the exact ratio is `2θ1/π`), added to the
/// sampled ones: the commonest case in thin fog, which uniform sampling of τ barely
/// touches.
pub const NO_EXTINCTION_TARGETS: usize = 60;

/// `dense` contributes `n / DENSE_SHARE` points (tried: 4 gave larger errors on both
/// domains than equal shares).
pub const DENSE_SHARE: usize = 1;

/// `n` points from `thin` and `n / DENSE_SHARE` from `dense` with a backward part starting at the
/// foot (γ ≤ π/2), the case the family is defined for, plus
/// [`NO_EXTINCTION_TARGETS`] evenly spaced `θ1` at κ = 0.
pub fn ratio_samples(n: usize, seed: u64) -> Vec<RatioSample> {
    // (κ, θ1, γ)
    let mut pts: Vec<(f64, f64, f64)> = (0..NO_EXTINCTION_TARGETS)
        .map(|i| (0.0, FRAC_PI_2 * (i as f64 + 1.0) / NO_EXTINCTION_TARGETS as f64, FRAC_PI_2))
        .collect();
    for (d, count) in [(Domain::Thin, n), (Domain::Dense, n / DENSE_SHARE)] {
        for p in d.validation_set((0.0, 0.0), count, seed).into_iter().take(count) {
            let (h, x0) = (p.gamma.sin(), p.gamma.cos());
            let theta1 = if p.rho.is_infinite() { FRAC_PI_2 } else { (p.rho - x0).atan2(h) };
            if p.gamma <= FRAC_PI_2 && theta1 > 0.0 {
                pts.push((p.tau * h, theta1, p.gamma));
            }
        }
    }
    airlight_truth::parallel::map(
        &pts,
        |&(kappa, theta1, gamma)| RatioSample {
            kappa,
            theta1,
            backward: exact_backward(kappa, 0.0, theta1),
            forward: exact_forward(kappa, 0.0, FRAC_PI_2),
            forward_part: if gamma < FRAC_PI_2 { exact_forward(kappa, 0.0, FRAC_PI_2 - gamma) } else { 0.0 },
        },
        &|_, _| {},
    )
}

/// Relative errors of the backward integral `ratio · forward` on `samples`.
pub fn backward_errors(r: &Ratio, samples: &[RatioSample]) -> Vec<f64> {
    samples.iter().map(|s| r.eval(s.theta1, s.kappa) * s.forward / s.backward - 1.0).collect()
}

/// Relative errors of `A` (exact forward part plus the ratio's backward part) on
/// `samples`: the fit's objective.
pub fn a_errors(r: &Ratio, samples: &[RatioSample]) -> Vec<f64> {
    samples
        .iter()
        .map(|s| (r.eval(s.theta1, s.kappa) * s.forward - s.backward) / (s.forward_part + s.backward))
        .collect()
}

/// Result of the ratio fit.
#[derive(Debug, Clone, PartialEq)]
pub struct RatioFit {
    /// The fitted family member.
    pub ratio: Ratio,
    /// What the search over `g, h` did.
    pub outcome: Outcome,
    /// Fit points.
    pub samples: usize,
    /// RMS relative error of the backward integral on the fit points.
    pub rms_rel: f64,
    /// Largest relative error of the backward integral on the fit points.
    pub max_rel: f64,
    /// RMS relative error of `A` (the objective) on the fit points.
    pub a_rms_rel: f64,
}

fn solve_f(g: [f64; 4], h: [f64; 4], samples: &[RatioSample]) -> Option<(Ratio, f64)> {
    let probe = Ratio { f: [0.0; 4], g, h };
    let mut m = DMatrix::<f64>::zeros(samples.len(), 4);
    for (i, s) in samples.iter().enumerate() {
        let base = probe.decay(s.theta1, s.kappa) * s.forward / (s.forward_part + s.backward);
        if !base.is_finite() {
            return None;
        }
        for j in 0..4 {
            m[(i, j)] = base * s.theta1.powi(3 - j as i32);
        }
    }
    let rhs = DVector::<f64>::from_iterator(
        samples.len(),
        samples.iter().map(|s| s.backward / (s.forward_part + s.backward)),
    );
    let x = lsq::solve(m.clone(), &rhs)?;
    let mse = (&m * &x - rhs).norm_squared() / samples.len() as f64;
    Some((Ratio { f: [x[0], x[1], x[2], x[3]], g, h }, mse))
}

/// Refits `f, g, h` from the paper's values.
pub fn fit(samples: &[RatioSample]) -> RatioFit {
    let split = |x: &[f64]| ([x[0], x[1], x[2], x[3]], [x[4], x[5], x[6], x[7]]);
    let cost = |x: &[f64]| {
        let (g, h) = split(x);
        solve_f(g, h, samples).map_or(f64::INFINITY, |(_, mse)| mse)
    };
    let p = Ratio::paper();
    let x0: Vec<f64> = p.g.iter().chain(&p.h).copied().collect();
    let step: Vec<f64> = x0.iter().map(|c| 0.2 * c.abs() + 0.05).collect();
    let c0 = cost(&x0);
    let outcome = lsq::nelder_mead_restarted(&cost, &x0, &step, c0 * 1e-10, 4000, 2);
    let (g, h) = split(&outcome.param);
    let (ratio, mse) = solve_f(g, h, samples).expect("the search ended at a finite cost");
    let (rms_rel, max_rel) = airlight_truth::stats::rms_max(&backward_errors(&ratio, samples));
    RatioFit { ratio, outcome, samples: samples.len(), rms_rel, max_rel, a_rms_rel: mse.sqrt() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backward_integral_limits() {
        assert!((exact_backward(0.0, 0.0, FRAC_PI_2) - FRAC_PI_2).abs() < 1e-13);
        assert!((exact_backward(0.0, 0.2, 0.7) - 0.5).abs() < 1e-14);
        // Large κ: ∫₀^∞ e^{−κ(1 + θ + θ²/2 + …)} ≈ e^{−κ}/κ · (1 − 1/κ …).
        let k = 200.0;
        let v = exact_backward(k, 0.0, FRAC_PI_2) * k * f64::exp(k);
        assert!((v - 1.0).abs() < 0.01, "{v}");
    }

    #[test]
    fn refit_beats_the_paper() {
        let s = ratio_samples(250, 99);
        let rms = |e: Vec<f64>| (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
        let paper = rms(backward_errors(&Ratio::paper(), &s));
        let fit = fit(&s);
        assert!(fit.rms_rel < paper, "{} vs {paper}", fit.rms_rel);
    }
}

//! Forward kernel family: a continuous piecewise-linear `k̂(θ) ≈ sec θ − tan θ` on
//! `[0, π/2]` with `N` segments (the paper's §3.1 has `N = 3`), and the exact
//! integral of `e^{base + slope·θ − T·k̂(θ)}` that every forward part uses.
//!
//! The fit minimises the least-squares *relative error of the forward integral*
//! `∫_lo^hi e^{−T k(θ)} dθ` over `(T, lo, hi)` drawn from the `thin` and `dense`
//! domains: for fixed breakpoints the segment values come from Gauss–Newton steps,
//! each a linear least-squares problem solved by SVD; the breakpoints are moved by
//! Nelder–Mead.

use airlight_truth::domains::Domain;
use crate::lsq::{self, Outcome};
use airlight_truth::quad::gauss_kronrod;
use airlight_truth::reference::Point;
use nalgebra::{DMatrix, DVector};
use std::f64::consts::FRAC_PI_2;

/// `sec θ − tan θ = cos θ / (1 + sin θ)`, without cancellation, for θ ∈ [0, π/2].
pub fn kernel(theta: f64) -> f64 {
    theta.cos() / (1.0 + theta.sin())
}

/// `(e^x − 1) / x`, 1 at 0, accurate for all x (no 0/0, no cancellation).
pub fn exprel(x: f64) -> f64 {
    if x == 0.0 {
        1.0
    } else {
        x.exp_m1() / x
    }
}

/// `∫₀¹ s e^{x s} ds = (e^x (x − 1) + 1) / x²`, by its series near 0.
fn exprel_moment(x: f64) -> f64 {
    if x.abs() < 0.5 {
        // Σ xⁿ / (n! (n + 2))
        let (mut term, mut sum) = (1.0, 0.5);
        for n in 1..30 {
            term *= x / n as f64;
            sum += term / (n + 2) as f64;
        }
        sum
    } else {
        (x.exp() * (x - 1.0) + 1.0) / (x * x)
    }
}

/// A continuous (or, as published, nearly continuous) piecewise-linear kernel.
#[derive(Debug, Clone, PartialEq)]
pub struct Segments {
    /// `N + 1` increasing breakpoints from 0 to π/2.
    pub breakpoints: Vec<f64>,
    /// Slope of each segment.
    pub slopes: Vec<f64>,
    /// Intercept of each segment (`k̂ = slope·θ + intercept`).
    pub intercepts: Vec<f64>,
}

impl Segments {
    /// The paper's three lines (§3.1), as printed.
    pub fn paper() -> Segments {
        Segments {
            breakpoints: vec![0.0, 0.3959, 0.8395, FRAC_PI_2],
            slopes: vec![-0.8405, -0.6331, -0.5216],
            intercepts: vec![0.9915, 0.9094, 0.8158],
        }
    }

    /// The continuous kernel through `(breakpoints[j], values[j])`.
    pub fn from_values(breakpoints: &[f64], values: &[f64]) -> Segments {
        let n = breakpoints.len() - 1;
        let mut slopes = Vec::with_capacity(n);
        let mut intercepts = Vec::with_capacity(n);
        for j in 0..n {
            let m = (values[j + 1] - values[j]) / (breakpoints[j + 1] - breakpoints[j]);
            slopes.push(m);
            intercepts.push(values[j] - m * breakpoints[j]);
        }
        Segments { breakpoints: breakpoints.to_vec(), slopes, intercepts }
    }

    /// Number of segments.
    pub fn n(&self) -> usize {
        self.slopes.len()
    }

    /// `k̂(θ)`.
    pub fn eval(&self, theta: f64) -> f64 {
        let j = self.breakpoints[1..self.n()].iter().take_while(|&&b| theta > b).count();
        self.slopes[j] * theta + self.intercepts[j]
    }

    /// `∫_lo^hi exp(base + slope·θ − t·k̂(θ)) dθ` for `0 ≤ lo ≤ hi ≤ π/2`, exact for
    /// the piecewise-linear kernel. Each segment's exponent is linear, so its part is
    /// `e^{max end} · L · exprel(−|λ| L)`: never 0/0, no cancellation, no overflow
    /// beyond the larger endpoint value.
    pub fn integrate(&self, lo: f64, hi: f64, t: f64, base: f64, slope: f64) -> f64 {
        self.integrate_span(lo, hi, hi - lo, t, base, slope)
    }

    /// [`Segments::integrate`] with the interval's length `len = hi − lo` given
    /// separately, to full precision: a short interval near π/2 (a surface just
    /// before the viewer, or γ → 0 with a surface before the light) has ends that
    /// agree in most of their digits, and its length must not be their difference.
    pub fn integrate_span(&self, lo: f64, hi: f64, len: f64, t: f64, base: f64, slope: f64) -> f64 {
        let piece = |j: usize, a: f64, len: f64| {
            let lambda = slope - t * self.slopes[j];
            let e0 = base - t * self.intercepts[j];
            let (ea, eb) = (e0 + lambda * a, e0 + lambda * (a + len));
            ea.max(eb).exp() * len * exprel(-lambda.abs() * len)
        };
        if len.is_nan() || len <= 0.0 {
            return 0.0;
        }
        // Inside one segment: one piece, of the given length.
        if let Some(j) = (0..self.n()).find(|&j| lo >= self.breakpoints[j] && hi <= self.breakpoints[j + 1]) {
            return piece(j, lo, len);
        }
        // Across breakpoints each piece's length is a difference of its ends; an
        // error there is relative to the whole interval, not to the piece.
        let mut sum = 0.0;
        for j in 0..self.n() {
            let a = lo.max(self.breakpoints[j]);
            let b = hi.min(self.breakpoints[j + 1]);
            if b > a {
                sum += piece(j, a, b - a);
            }
        }
        sum
    }

    /// Largest `|k̂ − k|` over `[0, π/2]` (dense sampling plus the breakpoints),
    /// and where it occurs.
    pub fn kernel_error(&self) -> (f64, f64) {
        let mut worst = (0.0, 0.0);
        let grid = (0..=4000).map(|i| FRAC_PI_2 * i as f64 / 4000.0).chain(self.breakpoints.iter().copied());
        for th in grid {
            let e = (self.eval(th) - kernel(th)).abs();
            if e > worst.0 {
                worst = (e, th);
            }
        }
        worst
    }
}

/// One target of the forward fit: `∫_lo^hi e^{−T k(θ)} dθ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForwardSample {
    /// `T = τ sin γ`.
    pub t: f64,
    /// Lower end (`> 0` when a surface stops the ray before the foot point).
    pub lo: f64,
    /// Upper end, `π/2 − γ`.
    pub hi: f64,
    /// The exact integral (adaptive quadrature, 1e-13 relative).
    pub exact: f64,
}

/// The forward interval of a canonical point, `(T, lo, hi)`, if it has one
/// (γ < π/2 and the surface beyond the viewer's end of it).
pub fn forward_interval(p: &Point) -> Option<(f64, f64, f64)> {
    let (h, x0) = (p.gamma.sin(), p.gamma.cos());
    let hi = FRAC_PI_2 - p.gamma;
    let theta_b = if p.rho.is_infinite() { FRAC_PI_2 } else { (p.rho - x0).atan2(h) };
    let lo = (-theta_b).max(0.0);
    (hi > lo).then_some((p.tau * h, lo, hi))
}

/// `∫_lo^hi e^{−T k(θ)} dθ` by adaptive Gauss–Kronrod.
pub fn exact_forward(t: f64, lo: f64, hi: f64) -> f64 {
    gauss_kronrod(|th| (-t * kernel(th)).exp(), &[lo, hi], 1e-13, 200).value
}

/// `n` points from each of `thin` and `dense` (low-discrepancy, `seed`, corners
/// included) that have a forward part, with their exact forward integrals.
pub fn samples(n: usize, seed: u64) -> Vec<ForwardSample> {
    let mut tasks = Vec::new();
    for d in [Domain::Thin, Domain::Dense] {
        for p in d.validation_set((0.0, 0.0), n, seed) {
            if let Some(iv) = forward_interval(&p) {
                tasks.push(iv);
            }
        }
    }
    airlight_truth::parallel::map(
        &tasks,
        |&(t, lo, hi)| ForwardSample { t, lo, hi, exact: exact_forward(t, lo, hi) },
        &|_, _| {},
    )
}

/// Result of fitting one `N`.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentsFit {
    /// The fitted kernel.
    pub segments: Segments,
    /// What the breakpoint search did.
    pub outcome: Outcome,
    /// Gauss–Newton steps in the final inner solve.
    pub inner_steps: usize,
    /// Number of `(T, lo, hi)` targets.
    pub samples: usize,
    /// Root-mean-square relative error of the forward integral on the targets.
    pub rms_rel: f64,
    /// Largest relative error of the forward integral on the targets.
    pub max_rel: f64,
}

/// Relative errors of the forward integral under `seg` on `samples`.
pub fn forward_errors(seg: &Segments, samples: &[ForwardSample]) -> Vec<f64> {
    samples.iter().map(|s| seg.integrate(s.lo, s.hi, s.t, 0.0, 0.0) / s.exact - 1.0).collect()
}

/// Best segment values for fixed breakpoints: Gauss–Newton on the relative
/// errors, each step a linear least-squares problem solved by SVD. Returns the
/// kernel, the mean squared relative error and the steps taken.
pub fn fit_values(breakpoints: &[f64], samples: &[ForwardSample]) -> (Segments, f64, usize) {
    let n = breakpoints.len() - 1;
    let mut y: Vec<f64> = breakpoints.iter().map(|&t| kernel(t)).collect();
    let mut steps = 0;
    for _ in 0..8 {
        let seg = Segments::from_values(breakpoints, &y);
        let mut jac = DMatrix::<f64>::zeros(samples.len(), n + 1);
        let mut res = DVector::<f64>::zeros(samples.len());
        for (i, s) in samples.iter().enumerate() {
            let mut total = 0.0;
            for j in 0..n {
                let a = s.lo.max(breakpoints[j]);
                let b = s.hi.min(breakpoints[j + 1]);
                if b <= a {
                    continue;
                }
                let (tj, dj) = (breakpoints[j], breakpoints[j + 1] - breakpoints[j]);
                let lambda = -s.t * seg.slopes[j];
                let ea = -s.t * (seg.slopes[j] * a + seg.intercepts[j]);
                let len = b - a;
                let i0 = ea.exp() * len * exprel(lambda * len);
                let i1 = ea.exp() * len * len * exprel_moment(lambda * len); // ∫ (θ − a) e^E
                let right = (i1 + (a - tj) * i0) / dj; // ∫ φ_{j+1} e^E
                let left = i0 - right; // ∫ φ_j e^E
                total += i0;
                jac[(i, j)] -= s.t * left / s.exact;
                jac[(i, j + 1)] -= s.t * right / s.exact;
            }
            res[i] = total / s.exact - 1.0;
        }
        let Some(delta) = lsq::solve(jac, &(-res)) else { break };
        steps += 1;
        let size = delta.amax();
        for (yj, dj) in y.iter_mut().zip(delta.iter()) {
            *yj += dj;
        }
        if size < 1e-13 {
            break;
        }
    }
    let seg = Segments::from_values(breakpoints, &y);
    let mse = forward_errors(&seg, samples).iter().map(|e| e * e).sum::<f64>() / samples.len() as f64;
    (seg, mse, steps)
}

/// Interior breakpoints from unconstrained parameters: segment widths are a
/// softmax of `(x, 0)` scaled to π/2, so any `x` gives ordered breakpoints.
fn breakpoints_from(x: &[f64]) -> Vec<f64> {
    let w: Vec<f64> = x.iter().copied().chain([0.0]).map(f64::exp).collect();
    let total: f64 = w.iter().sum();
    let mut out = vec![0.0];
    let mut acc = 0.0;
    for wi in &w[..w.len() - 1] {
        acc += wi / total;
        out.push(FRAC_PI_2 * acc);
    }
    out.push(FRAC_PI_2);
    out
}

/// Fits an `n`-segment kernel (2 ≤ n ≤ 16) to `samples`.
pub fn fit(n: usize, samples: &[ForwardSample]) -> SegmentsFit {
    assert!((2..=16).contains(&n), "segments: N = {n} outside 2..=16");
    let cost = |x: &[f64]| fit_values(&breakpoints_from(x), samples).1;
    // Equal widths to start.
    let start = vec![0.0; n - 1];
    let c0 = cost(&start);
    let outcome = lsq::nelder_mead_restarted(&cost, &start, &vec![0.3; n - 1], c0 * 1e-9, 150 * n as u64 + 200, 2);
    let (segments, _, inner_steps) = fit_values(&breakpoints_from(&outcome.param), samples);
    let (rms_rel, max_rel) = airlight_truth::stats::rms_max(&forward_errors(&segments, samples));
    SegmentsFit { segments, outcome, inner_steps, samples: samples.len(), rms_rel, max_rel }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integral_matches_quadrature_including_tiny_exponents() {
        let s = Segments::paper();
        for &(t, lo, hi, base, slope) in &[
            (0.0, 0.0, 1.5, 0.0, 0.0),
            (1e-12, 0.1, 1.2, 0.0, 0.0),
            (5.0, 0.0, FRAC_PI_2, -1.0, 3.0),
            (20.0, 0.3, 0.9, 0.0, -2.0),
        ] {
            let exact = gauss_kronrod(
                |th| (base + slope * th - t * s.eval(th)).exp(),
                &[lo, 0.3959, 0.8395, hi].iter().copied().filter(|&b| b >= lo && b <= hi).collect::<Vec<_>>(),
                1e-14,
                200,
            )
            .value;
            let got = s.integrate(lo, hi, t, base, slope);
            assert!((got / exact - 1.0).abs() < 1e-13, "{t} {lo} {hi}: {got} vs {exact}");
        }
        assert_eq!(s.integrate(0.2, 0.2, 3.0, 0.0, 0.0), 0.0);
    }

    #[test]
    fn moments_are_accurate_across_the_series_switch() {
        for x in [-30.0, -2.0, -0.5000001, -0.4999999, -1e-9, 0.0, 1e-9, 0.49, 0.51, 3.0] {
            let exact = gauss_kronrod(|s| s * (x * s).exp(), &[0.0, 1.0], 1e-15, 100).value;
            assert!((exprel_moment(x) / exact - 1.0).abs() < 1e-13, "{x}");
        }
    }

    #[test]
    fn refit_beats_the_paper_on_its_own_objective() {
        let samples = samples(300, 0x05EE_DF17);
        let paper = forward_errors(&Segments::paper(), &samples);
        let paper_rms = (paper.iter().map(|e| e * e).sum::<f64>() / samples.len() as f64).sqrt();
        let fit = fit(3, &samples);
        assert!(fit.rms_rel < paper_rms, "{} vs {}", fit.rms_rel, paper_rms);
        let more = super::fit(6, &samples);
        assert!(more.rms_rel < 0.5 * fit.rms_rel);
        // Continuity.
        let s = &more.segments;
        for j in 1..s.n() {
            let b = s.breakpoints[j];
            let l = s.slopes[j - 1] * b + s.intercepts[j - 1];
            let r = s.slopes[j] * b + s.intercepts[j];
            assert!((l - r).abs() < 1e-12);
        }
    }
}

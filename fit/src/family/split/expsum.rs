//! Backward weight family (this project's, not the paper's): in the u form of
//! docs/MATH.md §3 the backward part is
//!
//!   `(2 e^{−τ} / h) ∫_{max(ua, 1)}^{ub} e^{−T (u − ua)} w(u) du`,  `w(u) = 1 / (1 + u²)`,
//!
//! whose exponent is exactly linear in `u`. Approximating the weight by a sum of
//! exponentials, `w(u) ≈ Σ_k c_k e^{−s_k u}` on `u ∈ [1, U]`, makes every term an
//! elementary, positive integral — no differences, so no cancellation for any
//! geometry (γ > π/2 included) — and a relative error `ε` of `w` is a relative
//! error of at most `ε` of the backward part, for every `τ` (docs/MATH.md §3). Beyond
//! `U` the sum decays faster than `w`; the share of `A` lost there is at most
//! `max(ua, 1) / U` at τ = 0 and smaller for τ > 0.
//!
//! The fit: for fixed rates `s_k`, the amplitudes minimise the least-squares
//! relative error of `w` on a logarithmic grid (SVD); the rates (as logarithms) are
//! moved by Nelder–Mead to minimise the largest relative error.

use crate::lsq::{self, Outcome};
use nalgebra::{DMatrix, DVector};

/// Where the near sum (`w` itself) hands over to the far part (`q(u)/u²`).
pub const SPLIT: f64 = 16.0;
/// Far parts shorter than this ratio of their ends use the local sum.
pub const LOCAL_RATIO: f64 = 2.0;
const GRID: usize = 400;

/// What an exponential sum approximates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// `1/(1 + u²)` on `[1, SPLIT]`.
    Near,
    /// `1/y²` on `[1, LOCAL_RATIO]`.
    Local,
}

impl Target {
    /// The function.
    pub fn eval(self, x: f64) -> f64 {
        match self {
            Target::Near => weight(x),
            Target::Local => 1.0 / (x * x),
        }
    }
    /// Upper end of the range (the lower is 1).
    pub fn end(self) -> f64 {
        match self {
            Target::Near => SPLIT,
            Target::Local => LOCAL_RATIO,
        }
    }
}

/// `w(u) ≈ Σ c_k e^{−s_k u}` on `[1, U_MAX]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ExpSum {
    /// Amplitudes `c_k`.
    pub c: Vec<f64>,
    /// Rates `s_k` (positive).
    pub s: Vec<f64>,
}

/// The exact weight.
pub fn weight(u: f64) -> f64 {
    1.0 / (1.0 + u * u)
}

impl ExpSum {
    /// The approximate weight.
    pub fn eval(&self, u: f64) -> f64 {
        self.c.iter().zip(&self.s).map(|(c, s)| c * (-s * u).exp()).sum()
    }

    /// `e^{base} ∫_{u0}^{u0 + L} e^{− T (u − u0)} ŵ(u) p(u) du` for `u0 ≥ 1`, `L ≥ 0`
    /// (possibly ∞), with the slowly varying factor `p` taken at each term's mean
    /// point. Each term is `c e^{base − s u0} (1 − e^{−λ L}) / λ · p(ū)` with `λ = T + s` and
    /// `ū = u0 + L / (2 + λ L)` (`u0 + 1/λ` when `L = ∞`), the mean of `e^{−λ(u − u0)}`
    /// on the interval up to second order — exact for uniform and for fast decay.
    pub fn integrate(&self, u0: f64, len: f64, t: f64, base: f64, p: impl Fn(f64) -> f64) -> f64 {
        if len.is_nan() || len <= 0.0 {
            return 0.0;
        }
        self.c
            .iter()
            .zip(&self.s)
            .map(|(&c, &s)| {
                let lambda = t + s;
                let (part, mean) = if len.is_infinite() {
                    (1.0 / lambda, u0 + 1.0 / lambda)
                } else {
                    (-(-lambda * len).exp_m1() / lambda, u0 + len / (2.0 + lambda * len))
                };
                c * (base - s * u0).exp() * part * p(mean)
            })
            .sum()
    }

    /// Largest relative error against `target` on a fine logarithmic grid of its
    /// range (4× the fit grid, offset from it), and where.
    pub fn error(&self, target: Target) -> (f64, f64) {
        let n = 4 * GRID + 1;
        let mut worst = (0.0, 1.0);
        for i in 0..n {
            let u = target.end().powf((i as f64 + 0.37) / n as f64).min(target.end());
            let e = (self.eval(u) / target.eval(u) - 1.0).abs();
            if e > worst.0 {
                worst = (e, u);
            }
        }
        worst
    }
}

/// `φ(z) = 1 − z e^z E1(z) = z ∫₀^∞ e^{−z y}/(1 + y)² dy … ` in the form used here:
/// `∫_a^∞ e^{−T(u − a)} u^{−2} du = φ(T a) / a`. Abramowitz & Stegun 5.1.53 (series
/// with `ln z`, |error of E1| < 2e-7) for `z ≤ 1`, the rational 5.1.56 (|error of
/// `z e^z E1`| < 2e-8) up to 500, written as `(D − N)/D` so nothing cancels, and the
/// asymptotic series beyond.
pub fn phi(z: f64) -> f64 {
    if z <= 0.0 {
        1.0
    } else if z <= 1.0 {
        let e1 = -z.ln() - 0.577_215_66
            + z * (0.999_991_93 + z * (-0.249_910_55 + z * (0.055_199_68 + z * (-0.009_760_04 + z * 0.001_078_57))));
        1.0 - z * z.exp() * e1
    } else if z > 500.0 {
        // Asymptotic series: the rational's absolute 2e-8 would be large relative to φ ≈ 1/z.
        let r = 1.0 / z;
        r * (1.0 + r * (-2.0 + r * (6.0 + r * (-24.0 + r * 120.0))))
    } else {
        let (a1, a2, a3, a4) = (8.573_328_740_1, 18.059_016_973_0, 8.634_760_892_5, 0.267_773_734_3);
        let (b1, b2, b3, b4) = (9.573_322_345_4, 25.632_956_148_6, 21.099_653_082_7, 3.958_496_922_8);
        let d = (((z + b1) * z + b2) * z + b3) * z + b4;
        let diff = (((b1 - a1) * z + (b2 - a2)) * z + (b3 - a3)) * z + (b4 - a4);
        diff / d
    }
}

/// The backward weight in three pieces: `near` approximates `w(u)` on `[1, SPLIT]`;
/// beyond, `w(u) = q(u)/u²` with `q = u²/(1 + u²)` within 0.4% of 1 (taken at the
/// part's mean point), and `∫ e^{−T(u − a)} u^{−2}` is exact through [`phi`] — as a
/// difference of two `φ` terms only when the upper end is at least `LOCAL_RATIO`
/// times the lower (so it loses at most a bit); shorter far parts use `local`, a sum
/// for `1/y²` on `y = u/a ∈ [1, LOCAL_RATIO]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Backward {
    /// `w(u)` on `[1, SPLIT]`.
    pub near: ExpSum,
    /// `1/y²` on `[1, LOCAL_RATIO]`.
    pub local: ExpSum,
}

impl Backward {
    /// `e^{base} ∫_{u0}^{u0 + L} e^{−T (u − u0)} w(u) p(u) du` for `u0 ≥ 1`, `L ≥ 0`
    /// (∞: no surface), `p` slowly varying (taken at each term's or part's mean
    /// point). Every part is positive. The length is given, not the end, so that a
    /// short interval far out keeps its precision.
    pub fn integrate(&self, u0: f64, len: f64, t: f64, base: f64, p: impl Fn(f64) -> f64) -> f64 {
        let mut sum = 0.0;
        let u1 = u0 + len;
        if u0 < SPLIT {
            sum += self.near.integrate(u0, if u1 <= SPLIT { len } else { SPLIT - u0 }, t, base, &p);
        }
        if u1 > SPLIT {
            let a = u0.max(SPLIT);
            let shift = base - t * (a - u0);
            let q = |u: f64| u * u / (1.0 + u * u);
            if u1 <= LOCAL_RATIO * a {
                // y = u/a ∈ [1, u1/a]; its length from `len` when the part starts at u0.
                let ylen = if a == u0 { len / a } else { u1 / a - 1.0 };
                sum += self.local.integrate(1.0, ylen, t * a, shift, |y| q(a * y) * p(a * y)) / a;
            } else {
                let lambda = t + 2.0 / a;
                let (g, mean) = if u1.is_infinite() {
                    (phi(t * a) / a, a + 1.0 / lambda)
                } else {
                    let len = if a == u0 { len } else { u1 - a };
                    (phi(t * a) / a - (-t * len).exp() * phi(t * u1) / u1, a + len / (2.0 + lambda * len))
                };
                sum += shift.exp() * g * q(mean) * p(mean);
            }
        }
        sum
    }
}

fn grid(target: Target) -> Vec<f64> {
    (0..GRID).map(|i| target.end().powf(i as f64 / (GRID - 1) as f64)).collect()
}

/// Amplitudes for fixed rates: least squares on the relative error, then
/// Lawson's reweighting towards the minimax solution (SVD each time).
fn amplitudes(target: Target, s: &[f64], us: &[f64]) -> Option<ExpSum> {
    let base = DMatrix::from_fn(us.len(), s.len(), |i, k| (-s[k] * us[i]).exp() / target.eval(us[i]));
    let mut wts = vec![1.0f64; us.len()];
    let mut best: Option<(f64, ExpSum)> = None;
    for _ in 0..12 {
        let m = DMatrix::from_fn(us.len(), s.len(), |i, k| wts[i].sqrt() * base[(i, k)]);
        let rhs = DVector::from_iterator(us.len(), wts.iter().map(|w| w.sqrt()));
        let c = lsq::solve(m, &rhs)?;
        let r = &base * &c - DVector::from_element(us.len(), 1.0);
        let e = ExpSum { c: c.iter().copied().collect(), s: s.to_vec() };
        let mx = r.amax();
        if best.as_ref().is_none_or(|b| mx < b.0) {
            best = Some((mx, e));
        }
        let total: f64 = wts.iter().zip(r.iter()).map(|(w, ri)| w * ri.abs()).sum();
        for (w, ri) in wts.iter_mut().zip(r.iter()) {
            *w *= ri.abs() / total;
        }
    }
    best.map(|b| b.1)
}

fn max_rel(target: Target, e: &ExpSum, us: &[f64]) -> f64 {
    us.iter().map(|&u| (e.eval(u) / target.eval(u) - 1.0).abs()).fold(0.0, f64::max)
}

/// Result of the fit.
#[derive(Debug, Clone, PartialEq)]
pub struct ExpSumFit {
    /// The fitted sum.
    pub sum: ExpSum,
    /// The search over the rates.
    pub outcome: Outcome,
    /// Largest relative error against the target on the check grid, and where.
    pub max_rel: (f64, f64),
}

/// Fits `k` terms to `target`.
pub fn fit(target: Target, k: usize) -> ExpSumFit {
    let us = grid(target);
    let to_s = |x: &[f64]| -> Vec<f64> { x.iter().map(|v| v.exp()).collect() };
    let cost = |x: &[f64]| amplitudes(target, &to_s(x), &us).map_or(f64::INFINITY, |e| max_rel(target, &e, &us));
    // Rates spread geometrically from 0.3/end to about 3.
    let (lo, hi) = ((0.3 / target.end()).ln(), 3f64.ln());
    let x0: Vec<f64> = (0..k).map(|i| lo + (hi - lo) * i as f64 / (k - 1).max(1) as f64).collect();
    let outcome = lsq::nelder_mead_restarted(&cost, &x0, &vec![0.4; k], 1e-12, 600 * k as u64, 3);
    let sum = amplitudes(target, &to_s(&outcome.param), &us).expect("the search ended at a finite cost");
    ExpSumFit { max_rel: sum.error(target), sum, outcome }
}

#[cfg(test)]
mod tests {
    use super::*;
    use airlight_truth::quad::gauss_kronrod;

    #[test]
    fn integral_matches_quadrature() {
        let e = ExpSum { c: vec![0.3, 0.1], s: vec![0.5, 0.01] };
        for (u0, u1, t) in [(1.0, 3.0, 0.0), (2.0, 50.0, 0.7), (1.0, 1.0 + 1e-9, 5.0)] {
            let exact = gauss_kronrod(|u| (-t * (u - u0)).exp() * e.eval(u), &[u0, u1], 1e-14, 200).value;
            assert!((e.integrate(u0, u1 - u0, t, 0.0, |_| 1.0) / exact - 1.0).abs() < 1e-12);
        }
        let inf = e.integrate(1.0, f64::INFINITY, 0.3, 0.0, |_| 1.0);
        let exact: f64 = e.c.iter().zip(&e.s).map(|(c, s)| c * (-s).exp() / (0.3 + s)).sum();
        assert!((inf / exact - 1.0).abs() < 1e-14);
    }

    #[test]
    fn phi_matches_the_exponential_integral() {
        for z in [1e-8, 1e-3, 0.3, 0.999, 1.0, 1.001, 3.0, 40.0, 499.0, 501.0, 1e4] {
            let exact = 1.0 - z * airlight_truth::e1::exp_e1(airlight_truth::e1::Complex { re: z, im: 0.0 }).re;
            assert!((phi(z) / exact - 1.0).abs() < 1e-5, "{z}: {} vs {exact}", phi(z));
        }
        assert_eq!(phi(0.0), 1.0);
    }

    #[test]
    fn backward_pieces_match_quadrature() {
        let b = Backward { near: fit(Target::Near, 4).sum, local: fit(Target::Local, 3).sum };
        for (u0, u1, t) in [
            (1.0, f64::INFINITY, 0.0),
            (3.0, 40.0, 0.5),
            (20.0, 30.0, 2.0),
            (200.0, f64::INFINITY, 0.01),
            (17.0, 1e4, 0.0),
        ] {
            let cut = if u1.is_infinite() { 1e12 } else { u1 };
            let pts: Vec<f64> =
                [u0, 16.0, 32.0, 320.0, 3200.0, 1e5, 1e8, cut].into_iter().filter(|&x| x >= u0 && x <= cut).collect();
            let exact = gauss_kronrod(|u| (-t * (u - u0)).exp() * weight(u), &pts, 1e-12, 500).value
                + if u1.is_infinite() { 1e-12 } else { 0.0 };
            let got = b.integrate(u0, u1 - u0, t, 0.0, |_| 1.0);
            assert!((got / exact - 1.0).abs() < 3e-3, "{u0} {u1} {t}: {got} vs {exact}");
        }
    }

    #[test]
    fn more_terms_fit_better() {
        let a = fit(Target::Near, 2);
        let b = fit(Target::Near, 4);
        assert!(b.max_rel.0 < 0.5 * a.max_rel.0, "{:?} {:?}", a.max_rel, b.max_rel);
        assert!(b.sum.c.iter().all(|c| c.is_finite()));
    }
}

//! Backward weight family (this project's, not the paper's): in the u form of
//! MATH.md §3 the backward part is
//!
//!   `(2 e^{−τ} / h) ∫_{max(ua, 1)}^{ub} e^{−T (u − ua)} w(u) du`,  `w(u) = 1 / (1 + u²)`,
//!
//! whose exponent is exactly linear in `u`. Approximating the weight by a sum of
//! exponentials, `w(u) ≈ Σ_k c_k e^{−s_k u}` on `u ∈ [1, U]`, makes every term an
//! elementary, positive integral — no differences, so no cancellation for any
//! geometry (γ > π/2 included) — and a relative error `ε` of `w` is a relative
//! error of at most `ε` of the backward part, for every `τ` (MATH.md §3). Beyond
//! `U` the sum decays faster than `w`; the share of `A` lost there is at most
//! `max(ua, 1) / U` at τ = 0 and smaller for τ > 0.
//!
//! The fit: for fixed rates `s_k`, the amplitudes minimise the least-squares
//! relative error of `w` on a logarithmic grid (SVD); the rates (as logarithms) are
//! moved by Nelder–Mead to minimise the largest relative error.

use crate::lsq::{self, Outcome};
use nalgebra::{DMatrix, DVector};

/// Where the near sum (`w` itself) hands over to the far sum (scaled `1/y²`).
pub const SPLIT: f64 = 16.0;
/// Upper end of the far sum's range in `y = u / max(u0, SPLIT)`; beyond it a share
/// below `1/Y_MAX` of the far part is lost (at τ = 0; less for τ > 0).
pub const Y_MAX: f64 = 2e3;
const GRID: usize = 400;

/// What an exponential sum approximates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// `1/(1 + u²)` on `[1, SPLIT]`.
    Near,
    /// `1/y²` on `[1, Y_MAX]`.
    Far,
}

impl Target {
    /// The function.
    pub fn eval(self, x: f64) -> f64 {
        match self {
            Target::Near => weight(x),
            Target::Far => 1.0 / (x * x),
        }
    }
    /// Upper end of the range (the lower is 1).
    pub fn end(self) -> f64 {
        match self {
            Target::Near => SPLIT,
            Target::Far => Y_MAX,
        }
    }
    /// Name in files.
    pub fn name(self) -> &'static str {
        match self {
            Target::Near => "near",
            Target::Far => "far",
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

    /// `e^{base} ∫_{u0}^{u1} e^{− T (u − u0)} ŵ(u) p(u) du` for `1 ≤ u0 ≤ u1 ≤ ∞`, with
    /// the slowly varying factor `p` taken at each term's mean point. Each term is
    /// `c e^{base − s u0} (1 − e^{−λ L}) / λ · p(ū)` with `λ = T + s`, `L = u1 − u0` and
    /// `ū = u0 + L / (2 + λ L)` (`u0 + 1/λ` when `L = ∞`), the mean of `e^{−λ(u − u0)}`
    /// on the interval up to second order — exact for uniform and for fast decay.
    pub fn integrate(&self, u0: f64, u1: f64, t: f64, base: f64, p: impl Fn(f64) -> f64) -> f64 {
        let len = u1 - u0;
        if len <= 0.0 {
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

/// The backward weight in two ranges: `near` approximates `w(u)` on `[1, SPLIT]`;
/// beyond, `w(u) = q(u)/u²` with `q = u²/(1 + u²)` within 0.4% of 1, and `far`
/// approximates `1/y²` in the scaled variable `y = u/a`, `a = max(u0, SPLIT)`, so one
/// fit serves every start `u0` (γ up to π) with a range of only `Y_MAX`.
#[derive(Debug, Clone, PartialEq)]
pub struct Backward {
    /// `w(u)` on `[1, SPLIT]`.
    pub near: ExpSum,
    /// `1/y²` on `[1, Y_MAX]`.
    pub far: ExpSum,
}

impl Backward {
    /// `e^{base} ∫_{u0}^{u1} e^{−T (u − u0)} w(u) p(u) du` for `1 ≤ u0 < u1 ≤ ∞`, `p`
    /// slowly varying (taken at each term's mean point). Every term is positive.
    pub fn integrate(&self, u0: f64, u1: f64, t: f64, base: f64, p: impl Fn(f64) -> f64) -> f64 {
        let mut sum = 0.0;
        if u0 < SPLIT {
            sum += self.near.integrate(u0, u1.min(SPLIT), t, base, &p);
        }
        if u1 > SPLIT {
            let a = u0.max(SPLIT);
            let shift = base - t * (a - u0);
            let y1 = if u1.is_infinite() { u1 } else { u1 / a };
            let q = |u: f64| u * u / (1.0 + u * u);
            sum += self.far.integrate(1.0, y1, t * a, shift, |y| q(a * y) * p(a * y)) / a;
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
    // Nelder–Mead restarted from its own result with a fresh simplex until a
    // restart stops improving (it stalls in long valleys otherwise).
    let mut outcome = lsq::nelder_mead(&cost, &x0, &vec![0.4; k], 1e-12, 600 * k as u64);
    for _ in 0..3 {
        let again = lsq::nelder_mead(&cost, &outcome.param, &vec![0.2; k], 1e-12, 600 * k as u64);
        let better = again.cost < 0.98 * outcome.cost;
        let iterations = outcome.iterations + again.iterations;
        outcome = Outcome { iterations, ..if again.cost < outcome.cost { again } else { outcome } };
        if !better {
            break;
        }
    }
    let sum = amplitudes(target, &to_s(&outcome.param), &us).expect("the search ended at a finite cost");
    ExpSumFit { max_rel: sum.error(target), sum, outcome }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quad::gauss_kronrod;

    #[test]
    fn integral_matches_quadrature() {
        let e = ExpSum { c: vec![0.3, 0.1], s: vec![0.5, 0.01] };
        for (u0, u1, t) in [(1.0, 3.0, 0.0), (2.0, 50.0, 0.7), (1.0, 1.0 + 1e-9, 5.0)] {
            let exact = gauss_kronrod(|u| (-t * (u - u0)).exp() * e.eval(u), &[u0, u1], 1e-14, 200).value;
            assert!((e.integrate(u0, u1, t, 0.0, |_| 1.0) / exact - 1.0).abs() < 1e-12);
        }
        let inf = e.integrate(1.0, f64::INFINITY, 0.3, 0.0, |_| 1.0);
        let exact: f64 = e.c.iter().zip(&e.s).map(|(c, s)| c * (-s).exp() / (0.3 + s)).sum();
        assert!((inf / exact - 1.0).abs() < 1e-14);
    }

    #[test]
    fn more_terms_fit_better() {
        let a = fit(Target::Near, 2);
        let b = fit(Target::Near, 4);
        assert!(b.max_rel.0 < 0.5 * a.max_rel.0, "{:?} {:?}", a.max_rel, b.max_rel);
        assert!(b.sum.c.iter().all(|c| c.is_finite()));
    }
}

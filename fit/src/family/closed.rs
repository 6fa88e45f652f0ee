//! The no-extinction family: seed 003's exact closed form of the isotropic
//! integral with `τ = 0`, a whole-integral family (no forward/backward split).
//! Exact where extinction does not matter, and the cost floor of every kernel.
//!
//! `A(0, γ, ρ) = atan2(h ρ, 1 − ρ cos γ) / (4π h)`, `h = sin γ` (`ρ = ∞`:
//! `(π − γ) / (4π h)`); on the axis (`h = 0`) `ρ / (4π (1 − ρ))` before the light.

use crate::cost::{Cost, Shape};
use crate::reference::Point;
use std::f64::consts::PI;

/// The closed form (isotropic, extinction ignored).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NoExtinction;

impl NoExtinction {
    /// Its kind ([`crate::family::Body::kind`]).
    pub const KIND: &'static str = "no-extinction";

    /// `A(0, γ, ρ)` whatever `τ` and `g` the point has.
    pub fn eval(&self, p: Point) -> f64 {
        let (h, c) = (p.gamma.sin(), p.gamma.cos());
        if h == 0.0 {
            return if c > 0.0 && p.rho >= 1.0 {
                f64::INFINITY
            } else if c > 0.0 {
                p.rho / (4.0 * PI * (1.0 - p.rho))
            } else if p.rho.is_infinite() {
                1.0 / (4.0 * PI)
            } else {
                p.rho / (4.0 * PI * (1.0 + p.rho))
            };
        }
        let angle = if p.rho.is_infinite() { PI - p.gamma } else { (h * p.rho).atan2(1.0 - p.rho * c) };
        angle / (4.0 * PI * h)
    }

    /// One `atan2`, one `sin_cos`, two divisions, whatever the shape.
    pub fn ops(&self, _shape: Shape) -> Cost {
        Cost { exp: 0, log: 0, atan: 1, sqrt: 0, div: 2, sincos: 1 }
    }
}

/// The largest relative error of dropping extinction (`A(0)` for `A(τ)`) at
/// optical distance `tau` over `γ ∈ [0.01, π − 0.01]`, `ρ = ∞` and, with `surfaces`,
/// `ρ ∈ [0.01, 100]`, and the given `g`: measured with the reference on a grid (41
/// angles × 9 surface distances and ∞). The error only grows with `τ` (`A` falls
/// with it while `A(0)` stays), so this bounds every scene up to `tau`.
pub fn extinction_error(tau: f64, surfaces: bool, gs: &[f64]) -> f64 {
    if tau <= 0.0 {
        return 0.0;
    }
    let mut rhos = vec![f64::INFINITY];
    if surfaces {
        rhos.extend((0..9).map(|i| 0.01 * 10f64.powf(0.5 * f64::from(i))));
    }
    let mut worst = 0.0f64;
    for &g in gs {
        for &rho in &rhos {
            for i in 0..41 {
                let gamma = 0.01 + (PI - 0.02) * f64::from(i) / 40.0;
                let at = |tau| crate::reference::airlight(Point { tau, gamma, rho, g }).unwrap_or(f64::NAN);
                let (a, a0) = (at(tau), at(0.0));
                worst = worst.max(crate::stats::rel_error(a0, a));
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ignoring_extinction_costs_more_with_depth() {
        assert_eq!(extinction_error(0.0, true, &[0.0]), 0.0);
        let (a, b) = (extinction_error(1e-4, false, &[0.0]), extinction_error(0.1, true, &[0.0]));
        assert!(a > 0.0 && a < 1e-2 && b > a, "{a:e} {b:e}");
    }

    #[test]
    fn agrees_with_the_reference_without_extinction() {
        for &(gamma, rho) in &[(0.3, 0.5), (1.0, 2.0), (2.5, f64::INFINITY), (3.1, 100.0), (0.0, 0.5), (PI, 3.0)] {
            let p = Point { tau: 0.0, gamma, rho, g: 0.0 };
            let exact = crate::reference::airlight(p).unwrap();
            let got = NoExtinction.eval(p);
            assert!((got - exact).abs() <= 1e-12 * exact, "γ {gamma} ρ {rho}: {got} vs {exact}");
        }
    }
}

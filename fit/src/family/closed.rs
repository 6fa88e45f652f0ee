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

#[cfg(test)]
mod tests {
    use super::*;

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

//! Phase functions, normalised so that their integral over the sphere is 1.
//!
//! The scattering angle α enters only through `sin²(α/2)` and `cos²(α/2)`, which
//! every caller can form without cancellation (`1 − cos α` is never computed), so
//! Henyey–Greenstein stays accurate at its forward (g → 1) and backward (g → −1)
//! peaks.

use std::f64::consts::PI;

/// `1 − cos α` and `1 + cos α` from `cos α = x / t` with `t² = x² + h²`, each
/// formed without cancellation (`t ≥ |x|`).
#[inline]
pub fn one_minus_plus_cos(x: f64, h: f64, t: f64) -> (f64, f64) {
    let (a, b) = if x > 0.0 { (h * h / (t + x), t + x) } else { (t - x, h * h / (t - x)) };
    (a / t, b / t)
}

/// Henyey–Greenstein from `1 − cos α` and `1 + cos α`, written around the peak so
/// that it never cancels (`g = 0`: `1/(4π)`).
#[inline]
pub fn hg(g: f64, one_minus: f64, one_plus: f64) -> f64 {
    let d =
        if g >= 0.0 { (1.0 - g) * (1.0 - g) + 2.0 * g * one_minus } else { (1.0 + g) * (1.0 + g) - 2.0 * g * one_plus };
    (1.0 - g) * (1.0 + g) / (4.0 * PI * d * d.sqrt())
}

/// A phase function `P(α)`, `α = 0` forward scattering.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    /// `P = 1 / (4π)`.
    Isotropic,
    /// Henyey–Greenstein, `P = (1 − g²) / (4π (1 + g² − 2 g cos α)^{3/2})`, `g ∈ (−1, 1)`.
    HenyeyGreenstein {
        /// Asymmetry parameter (mean cosine of the scattering angle).
        g: f64,
    },
}

impl Phase {
    /// `g = 0` is isotropic; otherwise Henyey–Greenstein. The caller validates `|g| < 1`.
    pub fn from_g(g: f64) -> Phase {
        if g == 0.0 {
            Phase::Isotropic
        } else {
            Phase::HenyeyGreenstein { g }
        }
    }

    /// The asymmetry parameter (0 for isotropic).
    pub fn g(self) -> f64 {
        match self {
            Phase::Isotropic => 0.0,
            Phase::HenyeyGreenstein { g } => g,
        }
    }

    /// `P(α)` from `s2 = sin²(α/2)` and `c2 = cos²(α/2)` (`s2 + c2 = 1`).
    #[inline]
    pub fn eval_half(self, s2: f64, c2: f64) -> f64 {
        match self {
            Phase::Isotropic => 1.0 / (4.0 * PI),
            Phase::HenyeyGreenstein { g } => {
                // 1 + g² − 2g cos α, written around the peak so that it never cancels.
                let d =
                    if g >= 0.0 { (1.0 - g) * (1.0 - g) + 4.0 * g * s2 } else { (1.0 + g) * (1.0 + g) - 4.0 * g * c2 };
                (1.0 - g) * (1.0 + g) / (4.0 * PI * d * d.sqrt())
            }
        }
    }

    /// `P(α)` for an angle in radians (convenience; loses nothing for α ∈ [0, π]).
    pub fn eval(self, alpha: f64) -> f64 {
        let s = (0.5 * alpha).sin();
        let c = (0.5 * alpha).cos();
        self.eval_half(s * s, c * c)
    }

    /// Angular width of the peak, in radians: `1 − |g|` (∞ for isotropic). The
    /// reference places quadrature breakpoints on this scale.
    pub fn peak_width(self) -> f64 {
        match self {
            Phase::Isotropic => f64::INFINITY,
            Phase::HenyeyGreenstein { g } => 1.0 - g.abs(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ P dΩ = 2π ∫₀^π P(α) sin α dα = 1, by composite Simpson on a fine grid.
    #[test]
    fn normalised_over_the_sphere() {
        for g in [0.0, 0.3, -0.5, 0.9, -0.9] {
            let p = Phase::from_g(g);
            let n = 200_000;
            let dx = PI / n as f64;
            let mut sum = 0.0;
            for i in 0..=n {
                let a = i as f64 * dx;
                let w = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                sum += w * p.eval(a) * a.sin();
            }
            let integral = 2.0 * PI * sum * dx / 3.0;
            assert!((integral - 1.0).abs() < 1e-9, "g = {g}: {integral}");
        }
    }

    #[test]
    fn mirror_symmetry() {
        for a in [0.0, 0.3, 1.5, 3.0] {
            let l = Phase::from_g(0.7).eval(a);
            let r = Phase::from_g(-0.7).eval(PI - a);
            assert!(((l - r) / l).abs() < 1e-14);
        }
    }
}

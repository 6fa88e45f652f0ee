//! The u form the φ and lite families both integrate in (docs/MATH.md §3): its
//! cancellation-free geometry, `A` on the axis, and `eˣE₂` to double precision with
//! the polynomial form its fitted approximations use. Shared here so that neither
//! family reaches into the other.

use airlight_truth::reference::Point;
use std::f64::consts::PI;

/// `eˣE₂(x)` to double precision (the fit's target): `1 − x eˣE₁(x)` through the
/// reference exponential integral.
pub fn exp_e2_exact(x: f64) -> f64 {
    if x == 0.0 {
        return 1.0;
    }
    1.0 - x * airlight_truth::e1::exp_e1(airlight_truth::e1::Complex::new(x, 0.0)).re
}

/// `1 + Σ c_k t^k`.
pub fn horner1(c: &[f64], t: f64) -> f64 {
    let mut s = 0.0;
    for x in c.iter().rev() {
        s = (s + x) * t;
    }
    1.0 + s
}

/// The geometry of the u form, cancellation-free: `(h, ua, du = ub − ua, ub)`,
/// `ub = ∞` (and `du = ∞`) without a surface.
pub fn u_geometry(gamma: f64, rho: f64) -> (f64, f64, f64, f64) {
    let (h, x0) = (gamma.sin(), gamma.cos());
    let one_minus = if x0 >= 0.0 { h * h / (1.0 + x0) } else { 1.0 - x0 };
    let ua = if x0 >= 0.0 { h / (1.0 + x0) } else { (1.0 - x0) / h };
    if rho.is_infinite() {
        return (h, ua, f64::INFINITY, f64::INFINITY);
    }
    let tr = (rho - 1.0).hypot((2.0 * rho * one_minus).sqrt());
    // x0 − ρ from 1 − ρ (exact near 1) where cos γ rounds towards 1.
    let xr = if x0 >= 0.0 { (1.0 - rho) - one_minus } else { x0 - rho };
    let du = if xr <= 0.0 {
        rho * (tr - xr + one_minus) / ((tr + 1.0) * h)
    } else {
        2.0 * rho * h / ((1.0 + rho + tr) * (tr + xr))
    };
    (h, ua, du, ua + du)
}

/// `A` on the axis (`h = 0`, docs/MATH.md §5), for the families that integrate in
/// the u form: the light ahead, `P(0) e^{−τ} ρ/(1 − ρ)` before it, divergent through
/// it; behind, `A` is flat in `h` to O(h²), so `off_axis` evaluates it 1e-12 off.
pub fn on_axis(p: Point, g: f64, off_axis: &dyn Fn(Point) -> f64) -> f64 {
    if p.gamma >= 1.0 {
        off_axis(Point { gamma: PI - 1e-12, ..p })
    } else if p.rho < 1.0 {
        airlight_truth::phase::hg(g, 0.0, 2.0) * (-p.tau).exp() * p.rho / (1.0 - p.rho)
    } else {
        f64::INFINITY
    }
}

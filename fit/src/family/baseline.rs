//! Baselines: what a rendering engineer would use instead of a fitted model,
//! shipped as families so that the same toolchain measures, generates, gates and
//! benchmarks them beside airlight's own.
//!
//! * [`RayMarch`]: `N` uniform midpoint steps along the ray — the engines' method
//!   (Bevy marches 64 steps, three.js 12, Godot and Unreal 64 depth slices).
//! * [`Equiangular`]: Gauss–Legendre in the equiangular angle θ, `s = x0 + h tan θ`
//!   (Kulla & Fajardo 2012, its importance sampling made a deterministic rule).
//!
//! Both take Henyey–Greenstein `g` at run time and evaluate the phase function
//! exactly at each node. Neither is fitted: their parameters are the method's, and
//! their errors are measured like every model's.

use crate::cost::{Cost, PhaseShape, Shape};
use crate::reference::Point;
use crate::tomlfile::{FieldError, Reader};
use std::f64::consts::PI;
use std::fmt::Write;
use toml::Table;

/// The relative two-leg transmittance `e^{−τ(s + t − 1)}` at which a march with
/// no surface stops: beyond it the rest of the ray adds less than this share of
/// the light's unattenuated contribution.
pub const MARCH_CUTOFF: f64 = 1e-4;
/// The far plane of a march with no surface, in light distances `D`.
pub const FAR_PLANE: f64 = 1000.0;

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

/// Uniform midpoint ray marching with `steps` samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RayMarch {
    /// Samples along the ray.
    pub steps: usize,
}

/// Where a march with no surface ends: the distance at which the relative
/// two-leg transmittance `e^{−τ(s + t − 1)}` reaches [`MARCH_CUTOFF`], capped by
/// [`FAR_PLANE`]. `s + t` grows with `s` (`(s + t)' = 1 + (s − x0)/t ≥ 0`) and
/// `s + t = K` at `s = (K² − 1) / (2 (K − x0))`.
pub fn march_end(tau: f64, x0: f64) -> f64 {
    let k = 1.0 + (1.0 / MARCH_CUTOFF).ln() / tau;
    let s = (k * k - 1.0) / (2.0 * (k - x0));
    if s.is_finite() {
        s.min(FAR_PLANE)
    } else {
        FAR_PLANE
    }
}

impl RayMarch {
    /// Its kind ([`crate::family::Body::kind`]).
    pub const KIND: &'static str = "raymarch";
    /// The step counts the catalog ships.
    pub const STEPS: [usize; 7] = [8, 16, 32, 64, 128, 256, 1024];

    /// `A` at a valid point: `Δ Σ P(α) e^{−τ(s + t)} / t²` at `s = (i + ½) Δ`,
    /// `Δ = L / N`, `L = ρ` or [`march_end`].
    pub fn eval(&self, p: Point) -> f64 {
        let (h, x0) = (p.gamma.sin(), p.gamma.cos());
        let len = if p.rho.is_finite() { p.rho } else { march_end(p.tau, x0) };
        let dt = len / self.steps as f64;
        let mut sum = 0.0;
        for i in 0..self.steps {
            let s = (i as f64 + 0.5) * dt;
            let x = x0 - s;
            let t2 = x * x + h * h;
            let t = t2.sqrt();
            let (om, op) = one_minus_plus_cos(x, h, t);
            sum += hg(p.g, om, op) * (-p.tau * (s + t)).exp() / t2;
        }
        sum * dt
    }

    /// Per step: one `exp`, one `sqrt`, the phase's `sqrt` and three divisions;
    /// the end: one `log`-free division chain.
    pub fn ops(&self, _shape: Shape) -> Cost {
        let n = self.steps;
        Cost { exp: n, log: 0, atan: 0, sqrt: 2 * n, div: 3 * n + 3, sincos: 1 }
    }

    /// Its tables in a coefficient file.
    pub const TABLES: &'static [&'static str] = &["march"];

    /// Writes its table.
    pub fn render_toml(&self, o: &mut String) {
        o.push_str("\n[march]\nrule = \"midpoint\"\n");
        let _ = writeln!(o, "steps = {}", self.steps);
        let _ = writeln!(o, "# no surface: march to the relative two-leg transmittance below, capped by the far plane");
        let _ = writeln!(o, "cutoff_transmittance = {}", crate::coeffs::dec(MARCH_CUTOFF));
        let _ = writeln!(o, "far_plane = {} # light distances", crate::coeffs::dec(FAR_PLANE));
    }

    /// Reads its table.
    pub fn parse_toml(r: &Reader, doc: &Table) -> Result<RayMarch, FieldError> {
        let t = r.table(doc, "march")?;
        r.deny(t, "march", &["rule", "steps", "cutoff_transmittance", "far_plane"])?;
        r.expect_str(t, "march", "rule", "midpoint")?;
        let steps = r.uint(t, "march", "steps")?;
        if !(1..=4096).contains(&steps) {
            return Err(r.err("march", "steps", "must be 1..=4096"));
        }
        if r.float(t, "march", "cutoff_transmittance")? != MARCH_CUTOFF {
            return Err(r.err("march", "cutoff_transmittance", &format!("this airlight marches to {MARCH_CUTOFF}")));
        }
        if r.float(t, "march", "far_plane")? != FAR_PLANE {
            return Err(r.err("march", "far_plane", &format!("this airlight's far plane is {FAR_PLANE}")));
        }
        Ok(RayMarch { steps })
    }
}

/// Gauss–Legendre in the equiangular angle with `nodes` nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Equiangular {
    /// Nodes on `[−1, 1]`.
    pub x: Vec<f64>,
    /// Weights.
    pub w: Vec<f64>,
}

impl Equiangular {
    /// Its kind ([`crate::family::Body::kind`]).
    pub const KIND: &'static str = "equiangular";
    /// The node counts the catalog ships.
    pub const NODES: [usize; 5] = [2, 4, 8, 16, 32];
    /// Its tables in a coefficient file.
    pub const TABLES: &'static [&'static str] = &["quadrature"];

    /// The `n`-point rule.
    pub fn new(n: usize) -> Equiangular {
        let (x, w) = crate::quad::gauss_legendre(n);
        Equiangular { x, w }
    }

    /// Nodes.
    pub fn n(&self) -> usize {
        self.x.len()
    }

    /// `A = (1/h) ∫ P e^{−τ(s + t)} dθ` over `θ ∈ [γ − π/2, θb]` (MATH.md §3), taken
    /// in `β = (θ + π/2)/2 = α/2`: `s + t = x0 + h tan β`, `1 − cos α = 2 sin² β`,
    /// `1 + cos α = 2 cos² β` (no cancellation anywhere), and the interval's length
    /// the angle at the light between viewer and surface (`atan2(h ρ, 1 − ρ x0)`,
    /// `π − γ` without one), so that it never cancels either.
    pub fn eval(&self, p: Point) -> f64 {
        let (h, x0) = (p.gamma.sin(), p.gamma.cos());
        let span = if p.rho.is_finite() { (h * p.rho).atan2(1.0 - p.rho * x0) } else { PI - p.gamma };
        let half = 0.5 * span;
        // span/h, with its limit on the axis (h = 0).
        let ratio = if h > 0.0 {
            half / h
        } else if x0 > 0.0 && (p.rho.is_infinite() || p.rho >= 1.0) {
            f64::INFINITY
        } else if p.rho.is_infinite() {
            0.5
        } else {
            0.5 * p.rho / (1.0 - p.rho * x0)
        };
        let g = p.g;
        let mut sum = 0.0;
        for (&x, &w) in self.x.iter().zip(&self.w) {
            let beta = 0.5 * p.gamma + 0.5 * half * (1.0 + x);
            let (sb, cb) = beta.sin_cos();
            let st = (x0 + h * sb / cb).max(1.0);
            let d = if g >= 0.0 {
                (1.0 - g) * (1.0 - g) + 4.0 * g * sb * sb
            } else {
                (1.0 + g) * (1.0 + g) - 4.0 * g * cb * cb
            };
            sum += w * (-p.tau * st).exp() / (d * d.sqrt());
        }
        (1.0 - g) * (1.0 + g) / (4.0 * PI) * sum * ratio
    }

    /// Per node: `sin_cos`, `exp`, the phase's `sqrt` and three divisions; the
    /// interval: one `atan2`, one `sin_cos`.
    pub fn ops(&self, _shape: Shape) -> Cost {
        let n = self.n();
        Cost { exp: n, log: 0, atan: 1, sqrt: n, div: 3 * n + 1, sincos: n + 1 }
    }

    /// Writes its table.
    pub fn render_toml(&self, o: &mut String) {
        o.push_str("\n[quadrature]\nrule = \"gauss-legendre\"\n");
        o.push_str(
            "variable = \"equiangular angle θ: s = cos γ + sin γ tan θ, θ from γ − π/2 to the surface's angle\"\n",
        );
        let _ = writeln!(o, "nodes = {}", self.n());
        crate::coeffs::hex_list(o, "x", &self.x);
        crate::coeffs::hex_list(o, "w", &self.w);
    }

    /// Reads its table: the nodes and weights must be the Gauss–Legendre rule.
    pub fn parse_toml(r: &Reader, doc: &Table) -> Result<Equiangular, FieldError> {
        let t = r.table(doc, "quadrature")?;
        r.deny(t, "quadrature", &["rule", "variable", "nodes", "x", "w"])?;
        r.expect_str(t, "quadrature", "rule", "gauss-legendre")?;
        let n = r.uint(t, "quadrature", "nodes")?;
        if !(1..=256).contains(&n) {
            return Err(r.err("quadrature", "nodes", "must be 1..=256"));
        }
        let x = r.hexes(t, "quadrature", "x", Some(n))?;
        let w = r.hexes(t, "quadrature", "w", Some(n))?;
        let want = Equiangular::new(n);
        for (key, got, want) in [("x", &x, &want.x), ("w", &w, &want.w)] {
            if got.iter().zip(want).any(|(a, b)| (a - b).abs() > 1e-14) {
                return Err(r.err("quadrature", key, &format!("is not the {n}-point Gauss-Legendre rule")));
            }
        }
        Ok(Equiangular { x, w })
    }
}

/// How both take the phase: `g` at run time, exact at each node.
pub fn phase_shape() -> PhaseShape {
    PhaseShape::Exact
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference;

    #[test]
    fn converge_to_the_reference() {
        for &(tau, gamma, rho, g) in
            &[(0.5, 1.0, 3.0, 0.0), (3.0, 2.0, f64::INFINITY, 0.0), (1.0, 0.7, 10.0, 0.6), (2.0, 2.5, 5.0, -0.5)]
        {
            let p = Point { tau, gamma, rho, g };
            let exact = reference::airlight(p).unwrap();
            let e = Equiangular::new(64).eval(p);
            assert!((e / exact - 1.0).abs() < 1e-6, "equiangular {p:?}: {e} vs {exact}");
            if rho.is_finite() {
                let m = RayMarch { steps: 1 << 16 }.eval(p);
                assert!((m / exact - 1.0).abs() < 1e-4, "march {p:?}: {m} vs {exact}");
            }
        }
    }

    #[test]
    fn the_march_ends_where_the_transmittance_falls() {
        for &(tau, x0) in &[(0.1, 0.5), (3.0, -0.9), (10.0, 0.99)] {
            let s: f64 = march_end(tau, x0);
            let t = (s * s - 2.0 * s * x0 + 1.0).sqrt();
            assert!(((-tau * (s + t - 1.0)).exp() / MARCH_CUTOFF - 1.0).abs() < 1e-9);
        }
        assert_eq!(march_end(0.0, 0.3), FAR_PLANE);
        assert_eq!(march_end(1e-6, 0.3), FAR_PLANE);
    }
}

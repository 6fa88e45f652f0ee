//! The `equiangular` family, a baseline: Gauss–Legendre in the equiangular angle
//! θ, `s = x0 + h tan θ` (Kulla & Fajardo 2012, its importance sampling made a
//! deterministic rule). It takes Henyey–Greenstein `g` at run time and evaluates
//! the phase function exactly at each node. Nothing is fitted: its parameters are
//! the method's, and its errors are measured like every model's.

use airlight_shapes::cost::{Cost, PhaseShape, Shape};
use crate::family::{baseline_method, phase_label, Assembled, Family, Role};
use airlight_truth::reference::Point;
use airlight_shapes::template::{lits, Context, KernelView, Templates};
use airlight_truth::tomlfile::{FieldError, Reader};
use std::f64::consts::PI;
use std::fmt::Write;
use toml::Table;

/// Gauss–Legendre in the equiangular angle with `nodes` nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Equiangular {
    /// Nodes on `[−1, 1]`.
    pub x: Vec<f64>,
    /// Weights.
    pub w: Vec<f64>,
}

impl Equiangular {
    /// The `n`-point rule.
    pub fn new(n: usize) -> Equiangular {
        let (x, w) = airlight_truth::quad::gauss_legendre(n);
        Equiangular { x, w }
    }

    /// Nodes.
    pub fn n(&self) -> usize {
        self.x.len()
    }
}

impl Family for Equiangular {
    const KIND: &'static str = "equiangular";
    const DIR: &'static str = "equiangular";
    const ROLE: Role = Role::Baseline;
    const TABLES: &'static [&'static str] = &["quadrature"];
    const TEMPLATES: Templates = airlight_shapes::core_templates!();
    /// τ enters only the transmittances: the nodes are shared across channels.
    const SHARES_RGB_NODES: bool = true;
    /// The number of nodes.
    type Recipe = usize;
    type Fit = ();

    fn assemble(n: usize, g_range: (f64, f64), _: &()) -> Result<Assembled<Equiangular>, String> {
        Ok(Assembled {
            body: Equiangular::new(n),
            families: vec![format!("equiangular-{n} (Gauss-Legendre)"), phase_label(g_range)],
            provenance: Vec::new(),
            method: baseline_method(&format!(
                "{n}-point Gauss-Legendre in θ, s = cos γ + sin γ tan θ (ds/t² = dθ/h), nodes by Newton on P_n in f64"
            )),
        })
    }

    /// `g` at run time, exact at each node.
    fn phase_shape(&self) -> PhaseShape {
        PhaseShape::Exact
    }

    fn kernel_context(&self, k: &KernelView) -> Context {
        let mut ctx = Context::quadrature(k);
        ctx.insert("nodes", &lits(&self.x));
        ctx.insert("weights", &lits(&self.w));
        ctx
    }

    /// `A = (1/h) ∫ P e^{−τ(s + t)} dθ` over `θ ∈ [γ − π/2, θb]` (docs/MATH.md §3), taken
    /// in `β = (θ + π/2)/2 = α/2`: `s + t = x0 + h tan β`, `1 − cos α = 2 sin² β`,
    /// `1 + cos α = 2 cos² β` (no cancellation anywhere), and the interval's length
    /// the angle at the light between viewer and surface (`atan2(h ρ, 1 − ρ x0)`,
    /// `π − γ` without one), so that it never cancels either.
    fn eval(&self, p: Point) -> f64 {
        let (h, x0) = (p.gamma.sin(), p.gamma.cos());
        // π − γ to full precision (f64's π is 1.2e-16 below π), so that the interval
        // and each node's distance from β = π/2 keep their digits near the axis behind.
        let comp = (PI - p.gamma) + 1.224_646_799_147_353_2e-16;
        let span = if p.rho.is_finite() { (h * p.rho).atan2(1.0 - p.rho * x0) } else { comp };
        let half = 0.5 * span;
        // span/h, with its limit on the axis (h = 0: γ = 0, the light ahead).
        let ratio = if h > 0.0 {
            half / h
        } else if p.rho.is_infinite() || p.rho >= 1.0 {
            f64::INFINITY
        } else {
            0.5 * p.rho / (1.0 - p.rho * x0)
        };
        if ratio.is_infinite() {
            return f64::INFINITY;
        }
        let g = p.g;
        let mut sum = 0.0;
        for (&x, &w) in self.x.iter().zip(&self.w) {
            // β = α/2 and π/2 − β; the smaller goes to sin_cos, so that sin β and
            // cos β both keep their relative precision.
            let beta = 0.5 * p.gamma + 0.5 * half * (1.0 + x);
            let co = 0.5 * comp - 0.5 * half * (1.0 + x);
            let (s, c) = beta.min(co).max(0.0).sin_cos();
            let (sb, cb) = if beta <= co { (s, c) } else { (c, s) };
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
    fn ops(&self, _shape: Shape) -> Cost {
        let n = self.n();
        Cost { exp: n, log: 0, atan: 1, sqrt: n, div: 3 * n + 1, sincos: n + 1 }
    }

    /// Writes its table.
    fn render_toml(&self, _g_range: (f64, f64), o: &mut String, _prov: &dyn Fn(&mut String, &str)) {
        o.push_str("\n[quadrature]\nrule = \"gauss-legendre\"\n");
        o.push_str(
            "variable = \"equiangular angle θ: s = cos γ + sin γ tan θ, θ from γ − π/2 to the surface's angle\"\n",
        );
        let _ = writeln!(o, "nodes = {}", self.n());
        airlight_truth::tomlfile::hex_list(o, "x", &self.x);
        airlight_truth::tomlfile::hex_list(o, "w", &self.w);
    }

    /// Reads its table: the nodes and weights must be the Gauss–Legendre rule.
    fn parse_toml(r: &Reader, doc: &Table, _g_range: &[f64]) -> Result<Equiangular, FieldError> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use airlight_truth::reference;

    #[test]
    fn converges_to_the_reference() {
        for &(tau, gamma, rho, g) in
            &[(0.5, 1.0, 3.0, 0.0), (3.0, 2.0, f64::INFINITY, 0.0), (1.0, 0.7, 10.0, 0.6), (2.0, 2.5, 5.0, -0.5)]
        {
            let p = Point { tau, gamma, rho, g };
            let exact = reference::airlight(p).unwrap();
            let e = Equiangular::new(64).eval(p);
            assert!((e / exact - 1.0).abs() < 1e-6, "equiangular {p:?}: {e} vs {exact}");
        }
    }
}

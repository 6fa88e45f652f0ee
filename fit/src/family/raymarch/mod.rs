//! The `raymarch` family, a baseline: `N` uniform midpoint steps along the ray —
//! the engines' method (Bevy marches 64 steps, three.js 12, Godot and Unreal 64
//! depth slices). It takes Henyey–Greenstein `g` at run time and evaluates the
//! phase function exactly at each step. Nothing is fitted: its parameters are the
//! method's, and its errors are measured like every model's.

use airlight_shapes::cost::{Cost, PhaseShape, Shape};
use crate::family::{baseline_method, phase_label, Assembled, Family, Role};
use airlight_truth::phase::{hg, one_minus_plus_cos};
use airlight_truth::reference::Point;
use airlight_shapes::template::{lit, Context, KernelView, Templates};
use airlight_truth::tomlfile::{FieldError, Reader};
use airlight_truth::geometry::{march_end, FAR_PLANE, MARCH_CUTOFF};
use std::fmt::Write;
use toml::Table;

/// Uniform midpoint ray marching with `steps` samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RayMarch {
    /// Samples along the ray.
    pub steps: usize,
}

impl Family for RayMarch {
    const KIND: &'static str = "raymarch";
    const DIR: &'static str = "raymarch";
    const ROLE: Role = Role::Baseline;
    const TABLES: &'static [&'static str] = &["march"];
    const TEMPLATES: Templates = airlight_shapes::core_templates!();
    /// The number of steps.
    type Recipe = usize;
    type Fit = ();

    fn assemble(n: usize, g_range: (f64, f64), _: &()) -> Result<Assembled<RayMarch>, String> {
        Ok(Assembled {
            body: RayMarch { steps: n },
            families: vec![format!("raymarch-{n} (midpoint)"), phase_label(g_range)],
            provenance: Vec::new(),
            method: baseline_method(&format!(
                "{n} uniform midpoint samples of P e^(-τ(s + t))/t² over [0, ρ]; no surface: to the relative two-leg transmittance {MARCH_CUTOFF}, capped at {FAR_PLANE} light distances"
            )),
        })
    }

    /// `A` at a valid point: `Δ Σ P(α) e^{−τ(s + t)} / t²` at `s = (i + ½) Δ`,
    /// `Δ = L / N`, `L = ρ` or [`march_end`].
    fn eval(&self, p: Point) -> f64 {
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
    fn ops(&self, _shape: Shape) -> Cost {
        let n = self.steps;
        Cost { exp: n, log: 0, atan: 0, sqrt: 2 * n, div: 3 * n + 3, sincos: 1 }
    }

    /// `g` at run time, exact at each step.
    fn phase_shape(&self) -> PhaseShape {
        PhaseShape::Exact
    }

    fn kernel_context(&self, k: &KernelView) -> Context {
        let mut ctx = Context::quadrature(k);
        ctx.insert("steps", &self.steps);
        ctx.insert("far", &lit(FAR_PLANE));
        ctx.insert("far_doc", &FAR_PLANE);
        ctx.insert("ln_cutoff", &lit((1.0 / MARCH_CUTOFF).ln()));
        ctx.insert("cutoff_doc", &format!("{MARCH_CUTOFF:e}"));
        ctx
    }

    /// Writes its table.
    fn render_toml(&self, _g_range: (f64, f64), o: &mut String, _prov: &dyn Fn(&mut String, &str)) {
        o.push_str("\n[march]\nrule = \"midpoint\"\n");
        let _ = writeln!(o, "steps = {}", self.steps);
        let _ = writeln!(o, "# no surface: march to the relative two-leg transmittance below, capped by the far plane");
        let _ = writeln!(o, "cutoff_transmittance = {}", airlight_truth::tomlfile::dec(MARCH_CUTOFF));
        let _ = writeln!(o, "far_plane = {} # light distances", airlight_truth::tomlfile::dec(FAR_PLANE));
    }

    /// Reads its table.
    fn parse_toml(r: &Reader, doc: &Table, _g_range: &[f64]) -> Result<RayMarch, FieldError> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use airlight_truth::reference;

    #[test]
    fn converges_to_the_reference() {
        for &(tau, gamma, rho, g) in &[(0.5, 1.0, 3.0, 0.0), (1.0, 0.7, 10.0, 0.6), (2.0, 2.5, 5.0, -0.5)] {
            let p = Point { tau, gamma, rho, g };
            let exact = reference::airlight(p).unwrap();
            let m = RayMarch { steps: 1 << 16 }.eval(p);
            assert!((m / exact - 1.0).abs() < 1e-4, "march {p:?}: {m} vs {exact}");
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

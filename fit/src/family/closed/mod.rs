//! The no-extinction family: seed 003's exact closed form of the isotropic
//! integral with `τ = 0`, a whole-integral family (no forward/backward split).
//! Exact where extinction does not matter, and the cost floor of every kernel.
//!
//! `A(0, γ, ρ) = atan2(h ρ, 1 − ρ cos γ) / (4π h)`, `h = sin γ` (`ρ = ∞`:
//! `(π − γ) / (4π h)`); on the axis (`h = 0`) `ρ / (4π (1 − ρ))` before the light.

use airlight_shapes::cost::{Cost, PhaseShape, Shape};
use crate::family::{baseline_method, phase_label, Assembled, Family, Role};
use airlight_truth::reference::Point;
use airlight_shapes::template::{Context, KernelView, Templates};
use airlight_truth::tomlfile::{FieldError, Reader};
use toml::Table;

/// The closed form (isotropic, extinction ignored).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NoExtinction;

impl Family for NoExtinction {
    const KIND: &'static str = "no-extinction";
    const DIR: &'static str = "closed";
    const ROLE: Role = Role::Baseline;
    const ON_THE_MENU: bool = true;
    const TABLES: &'static [&'static str] = &[];
    const TEMPLATES: Templates = airlight_shapes::core_templates!();
    const EXTINCTION: bool = false;
    const COST_FLOOR: bool = true;
    type Recipe = ();
    type Fit = ();

    fn assemble(_: (), g_range: (f64, f64), _: &()) -> Result<Assembled<NoExtinction>, String> {
        Ok(Assembled {
            body: NoExtinction,
            families: vec!["no-extinction (seed 003)".to_string(), phase_label(g_range)],
            provenance: Vec::new(),
            method: baseline_method(
                "A(0, γ, ρ) = atan2(h ρ, 1 − ρ cos γ)/(4π h) whatever τ: exact at τ = 0, error growing with τ",
            ),
        })
    }

    /// `A(0, γ, ρ)` whatever `τ` and `g` the point has.
    fn eval(&self, p: Point) -> f64 {
        airlight_truth::reference::no_extinction(p.gamma, p.rho)
    }

    /// One `atan2`, one `sin_cos`, two divisions, whatever the shape.
    fn ops(&self, _shape: Shape) -> Cost {
        Cost { exp: 0, log: 0, atan: 1, sqrt: 0, div: 2, sincos: 1 }
    }

    fn phase_shape(&self) -> PhaseShape {
        PhaseShape::Isotropic
    }

    fn render_toml(&self, _g_range: (f64, f64), _out: &mut String, _prov: &dyn Fn(&mut String, &str)) {}

    fn parse_toml(_r: &Reader, _doc: &Table, _g_range: &[f64]) -> Result<NoExtinction, FieldError> {
        Ok(NoExtinction)
    }

    fn kernel_context(&self, k: &KernelView) -> Context {
        let mut ctx = Context::new();
        // A scene's plan may pick the closed form itself, with no model behind it.
        let summary = match k.model_summary {
            Some(_) => k.summary_line(),
            None => "isotropic scattering without extinction, exact.".to_string(),
        };
        ctx.insert("summary", &summary);
        ctx
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn agrees_with_the_reference_without_extinction() {
        for &(gamma, rho) in &[(0.3, 0.5), (1.0, 2.0), (2.5, f64::INFINITY), (3.1, 100.0), (0.0, 0.5), (PI, 3.0)] {
            let p = Point { tau: 0.0, gamma, rho, g: 0.0 };
            let exact = airlight_truth::reference::airlight(p).unwrap();
            let got = NoExtinction.eval(p);
            assert!((got - exact).abs() <= 1e-12 * exact, "γ {gamma} ρ {rho}: {got} vs {exact}");
        }
    }
}

//! The approximation families, one module each: its representation, f64
//! evaluation, fit, coefficient schema and cost. A model's [`Body`] is the family
//! values it is evaluated with (see [`crate::approx`]).
//!
//! Adding a family: a module here, a variant of [`Body`] and its arms below, its
//! kernel templates and the catalog entries that use it (README, "Adding a family").

pub mod baseline;
pub mod closed;
pub mod expsum;
pub mod phase_exp;
pub mod phi;
pub mod ratio;
pub mod segments;
pub mod split;
pub mod sun;

use crate::cost::{Cost, PhaseShape, Shape};
use crate::reference::Point;
use crate::tomlfile::{FieldError, Reader};
use toml::Table;

/// What a model evaluates `A` with. (Bodies are few and long-lived: the size
/// difference between variants costs nothing.)
#[derive(Debug, Clone, PartialEq)]
#[allow(clippy::large_enum_variant)]
pub enum Body {
    /// A forward part plus a backward part: the paper's three families and their refits.
    Split(split::Split),
    /// The whole integral without extinction, in closed form (exact at `τ = 0`).
    NoExtinction(closed::NoExtinction),
    /// Uniform midpoint ray marching (a baseline).
    RayMarch(baseline::RayMarch),
    /// Gauss–Legendre in the equiangular angle (a baseline).
    Equiangular(baseline::Equiangular),
    /// Sun et al.'s table of `F(u, v)`, bilinear (a baseline).
    Sun2005(sun::SunTable),
    /// The whole of `A` by a composite rule in the HG variable φ, `eˣE₂` and Gauss–Laguerre.
    Phi(phi::PhiRule),
}

impl Body {
    /// Every kind, in the order of the variants.
    pub const KINDS: [&'static str; 6] = [
        split::Split::KIND,
        closed::NoExtinction::KIND,
        baseline::RayMarch::KIND,
        baseline::Equiangular::KIND,
        sun::SunTable::KIND,
        phi::PhiRule::KIND,
    ];

    /// The family's name: the `kind` key of coefficient files and the key of its
    /// templates in `codegen/outputs.toml`.
    pub fn kind(&self) -> &'static str {
        match self {
            Body::Split(_) => split::Split::KIND,
            Body::NoExtinction(_) => closed::NoExtinction::KIND,
            Body::RayMarch(_) => baseline::RayMarch::KIND,
            Body::Equiangular(_) => baseline::Equiangular::KIND,
            Body::Sun2005(_) => sun::SunTable::KIND,
            Body::Phi(_) => phi::PhiRule::KIND,
        }
    }

    /// Whether it is a baseline — what a user would pick instead of a fitted
    /// model — rather than one of airlight's own models.
    pub fn is_baseline(&self) -> bool {
        !matches!(self, Body::Split(_) | Body::Phi(_))
    }

    /// The table it reads (bytes of f32 texels), if it has one.
    pub fn table(&self) -> Option<&sun::SunTable> {
        match self {
            Body::Sun2005(t) => Some(t),
            _ => None,
        }
    }

    /// Whether it models extinction (takes τ).
    pub fn extinction(&self) -> bool {
        !matches!(self, Body::NoExtinction(_))
    }

    /// `A` at a valid point.
    pub fn eval(&self, p: Point) -> f64 {
        match self {
            Body::Split(s) => s.eval(p),
            Body::NoExtinction(c) => c.eval(p),
            Body::RayMarch(m) => m.eval(p),
            Body::Equiangular(q) => q.eval(p),
            Body::Sun2005(t) => t.eval(p),
            Body::Phi(r) => r.eval(p),
        }
    }

    /// How its phase function costs.
    pub fn phase_shape(&self) -> PhaseShape {
        match self {
            Body::Split(s) => s.phase_shape(),
            Body::NoExtinction(_) | Body::Sun2005(_) => PhaseShape::Isotropic,
            Body::RayMarch(_) | Body::Equiangular(_) | Body::Phi(_) => baseline::phase_shape(),
        }
    }

    /// Operation counts of one f32 kernel evaluation in `shape`: the one source
    /// of cost for the planner, the plans and the report.
    pub fn ops(&self, shape: Shape) -> Cost {
        match self {
            Body::Split(s) => s.ops(shape),
            Body::NoExtinction(c) => c.ops(shape),
            Body::RayMarch(m) => m.ops(shape),
            Body::Equiangular(q) => q.ops(shape),
            Body::Sun2005(t) => t.ops(shape),
            Body::Phi(r) => r.ops(shape),
        }
    }

    /// The top-level tables a coefficient file of family `kind` has (besides
    /// `[model]`, `[error.*]` and `[provenance]`); `None` for an unknown kind.
    pub fn tables(kind: &str) -> Option<&'static [&'static str]> {
        match kind {
            split::Split::KIND => Some(split::Split::TABLES),
            closed::NoExtinction::KIND => Some(&[]),
            baseline::RayMarch::KIND => Some(baseline::RayMarch::TABLES),
            baseline::Equiangular::KIND => Some(baseline::Equiangular::TABLES),
            sun::SunTable::KIND => Some(sun::SunTable::TABLES),
            phi::PhiRule::KIND => Some(phi::PhiRule::TABLES),
            _ => None,
        }
    }

    /// Writes the family's tables of a coefficient file; `prov(out, table)` writes
    /// the provenance table `table` where it belongs.
    pub fn render_toml(&self, g_range: (f64, f64), out: &mut String, prov: &dyn Fn(&mut String, &str)) {
        match self {
            Body::Split(s) => s.render_toml(g_range, out, prov),
            Body::NoExtinction(_) => {}
            Body::RayMarch(m) => m.render_toml(out),
            Body::Equiangular(q) => q.render_toml(out),
            Body::Sun2005(t) => t.render_toml(out),
            Body::Phi(r) => r.render_toml(out, prov),
        }
    }

    /// Reads the tables of a coefficient file of family `kind` (checked by [`Body::tables`]).
    pub fn parse_toml(kind: &str, r: &Reader, doc: &Table, g_range: &[f64]) -> Result<Body, FieldError> {
        Ok(match kind {
            split::Split::KIND => Body::Split(split::Split::parse_toml(r, doc, g_range)?),
            closed::NoExtinction::KIND => Body::NoExtinction(closed::NoExtinction),
            baseline::RayMarch::KIND => Body::RayMarch(baseline::RayMarch::parse_toml(r, doc)?),
            baseline::Equiangular::KIND => Body::Equiangular(baseline::Equiangular::parse_toml(r, doc)?),
            sun::SunTable::KIND => Body::Sun2005(sun::SunTable::parse_toml(r, doc, g_range)?),
            phi::PhiRule::KIND => Body::Phi(phi::PhiRule::parse_toml(r, doc)?),
            other => return Err(r.err("model", "kind", &format!("unknown family '{other}'"))),
        })
    }
}

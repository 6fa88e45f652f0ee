//! What a family's kernel templates are given: how the kernel takes the phase
//! ([`KernelPhase`]), what it was specialised to ([`KernelView`]), the context the
//! family fills for its core templates ([`Context`]), and the f32 literals every
//! constant is printed as ([`lit`]).
//!
//! The generator (airlight-codegen) owns the shared entry templates and renders;
//! each family (`fit/src/family/<name>/`) owns its core templates and fills their
//! context from its coefficients. Neither names the other's internals.

use crate::vocab::Target;
use serde::Serialize;
use std::collections::BTreeMap;

/// How a kernel evaluates the phase function.
#[derive(Debug, Clone, PartialEq)]
pub enum KernelPhase {
    /// `1/(4π)`: no phase code.
    Isotropic,
    /// One `g`, its terms baked in.
    Fixed(f64),
    /// `g` at run time, over these bands of `|g|` (a band search).
    Banded(Vec<usize>),
    /// `g` at run time, Henyey–Greenstein evaluated exactly.
    Exact,
}

impl KernelPhase {
    /// The baked `g`, if the phase is [`KernelPhase::Fixed`].
    pub fn fixed_g(&self) -> Option<f64> {
        match self {
            KernelPhase::Fixed(g) => Some(*g),
            _ => None,
        }
    }
}

/// The phase a kernel is asked for: a model's general kernel, or a scene's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WantPhase {
    /// The model's whole `g` range (its general kernel).
    General,
    /// Isotropic scattering.
    Isotropic,
    /// One `g`.
    Fixed(f64),
    /// `g` at run time within `[lo, hi]`.
    Range(f64, f64),
}

/// The core templates of a family, one per target.
#[derive(Debug, Clone, Copy)]
pub struct Templates {
    /// WGSL (also the source of the Bevy, WESL, HLSL and MSL outputs).
    pub wgsl: &'static str,
    /// GLSL.
    pub glsl: &'static str,
    /// A module of the Rust crate `airlight-kernels`.
    pub rust: &'static str,
}

impl Templates {
    /// The template for `target`.
    pub fn get(&self, target: Target) -> &'static str {
        match target {
            Target::Wgsl => self.wgsl,
            Target::Glsl => self.glsl,
            Target::Rust => self.rust,
        }
    }
}

/// A family's core templates, from the files `core.wgsl.tera`, `core.glsl.tera`
/// and `core.rs.tera` beside the module that calls it.
#[macro_export]
macro_rules! core_templates {
    () => {
        $crate::template::Templates {
            wgsl: include_str!("core.wgsl.tera"),
            glsl: include_str!("core.glsl.tera"),
            rust: include_str!("core.rs.tera"),
        }
    };
}

/// What a family's kernel context is computed from: the kernel's name and
/// specialisations, as the generator decided them.
#[derive(Debug, Clone)]
pub struct KernelView<'a> {
    /// `segments-8`, `scene-fog-street`.
    pub name: &'a str,
    /// The model it evaluates (`None`: no model, the closed form itself).
    pub model_name: Option<&'a str>,
    /// The model's one-line summary.
    pub model_summary: Option<&'a str>,
    /// What the kernel was specialised to, in words.
    pub specialisations: &'a str,
    /// How it takes the phase.
    pub phase: &'a KernelPhase,
    /// Whether rays can end on a surface.
    pub surfaces: bool,
    /// Whether the backward part is kept.
    pub backscatter: bool,
    /// Whether it has the spot entry.
    pub spot: bool,
    /// The language.
    pub target: Target,
    /// The prefix of every item in this output (`airlight_phi_8_`, or empty).
    pub prefix: &'a str,
}

impl KernelView<'_> {
    /// `"{summary} ({specialisations})."`: the summary line of a kernel of a model.
    pub fn summary_line(&self) -> String {
        format!("{} ({}).", self.model_summary.unwrap_or_default(), self.specialisations)
    }
}

/// The values a template sees, by name (serialised once, rendered by tera).
#[derive(Debug, Clone, Default, Serialize)]
#[serde(transparent)]
pub struct Context(BTreeMap<String, serde_json::Value>);

impl Context {
    /// An empty context.
    pub fn new() -> Context {
        Context::default()
    }

    /// Sets `key` to `value`.
    pub fn insert<T: Serialize + ?Sized>(&mut self, key: &str, value: &T) {
        let v = serde_json::to_value(value).expect("template values are plain data");
        self.0.insert(key.to_string(), v);
    }

    /// The context of the quadrature families' templates (the baselines' and
    /// φ's): the summary and how the phase is taken.
    pub fn quadrature(k: &KernelView) -> Context {
        let mut ctx = Context::new();
        ctx.insert("summary", &k.summary_line());
        ctx.insert("phase_iso", &(*k.phase == KernelPhase::Isotropic));
        ctx.insert("phase_exact", &(*k.phase == KernelPhase::Exact));
        let fixed = k.phase.fixed_g();
        ctx.insert("phase_fixed", &fixed.is_some());
        ctx.insert("fixed_g", &fixed.map_or(String::new(), |g| format!("{g}")));
        ctx.insert("fixed_g_lit", &fixed.map_or(String::new(), lit));
        ctx
    }
}

/// The nearest f32 to `x`, printed with 9 significant digits (round-trips in every target).
pub fn lit(x: f64) -> String {
    let v = x as f32;
    if v == 0.0 {
        return "0.0".into();
    }
    format!("{v:.8e}")
}

/// [`lit`] of each.
pub fn lits(xs: &[f64]) -> Vec<String> {
    xs.iter().map(|&x| lit(x)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_read_back_as_the_same_f32() {
        for x in [0.1, -1.0 / 3.0, 1e-30, 6.02e23, std::f64::consts::PI, 16.0] {
            let s = lit(x);
            assert_eq!(s.parse::<f32>().unwrap(), x as f32, "{s}");
            assert_eq!(s.parse::<f64>().unwrap() as f32, x as f32, "{s}");
        }
        assert_eq!(lit(0.0), "0.0");
    }
}

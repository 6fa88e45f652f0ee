//! Models: complete evaluators of `A(τ, γ, ρ; g)`, looked up by name.
//!
//! The reference is the only model so far; fitted approximations join this
//! registry as they are built, so `airlight eval --model NAME` and every report
//! see them without further wiring.

use crate::reference::{self, Param, ParamError, Point};
use std::fmt;

/// A complete evaluator of the canonical airlight.
pub trait Model: Sync {
    /// Name used on the command line and in file names.
    fn name(&self) -> &'static str;
    /// One line for tables and help.
    fn summary(&self) -> &'static str;
    /// The Henyey–Greenstein `g` it supports, `[lo, hi]`; `[0, 0]` is isotropic only.
    fn g_range(&self) -> (f64, f64);
    /// The g range as written in tables: `[lo, hi]`.
    fn g_range_label(&self) -> String {
        let (lo, hi) = self.g_range();
        format!("[{lo}, {hi}]")
    }
    /// `A` at a point that passed [`Model::check`].
    fn eval_unchecked(&self, p: Point) -> f64;
    /// Whether `p` is in the domain of `A` and in this model's g range.
    fn check(&self, p: &Point) -> Result<(), ParamError> {
        p.validate()?;
        let (lo, hi) = self.g_range();
        if p.g < lo || p.g > hi {
            return Err(ParamError { param: Param::G, value: p.g });
        }
        Ok(())
    }
    /// `A` at `p`, or which parameter is out of this model's domain.
    fn eval(&self, p: Point) -> Result<f64, ParamError> {
        self.check(&p)?;
        Ok(self.eval_unchecked(p))
    }
}

/// The high-precision reference quadrature (≤ 1e-12 relative).
#[derive(Debug, Clone, Copy, Default)]
pub struct Reference;

impl Model for Reference {
    fn name(&self) -> &'static str {
        "reference"
    }
    fn summary(&self) -> &'static str {
        "adaptive Gauss–Kronrod quadrature of the exact integral, f64, ≤ 1e-12 relative"
    }
    /// The open interval (−1, 1): every Henyey–Greenstein medium.
    fn g_range(&self) -> (f64, f64) {
        (-1.0, 1.0)
    }
    fn g_range_label(&self) -> String {
        "(-1, 1)".into()
    }
    fn check(&self, p: &Point) -> Result<(), ParamError> {
        p.validate()
    }
    fn eval_unchecked(&self, p: Point) -> f64 {
        reference::airlight(p).expect("point validated by Model::check")
    }
}

/// Every model, in the order tables list them.
pub fn all() -> Vec<&'static dyn Model> {
    vec![&Reference]
}

/// A `--model` name that matches no model.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownModel(pub String);

impl fmt::Display for UnknownModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = all().iter().map(|m| m.name()).collect();
        write!(f, "unknown model '{}'; known models: {}", self.0, names.join(", "))
    }
}

impl std::error::Error for UnknownModel {}

/// The model called `name`.
pub fn by_name(name: &str) -> Result<&'static dyn Model, UnknownModel> {
    all().into_iter().find(|m| m.name() == name).ok_or_else(|| UnknownModel(name.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup() {
        assert_eq!(by_name("reference").unwrap().name(), "reference");
        let e = by_name("nope").err().unwrap().to_string();
        assert_eq!(e, "unknown model 'nope'; known models: reference");
    }
}

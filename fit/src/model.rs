//! Models: complete evaluators of `A(τ, γ, ρ; g)`, looked up by name.
//!
//! The reference is built in; fitted models come from their coefficient files
//! (`generated/coefficients/<name>.toml`, see the `coeffs` module) and join a
//! [`Registry`], so `airlight eval --model NAME` and every report see them.

use airlight_truth::reference::{self, Param, ParamError, Point};
use std::fmt;

/// A complete evaluator of the canonical airlight.
pub trait Model: Sync {
    /// Name used on the command line and in file names.
    fn name(&self) -> &str;
    /// One line for tables and help.
    fn summary(&self) -> &str;
    /// The Henyey–Greenstein `g` it supports, `[lo, hi]`; `[0, 0]` is isotropic only.
    fn g_range(&self) -> (f64, f64);
    /// The g range as written in tables: `[lo, hi]`.
    fn g_range_label(&self) -> String {
        let (lo, hi) = self.g_range();
        format!("[{lo}, {hi}]")
    }
    /// `A` at a point that passed [`Model::check`].
    fn eval_unchecked(&self, p: Point) -> f64;
    /// The steps of a uniform ray march (the engines' baseline), which looks the
    /// shadow map up at each of its own steps (docs/MATH.md §8); `None` otherwise.
    fn march_steps(&self) -> Option<usize> {
        None
    }
    /// Whether `p` is in the domain of `A` and in this model's g range.
    fn check(&self, p: &Point) -> Result<(), ParamError> {
        p.validate()?;
        let (lo, hi) = self.g_range();
        if p.g < lo || p.g > hi {
            return Err(ParamError { param: Param::G, value: p.g, allowed: Some((lo, hi)) });
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
    fn name(&self) -> &str {
        "reference"
    }
    fn summary(&self) -> &str {
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

/// A set of models looked up by name: the reference first, then fitted models
/// in the order they were added.
pub struct Registry {
    models: Vec<Box<dyn Model + Send>>,
}

impl Default for Registry {
    fn default() -> Self {
        Registry { models: vec![Box::new(Reference)] }
    }
}

impl Registry {
    /// Adds a model (a later model with the same name is never found).
    pub fn add(&mut self, m: Box<dyn Model + Send>) {
        self.models.push(m);
    }

    /// Every model, in table order.
    pub fn iter(&self) -> impl Iterator<Item = &dyn Model> {
        self.models.iter().map(|m| m.as_ref() as &dyn Model)
    }

    /// The model called `name`.
    pub fn get(&self, name: &str) -> Result<&dyn Model, UnknownModel> {
        self.iter().find(|m| m.name() == name).ok_or_else(|| UnknownModel {
            name: name.to_string(),
            known: self.iter().map(|m| m.name().to_string()).collect(),
        })
    }
}

/// A `--model` name that matches no model.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownModel {
    /// The name asked for.
    pub name: String,
    /// The names that exist.
    pub known: Vec<String>,
}

impl fmt::Display for UnknownModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown model '{}'; known models: {}", self.name, self.known.join(", "))
    }
}

impl std::error::Error for UnknownModel {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup() {
        let r = Registry::default();
        assert_eq!(r.get("reference").unwrap().name(), "reference");
        let e = r.get("nope").err().unwrap().to_string();
        assert_eq!(e, "unknown model 'nope'; known models: reference");
    }
}

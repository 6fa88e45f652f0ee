//! Fitted models: complete evaluators of `A(τ, γ, ρ; g)`. A model is a name, a
//! `g` range and a [`Body`]: the family values it evaluates `A` with (see
//! [`crate::family`], one module per family).

use crate::family::raymarch::RayMarch;
pub use crate::family::split::{PhaseModel, Split};
pub use crate::family::Body;
use crate::family::Variant;
use crate::model::Model;
use airlight_shapes::cost::{Cost, PhaseShape, Shape};
use airlight_truth::reference::Point;

/// A model: what it is called, which `g` it takes, and its families.
#[derive(Debug, Clone, PartialEq)]
pub struct Approximation {
    /// Name on the command line and in file names.
    pub name: String,
    /// One line for tables.
    pub summary: String,
    /// Supported `g`.
    pub g_range: (f64, f64),
    /// The families that evaluate it.
    pub body: Body,
}

impl Approximation {
    /// The forward + backward composition, if that is what this model is.
    pub fn split(&self) -> Option<&Split> {
        Split::of(&self.body)
    }

    /// Operation counts of its general kernel (every part, surfaces, `g` at run
    /// time; no phase code for an isotropic model).
    pub fn ops(&self) -> Cost {
        let phase = if self.g_range == (0.0, 0.0) { PhaseShape::Isotropic } else { self.body.phase_shape() };
        self.body.ops(Shape::general(phase))
    }

    /// The planner's and the report's cost: transcendental calls of [`Approximation::ops`].
    pub fn cost(&self) -> usize {
        self.ops().transcendental()
    }
}

impl Model for Approximation {
    fn name(&self) -> &str {
        &self.name
    }
    fn summary(&self) -> &str {
        &self.summary
    }
    fn g_range(&self) -> (f64, f64) {
        self.g_range
    }
    fn eval_unchecked(&self, p: Point) -> f64 {
        self.body.eval(p)
    }
    fn march_steps(&self) -> Option<usize> {
        RayMarch::of(&self.body).map(|m| m.steps)
    }
}

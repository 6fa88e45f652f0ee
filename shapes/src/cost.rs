//! What one evaluation of a kernel costs, counted once per family: the planner
//! ranks models by it where no bench was run (otherwise by the measured cost),
//! and the plans and the report print it.

use serde::Serialize;

/// Operation counts of one f32 kernel evaluation on its worst path (the
/// canonical entry).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct Cost {
    /// `exp` calls (exprel included).
    pub exp: usize,
    /// `log` calls.
    pub log: usize,
    /// `atan`/`atan2` calls.
    pub atan: usize,
    /// `sqrt` calls.
    pub sqrt: usize,
    /// Divisions.
    pub div: usize,
    /// `sin_cos` calls.
    pub sincos: usize,
}

impl Cost {
    /// In words: `3 exp, 1 log, 0 atan, 2 sqrt, 1 sin_cos, 9 div`.
    pub fn describe(&self) -> String {
        format!(
            "{} exp, {} log, {} atan, {} sqrt, {} sin_cos, {} div",
            self.exp, self.log, self.atan, self.sqrt, self.sincos, self.div
        )
    }

    /// Both paths taken (a sum).
    pub fn add(&self, o: &Cost) -> Cost {
        Cost {
            exp: self.exp + o.exp,
            log: self.log + o.log,
            atan: self.atan + o.atan,
            sqrt: self.sqrt + o.sqrt,
            div: self.div + o.div,
            sincos: self.sincos + o.sincos,
        }
    }

    /// The worse of two alternative paths, count by count.
    pub fn max(&self, o: &Cost) -> Cost {
        Cost {
            exp: self.exp.max(o.exp),
            log: self.log.max(o.log),
            atan: self.atan.max(o.atan),
            sqrt: self.sqrt.max(o.sqrt),
            div: self.div.max(o.div),
            sincos: self.sincos.max(o.sincos),
        }
    }

    /// Transcendental calls in all: the planner's measure of cost.
    pub fn transcendental(&self) -> usize {
        self.exp + self.log + self.atan + self.sqrt + self.sincos
    }
}

/// What a kernel keeps of its model, as far as its cost goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shape {
    /// Phase evaluations per term (0: isotropic, no phase code).
    pub phase: PhaseShape,
    /// Whether the backward part is kept.
    pub backscatter: bool,
    /// Whether rays can end on a surface.
    pub surfaces: bool,
}

/// How a kernel evaluates the phase function.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PhaseShape {
    /// `1/(4π)`: no phase code.
    Isotropic,
    /// `g` fixed or at run time, `terms` exponentials per band.
    Exp {
        /// Terms per band.
        terms: usize,
    },
    /// Henyey–Greenstein evaluated exactly where it is needed (`g` at run time).
    Exact,
}

impl Shape {
    /// A model's general kernel: every part, surfaces, its phase at run time.
    pub fn general(phase: PhaseShape) -> Shape {
        Shape { phase, backscatter: true, surfaces: true }
    }
}

//! `generated/bench.json`: how long the fits take and how fast each model
//! evaluates, measured by `airlight bench` (timings never enter the tests; the
//! report quotes this file, so regenerating stays byte-identical).

use crate::catalog;
use crate::coeffs::ModelFile;
use crate::domains::{Domain, VALIDATION_SEED};
use crate::model::Model;
use crate::reference::Point;
use serde::{Deserialize, Serialize};
use std::hint::black_box;
use std::time::Instant;

/// One model's single-core throughput.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelSpeed {
    /// Model name.
    pub model: String,
    /// Evaluations per second on the thin validation-like set, one core.
    pub thin_per_s: f64,
    /// Same on dense.
    pub dense_per_s: f64,
}

/// Everything `airlight bench` measures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bench {
    /// Cores the fits could use.
    pub cores: usize,
    /// Wall-clock seconds to fit every family.
    pub fit_s: f64,
    /// Wall-clock seconds to assemble and measure every model.
    pub measure_s: f64,
    /// Per-model f64 throughput (the reference first).
    pub models: Vec<ModelSpeed>,
    /// Per-kernel throughput of the generated f32 Rust kernels (`airlight-kernels`).
    #[serde(default)]
    pub kernels: Vec<ModelSpeed>,
}

impl Bench {
    /// The file's text (pretty JSON, trailing newline): deterministic for a value.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serialises") + "\n"
    }
    /// Reads the file's text.
    pub fn from_json(text: &str) -> Result<Bench, String> {
        serde_json::from_str(text).map_err(|e| format!("line {}: {e}", e.line()))
    }
}

fn throughput(model: &dyn Model, domain: Domain) -> f64 {
    throughput_of(|p| model.eval_unchecked(p), model.g_range(), domain)
}

/// Single-core evaluations per second of `eval` on 20,000 points of `domain` with
/// `g` in `g_range` (best of three passes): the same points for every model and
/// kernel, so their figures compare.
pub fn throughput_of<T>(eval: impl Fn(Point) -> T, g_range: (f64, f64), domain: Domain) -> f64 {
    // The reference takes every g in (−1, 1); time it on the public data's range.
    let (lo, hi) = g_range;
    let pts = domain.validation_set((lo.max(-0.9), hi.min(0.95)), 20_000, VALIDATION_SEED ^ 0xBE7C);
    let mut best = 0.0f64;
    for _ in 0..3 {
        let t = Instant::now();
        for &p in &pts {
            black_box(eval(black_box(p)));
        }
        best = best.max(pts.len() as f64 / t.elapsed().as_secs_f64());
    }
    best
}

/// Times the fit and measurement pipeline once and each model's evaluation.
pub fn run(progress: &(dyn Fn(&str) + Sync)) -> Result<(Bench, Vec<ModelFile>), String> {
    progress("fitting");
    let t = Instant::now();
    let fits = catalog::fit(None, &|_, _| {});
    let fit_s = t.elapsed().as_secs_f64();
    progress("measuring");
    let t = Instant::now();
    let files = catalog::build(&fits, &|_, _| {})?;
    let measure_s = t.elapsed().as_secs_f64();
    let mut models = Vec::new();
    let reference = crate::model::Reference;
    let all: Vec<&dyn Model> =
        std::iter::once(&reference as &dyn Model).chain(files.iter().map(|f| &f.model as &dyn Model)).collect();
    for m in all {
        progress(m.name());
        models.push(ModelSpeed {
            model: m.name().to_string(),
            thin_per_s: throughput(m, Domain::Thin),
            dense_per_s: throughput(m, Domain::Dense),
        });
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    Ok((Bench { cores, fit_s, measure_s, models, kernels: Vec::new() }, files))
}

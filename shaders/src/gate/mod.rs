//! The error-bound gate (`airlight check`): every generated kernel, on every
//! target — the Rust f32 kernel on the CPU, the WGSL and the GLSL kernel on the
//! GPU adapter — against the reference on the validation sets of its domains
//! (the points its model's declared bounds were measured on) and on the extreme
//! set of docs/MATH.md §5. A kernel fails when its error exceeds the declared bound
//! plus the f32 allowance ([`Row::limit`]), or when it returns NaN, ∞ or a
//! negative value where `A` is finite.
//!
//! Scene kernels take fewer arguments than their model: their points are the
//! same sets projected onto the scene (`ρ = ∞` without surfaces, `τ = 0` without
//! extinction, a fixed `g`), with the reference recomputed there.

mod cases;
mod spot;
pub(crate) mod subject;

pub use subject::declared_max;
use subject::{declared, f64_model, model_file, Subject};

pub use cases::*;
pub use spot::*;

use crate::{Gpu, GpuError, KernelSource};
use airlight_fit::catalog::{self};
use airlight_fit::model::Model;
pub use airlight_shapes::record::{target_label, F32Bound, EDGE, PHYSICAL, PHYS_EXTREME, SHADOWED, SHADOW_MAP, SPOT};
pub use airlight_shapes::vocab::{
    f32_domain_limit, f32_limit, Target, F32_ADAPTER_ALLOWANCE, F32_ALLOWANCE, F32_RANGE, F32_REL_ALLOWANCE,
};
use airlight_shapes::vocab::{CompiledKernel, Entry, Index, IndexEntry};
use airlight_truth::domains::Domain;
use airlight_truth::reference::Point;
use std::fmt;
use std::path::Path;

/// One kernel × target × domain.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Kernel name.
    pub kernel: String,
    /// Where it ran; `None`: the f64 model (reported, never failing the gate).
    pub target: Option<Target>,
    /// `thin`, `dense`, `extreme` (canonical entry), `physical` or
    /// `phys-extreme` (physical entry).
    pub domain: &'static str,
    /// Points with `A` in f32's range (the error statistics' population).
    pub points: usize,
    /// Largest relative error.
    pub max: f64,
    /// 99th-percentile relative error.
    pub p99: f64,
    /// The declared bound it is held to: the f64 model's for the f64 row, the
    /// kernel's f32 bound for an f32 target ([`Bound`]).
    pub declared: f64,
    /// Where the largest error occurs.
    pub worst: Option<Point>,
    /// NaN, ∞ or negative results where the value is finite (the kernels' `HUGE`
    /// counts as ∞ unless the exact value is beyond f32's checked range).
    pub bad: usize,
    /// The first such point and value.
    pub first_bad: Option<(Point, f64)>,
}

impl Row {
    /// The limit the error must stay within: on `thin` and `dense` an f32 target's
    /// own bound widened only by another adapter's rounding
    /// ([`f32_domain_limit`]); elsewhere (the edge, extreme and physical sets, the
    /// spot and shafts entries, none of which the f32 bound was measured on) the
    /// bound plus the f32 allowance ([`f32_limit`]).
    pub fn limit(&self) -> f64 {
        if self.target.is_some() && (self.domain == Domain::Thin.name() || self.domain == Domain::Dense.name()) {
            f32_domain_limit(self.declared)
        } else {
            f32_limit(self.declared)
        }
    }
    /// Whether this row passes: no bad value and, for an f32 target, the error
    /// within [`Row::limit`]. The f64 rows hold the model's own error and only
    /// need to be free of bad values (their bounds are the fit's business).
    pub fn passes(&self) -> bool {
        self.bad == 0 && (self.target.is_none() || self.max <= self.limit())
    }
}

/// What a set of rows is held to: the f64 model's declared bound (its f64 row)
/// and the kernel's f32 bound (its f32 targets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// The model's declared bound.
    pub model: f64,
    /// The kernel's f32 bound.
    pub f32: f64,
}

impl Bound {
    /// The bound of a row on `target`.
    pub fn on(self, target: Option<Target>) -> f64 {
        if target.is_some() {
            self.f32
        } else {
            self.model
        }
    }

    /// The larger of two, each part.
    pub(crate) fn max(self, o: Bound) -> Bound {
        Bound { model: self.model.max(o.model), f32: self.f32.max(o.f32) }
    }
}

/// Why the gate could not run at all.
#[derive(Debug)]
pub enum GateError {
    /// An input file is missing or malformed (message names it).
    Input(String),
    /// The GPU failed on a kernel (not: produced wrong numbers).
    Gpu(String, GpuError),
}

impl fmt::Display for GateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GateError::Input(m) => write!(f, "{m}"),
            GateError::Gpu(k, e) => write!(f, "{k}: {e}"),
        }
    }
}

impl std::error::Error for GateError {}

/// The kernels to check: every entry of `generated/kernels.toml` (or those named).
pub fn load_index(generated: &Path) -> Result<Index, GateError> {
    Index::load(generated).map_err(|e| GateError::Input(e.to_string()))
}

/// The shader files of `k` under `generated` that a GPU runs (WGSL, GLSL).
pub(crate) fn shader_texts(generated: &Path, k: &IndexEntry) -> Result<Vec<(Target, String)>, GateError> {
    let mut texts = Vec::new();
    for target in Target::ALL.into_iter().filter(|t| t.is_shader()) {
        if let Some(f) = k.file(target) {
            let path = generated.join(f);
            let text = std::fs::read_to_string(&path)
                .map_err(|e| GateError::Input(format!("{}: cannot read: {e}", path.display())))?;
            texts.push((target, text));
        }
    }
    Ok(texts)
}

/// The kernels of the index the gate runs (all, or those in `only`).
pub(crate) fn selected<'i>(
    index: &'i Index,
    only: &[String],
    generated: &Path,
) -> Result<Vec<&'i IndexEntry>, GateError> {
    if let Some(missing) = only.iter().find(|n| !index.kernel.iter().any(|k| &&k.name == n)) {
        return Err(GateError::Input(format!("no kernel '{missing}' in {}/kernels.toml", generated.display())));
    }
    Ok(index.kernel.iter().filter(|k| only.is_empty() || only.iter().any(|n| n == &k.name)).collect())
}

/// Runs the gate over the kernels under `generated` (all, or those in `only`):
/// the compiled Rust kernels in `rust` (they must be the ones under `generated`;
/// empty: the Rust target is not checked), the WGSL and GLSL files when `gpu` is
/// given, each f32 target held to the f32 bound `kernels.toml` declares.
/// `progress` gets a line per step.
pub fn run(
    generated: &Path,
    gpu: Option<&Gpu>,
    rust: &[CompiledKernel],
    only: &[String],
    progress: &dyn Fn(&str),
) -> Result<Vec<Row>, GateError> {
    Ok(run_with(generated, gpu, rust, only, false, progress)?.0)
}

/// [`run`], but measuring each kernel's f32 bounds first ([`F32Bound`]: what
/// `airlight check --record` writes) and holding the f32 targets to those.
pub fn run_measuring(
    generated: &Path,
    gpu: Option<&Gpu>,
    rust: &[CompiledKernel],
    only: &[String],
    progress: &dyn Fn(&str),
) -> Result<(Vec<Row>, Vec<F32Bound>), GateError> {
    run_with(generated, gpu, rust, only, true, progress)
}

pub(crate) fn run_with(
    generated: &Path,
    gpu: Option<&Gpu>,
    rust: &[CompiledKernel],
    only: &[String],
    measuring: bool,
    progress: &dyn Fn(&str),
) -> Result<(Vec<Row>, Vec<F32Bound>), GateError> {
    let index = load_index(generated)?;
    let models = catalog::load(&generated.join("coefficients")).map_err(|e| GateError::Input(e.to_string()))?;
    let kernels = selected(&index, only, generated)?;
    let mut ranges: Vec<(f64, f64)> = kernels.iter().filter(|k| k.scene.is_none()).map(|k| (k.g[0], k.g[1])).collect();
    ranges.sort_by(|a, b| a.partial_cmp(b).expect("no NaN"));
    ranges.dedup();
    progress("reference values on the validation sets");
    let validations = catalog::validations(&ranges, &|_, _| {});
    let walk = crate::shafts::WalkTexts::load(generated).map_err(|e| GateError::Input(e.to_string()))?;
    let (mut rows, mut bounds) = (Vec::new(), Vec::new());
    for k in kernels {
        progress(&k.name);
        let texts = shader_texts(generated, k)?;
        let table = crate::load_table(generated, k).map_err(|e| GateError::Input(e.to_string()))?;
        let compiled = match (rust.is_empty(), &k.rust) {
            (false, Some(_)) => Some(rust.iter().find(|r| r.name == k.name).ok_or_else(|| {
                GateError::Input(format!("kernel {} is not in the compiled airlight-kernels (rebuild)", k.name))
            })?),
            _ => None,
        };
        let subject = Subject {
            k,
            model: f64_model(k, &models)?,
            compiled,
            shaders: texts
                .iter()
                .map(|(t, text)| (*t, KernelSource::of(k, *t, text).with_table(table.as_ref())))
                .collect(),
            gpu,
            walk: walk.sources(),
            marches: model_file(k, &models)?.is_some_and(|m| m.model.march_steps().is_some()),
        };
        let sets = point_sets(k, &validations)?;
        // Each domain's bound: the model's, and the kernel's f32 bound (on the
        // extreme set, which it is not measured on, the model's).
        let mut domain_bounds = Vec::new();
        for d in Domain::ALL.into_iter().filter(|d| k.domains.contains(d) || *d == Domain::Extreme) {
            let model = declared(k, &models, d)?;
            let f32 = match (d, measuring) {
                (Domain::Extreme, _) | (_, true) => model,
                (d, false) => k.f32_bound(d).ok_or_else(|| {
                    let path = generated.join(airlight_shapes::vocab::INDEX_FILE);
                    let text = std::fs::read_to_string(&path).unwrap_or_default();
                    let n = index.kernel.iter().position(|e| e.name == k.name).unwrap_or(0);
                    let line = airlight_truth::tomlfile::locate_nth(&text, "kernel", n, &format!("f32_{d}_max_rel"));
                    GateError::Input(format!(
                        "{}:{line}: kernel {}: no f32_{d}_max_rel (its f32 bound on {d}): the gate record does not \
                         cover these kernel sources; run `airlight check --record`, then `airlight generate`",
                        path.display(),
                        k.name
                    ))
                })?,
            };
            domain_bounds.push((d, Bound { model, f32 }));
        }
        let bound_of = |d: Domain, b: &[(Domain, Bound)]| b.iter().find(|x| x.0 == d).map(|x| x.1);
        let mut canonical = Vec::new();
        for (d, pts) in &sets {
            let b = bound_of(*d, &domain_bounds).expect("one bound per checked domain");
            canonical.extend(subject.point_rows(d.name(), pts, b)?);
        }
        if measuring {
            let found = subject.f32_bounds(&sets, &canonical, &validations, &domain_bounds)?;
            for b in &found {
                if let Some(x) = domain_bounds.iter_mut().find(|x| x.0.name() == b.domain) {
                    x.1.f32 = b.max_rel;
                }
                for r in canonical.iter_mut().filter(|r| r.target.is_some() && r.domain == b.domain) {
                    r.declared = b.max_rel;
                }
            }
            bounds.extend(found);
        }
        rows.extend(canonical);
        let zero = Bound { model: 0.0, f32: 0.0 };
        let sampled = k.domains.iter().filter_map(|&d| bound_of(d, &domain_bounds)).fold(zero, Bound::max);
        let hull = sampled.max(bound_of(Domain::Extreme, &domain_bounds).unwrap_or(zero));
        rows.extend(subject.edge_rows(hull)?);
        rows.extend(subject.physical_rows(sampled, hull)?);
        if k.has(Entry::Spot) {
            rows.extend(subject.spot_rows(sampled)?);
        }
        // The march looks visibility up at its own steps: its error is not the
        // family's bound (docs/MATH.md §8), so it has no shadowed rows.
        if k.shafts && !subject.marches {
            rows.extend(subject.shadowed_rows(hull)?);
            rows.extend(subject.mapped_rows(hull)?);
        }
    }
    Ok((rows, bounds))
}

/// The gate's rows as `generated/gate.toml` holds them, tied by digest to the
/// kernel sources under `generated` that were measured.
pub fn record(
    generated: &Path,
    rows: &[Row],
    f32_bounds: Vec<F32Bound>,
    adapter: String,
) -> Result<airlight_shapes::record::GateRecord, String> {
    let mut files = Vec::new();
    for dir in ["wgsl", "wgsl/bevy", "glsl", "airlight-kernels/src"] {
        let entries = std::fs::read_dir(generated.join(dir))
            .map_err(|e| format!("{}: cannot read: {e}", generated.join(dir).display()))?;
        for e in entries.flatten() {
            if e.path().is_file() {
                let bytes =
                    std::fs::read(e.path()).map_err(|err| format!("{}: cannot read: {err}", e.path().display()))?;
                files.push((format!("{dir}/{}", e.file_name().to_string_lossy()), bytes));
            }
        }
    }
    Ok(airlight_shapes::record::GateRecord {
        adapter,
        kernels_digest: airlight_shapes::record::digest(&files),
        rows: rows
            .iter()
            .map(|r| airlight_shapes::record::GateRow {
                kernel: r.kernel.clone(),
                target: target_label(r.target).to_string(),
                domain: r.domain.to_string(),
                points: r.points,
                max_rel: r.max,
                p99_rel: r.p99,
                limit: r.limit(),
                bad: r.bad,
            })
            .collect(),
        f32_bounds,
    })
}

/// The line `airlight check` prints after its rows: kernels, targets, rows, the
/// limit, and how much of the f32 allowance the worst row uses (negative: within
/// the f64 bound).
pub fn summary(rows: &[Row]) -> String {
    let kernels: std::collections::BTreeSet<&str> = rows.iter().map(|r| r.kernel.as_str()).collect();
    let targets: std::collections::BTreeSet<&str> = rows.iter().map(|r| target_label(r.target)).collect();
    let worst = rows
        .iter()
        .filter(|r| r.target.is_some())
        .map(|r| (r.max - r.declared) / (r.limit() - r.declared))
        .fold(f64::NEG_INFINITY, f64::max);
    format!(
        "check: {} kernels × {{{}}} × domains = {} rows; f32 targets on thin and dense: limit = f32 bound × (1 + {:.0e}) + {:.1e}, elsewhere = bound × (1 + {:.0e}) + {:.0e}; the worst row uses {:.1}% of its allowance",
        kernels.len(),
        targets.into_iter().collect::<Vec<_>>().join(", "),
        rows.len(),
        F32_REL_ALLOWANCE,
        F32_ADAPTER_ALLOWANCE,
        F32_REL_ALLOWANCE,
        F32_ALLOWANCE,
        100.0 * worst
    )
}

/// The table `airlight check` prints: every row, or only failures.
pub fn table(rows: &[Row], failures_only: bool) -> String {
    let mut out = format!(
        "{:<20} {:<8} {:<8} {:>6} {:>9} {:>9} {:>9}  {:<6} worst point\n",
        "kernel", "target", "domain", "points", "max", "p99", "limit", "status"
    );
    for r in rows.iter().filter(|r| !failures_only || !r.passes()) {
        let worst = match (&r.first_bad, &r.worst) {
            (Some((p, v)), _) => format!("{} bad value(s), first {v} at {}", r.bad, fmt_point(p)),
            (None, Some(p)) => fmt_point(p),
            (None, None) => "—".into(),
        };
        out.push_str(&format!(
            "{:<20} {:<8} {:<8} {:>6} {:>9.2e} {:>9.2e} {:>9.2e}  {:<6} {worst}\n",
            r.kernel,
            target_label(r.target),
            r.domain,
            r.points,
            r.max,
            r.p99,
            r.limit(),
            if r.passes() { "ok" } else { "FAIL" }
        ));
    }
    out
}

pub(crate) fn fmt_point(p: &Point) -> String {
    format!(
        "(τ {:.6}, γ {:.6}, ρ {}, g {:.4})",
        p.tau,
        p.gamma,
        if p.rho.is_infinite() { "∞".into() } else { format!("{:.6}", p.rho) },
        p.g
    )
}

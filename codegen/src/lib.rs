//! airlight-codegen: everything under `generated/` is rendered here, from tera
//! templates and data computed in Rust, and written (or checked) as one set of
//! outputs.
//!
//! Templates are compiled into the binary (`include_str!`), so the generator
//! works from any directory; each text output names its source (template or
//! fitter) in its header.
//!
//! The generator names no family: a kernel's core template and what it is
//! given, a report section and a figure all come from the kernel's family
//! through `airlight_fit::family`; what is here is shared by every family (the
//! kernel templates with the entry points, the output table, the report's
//! frame, the drawing).

#![warn(missing_docs)]

pub mod front;
pub mod kernel;
pub mod output;
pub mod plots;
pub mod report;
pub mod scene;
pub mod translate;

pub use output::{write_all, Difference, Output};

use airlight_fit::coeffs::{self, ModelFile};
use airlight_shapes::bench::Bench;
use airlight_truth::selfcheck::SelfCheck;
use std::fmt;

/// Why rendering failed.
#[derive(Debug)]
pub enum RenderError {
    /// A template failed.
    Template(tera::Error),
    /// A figure failed.
    Plot(plots::PlotError),
    /// A scene has no plan (the error names file, line and field).
    Scene(scene::SceneError),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::Template(e) => {
                write!(f, "template: {e}")?;
                // tera keeps the cause (file, line, what) in the source chain
                let mut cause = std::error::Error::source(e);
                while let Some(c) = cause {
                    write!(f, ": {c}")?;
                    cause = c.source();
                }
                Ok(())
            }
            RenderError::Plot(e) => write!(f, "{e}"),
            RenderError::Scene(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RenderError {}

/// The files under `generated/render/` (written by `airlight render --report`), as
/// outputs to pass through; none if the directory does not exist.
pub fn read_renders(generated: &std::path::Path) -> std::io::Result<Vec<Output>> {
    let dir = generated.join("render");
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut paths: Vec<_> = std::fs::read_dir(&dir)?.flatten().map(|e| e.path()).filter(|p| p.is_file()).collect();
    paths.sort();
    paths
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap_or_default().to_string_lossy().into_owned();
            Ok(Output { path: format!("render/{name}"), contents: std::fs::read(&p)? })
        })
        .collect()
}

/// `generated/selfcheck.toml`, the figures `airlight regenerate` measured (passed
/// through by `generate`, which never reruns the self-check).
pub fn read_selfcheck(generated: &std::path::Path) -> Result<SelfCheck, airlight_truth::tomlfile::FieldError> {
    let path = generated.join(airlight_truth::selfcheck::FILE);
    let (name, text) = airlight_truth::tomlfile::read(&path, " (run `airlight regenerate`)")?;
    SelfCheck::from_toml(&name, &text)
}

/// The files under `generated/` that other commands write and the generator only
/// reads (each absent until first written): `bench.json` (`airlight bench`),
/// `gate.toml` (`airlight check --record`), `fuzz.toml` (`fuzz/run`) and the folder
/// `render/` (`airlight render --report`). They are not in the table of outputs, so
/// `generate` never writes them and `--check` does not take them for orphans.
pub const RECORDED: [&str; 4] =
    [airlight_shapes::bench::FILE, airlight_shapes::record::FILE, airlight_shapes::record::FUZZ_FILE, "render/"];

/// Whether `rel` (a path under `generated/`, `/`-separated) is one of [`RECORDED`].
pub fn is_recorded(rel: &str) -> bool {
    RECORDED.iter().any(|r| if r.ends_with('/') { rel.starts_with(r) } else { rel == *r })
}

/// What other commands measured on some machine, read for the planner and the
/// report to quote ([`RECORDED`]).
#[derive(Debug, Clone, Default)]
pub struct Recorded {
    /// `generated/bench.json`.
    pub bench: Option<Bench>,
    /// `generated/gate.toml`.
    pub gate: Option<airlight_shapes::record::GateRecord>,
    /// `generated/fuzz.toml`.
    pub fuzz: Option<airlight_shapes::record::FuzzRecord>,
}

/// Reads [`Recorded`] from `generated`: a missing file is `None`, a damaged one
/// an error naming it (and its line).
pub fn read_recorded(generated: &std::path::Path) -> Result<Recorded, String> {
    let text = |name: &str| {
        let path = generated.join(name);
        std::fs::read_to_string(&path).ok().map(|t| (path.display().to_string(), t))
    };
    Ok(Recorded {
        bench: text(airlight_shapes::bench::FILE)
            .map(|(path, t)| Bench::from_json(&t).map_err(|e| format!("{path}:{e}")))
            .transpose()?,
        gate: text(airlight_shapes::record::FILE)
            .map(|(path, t)| airlight_shapes::record::GateRecord::from_toml(&path, &t).map_err(|e| e.to_string()))
            .transpose()?,
        fuzz: text(airlight_shapes::record::FUZZ_FILE)
            .map(|(path, t)| airlight_shapes::record::FuzzRecord::from_toml(&path, &t).map_err(|e| e.to_string()))
            .transpose()?,
    })
}

/// Every file under `generated/`, rendered from the reference self-check and the
/// coefficient files (which are re-rendered too, so a hand edit shows as stale).
/// This list is the generator's table of outputs: a file not in it is orphaned.
///
/// `recorded` holds the measurements other commands wrote ([`read_recorded`]): the
/// planner and the report read them; they are inputs ([`RECORDED`]), never outputs.
/// `scenes` are the scene files (`codegen/scenes/`); each gets its own kernels and plan.
/// `renders` are the files `airlight render --report` wrote under `generated/render/`
/// (a GPU's output, like `bench.json`: an input the report quotes).
pub fn render_all(
    check: &SelfCheck,
    models: &[ModelFile],
    recorded: &Recorded,
    scenes: &[scene::Scene],
    renders: &[Output],
) -> Result<Vec<Output>, RenderError> {
    let mut specs: Vec<kernel::KernelSpec> = models.iter().map(kernel::KernelSpec::for_model).collect();
    let mut plans = Vec::new();
    for s in scenes {
        let (_, spec, plan_file) = plan_scene(s, models, recorded.bench.as_ref())?;
        plans.push(plan_file);
        specs.push(spec);
    }
    let (bench, record, fuzz) = (recorded.bench.as_ref(), recorded.gate.as_ref(), recorded.fuzz.as_ref());
    for spec in specs.iter_mut().filter(|s| s.scene.is_none()) {
        spec.measured = bench.and_then(|b| b.models.iter().find(|m| m.name == spec.name)).map(|m| kernel::Measured {
            cpu_ns: m.cpu_ns_per_eval,
            gpu_ns: (m.gpu_frame_evals_per_s > 0.0).then(|| 1e9 / m.gpu_frame_evals_per_s),
        });
    }
    let mut kernels = kernel::render(&specs).map_err(RenderError::Template)?;
    // Whether the recorded gate measured these kernels.
    let current = record.map(|r| {
        let files: Vec<(String, Vec<u8>)> = kernels.iter().map(|o| (o.path.clone(), o.contents.clone())).collect();
        airlight_shapes::record::digest(&files) == r.kernels_digest
    });
    // The f32 bounds it measured on them: into the registries (kernels.toml, the
    // crate's `KERNELS`), which are not kernel sources.
    if let (Some(r), Some(true)) = (record, current) {
        for spec in &mut specs {
            spec.f32 = spec.domains.iter().filter_map(|&d| r.f32_bound(&spec.name, d).map(|e| (d, e))).collect();
        }
        let registry = kernel::render_crate(&specs).map_err(RenderError::Template)?;
        for o in registry {
            if let Some(slot) = kernels.iter_mut().find(|k| k.path == o.path) {
                *slot = o;
            }
        }
    }
    let gate = record.zip(current);
    let ir = report::kernel_ir(&specs, &kernels).map_err(RenderError::Template)?;
    let mut out =
        vec![report::render(check, models, bench, gate, fuzz, &specs, &ir, renders).map_err(RenderError::Template)?];
    out.push(Output::text(airlight_truth::selfcheck::FILE, check.to_toml()));
    if let Some(b) = bench {
        out.extend(plots::pareto(b).map_err(RenderError::Plot)?);
    }
    for m in models {
        out.push(Output::text(format!("coefficients/{}.toml", m.model.name), coeffs::render(m)));
    }
    out.extend(plots::render(models).map_err(RenderError::Plot)?);
    out.extend(plans);
    out.extend(kernels);
    out.push(kernel::render_index(&specs));
    Ok(out)
}

/// A scene's plan, its kernel's spec and the plan's file (`plans/<kernel>.md`):
/// the planner's pick among `models` by `bench`'s measured costs.
fn plan_scene(
    s: &scene::Scene,
    models: &[ModelFile],
    bench: Option<&Bench>,
) -> Result<(scene::Plan, kernel::KernelSpec, Output), RenderError> {
    let plan = scene::plan(s, models, bench).map_err(|e| RenderError::Scene(s.plan_error(&e)))?;
    let spec = kernel::KernelSpec::for_scene(s, &plan, models, &s.file);
    let file = kernel::render_plan(s, &plan, &spec).map_err(RenderError::Template)?;
    Ok((plan, spec, file))
}

/// One scene planned and its kernel rendered, in memory, from a scene file
/// anywhere: what `generate` writes for a scene of `codegen/scenes/`, byte for
/// byte (the scene's `file` as shown is the only input that names a path).
#[derive(Debug, Clone)]
pub struct SceneKernel {
    /// The plan: every candidate with its bound and cost, and the pick.
    pub plan: scene::Plan,
    /// The plan as `generate` writes it (`plans/<kernel>.md`).
    pub plan_file: Output,
    /// The kernel's files, paths as under `generated/`: its source per target
    /// and their translations (HLSL, MSL, the Bevy module); for a scene with
    /// shadows, the shadow-map walk and pyramid passes it is used with; a
    /// table-driven model's table.
    pub files: Vec<Output>,
    /// Its entry in an index (`kernels.toml`'s shape): what the GPU harness
    /// and `render` need to call it.
    pub index: airlight_shapes::vocab::IndexEntry,
}

/// Plans `s` (a parsed scene file) among `models` by the measured costs of
/// `recorded`'s bench and renders its kernel ([`SceneKernel`]).
pub fn scene_kernel(s: &scene::Scene, models: &[ModelFile], recorded: &Recorded) -> Result<SceneKernel, RenderError> {
    let (plan, spec, plan_file) = plan_scene(s, models, recorded.bench.as_ref())?;
    let shared: Vec<String> = kernel::OutputTable::standard().shared_file.iter().map(|f| f.path.clone()).collect();
    let files = kernel::render_sources(std::slice::from_ref(&spec))
        .map_err(RenderError::Template)?
        .into_iter()
        .filter(|o| s.shadows || !shared.contains(&o.path))
        .collect();
    Ok(SceneKernel { plan, plan_file, files, index: kernel::index_entry_of(&spec) })
}

/// Compares every output with the file under `generated`, and lists the files
/// there that no output produces and no other command records ([`RECORDED`]);
/// empty when all match.
pub fn check(generated: &std::path::Path, outputs: &[Output]) -> Vec<Difference> {
    output::check(generated, outputs)
        .into_iter()
        .filter(|d| match d {
            Difference::Orphaned(p) => {
                let rel = p.strip_prefix(generated).unwrap_or(p).to_string_lossy().replace('\\', "/");
                !is_recorded(&rel)
            }
            _ => true,
        })
        .collect()
}

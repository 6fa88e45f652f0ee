//! The `airlight` command line, shared by its two binaries: a thin layer over the
//! airlight libraries that parses arguments, calls them, prints, and sets the exit
//! code: 0 on success, 2 for bad input (a one-line message naming file, line and
//! column), 1 when a check fails or a file cannot be written.
//!
//! - `airlight` (`src/main.rs`) does not link the generated Rust kernels, so it
//!   builds and runs (`generate` repairs them) however broken they are. The
//!   commands that run compiled Rust kernels — `eval --precision f32`, `check`,
//!   `render`, `bench` and the gate that ends `regenerate` — it hands to
//! - `airlight-run` (`run/`, the crate that links `airlight-kernels`), which it
//!   builds first through cargo: when the kernels do not compile, that is one
//!   line naming the first error, and exit 1.

use airlight_fit::catalog;
use airlight_fit::family::Fits;
use airlight_fit::coeffs::{self, ModelFile};
use airlight_fit::model;
use airlight_fit::vocab::{CompiledKernel, Domain, Target};
use airlight_fit::{points_csv, selfcheck};
use airlight_shaders::gate;
use airlight_shaders::{Gpu, KernelSource};
use clap::{Parser, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "airlight",
    version,
    about = "Fast, measured single-scattering glow (airlight) around point lights in fog, smoke, haze and water",
    long_about = "airlight computes the light a point light scatters into a view ray through a homogeneous \
participating medium (fog, smoke, haze, water), in the canonical form A(tau, gamma, rho; g) of MATH.md:\n\n  \
radiance = sigma_s * I / D * A(tau, gamma, rho; g)\n\n  \
tau   = sigma_t * D, the optical distance from the viewer to the light (D = viewer-light distance)\n  \
gamma = angle between the view ray and the direction to the light, radians in [0, pi]\n  \
rho   = distance to the first surface along the ray divided by D (inf: no surface)\n  \
g     = Henyey-Greenstein asymmetry in (-1, 1); 0 is isotropic scattering\n\n\
It fits fast approximations against a high-precision reference and reports their measured error.",
    after_help = "Exit status: 0 on success; 2 for bad input or usage (a one-line message naming the file, \
line and field or column; nothing is written); 1 when a check fails, a file cannot be written or the GPU fails."
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Arithmetic of `eval`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Precision {
    /// The f64 model.
    F64,
    /// The generated f32 Rust kernel.
    F32,
}

/// Which entry point `eval` feeds.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum EvalEntry {
    /// The canonical `A(tau, gamma, rho; g)`: columns tau,gamma,rho,g.
    #[value(alias = "canonical")]
    Airlight,
    /// The physical entry, radiance = sigma_s * I / D * A: columns
    /// ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g.
    Radiance,
    /// The spot entry, RGB radiance from a spot light (cos_outer = -1: a point
    /// light) in an RGB medium: columns ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,ax,ay,az,
    /// cos_outer,cos_inner,intensity,sigma_t_r,sigma_t_g,sigma_t_b,sigma_s_r,
    /// sigma_s_g,sigma_s_b,g; output columns r,g_out,b.
    Spot,
}

/// Where `eval` runs: `cpu`, or a generated shader's language.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct EvalTarget(Option<Target>);

impl std::str::FromStr for EvalTarget {
    type Err = String;
    fn from_str(s: &str) -> Result<EvalTarget, String> {
        if s == "cpu" {
            return Ok(EvalTarget(None));
        }
        match s.parse::<Target>() {
            Ok(t) if t.is_shader() => Ok(EvalTarget(Some(t))),
            _ => {
                let shaders: Vec<&str> = Target::ALL.iter().filter(|t| t.is_shader()).map(|t| t.name()).collect();
                Err(format!("'{s}' is not cpu or a shading language ({})", shaders.join(", ")))
            }
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Evaluate a model at the points of a CSV file.
    ///
    /// The input has a header with the columns tau,gamma,rho,g (any order; other
    /// columns are ignored) and one point per line; rho may be `inf`. The output
    /// repeats those four columns and adds `airlight`, the value of A printed so
    /// that it reads back as the same f64 (`inf` when the ray passes through the
    /// light). Nothing is written unless every line is valid.
    ///
    /// With --entry radiance the input is rays instead, columns
    /// ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g (surface
    /// negative or inf: none), and the output adds `radiance` = sigma_s * I / D * A
    /// (f64: `inf` where A diverges, the light on the ray ahead or at the viewer;
    /// a generated f32 kernel's value as it returns it: the largest finite f32,
    /// 3.4028234663852886e38, where A diverges or the radiance passes f32's range).
    Eval {
        /// Model to evaluate; `airlight models` lists them.
        #[arg(long, default_value = "reference")]
        model: String,
        /// CSV file of points.
        #[arg(long, short)]
        input: PathBuf,
        /// Where to write the result: replaced atomically (a symbolic link is written
        /// through, its target keeps its permissions; a directory, FIFO or device is
        /// refused); `-` or omitted: standard output.
        #[arg(long, short)]
        output: Option<PathBuf>,
        /// f64: the model as fitted (fit/); f32: the generated Rust kernel of the
        /// same name (generated/airlight-kernels/, as compiled into this binary;
        /// scene kernels `scene-<name>` too).
        #[arg(long, value_enum, default_value_t = Precision::F64)]
        precision: Precision,
        /// cpu, or a generated shader kernel evaluated on the GPU adapter: wgsl, or
        /// glsl (GLSL 4.50 compute through wgpu); f32, `--precision` is then
        /// ignored. Prints the adapter on standard error.
        #[arg(long, default_value = "cpu")]
        target: EvalTarget,
        /// airlight: the canonical entry (points); radiance: the physical entry
        /// (rays; a file whose header names cos_outer goes to the spot entry);
        /// spot: the spot entry (spot rays, RGB).
        #[arg(long, value_enum, default_value_t = EvalEntry::Airlight)]
        entry: EvalEntry,
        /// Repository root (the directory holding generated/coefficients/); found
        /// from the current directory if omitted. Only the reference works without it.
        #[arg(long)]
        root: Option<PathBuf>,
    },
    /// List the models: g range and measured max / 99th-percentile relative error
    /// on the thin and dense domains (from generated/coefficients/).
    Models {
        /// Repository root; found from the current directory if omitted.
        #[arg(long)]
        root: Option<PathBuf>,
    },
    /// Fit the approximation families against the reference and write the
    /// coefficient files (generated/coefficients/*.toml) with their measured errors.
    ///
    /// With --family, fit only that family and print its figures; nothing is
    /// written (a model needs all of its families).
    Fit {
        /// The family part to fit: segments, phase or backscatter (the split
        /// family's parts) or phi.
        #[arg(long)]
        family: Option<String>,
        /// Repository root; found from the current directory if omitted.
        #[arg(long)]
        root: Option<PathBuf>,
    },
    /// Render everything under generated/ from the measurements, or with --check
    /// compare it with what is committed.
    ///
    /// --check writes nothing; it fails naming every file that is missing, differs
    /// or is orphaned (present under generated/ but not produced).
    Generate {
        /// Compare instead of writing; exit 1 on any difference.
        #[arg(long)]
        check: bool,
        /// Repository root (the directory holding generated/); found from the
        /// current directory if omitted.
        #[arg(long)]
        root: Option<PathBuf>,
    },
    /// The speed/accuracy trade: every model's f32 kernel (airlight's and the
    /// baselines) on the same seeded points — errors per g against the reference,
    /// CPU ns/eval (thread CPU time), naga IR operations, GPU throughput; writes
    /// generated/bench.json, which REPORT.md quotes (timings never enter
    /// `regenerate`'s own output).
    Bench {
        /// Points per (g, domain) for the errors.
        #[arg(long, default_value_t = airlight_fit::bench::ERROR_POINTS)]
        points: usize,
        /// Points in the timing batch.
        #[arg(long, default_value_t = airlight_fit::bench::COST_BATCH)]
        batch: usize,
        /// Interleaved timing repeats (the median is quoted).
        #[arg(long, default_value_t = airlight_fit::bench::REPEATS)]
        repeats: usize,
        /// Where to write the JSON (default generated/bench.json).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Repository root; found from the current directory if omitted.
        #[arg(long)]
        root: Option<PathBuf>,
    },
    /// The error-bound gate: every generated kernel on every target (the Rust
    /// f32 kernels on the CPU, WGSL and GLSL on the GPU adapter) against the
    /// reference on the validation sets of its domains and on the extreme set.
    /// Fails (exit 1, a table of the failures) if any error exceeds the declared
    /// bound plus the f32 allowance, or any value is NaN, infinite or negative
    /// where A is finite. Prints the adapter; without one the GPU targets are
    /// SKIPPED, unless --require-gpu or AIRLIGHT_REQUIRE_GPU=1 makes that a failure.
    Check {
        /// Fail when no GPU adapter can be opened.
        #[arg(long)]
        require_gpu: bool,
        /// Check only this kernel (repeatable); all kernels by default.
        #[arg(long)]
        kernel: Vec<String>,
        /// Print every row, not just the summary and failures.
        #[arg(long)]
        all: bool,
        /// Also write every row, with the adapter, to generated/gate.toml, which
        /// REPORT.md quotes after `airlight generate` (all kernels only; not done by
        /// `regenerate`, whose output must not depend on the machine's GPU).
        #[arg(long)]
        record: bool,
        /// Repository root (the directory holding generated/); found from the
        /// current directory if omitted.
        #[arg(long)]
        root: Option<PathBuf>,
    },
    /// Render a scene's point lights in fog headlessly: a full-screen fragment
    /// pass that includes the scene's generated WGSL kernel, three panels of
    /// increasing σt. Also renders the same image with the Rust kernel on the CPU
    /// and with the reference, and a relative-difference image; prints the max
    /// and mean relative errors. Writes OUT (GPU), OUT-rust.png, OUT-reference.png
    /// and OUT-diff.png; with --report, into generated/render/ for REPORT.md.
    Render {
        /// The scene file (codegen/scenes/<name>.toml); its kernels must be generated.
        #[arg(long)]
        scene: PathBuf,
        /// The GPU image (PNG); the others are written next to it.
        #[arg(long, short)]
        output: Option<PathBuf>,
        /// Write into generated/render/ (quoted by REPORT.md after `airlight generate`).
        #[arg(long)]
        report: bool,
        /// Width of each of the three panels, pixels.
        #[arg(long, default_value_t = 320)]
        width: u32,
        /// Height, pixels.
        #[arg(long, default_value_t = 240)]
        height: u32,
        /// Repository root (the directory holding generated/); found from the
        /// current directory if omitted.
        #[arg(long)]
        root: Option<PathBuf>,
    },
    /// The main job: fit every family, measure every model, then regenerate
    /// everything under generated/ (coefficients, kernels, REPORT.md, plots), and
    /// end with the error gate (`airlight check`).
    ///
    /// Deterministic: running it twice writes identical files.
    Regenerate {
        /// Repository root (the directory holding generated/); found from the
        /// current directory if omitted.
        #[arg(long)]
        root: Option<PathBuf>,
    },
}

/// A failure: its exit code and one line for the user (empty: already printed).
pub struct Failure(pub u8, pub String);

fn bad_input(msg: impl std::fmt::Display) -> Failure {
    Failure(2, msg.to_string())
}

/// The compiled Rust kernels a binary has: `Linked` in `airlight-run`, `Elsewhere`
/// in `airlight` (which runs `airlight-run` for the commands that need them).
#[derive(Clone, Copy)]
pub enum Kernels<'a> {
    /// Compiled into this binary.
    Linked(&'a [CompiledKernel]),
    /// Not linked: run `airlight-run`, built from the workspace, instead.
    Elsewhere,
}

/// Parses the command line and runs it; the process's exit code.
pub fn main_with(kernels: Kernels) -> ExitCode {
    let cli = Cli::parse();
    report(run(cli.command, kernels))
}

/// The exit code of a result, its message printed on standard error.
pub fn report(result: Result<(), Failure>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(code, msg)) => {
            if !msg.is_empty() {
                eprintln!("error: {msg}");
            }
            ExitCode::from(code)
        }
    }
}

fn run(command: Command, kernels: Kernels) -> Result<(), Failure> {
    let linked = match kernels {
        Kernels::Linked(k) => Some(k),
        Kernels::Elsewhere => None,
    };
    match command {
        Command::Eval { model, input, output, precision, target, entry, root } => {
            // A rays file with a cone's columns is the spot entry's.
            let rays = match entry {
                EvalEntry::Radiance if names_spot_columns(&input) => EvalEntry::Spot,
                e => e,
            };
            match (target.0, precision, linked) {
                (Some(target), _, _) => eval_gpu(&model, &input, output.as_deref(), target, rays, root),
                (None, Precision::F32, None) => delegate(root, None),
                (None, Precision::F32, Some(k)) => eval(&model, &input, output.as_deref(), Some(k), rays, root),
                (None, Precision::F64, _) => eval(&model, &input, output.as_deref(), None, rays, root),
            }
        }
        Command::Check { root, .. } | Command::Render { root, .. } | Command::Bench { root, .. }
            if linked.is_none() =>
        {
            delegate(root, None)
        }
        Command::Check { require_gpu, kernel, all, record, root } => {
            check(root, require_gpu, &kernel, all, record, linked.unwrap_or_default())
        }
        Command::Render { scene, output, report, width, height, root } => {
            render_scene(&scene, output.as_deref(), report, width, height, root, linked.unwrap_or_default())
        }
        Command::Bench { points, batch, repeats, out, root } => {
            bench(root, linked.unwrap_or_default(), BenchSize { points, batch, repeats }, out)
        }
        Command::Models { root } => models(root),
        Command::Fit { family, root } => fit(family.as_deref(), root),
        Command::Generate { check, root } => generate(root, check),
        Command::Regenerate { root } => regenerate(root, linked),
    }
}

/// The package whose binary runs compiled Rust kernels.
pub const RUNNER: &str = "airlight-run";

/// Runs this command line (or `args` instead) in `airlight-run`, built first
/// from the workspace this binary was built from (else the one at the root): the
/// commands that need the compiled Rust kernels. A build failure (the generated
/// kernels do not compile) is one line.
fn delegate(root: Option<PathBuf>, args: Option<Vec<String>>) -> Result<(), Failure> {
    let own = Path::new(env!("CARGO_MANIFEST_DIR")).join("../Cargo.toml");
    let manifest = if own.is_file() {
        own
    } else {
        match root {
            Some(r) => r,
            None => find_root()?,
        }
        .join("Cargo.toml")
    };
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let cargo_args = |verb: &str| {
        let mut c = std::process::Command::new(&cargo);
        c.args([verb, "--release", "--quiet", "-p", RUNNER, "--manifest-path"]).arg(&manifest);
        c
    };
    let built = cargo_args("build")
        .arg("--message-format=short")
        .output()
        .map_err(|e| Failure(1, format!("cannot run cargo to build {RUNNER}: {e}")))?;
    if !built.status.success() {
        let stderr = String::from_utf8_lossy(&built.stderr);
        let first = stderr.lines().find(|l| l.contains("error")).unwrap_or("(cargo printed no error)").trim();
        let what = if first.contains("airlight-kernels") {
            "the generated Rust kernels do not compile (`airlight generate` rewrites them from the templates)"
        } else {
            "it does not build"
        };
        return Err(Failure(1, format!("cannot run the compiled Rust kernels ({RUNNER}): {what}: {first}")));
    }
    let args = args.unwrap_or_else(|| std::env::args().skip(1).collect());
    let status = cargo_args("run")
        .arg("--")
        .args(&args)
        .status()
        .map_err(|e| Failure(1, format!("cannot run {RUNNER}: {e}")))?;
    match status.code() {
        Some(0) => Ok(()),
        // It printed its own message.
        Some(code) => Err(Failure(u8::try_from(code).unwrap_or(1), String::new())),
        None => Err(Failure(1, format!("{RUNNER} was killed ({status})"))),
    }
}

/// The reference plus every model in `root/generated/coefficients/` (just the
/// reference when no root is given or found).
fn registry(root: Option<PathBuf>) -> Result<(model::Registry, Vec<ModelFile>), Failure> {
    let mut reg = model::Registry::default();
    let root = match root {
        Some(r) => Some(r),
        None => find_root().ok(),
    };
    let mut files = Vec::new();
    if let Some(root) = root {
        let dir = root.join("generated").join("coefficients");
        if dir.is_dir() {
            files = catalog::load(&dir).map_err(bad_input)?;
            for f in &files {
                reg.add(Box::new(f.model.clone()));
            }
        }
    }
    Ok((reg, files))
}

/// `eval` on the CPU: the f64 model, or the compiled Rust kernel of that name
/// when `kernels` are given.
fn eval(
    model: &str,
    input: &Path,
    output: Option<&Path>,
    kernels: Option<&[CompiledKernel]>,
    entry_kind: EvalEntry,
    root: Option<PathBuf>,
) -> Result<(), Failure> {
    let rays = entry_kind == EvalEntry::Radiance;
    let (reg, _) = registry(root.clone())?;
    let kernel = match kernels {
        None => None,
        Some(ks) => Some(ks.iter().find(|k| k.name == model).ok_or_else(|| {
            let known: Vec<&str> = ks.iter().map(|k| k.name).collect();
            bad_input(format!("no generated f32 kernel '{model}'; kernels: {}", known.join(", ")))
        })?),
    };
    let m = match kernel {
        // A generated kernel checks the points against what it takes (its index entry).
        Some(k) => {
            let index = gate::load_index(&generated_dir(root)?).map_err(|e| bad_input(e.to_string()))?;
            let entry = index.get(model).map_err(bad_input)?;
            if entry_kind == EvalEntry::Spot {
                let f = k.spot.ok_or_else(|| bad_input(format!("kernel '{model}' has no spot entry")))?;
                let rows = read_spots(input, &|r, g| entry.check_ray(r, g))?;
                let values: Vec<[f64; 3]> = rows
                    .iter()
                    .map(|r| {
                        let s = kernel_spot(r);
                        f(
                            s.origin,
                            s.dir,
                            s.surface,
                            s.light,
                            s.axis,
                            s.cos_outer,
                            s.cos_inner,
                            s.intensity,
                            s.sigma_t,
                            s.sigma_s,
                            s.g,
                        )
                        .map(f64::from)
                    })
                    .collect();
                return write_csv(output, &points_csv::render_spots(&rows, &values));
            }
            if rays {
                let rows = read_rays(input, &|r, g| entry.check_ray(r, g))?;
                let values: Vec<f64> = rows.iter().map(|r| f64::from(kernel_ray(r).radiance_of(k))).collect();
                return write_csv(output, &points_csv::render_rays(&rows, &values));
            }
            let rows = read_points(input, &|p| entry.check(p))?;
            let values: Vec<f64> = rows.iter().map(|r| f32_value(k, r.point)).collect();
            return write_csv(output, &points_csv::render(&rows, &values));
        }
        None => reg.get(model).map_err(bad_input)?,
    };
    let g_ok = |_: &airlight_fit::geometry::PhysicalRay, g: f64| {
        m.check(&airlight_fit::reference::Point { tau: 0.0, gamma: 1.0, rho: f64::INFINITY, g })
            .map_err(|e| ("g", e.to_string()))
    };
    if entry_kind == EvalEntry::Spot {
        let rows = read_spots(input, &g_ok)?;
        let values = airlight_fit::parallel::map(&rows, |r| r.radiance(&|p| m.eval_unchecked(p)), &|_, _| {});
        let mut out = Vec::with_capacity(rows.len());
        for (r, v) in rows.iter().zip(values) {
            out.push(v.map_err(|e| bad_input(format!("{}:{}: {e}", input.display(), r.line)))?);
        }
        return write_csv(output, &points_csv::render_spots(&rows, &out));
    }
    if rays {
        // The f64 model's g range, on the ray's g.
        let rows = read_rays(input, &g_ok)?;
        let values = airlight_fit::parallel::map(
            &rows,
            |r| r.ray.radiance(r.g, &|p| m.eval_unchecked(p)).unwrap_or(f64::NAN),
            &|_, _| {},
        );
        if let Some((r, _)) = rows.iter().zip(&values).find(|(_, v)| v.is_nan()) {
            let e = r.ray.radiance(r.g, &|_| 0.0).err().map(|e| e.to_string()).unwrap_or_default();
            return Err(bad_input(format!("{}:{}: {e}", input.display(), r.line)));
        }
        return write_csv(output, &points_csv::render_rays(&rows, &values));
    }
    // The f64 model checks the points (its g range).
    let rows = read_points(input, &|p| m.check(p))?;
    let values = airlight_fit::parallel::map(&rows, |r| m.eval_unchecked(r.point), &|_, _| {});
    write_csv(output, &points_csv::render(&rows, &values))
}

/// The points of an `eval` CSV, each checked by `check` (the f64 model's domain,
/// or what a generated kernel takes).
fn read_points(
    input: &Path,
    check: &dyn Fn(&airlight_fit::reference::Point) -> Result<(), airlight_fit::ParamError>,
) -> Result<Vec<points_csv::Row>, Failure> {
    let name = input.display().to_string();
    let text = std::fs::read_to_string(input).map_err(|e| bad_input(format!("{name}: cannot read: {e}")))?;
    points_csv::parse(&name, &text, check).map_err(bad_input)
}

/// The rays of an `eval --entry radiance` CSV, each checked by `check`.
fn read_rays(input: &Path, check: &points_csv::RayCheck) -> Result<Vec<points_csv::RayRow>, Failure> {
    let name = input.display().to_string();
    let text = std::fs::read_to_string(input).map_err(|e| bad_input(format!("{name}: cannot read: {e}")))?;
    points_csv::parse_rays(&name, &text, check).map_err(bad_input)
}

/// Whether the header of `input` names the spot entry's cone (`cos_outer`): such
/// a file given to `--entry radiance` goes to the spot entry.
fn names_spot_columns(input: &Path) -> bool {
    std::fs::read_to_string(input)
        .ok()
        .and_then(|t| t.lines().find(|l| !l.trim().is_empty()).map(|h| h.split(',').any(|c| c.trim() == "cos_outer")))
        .unwrap_or(false)
}

/// The rays of an `eval --entry spot` CSV, each channel checked by `check`.
fn read_spots(input: &Path, check: &points_csv::RayCheck) -> Result<Vec<points_csv::SpotRow>, Failure> {
    let name = input.display().to_string();
    let text = std::fs::read_to_string(input).map_err(|e| bad_input(format!("{name}: cannot read: {e}")))?;
    points_csv::parse_spots(&name, &text, check).map_err(bad_input)
}

/// A spot row as a kernel's spot entry takes it (f32; no surface: −1; a point light: cos_outer −1).
fn kernel_spot(r: &points_csv::SpotRow) -> airlight_shaders::SpotRay {
    let f = |v: [f64; 3]| v.map(|x| x as f32);
    let ray = &r.rays[0];
    let (axis, co, ci) = match &r.cone {
        Some(c) => (f(c.axis), c.cos_outer as f32, c.cos_inner as f32),
        None => ([0.0, 0.0, 1.0], -1.0, -1.0),
    };
    airlight_shaders::SpotRay {
        origin: f(ray.origin),
        dir: f(ray.direction),
        surface: ray.surface_distance.map_or(-1.0, |s| s as f32),
        light: f(ray.light),
        axis,
        cos_outer: co,
        cos_inner: ci,
        intensity: ray.intensity as f32,
        sigma_t: r.rays.each_ref().map(|x| x.sigma_t as f32),
        sigma_s: r.rays.each_ref().map(|x| x.sigma_s as f32),
        g: r.g as f32,
    }
}

/// A ray as a kernel's physical entry takes it (f32; no surface: −1).
fn kernel_ray(r: &points_csv::RayRow) -> airlight_shaders::Ray {
    let f = |v: [f64; 3]| v.map(|x| x as f32);
    airlight_shaders::Ray {
        origin: f(r.ray.origin),
        dir: f(r.ray.direction),
        surface: r.ray.surface_distance.map_or(-1.0, |s| s as f32),
        light: f(r.ray.light),
        intensity: r.ray.intensity as f32,
        sigma_t: r.ray.sigma_t as f32,
        sigma_s: r.ray.sigma_s as f32,
        g: r.g as f32,
    }
}

/// `eval --target wgsl|glsl`: the generated shader kernel on the GPU adapter.
fn eval_gpu(
    name: &str,
    input: &Path,
    output: Option<&Path>,
    language: Target,
    entry_kind: EvalEntry,
    root: Option<PathBuf>,
) -> Result<(), Failure> {
    let rays = entry_kind == EvalEntry::Radiance;
    let generated = generated_dir(root.clone())?;
    let index = gate::load_index(&generated).map_err(|e| bad_input(e.to_string()))?;
    let k = index.get(name).map_err(bad_input)?;
    let file = k.file(language).ok_or_else(|| bad_input(format!("kernel '{name}' has no {language} file")))?;
    let path = generated.join(file);
    let source =
        std::fs::read_to_string(&path).map_err(|e| Failure(1, format!("{}: cannot read: {e}", path.display())))?;
    let table = airlight_shaders::load_table(&generated, k).map_err(|e| Failure(1, e.to_string()))?;
    let src = KernelSource::of(k, language, &source).with_table(table.as_ref());
    if entry_kind == EvalEntry::Spot {
        if !k.has(airlight_fit::vocab::Entry::Spot) {
            return Err(bad_input(format!("kernel '{name}' has no spot entry")));
        }
        let rows = read_spots(input, &|r, g| k.check_ray(r, g))?;
        let gpu = Gpu::open().map_err(|e| Failure(1, format!("{e}")))?;
        eprintln!("adapter: {}", gpu.adapter());
        let plain: Vec<airlight_shaders::SpotRay> = rows.iter().map(kernel_spot).collect();
        let got = gpu.spot(&src, &plain).map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
        let values: Vec<[f64; 3]> = got.iter().map(|v| v.map(f64::from)).collect();
        return write_csv(output, &points_csv::render_spots(&rows, &values));
    }
    if rays {
        let rows = read_rays(input, &|r, g| k.check_ray(r, g))?;
        let gpu = Gpu::open().map_err(|e| Failure(1, format!("{e}")))?;
        eprintln!("adapter: {}", gpu.adapter());
        let plain: Vec<airlight_shaders::Ray> = rows.iter().map(kernel_ray).collect();
        let got = gpu.radiance(&src, &plain).map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
        let values: Vec<f64> = got.iter().map(|&v| f64::from(v)).collect();
        return write_csv(output, &points_csv::render_rays(&rows, &values));
    }
    let rows = read_points(input, &|p| k.check(p))?;
    let gpu = Gpu::open().map_err(|e| Failure(1, format!("{e}")))?;
    eprintln!("adapter: {}", gpu.adapter());
    let raw: Vec<[f64; 4]> = rows.iter().map(|r| [r.point.tau, r.point.gamma, r.point.rho, r.point.g]).collect();
    let got = gpu.airlight(&src, &raw).map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
    let values: Vec<f64> = got.iter().map(|&v| airlight_shaders::from_kernel(v)).collect();
    write_csv(output, &points_csv::render(&rows, &values))
}

/// Writes a CSV to `output` (atomically, through a symbolic link; `-` or none:
/// standard output, where a closed pipe ends the run quietly).
fn write_csv(output: Option<&Path>, csv: &str) -> Result<(), Failure> {
    match output {
        Some(path) if path != Path::new("-") => airlight_fit::io::write_atomic(path, csv.as_bytes()).map_err(|e| {
            // A special file named as the output is a usage error (2); a failing write, a runtime one (1).
            let code = if e.kind() == std::io::ErrorKind::InvalidInput { 2 } else { 1 };
            Failure(code, format!("{}: cannot write: {e}", path.display()))
        }),
        _ => {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            match out.write_all(csv.as_bytes()).and_then(|()| out.flush()) {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    Err(Failure(1, format!("standard output: cannot write: {e}")))
                }
                _ => Ok(()),
            }
        }
    }
}

/// Opens the GPU adapter for the gate: `None` (and SKIPPED) without one, unless required.
fn gate_gpu(require: bool) -> Result<Option<Gpu>, Failure> {
    match Gpu::open() {
        Ok(gpu) => {
            println!("adapter: {}", gpu.adapter());
            Ok(Some(gpu))
        }
        Err(e) if require => Err(Failure(
            1,
            format!("no GPU adapter, and one is required (--require-gpu or AIRLIGHT_REQUIRE_GPU=1): {e}"),
        )),
        Err(e) => {
            println!("GPU targets SKIPPED: {e} (--require-gpu or AIRLIGHT_REQUIRE_GPU=1 makes this a failure)");
            Ok(None)
        }
    }
}

/// Runs the gate and prints its table; fails if any row fails.
fn run_gate(
    generated: &Path,
    gpu: Option<&Gpu>,
    rust: &[CompiledKernel],
    only: &[String],
    all: bool,
    record: bool,
) -> Result<(), Failure> {
    let spinner = indicatif::ProgressBar::new_spinner();
    let rows =
        gate::run(generated, gpu, rust, only, &|what| spinner.set_message(format!("check: {what}"))).map_err(|e| {
            match e {
                gate::GateError::Input(m) => bad_input(m),
                e => Failure(1, e.to_string()),
            }
        })?;
    spinner.finish_and_clear();
    let failures: Vec<gate::Row> = rows.iter().filter(|r| !r.passes()).cloned().collect();
    if all {
        print!("{}", gate::table(&rows, false));
    }
    let kernels: std::collections::BTreeSet<&str> = rows.iter().map(|r| r.kernel.as_str()).collect();
    let targets: std::collections::BTreeSet<&str> = rows.iter().map(|r| gate::target_label(r.target)).collect();
    // How much of the f32 allowance the worst row uses (negative: within the f64 bound).
    let worst = rows
        .iter()
        .filter(|r| r.target.is_some())
        .map(|r| (r.max - r.declared) / (r.limit() - r.declared))
        .fold(f64::NEG_INFINITY, f64::max);
    println!(
        "check: {} kernels × {{{}}} × domains = {} rows; limit = declared × (1 + {:.0e}) + {:.0e}; the worst row uses {:.1}% of that allowance",
        kernels.len(),
        targets.into_iter().collect::<Vec<_>>().join(", "),
        rows.len(),
        gate::F32_REL_ALLOWANCE,
        gate::F32_ALLOWANCE,
        100.0 * worst
    );
    if record {
        let adapter = gpu.map_or("none: the GPU targets were not run".to_string(), |g| g.adapter().to_string());
        let path = generated.join(airlight_fit::record::FILE);
        airlight_fit::io::write_atomic(&path, gate_record(generated, &rows, adapter)?.to_toml().as_bytes())
            .map_err(|e| Failure(1, format!("{}: cannot write: {e}", path.display())))?;
        println!("wrote {}; `airlight generate` puts it into REPORT.md", path.display());
    }
    if failures.is_empty() {
        println!("check: every kernel within its declared bound");
        Ok(())
    } else {
        Err(Failure(
            1,
            format!(
                "check FAILED: {} row(s) out of bounds\n{}",
                failures.len(),
                gate::table(&failures, false).trim_end()
            ),
        ))
    }
}

/// The gate's rows as `generated/gate.toml` holds them, tied by digest to the
/// kernel sources under `generated` that were measured.
fn gate_record(
    generated: &Path,
    rows: &[gate::Row],
    adapter: String,
) -> Result<airlight_fit::record::GateRecord, Failure> {
    let mut files = Vec::new();
    for dir in ["wgsl", "wgsl/bevy", "glsl", "airlight-kernels/src"] {
        let entries = std::fs::read_dir(generated.join(dir))
            .map_err(|e| Failure(1, format!("{}: cannot read: {e}", generated.join(dir).display())))?;
        for e in entries.flatten() {
            if e.path().is_file() {
                let bytes = std::fs::read(e.path())
                    .map_err(|err| Failure(1, format!("{}: cannot read: {err}", e.path().display())))?;
                files.push((format!("{dir}/{}", e.file_name().to_string_lossy()), bytes));
            }
        }
    }
    Ok(airlight_fit::record::GateRecord {
        adapter,
        kernels_digest: airlight_fit::record::digest(&files),
        rows: rows
            .iter()
            .map(|r| airlight_fit::record::GateRow {
                kernel: r.kernel.clone(),
                target: gate::target_label(r.target).to_string(),
                domain: r.domain.to_string(),
                points: r.points,
                max_rel: r.max,
                p99_rel: r.p99,
                limit: r.limit(),
                bad: r.bad,
            })
            .collect(),
    })
}

fn check(
    root: Option<PathBuf>,
    require_gpu: bool,
    only: &[String],
    all: bool,
    record: bool,
    kernels: &[CompiledKernel],
) -> Result<(), Failure> {
    if record && !only.is_empty() {
        return Err(bad_input("--record needs every kernel: drop --kernel"));
    }
    let generated = generated_dir(root)?;
    let gpu = gate_gpu(require_gpu || airlight_shaders::gpu_required())?;
    run_gate(&generated, gpu.as_ref(), kernels, only, all, record)
}

fn render_scene(
    scene_file: &Path,
    output: Option<&Path>,
    report: bool,
    width: u32,
    height: u32,
    root: Option<PathBuf>,
    kernels: &[CompiledKernel],
) -> Result<(), Failure> {
    use airlight_shaders::render;
    let generated = generated_dir(root)?;
    let shown = scene_file.display().to_string();
    let text = std::fs::read_to_string(scene_file).map_err(|e| bad_input(format!("{shown}: cannot read: {e}")))?;
    let scene = airlight_codegen::scene::parse(&shown, &text).map_err(bad_input)?;
    let index = gate::load_index(&generated).map_err(|e| bad_input(e.to_string()))?;
    let name = format!("scene-{}", scene.name);
    let k = index.get(&name).map_err(|e| bad_input(format!("{shown}: {e} (run `airlight generate`)")))?;
    let wgsl = k.wgsl.as_ref().ok_or_else(|| bad_input(format!("{shown}: the scene has no wgsl target")))?;
    let kernel = std::fs::read_to_string(generated.join(wgsl))
        .map_err(|e| Failure(1, format!("{}: cannot read: {e}", generated.join(wgsl).display())))?;
    if width == 0 || height == 0 || width > 4096 || height > 4096 {
        return Err(bad_input("--width and --height must be between 1 and 4096"));
    }
    let (base, dir) = match (output, report) {
        (_, true) => (scene.name.clone(), generated.join("render")),
        (Some(o), false) => (
            o.file_stem().map_or("render".into(), |s| s.to_string_lossy().into_owned()),
            o.parent().map_or(PathBuf::from("."), Path::to_path_buf),
        ),
        (None, false) => return Err(bad_input("name the image with -o OUT.png, or pass --report")),
    };
    let gpu = Gpu::open().map_err(|e| Failure(1, e.to_string()))?;
    println!("adapter: {}", gpu.adapter());
    let view = render::View::for_scene(k, scene.sigma_t.1, scene.max_distance, width, height);
    // The images, tone-mapped, and their errors against the reference: one
    // channel (point lights), or RGB (spot lights in a coloured medium).
    type Pixels = Vec<[u8; 3]>;
    struct Images {
        gpu: Pixels,
        reference: Pixels,
        diff: Pixels,
        gpu_err: (f64, f64),
        rust: Option<(Pixels, (f64, f64))>,
    }
    let as64 = |v: &[f32]| v.iter().map(|&x| f64::from(x)).collect::<Vec<_>>();
    let rk = kernels.iter().find(|rk| rk.name == name);
    let images = if scene.spot {
        let image = gpu.render_spot(k, &kernel, &view).map_err(|e| Failure(1, format!("{name}: {e}")))?;
        let reference = render::render_spot_reference(k, &view);
        let flat = render::channels(&reference);
        let exposure = render::exposure(&flat);
        let rgb64 = |v: &[[f32; 3]]| v.iter().map(|p| p.map(f64::from)).collect::<Vec<_>>();
        Images {
            gpu: render::tone_map_rgb(&rgb64(&image), exposure),
            reference: render::tone_map_rgb(&reference, exposure),
            diff: render::difference_rgb(&image, &reference),
            gpu_err: render::compare(&render::channels(&image), &flat),
            rust: rk
                .and_then(|rk| render::render_spot_rust(rk, &view))
                .map(|r| (render::tone_map_rgb(&rgb64(&r), exposure), render::compare(&render::channels(&r), &flat))),
        }
    } else {
        let image = gpu.render(k, &kernel, &view).map_err(|e| Failure(1, format!("{name}: {e}")))?;
        let reference = render::render_reference(k, &view);
        let exposure = render::exposure(&reference);
        Images {
            gpu: render::tone_map(&as64(&image), exposure),
            reference: render::tone_map(&reference, exposure),
            diff: render::difference(&image, &reference),
            gpu_err: render::compare(&image, &reference),
            rust: rk.map(|rk| {
                let r = render::render_rust(rk, &view);
                (render::tone_map(&as64(&r), exposure), render::compare(&r, &reference))
            }),
        }
    };
    let w = view.width();
    std::fs::create_dir_all(&dir).map_err(|e| Failure(1, format!("{}: {e}", dir.display())))?;
    let png = |suffix: &str, pixels: &[[u8; 3]]| -> Result<PathBuf, Failure> {
        let path = dir.join(format!("{base}{suffix}.png"));
        render::write_png(&path, w, height, pixels).map_err(|e| Failure(1, e))?;
        Ok(path)
    };
    let gpu_png = png(if report { "-gpu" } else { "" }, &images.gpu)?;
    png("-reference", &images.reference)?;
    png("-diff", &images.diff)?;
    let (gmax, gmean) = images.gpu_err;
    println!("{}: {w}×{height}, σt = {:?}", gpu_png.display(), view.sigma_t);
    println!("GPU (WGSL) vs reference: max relative error {gmax:.2e}, mean {gmean:.2e}");
    let mut summary = vec![
        ("adapter".to_string(), format!("\"{}\"", gpu.adapter().to_string().replace('"', "'"))),
        ("gpu_max_rel".into(), format!("{gmax:e}")),
        ("gpu_mean_rel".into(), format!("{gmean:e}")),
    ];
    if let Some((pixels, (rmax, rmean))) = &images.rust {
        png("-rust", pixels)?;
        println!("Rust kernel (CPU) vs reference: max relative error {rmax:.2e}, mean {rmean:.2e}");
        summary.push(("rust_max_rel".into(), format!("{rmax:e}")));
        summary.push(("rust_mean_rel".into(), format!("{rmean:e}")));
    }
    if report {
        let mut toml = format!(
            "# Written by `airlight render --scene {} --report`; quoted by REPORT.md.\nkernel = \"{name}\"\nwidth = {w}\nheight = {height}\nsigma_t = {:?}\n",
            scene.file, view.sigma_t
        );
        for (k, v) in summary {
            toml.push_str(&format!("{k} = {v}\n"));
        }
        airlight_fit::io::write_atomic(&dir.join(format!("{base}.toml")), toml.as_bytes())
            .map_err(|e| Failure(1, format!("{}: {e}", dir.display())))?;
        println!("wrote {}/{base}*; `airlight generate` puts them into REPORT.md", dir.display());
    }
    Ok(())
}

/// A generated kernel's value at `p` (arguments rounded to f32, `ρ = ∞` passed as
/// −1), as f64; the kernel's `HUGE` (the ray through the light) is ∞.
fn f32_value(k: &CompiledKernel, p: airlight_fit::reference::Point) -> f64 {
    airlight_shaders::from_kernel((k.airlight)(
        p.tau as f32,
        p.gamma as f32,
        airlight_shaders::rho_arg(p.rho),
        p.g as f32,
    ))
}

fn models(root: Option<PathBuf>) -> Result<(), Failure> {
    let (reg, files) = registry(root)?;
    println!(
        "{:<18} {:<14} {:>9} {:>9} {:>9} {:>9}  description",
        "model", "g range", "thin max", "thin p99", "dense max", "dense p99"
    );
    for m in reg.iter() {
        let e = |d: Domain, f: fn(&airlight_fit::domains::DomainErrors) -> f64| {
            files
                .iter()
                .find(|f| f.model.name == m.name())
                .and_then(|f| f.error(d))
                .map_or("-".to_string(), |e| format!("{:.1e}", f(e)))
        };
        println!(
            "{:<18} {:<14} {:>9} {:>9} {:>9} {:>9}  {}",
            m.name(),
            m.g_range_label(),
            e(Domain::Thin, |e| e.max_rel),
            e(Domain::Thin, |e| e.p99_rel),
            e(Domain::Dense, |e| e.max_rel),
            e(Domain::Dense, |e| e.p99_rel),
            m.summary()
        );
    }
    Ok(())
}

/// Fits (every family, or the one part named) with a progress bar.
fn run_fits(only: Option<&str>) -> Fits {
    with_progress("fitting families", |progress| Fits::fit(only, progress))
}

/// Assembles and measures every shipped model from the fits (progress bar).
fn build_models(fits: &Fits) -> Result<Vec<ModelFile>, Failure> {
    with_progress("measuring models", |progress| catalog::build(fits, progress)).map_err(|e| Failure(1, e))
}

fn print_fits(fits: &Fits) {
    for line in fits.summary() {
        println!("{line}");
    }
}

fn fit(family: Option<&str>, root: Option<PathBuf>) -> Result<(), Failure> {
    let only = match family {
        None => None,
        Some(name) => Some(airlight_fit::family::fit_parts().into_iter().find(|p| *p == name).ok_or_else(|| {
            let known = airlight_fit::family::fit_parts();
            bad_input(format!("unknown family '{name}'; known families: {}", known.join(", ")))
        })?),
    };
    let start = Instant::now();
    let fits = run_fits(only);
    print_fits(&fits);
    if only.is_some() {
        println!(
            "fitted in {:.1} s; nothing written (`airlight fit` without --family writes the coefficients)",
            start.elapsed().as_secs_f64()
        );
        return Ok(());
    }
    let files = build_models(&fits)?;
    let generated = generated_dir(root)?;
    let outputs: Vec<airlight_codegen::Output> = files
        .iter()
        .map(|f| airlight_codegen::Output::text(format!("coefficients/{}.toml", f.model.name), coeffs::render(f)))
        .collect();
    let written = write_outputs(&generated, &outputs)?.len();
    println!(
        "{written} of {} coefficient file(s) changed under {} in {:.1} s",
        outputs.len(),
        generated.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The nearest ancestor of the current directory holding `generated/` and a `Cargo.toml`.
fn find_root() -> Result<PathBuf, Failure> {
    let cwd = std::env::current_dir().map_err(|e| Failure(1, format!("cannot read the current directory: {e}")))?;
    cwd.ancestors()
        .find(|d| d.join("generated").is_dir() && d.join("Cargo.toml").is_file())
        .map(Path::to_path_buf)
        .ok_or_else(|| bad_input("no directory with generated/ and Cargo.toml above the current one; pass --root"))
}

fn progress_bar(len: u64, what: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg:>24} [{bar:40}] {pos}/{len} {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}

/// Runs the reference self-check with a progress bar.
fn measure() -> selfcheck::SelfCheck {
    with_progress("reference self-check", selfcheck::run_standard)
}

/// Runs `work` with a progress bar fed by its `(done, total)` callback.
fn with_progress<T>(what: &str, work: impl FnOnce(&(dyn Fn(usize, usize) + Sync)) -> T) -> T {
    let bar = progress_bar(0, what);
    let out = work(&|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    out
}

/// Everything under `generated/`, with the scenes of `codegen/scenes/` (next to `generated/`).
fn render(
    check: &selfcheck::SelfCheck,
    models: &[ModelFile],
    generated: &Path,
) -> Result<Vec<airlight_codegen::Output>, Failure> {
    let root = generated.parent().unwrap_or(Path::new("."));
    let scenes = airlight_codegen::scene::load_dir(&root.join("codegen/scenes"), "codegen/scenes")
        .map_err(|e| Failure(2, e.to_string()))?;
    let renders = airlight_codegen::read_renders(generated)
        .map_err(|e| Failure(1, format!("{}: cannot read: {e}", generated.join("render").display())))?;
    let recorded = airlight_codegen::read_recorded(generated).map_err(bad_input)?;
    airlight_codegen::render_all(check, models, &recorded, &scenes, &renders).map_err(|e| match e {
        airlight_codegen::RenderError::Scene(..) => Failure(2, e.to_string()),
        _ => Failure(1, format!("rendering generated/: {e}")),
    })
}

/// How much `airlight bench` measures.
struct BenchSize {
    points: usize,
    batch: usize,
    repeats: usize,
}

/// The CPU's model name (`/proc/cpuinfo`), or the architecture.
fn cpu_name() -> String {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let name = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    format!("{name} ({cores} cores visible; one thread timed)")
}

fn bench(
    root: Option<PathBuf>,
    kernels: &[CompiledKernel],
    size: BenchSize,
    out: Option<PathBuf>,
) -> Result<(), Failure> {
    use airlight_fit::bench::{self, BenchModel};
    let generated = generated_dir(root)?;
    let files = catalog::load(&generated.join("coefficients")).map_err(bad_input)?;
    let index = gate::load_index(&generated).map_err(|e| bad_input(e.to_string()))?;
    if size.points == 0 || size.batch == 0 || size.repeats == 0 {
        return Err(Failure(2, "bench: --points, --batch and --repeats must be at least 1".into()));
    }
    let bar = indicatif::ProgressBar::new(0);
    bar.set_message("bench: reference values");
    let sets = bench::error_sets(size.points, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    let points = bench::cost_batch(size.batch);
    let batch = bench::canonical_args(&points);
    let batch64: Vec<[f64; 4]> = points.iter().map(|p| [p.tau, p.gamma, p.rho, p.g]).collect();
    let gpu = Gpu::open();
    let adapter = match &gpu {
        Ok(g) => {
            let a = g.adapter();
            let emulated = a.device_type == "Cpu" || a.name.contains("llvmpipe");
            format!("{a}{}", if emulated { " — CPU emulation (lavapipe), not a GPU" } else { "" })
        }
        Err(e) => format!("none ({e})"),
    };
    // The RGB timing's rays, for the spot entry against three scalar calls.
    const ST: [f32; 3] = [0.03, 0.05, 0.08];
    let rgb_rays = bench::rgb_rays(size.batch);
    let rgb_scalar: Vec<airlight_shaders::Ray> = rgb_rays
        .iter()
        .map(|r| airlight_shaders::Ray {
            origin: [0.0; 3],
            dir: r[0],
            surface: -1.0,
            light: r[1],
            intensity: 100.0,
            sigma_t: ST[0],
            sigma_s: 0.8 * ST[0],
            g: 0.5,
        })
        .collect();
    let rgb_spots: Vec<airlight_shaders::SpotRay> = rgb_rays
        .iter()
        .map(|r| airlight_shaders::SpotRay {
            origin: [0.0; 3],
            dir: r[0],
            surface: -1.0,
            light: r[1],
            axis: r[2],
            cos_outer: -1.0,
            cos_inner: -1.0,
            intensity: 100.0,
            sigma_t: ST,
            sigma_s: ST.map(|x| 0.8 * x),
            g: 0.5,
        })
        .collect();
    let mut gpu_rgb_rates = Vec::new();
    let mut rows = Vec::new();
    let mut fns = Vec::new();
    for f in &files {
        let name = &f.model.name;
        let k = kernels.iter().find(|k| k.name == name.as_str()).ok_or_else(|| {
            Failure(1, format!("bench: no compiled kernel '{name}': run `airlight generate` and rebuild"))
        })?;
        bar.set_message(format!("bench: {name} errors"));
        let errors = bench::errors(&|p| f32_value(k, p), f.model.g_range, &sets);
        let entry = index.get(name).map_err(bad_input)?;
        let wgsl = entry.file(Target::Wgsl).ok_or_else(|| bad_input(format!("kernel '{name}' has no WGSL file")))?;
        let path = generated.join(wgsl);
        let source =
            std::fs::read_to_string(&path).map_err(|e| Failure(1, format!("{}: cannot read: {e}", path.display())))?;
        let cost = airlight_shaders::ircost::ir_cost(&source, &format!("{}airlight", entry.prefix))
            .map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
        bar.set_message(format!("bench: {name} on the GPU"));
        let (mut gpu_evals_per_s, mut gpu_rgb) = (0.0, (0.0, 0.0));
        if let Ok(g) = &gpu {
            let table = airlight_shaders::load_table(&generated, entry).map_err(|e| Failure(1, e.to_string()))?;
            let src = KernelSource::of(entry, Target::Wgsl, &source).with_table(table.as_ref());
            let err = |e: airlight_shaders::GpuError| Failure(1, format!("{}: {e}", path.display()));
            gpu_evals_per_s = g.throughput(&src, &batch64, size.repeats).map_err(err)?.unwrap_or(0.0);
            // RGB: the physical entry's rate over three, against the spot entry with a point light.
            if k.spot.is_some() {
                gpu_rgb = (
                    g.radiance_throughput(&src, &rgb_scalar, size.repeats).map_err(err)?.unwrap_or(0.0) / 3.0,
                    g.spot_throughput(&src, &rgb_spots, size.repeats).map_err(err)?.unwrap_or(0.0),
                );
            }
        }
        gpu_rgb_rates.push(gpu_rgb);
        rows.push(BenchModel {
            name: name.clone(),
            kind: if f.model.body.is_baseline() { "baseline" } else { "airlight" }.into(),
            g_range: [f.model.g_range.0, f.model.g_range.1],
            errors,
            cpu_ns_per_eval: 0.0,
            cpu_ns_range: [0.0, 0.0],
            ops: cost.ops,
            transcendentals: cost.transcendentals,
            gpu_evals_per_s,
            bytes: f.model.body.texture().map_or(0, |t| t.bytes()),
        });
        fns.push(k.airlight);
    }
    bar.set_length(size.repeats as u64);
    bar.set_position(0);
    bar.set_message("bench: CPU time (interleaved repeats)");
    let times = bench::time_kernels(&fns, &batch, size.repeats, &|r| bar.set_position(r as u64));
    for (row, (median, lo, hi)) in rows.iter_mut().zip(times) {
        row.cpu_ns_per_eval = median;
        row.cpu_ns_range = [lo, hi];
    }
    // RGB: the spot entry against three scalar calls, on the same rays.
    bar.set_message("bench: RGB against three scalar calls");
    let mut rgb = Vec::new();
    for (f, &(g3, gp)) in files.iter().zip(&gpu_rgb_rates) {
        let Some(k) = kernels.iter().find(|k| k.name == f.model.name.as_str()) else { continue };
        let Some(spot) = k.spot else { continue };
        let radiance = k.radiance;
        let three = |r: &[[f32; 3]; 3]| -> f32 {
            ST.iter().map(|&st| radiance([0.0; 3], r[0], -1.0, r[1], 100.0, st, 0.8 * st, 0.5)).sum()
        };
        let one = |r: &[[f32; 3]; 3], co: f32, ci: f32| -> f32 {
            spot([0.0; 3], r[0], -1.0, r[1], r[2], co, ci, 100.0, ST, ST.map(|x| 0.8 * x), 0.5).iter().sum()
        };
        let [t3, tp, th, ts] = bench::time_rgb(&three, &one, &rgb_rays, size.repeats);
        rgb.push(bench::RgbCost {
            name: f.model.name.clone(),
            three_scalar_ns: t3,
            rgb_point_ns: tp,
            rgb_hard_cone_ns: th,
            rgb_soft_cone_ns: ts,
            gpu_three_scalar_rays_per_s: g3,
            gpu_rgb_point_rays_per_s: gp,
        });
    }
    bar.finish_and_clear();
    let b = bench::Bench {
        adapter,
        cpu: cpu_name(),
        error_points: size.points,
        cost_batch: size.batch,
        repeats: size.repeats,
        models: rows,
        rgb,
    };
    println!("adapter: {}\ncpu: {}", b.adapter, b.cpu);
    println!(
        "{:<16} {:>9} {:>9} {:>9} {:>9} {:>10} {:>6} {:>5} {:>12}",
        "model", "thin max", "dense max", "thin p50", "dense p50", "ns/eval", "ops", "tr", "GPU evals/s"
    );
    for m in &b.models {
        let e = m.errors.first();
        let f = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.2e}"));
        println!(
            "{:<16} {:>9} {:>9} {:>9} {:>9} {:>10.1} {:>6} {:>5} {:>12.3e}   (g = {})",
            m.name,
            f(e.map(|e| e.max_rel.thin)),
            f(e.map(|e| e.max_rel.dense)),
            f(e.map(|e| e.p50_rel.thin)),
            f(e.map(|e| e.p50_rel.dense)),
            m.cpu_ns_per_eval,
            m.ops,
            m.transcendentals,
            m.gpu_evals_per_s,
            e.map_or(0.0, |e| e.g)
        );
    }
    println!("\nRGB, CPU ns per ray: three scalar `radiance` calls against one `spot` call");
    println!(
        "{:<16} {:>10} {:>10} {:>7} {:>10} {:>10} {:>12} {:>12}",
        "model", "3 scalar", "RGB point", "ratio", "hard cone", "soft cone", "GPU 3 scalar", "GPU RGB"
    );
    for r in &b.rgb {
        println!(
            "{:<16} {:>10.1} {:>10.1} {:>7.2} {:>10.1} {:>10.1} {:>12.3e} {:>12.3e}",
            r.name,
            r.three_scalar_ns,
            r.rgb_point_ns,
            r.rgb_point_ns / r.three_scalar_ns,
            r.rgb_hard_cone_ns,
            r.rgb_soft_cone_ns,
            r.gpu_three_scalar_rays_per_s,
            r.gpu_rgb_point_rays_per_s
        );
    }
    let path = out.unwrap_or_else(|| generated.join("bench.json"));
    airlight_fit::io::write_atomic(&path, b.to_json().as_bytes())
        .map_err(|e| Failure(1, format!("{}: cannot write: {e}", path.display())))?;
    println!("wrote {}; `airlight generate` puts it into REPORT.md", path.display());
    Ok(())
}

/// `root/generated`, with the root found from the current directory if not given.
fn generated_dir(root: Option<PathBuf>) -> Result<PathBuf, Failure> {
    Ok(match root {
        Some(r) => r,
        None => find_root()?,
    }
    .join("generated"))
}

/// Writes the outputs, returning the files that changed.
fn write_outputs(generated: &Path, outputs: &[airlight_codegen::Output]) -> Result<Vec<PathBuf>, Failure> {
    airlight_codegen::write_all(generated, outputs).map_err(|e| Failure(1, e.to_string()))
}

fn generate(root: Option<PathBuf>, check_only: bool) -> Result<(), Failure> {
    let generated = generated_dir(root.clone())?;
    let (_, files) = registry(Some(generated.parent().map(Path::to_path_buf).unwrap_or_default()))?;
    if files.is_empty() {
        return Err(bad_input(format!(
            "{}: no coefficient files; run `airlight fit` (or `airlight regenerate`) first",
            generated.join("coefficients").display()
        )));
    }
    let check = airlight_codegen::read_selfcheck(&generated).map_err(bad_input)?;
    let outputs = render(&check, &files, &generated)?;
    if check_only {
        let diffs = airlight_codegen::check(&generated, &outputs);
        for d in &diffs {
            eprintln!("{d}");
        }
        if !diffs.is_empty() {
            return Err(Failure(
                1,
                format!("{} file(s) under generated/ are stale; run `airlight regenerate`", diffs.len()),
            ));
        }
        println!("generated/ is current ({} file(s))", outputs.len());
        return Ok(());
    }
    let written = write_outputs(&generated, &outputs)?.len();
    println!("{written} of {} file(s) changed under {}", outputs.len(), generated.display());
    Ok(())
}

fn regenerate(root: Option<PathBuf>, kernels: Option<&[CompiledKernel]>) -> Result<(), Failure> {
    let generated = generated_dir(root.clone())?;
    let start = Instant::now();
    let check = measure();
    let fits = run_fits(None);
    print_fits(&fits);
    let files = build_models(&fits)?;
    let outputs = render(&check, &files, &generated)?;
    let written = write_outputs(&generated, &outputs)?;
    for f in &files {
        let e =
            |d: Domain| f.error(d).map_or("-".to_string(), |e| format!("max {:.1e} p99 {:.1e}", e.max_rel, e.p99_rel));
        println!("{:<18} thin {}  dense {}", f.model.name, e(Domain::Thin), e(Domain::Dense));
    }
    for d in &check.domains {
        let e1 = d.vs_e1.map_or(String::new(), |s| format!(", vs E1 {:.1e}", s.max));
        println!(
            "reference {:<8} {:<9} {:>6} points: vs s form {:.1e}{e1}",
            d.domain.name(),
            d.phase_label(),
            d.points,
            d.vs_s_form.max
        );
    }
    for f in &check.fixtures {
        println!("reference vs {}: max {:.1e} over {} points", f.name, f.stats.max, f.finite);
    }
    println!(
        "{} of {} file(s) changed under {} in {:.1} s",
        written.len(),
        outputs.len(),
        generated.display(),
        start.elapsed().as_secs_f64()
    );
    let problems = check.problems();
    if !problems.is_empty() {
        return Err(Failure(1, format!("reference self-check failed: {}", problems.join("; "))));
    }
    // The gate, on the kernels just written: `airlight-run` is built from them.
    match kernels {
        None => {
            let mut args = vec!["check".to_string()];
            if let Some(r) = &root {
                args.extend(["--root".to_string(), r.display().to_string()]);
            }
            delegate(root, Some(args))
        }
        Some(k) => {
            let changed = written.iter().any(|p| p.starts_with(generated.join("airlight-kernels")));
            if changed {
                println!("the Rust kernels changed: run `airlight check` to gate the rebuilt ones too");
            }
            let gpu = gate_gpu(airlight_shaders::gpu_required())?;
            run_gate(&generated, gpu.as_ref(), if changed { &[] } else { k }, &[], false, false)
        }
    }
}

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
//!
//! One module per command (`eval`, `check`, `render`, `models`, `fit`, `bench`,
//! `generate`), and `workspace` for where they work; what they compute lives in
//! the libraries (the gate and the bench in `airlight-shaders`, CSVs and fits in
//! `airlight-fit`, rendering `generated/` in `airlight-codegen`).

mod bench;
mod check;
mod eval;
mod fit;
mod generate;
mod models;
mod plan;
mod render;
mod shafts;
mod workspace;

pub use workspace::RUNNER;

use airlight_shaders::bench::BenchSize;
use airlight_shapes::vocab::{CompiledKernel, Target};
use clap::{Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "airlight",
    version,
    about = "Fast, measured single-scattering glow (airlight) around point lights in fog, smoke, haze and water",
    long_about = "airlight computes the light a point light scatters into a view ray through a homogeneous \
participating medium (fog, smoke, haze, water), in the canonical form A(tau, gamma, rho; g) of docs/MATH.md:\n\n  \
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
pub(crate) enum EvalEntry {
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
    /// Light shafts: the radiance (or spot) entry's columns plus `spheres`, the
    /// occluders as `cx cy cz r` quadruples separated by `;` (empty: none), the
    /// view ray ending at `surface`; the shafts accumulator fed the exact lit
    /// intervals, or with --samples N a shadow map's N look-ups. Output column
    /// radiance (r,g_out,b for a spot file).
    Shadowed,
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

/// A section of `bench.json` that `airlight bench --only` measures alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum BenchSection {
    /// The exact shadow-map walk against the march and the sampled accumulator
    /// (`shadow_map`).
    ShadowMap,
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
        /// With --entry shadowed: feed the accumulator N visibility samples, taken
        /// where raymarch-N takes its steps (midpoints of N equal steps to the
        /// surface, or to the march's cut-off on an open ray), between the
        /// viewer's and the surface's visibility (look-ups a renderer already
        /// makes), instead of the exact lit intervals. A raymarch-N model always
        /// looks visibility up at its own N steps alone (the engines' march).
        #[arg(long, value_name = "N")]
        samples: Option<usize>,
        /// With --entry shadowed: cast each row's spheres and boxes into a shadow
        /// map of RES² texels per face (a power of two up to 8192) at its light —
        /// a cube map for a point light, one face covering the cone for a spot
        /// light — and feed the accumulator the lit runs of the walk through its
        /// min-max pyramid (exact with respect to the map's nearest-texel test): the
        /// f64 reference walk on --precision f64, the generated walk on f32, WGSL
        /// and GLSL (the pyramid built there by the shipped pass). Prints the
        /// walk's steps on standard error; a ray whose walk runs out of its
        /// steps (the generated walk's 4096) fails the run, naming its line. A
        /// spot cone wider than 60° (half-angle) gets a cube map: one face
        /// cannot cover a cone of 90° or more.
        #[arg(long, value_name = "RES", allow_negative_numbers = true)]
        shadow_map: Option<i64>,
        /// With --shadow-map: the depth test's bias (lit where depth <= stored + B),
        /// in world units, finite and >= 0 (default 0).
        #[arg(long, value_name = "B", allow_negative_numbers = true)]
        bias: Option<f64>,
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
        /// family's parts), phi or lite.
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
        /// Measure one section alone and put it into the JSON already at the
        /// output path, the rest as it was measured (the models' rows, which
        /// the planner ranks by, stay; the section is marked as measured alone).
        /// The section has its own seeded rays: --points and --batch do not apply.
        #[arg(long, value_enum, conflicts_with_all = ["points", "batch"])]
        only: Option<BenchSection>,
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
    ///
    /// A scene with shadows draws light shafts instead: a spot light through a
    /// pergola into a smoky room, a shadow map from a depth pass, the fog by the
    /// scene kernel's shafts accumulator (OUT) and by the engines' march at about
    /// the same GPU time (OUT-march.png), the reference over exact lit intervals
    /// (OUT-reference.png), and each one's relative fog error (OUT-diff*.png).
    Render {
        /// The scene file (any path; planned as `airlight plan` plans it, its
        /// kernel rendered in memory, so an edited copy draws its own kernel).
        #[arg(long)]
        scene: PathBuf,
        /// The GPU image (PNG); the others are written next to it.
        #[arg(long, short)]
        output: Option<PathBuf>,
        /// Write into generated/render/ (quoted by REPORT.md after `airlight generate`).
        #[arg(long)]
        report: bool,
        /// Width of each of the three panels, pixels (default 320); for a scene
        /// with shadows, of the whole frame (default 640).
        #[arg(long)]
        width: Option<u32>,
        /// Height, pixels (default 240; 360 for a scene with shadows).
        #[arg(long)]
        height: Option<u32>,
        /// Repository root (the directory holding generated/); found from the
        /// current directory if omitted.
        #[arg(long)]
        root: Option<PathBuf>,
    },
    /// Plan a scene file from anywhere (codegen/scenes/*.toml, or your own): print
    /// the plan (every model that covers the scene, cheapest first by the measured
    /// costs of generated/bench.json, with its declared bound over the error domains
    /// the scene reaches, and the pick) and, with --out DIR, write the scene's kernel
    /// for each target it names under DIR, laid out as under generated/ (wgsl/,
    /// glsl/, hlsl/, msl/, airlight-kernels/src/, plans/): the bytes `airlight
    /// generate` writes for a scene file of codegen/scenes/ named by the same path.
    /// Nothing is written unless the whole scene plans.
    Plan {
        /// The scene file.
        scene: PathBuf,
        /// Where to write the kernel's files (created if missing).
        #[arg(long, short)]
        out: Option<PathBuf>,
        /// Repository root (the directory holding generated/, whose models and
        /// bench the plan reads); found from the current directory if omitted.
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

pub(crate) fn bad_input(msg: impl std::fmt::Display) -> Failure {
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
        Command::Eval { model, input, output, precision, target, entry, samples, shadow_map, bias, root } => {
            if samples.is_some() && entry != EvalEntry::Shadowed {
                return Err(bad_input("--samples goes with --entry shadowed"));
            }
            if shadow_map.is_some() && entry != EvalEntry::Shadowed {
                return Err(bad_input("--shadow-map goes with --entry shadowed"));
            }
            if shadow_map.is_some() && samples.is_some() {
                return Err(bad_input("give --samples or --shadow-map, not both"));
            }
            if shadow_map.is_none() && bias.is_some() {
                return Err(bad_input("--bias goes with --shadow-map (the depth test's bias)"));
            }
            let map = shadow_map.map(|res| shafts::MapFeed::new(res, bias.unwrap_or(0.0))).transpose()?;
            if entry == EvalEntry::Shadowed {
                let on = match (target.0, precision, linked) {
                    (Some(t), _, _) => shafts::Runner::Gpu(t),
                    (None, Precision::F32, None) => return workspace::delegate(root, None),
                    (None, Precision::F32, Some(k)) => shafts::Runner::F32(k),
                    (None, Precision::F64, _) => shafts::Runner::F64,
                };
                return shafts::eval_shadowed(&model, &input, output.as_deref(), on, samples, map, root);
            }
            // A rays file with a cone's columns is the spot entry's.
            let rays = match entry {
                EvalEntry::Radiance if eval::names_spot_columns(&input) => EvalEntry::Spot,
                e => e,
            };
            match (target.0, precision, linked) {
                (Some(target), _, _) => eval::eval_gpu(&model, &input, output.as_deref(), target, rays, root),
                (None, Precision::F32, None) => workspace::delegate(root, None),
                (None, Precision::F32, Some(k)) => eval::eval(&model, &input, output.as_deref(), Some(k), rays, root),
                (None, Precision::F64, _) => eval::eval(&model, &input, output.as_deref(), None, rays, root),
            }
        }
        Command::Check { root, .. } | Command::Render { root, .. } | Command::Bench { root, .. }
            if linked.is_none() =>
        {
            workspace::delegate(root, None)
        }
        Command::Check { require_gpu, kernel, all, record, root } => {
            check::check(root, require_gpu, &kernel, all, record, linked.unwrap_or_default())
        }
        Command::Render { scene, output, report, width, height, root } => {
            render::render_scene(&scene, output.as_deref(), report, width, height, root, linked.unwrap_or_default())
        }
        Command::Bench { points, batch, repeats, out, only: None, root } => {
            bench::bench(root, linked.unwrap_or_default(), BenchSize { points, batch, repeats }, out)
        }
        Command::Bench { repeats, out, only: Some(BenchSection::ShadowMap), root, .. } => {
            bench::bench_shadow_map(root, linked.unwrap_or_default(), repeats, out)
        }
        Command::Models { root } => models::models(root),
        Command::Plan { scene, out, root } => plan::plan(&scene, out.as_deref(), root),
        Command::Fit { family, root } => fit::fit(family.as_deref(), root),
        Command::Generate { check, root } => generate::generate(root, check),
        Command::Regenerate { root } => generate::regenerate(root, linked),
    }
}

//! `airlight`: a thin command line over the airlight libraries. It parses
//! arguments, calls the libraries, prints, and sets the exit code: 0 on success,
//! 2 for bad input (a one-line message naming file, line and column), 1 when a
//! check fails or a file cannot be written.

use airlight_fit::model;
use airlight_fit::{points_csv, selfcheck};
use clap::{Parser, Subcommand};
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
It fits fast approximations against a high-precision reference and reports their measured error."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
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
    Eval {
        /// Model to evaluate; `airlight models` lists them.
        #[arg(long, default_value = "reference")]
        model: String,
        /// CSV file of points.
        #[arg(long, short)]
        input: PathBuf,
        /// Where to write the result (replaced atomically); standard output if omitted.
        #[arg(long, short)]
        output: Option<PathBuf>,
    },
    /// List the models with the g range each supports.
    Models,
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
    /// The main job: measure, then regenerate everything under generated/.
    ///
    /// Runs the reference self-check (the fits join here as they are built) and
    /// writes REPORT.md. Deterministic: running it twice writes identical files.
    Regenerate {
        /// Repository root (the directory holding generated/); found from the
        /// current directory if omitted.
        #[arg(long)]
        root: Option<PathBuf>,
    },
}

/// A failure: its exit code and one line for the user.
struct Failure(u8, String);

fn bad_input(msg: impl std::fmt::Display) -> Failure {
    Failure(2, msg.to_string())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Eval { model, input, output } => eval(&model, &input, output.as_deref()),
        Command::Models => models(),
        Command::Generate { check, root } => generate(root, check),
        Command::Regenerate { root } => regenerate(root),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(code, msg)) => {
            eprintln!("error: {msg}");
            ExitCode::from(code)
        }
    }
}

fn eval(model: &str, input: &Path, output: Option<&Path>) -> Result<(), Failure> {
    let model = model::by_name(model).map_err(bad_input)?;
    let name = input.display().to_string();
    let text = std::fs::read_to_string(input).map_err(|e| bad_input(format!("{name}: cannot read: {e}")))?;
    let rows = points_csv::parse(&name, &text, |p| model.check(p)).map_err(bad_input)?;
    let values = airlight_fit::parallel::map(&rows, |r| model.eval_unchecked(r.point), &|_, _| {});
    let csv = points_csv::render(&rows, &values);
    match output {
        Some(path) => airlight_fit::io::write_atomic(path, csv.as_bytes())
            .map_err(|e| Failure(1, format!("{}: cannot write: {e}", path.display()))),
        None => {
            print!("{csv}");
            Ok(())
        }
    }
}

fn models() -> Result<(), Failure> {
    println!("{:<12} {:<16} description", "model", "g range");
    for m in model::all() {
        println!("{:<12} {:<16} {}", m.name(), m.g_range_label(), m.summary());
    }
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
    let bar = progress_bar(0, "reference self-check");
    let check = selfcheck::run_standard(&|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    check
}

fn render(check: &selfcheck::SelfCheck) -> Result<Vec<airlight_codegen::Output>, Failure> {
    airlight_codegen::render_all(check).map_err(|e| Failure(1, format!("rendering generated/: {e}")))
}

/// `root/generated`, with the root found from the current directory if not given.
fn generated_dir(root: Option<PathBuf>) -> Result<PathBuf, Failure> {
    Ok(match root {
        Some(r) => r,
        None => find_root()?,
    }
    .join("generated"))
}

/// Writes the outputs, returning how many files changed.
fn write_outputs(generated: &Path, outputs: &[airlight_codegen::Output]) -> Result<usize, Failure> {
    airlight_codegen::write_all(generated, outputs)
        .map(|w| w.len())
        .map_err(|e| Failure(1, format!("{}: cannot write: {e}", generated.display())))
}

fn generate(root: Option<PathBuf>, check_only: bool) -> Result<(), Failure> {
    let generated = generated_dir(root)?;
    let outputs = render(&measure())?;
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
    let written = write_outputs(&generated, &outputs)?;
    println!("{written} of {} file(s) changed under {}", outputs.len(), generated.display());
    Ok(())
}

fn regenerate(root: Option<PathBuf>) -> Result<(), Failure> {
    let generated = generated_dir(root)?;
    let start = Instant::now();
    let check = measure();
    let outputs = render(&check)?;
    let written = write_outputs(&generated, &outputs)?;
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
        "{written} of {} file(s) changed under {} in {:.1} s",
        outputs.len(),
        generated.display(),
        start.elapsed().as_secs_f64()
    );
    let problems = check.problems();
    if !problems.is_empty() {
        return Err(Failure(1, format!("reference self-check failed: {}", problems.join("; "))));
    }
    Ok(())
}

//! Where the commands work: the repository root and its `generated/`, writing
//! outputs, progress bars, the model registry, and handing the commands that run
//! compiled Rust kernels to `airlight-run`.

use crate::{bad_input, Failure};
use airlight_fit::catalog;
use airlight_fit::coeffs::ModelFile;
use airlight_fit::model;
use std::path::{Path, PathBuf};

/// The package whose binary runs compiled Rust kernels.
pub const RUNNER: &str = "airlight-run";

/// Runs this command line (or `args` instead) in `airlight-run`, built first (in
/// this binary's profile) from the workspace this binary was built from (else the
/// one at the root): the
/// commands that need the compiled Rust kernels. A build failure (the generated
/// kernels do not compile) is one line.
pub(crate) fn delegate(root: Option<PathBuf>, args: Option<Vec<String>>) -> Result<(), Failure> {
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
    // The runner in this binary's own profile: `cargo run --release` hands over to
    // a release runner, the tests' debug build to a debug one (sharing the
    // dependencies the tests built, instead of a second, release build of them).
    let profile: &[&str] = if cfg!(debug_assertions) { &[] } else { &["--release"] };
    let cargo_args = |verb: &str| {
        let mut c = std::process::Command::new(&cargo);
        c.arg(verb).args(profile).args(["--quiet", "-p", RUNNER, "--manifest-path"]).arg(&manifest);
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
pub(crate) fn registry(root: Option<PathBuf>) -> Result<(model::Registry, Vec<ModelFile>), Failure> {
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

/// The nearest ancestor of the current directory holding `generated/` and a `Cargo.toml`.
pub(crate) fn find_root() -> Result<PathBuf, Failure> {
    let cwd = std::env::current_dir().map_err(|e| Failure(1, format!("cannot read the current directory: {e}")))?;
    cwd.ancestors()
        .find(|d| d.join("generated").is_dir() && d.join("Cargo.toml").is_file())
        .map(Path::to_path_buf)
        .ok_or_else(|| bad_input("no directory with generated/ and Cargo.toml above the current one; pass --root"))
}

pub(crate) fn progress_bar(len: u64, what: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg:>24} [{bar:40}] {pos}/{len} {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}

/// Runs `work` with a progress bar fed by its `(done, total)` callback.
pub(crate) fn with_progress<T>(what: &str, work: impl FnOnce(&(dyn Fn(usize, usize) + Sync)) -> T) -> T {
    let bar = progress_bar(0, what);
    let out = work(&|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    out
}

/// `root/generated`, with the root found from the current directory if not given.
pub(crate) fn generated_dir(root: Option<PathBuf>) -> Result<PathBuf, Failure> {
    Ok(match root {
        Some(r) => r,
        None => find_root()?,
    }
    .join("generated"))
}

/// Writes the outputs, returning the files that changed.
pub(crate) fn write_outputs(generated: &Path, outputs: &[airlight_codegen::Output]) -> Result<Vec<PathBuf>, Failure> {
    airlight_codegen::write_all(generated, outputs).map_err(|e| Failure(1, e.to_string()))
}

//! `airlight check`: the error gate over every generated kernel on every
//! target, and its record (`generated/gate.toml`).

use crate::workspace::generated_dir;
use crate::{bad_input, Failure};
use airlight_shaders::{gate, Gpu};
use airlight_shapes::vocab::CompiledKernel;
use std::path::{Path, PathBuf};

/// Opens the GPU adapter for the gate: `None` (and SKIPPED) without one, unless required.
pub(crate) fn gate_gpu(require: bool) -> Result<Option<Gpu>, Failure> {
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
pub(crate) fn run_gate(
    generated: &Path,
    gpu: Option<&Gpu>,
    rust: &[CompiledKernel],
    only: &[String],
    all: bool,
    record: bool,
) -> Result<(), Failure> {
    let spinner = indicatif::ProgressBar::new_spinner();
    let progress = |what: &str| spinner.set_message(format!("check: {what}"));
    let (rows, f32_bounds) = if record {
        gate::run_measuring(generated, gpu, rust, only, &progress)
    } else {
        gate::run(generated, gpu, rust, only, &progress).map(|r| (r, Vec::new()))
    }
    .map_err(|e| match e {
        gate::GateError::Input(m) => bad_input(m),
        e => Failure(1, e.to_string()),
    })?;
    spinner.finish_and_clear();
    let failures: Vec<gate::Row> = rows.iter().filter(|r| !r.passes()).cloned().collect();
    if all {
        print!("{}", gate::table(&rows, false));
    }
    println!("{}", gate::summary(&rows));
    if record {
        let adapter = gpu.map_or("none: the GPU targets were not run".to_string(), |g| g.adapter().to_string());
        let path = generated.join(airlight_shapes::record::FILE);
        let record = gate::record(generated, &rows, f32_bounds, adapter).map_err(|e| Failure(1, e))?;
        airlight_truth::io::write_atomic(&path, record.to_toml().as_bytes())
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

pub(crate) fn check(
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

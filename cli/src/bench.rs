//! `airlight bench`: the speed/accuracy trade of every model against the
//! baselines (`airlight_shaders::bench`), printed and written to `bench.json`.

use crate::workspace::generated_dir;
use crate::{bad_input, Failure};
use airlight_fit::catalog;
use airlight_shaders::bench::{BenchError, BenchSize};
use airlight_shapes::bench::Bench;
use airlight_shapes::vocab::CompiledKernel;
use std::path::{Path, PathBuf};

pub(crate) fn bench(
    root: Option<PathBuf>,
    kernels: &[CompiledKernel],
    size: BenchSize,
    out: Option<PathBuf>,
) -> Result<(), Failure> {
    let generated = generated_dir(root)?;
    let files = catalog::load(&generated.join("coefficients")).map_err(bad_input)?;
    let b = with_progress(|progress| airlight_shaders::bench::measure(&generated, &files, kernels, size, progress))?;
    let path = out.unwrap_or_else(|| generated.join(airlight_shapes::bench::FILE));
    write(&b, &path)?;
    println!("wrote {}; `airlight generate` puts it into REPORT.md", path.display());
    Ok(())
}

/// `airlight bench --only shadow-map`: the shadow-map section measured alone and
/// put into the bench JSON already at the output path (the rest untouched, so no
/// plan moves); refused, with nothing written, where there is none to put it in.
pub(crate) fn bench_shadow_map(
    root: Option<PathBuf>,
    kernels: &[CompiledKernel],
    repeats: usize,
    out: Option<PathBuf>,
) -> Result<(), Failure> {
    let generated = generated_dir(root)?;
    let path = out.unwrap_or_else(|| generated.join(airlight_shapes::bench::FILE));
    let text = std::fs::read_to_string(&path).map_err(|e| {
        bad_input(format!("{}: cannot read ({e}): `--only` puts a section into a full bench's JSON", path.display()))
    })?;
    let mut b = Bench::from_json(&text).map_err(|e| bad_input(format!("{}: {e}", path.display())))?;
    let (adapter, rows) =
        with_progress(|progress| airlight_shaders::bench::measure_shadow_map(&generated, kernels, repeats, progress))?;
    b.shadow_map = rows;
    b.shadow_map_alone = Some(adapter);
    write(&b, &path)?;
    println!("wrote the shadow-map section into {}; `airlight generate` puts it into REPORT.md", path.display());
    Ok(())
}

/// Runs a measurement under a progress bar; its errors as the command's.
fn with_progress<T>(
    measure: impl FnOnce(&airlight_shaders::bench::Progress) -> Result<T, BenchError>,
) -> Result<T, Failure> {
    let bar = indicatif::ProgressBar::new(0);
    let result = measure(&|what, done, total| {
        bar.set_message(what.to_string());
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
    .map_err(|e| match e {
        BenchError::Input(m) => bad_input(m),
        BenchError::Failed(m) => Failure(1, m),
    });
    bar.finish_and_clear();
    result
}

/// Prints the bench's table and writes its JSON to `path` (whole or not at all).
fn write(b: &Bench, path: &Path) -> Result<(), Failure> {
    println!("{}", b.table());
    airlight_truth::io::write_atomic(path, b.to_json().as_bytes())
        .map_err(|e| Failure(1, format!("{}: cannot write: {e}", path.display())))
}

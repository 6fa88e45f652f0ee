//! `airlight bench`: the speed/accuracy trade of every model against the
//! baselines (`airlight_shaders::bench`), printed and written to `bench.json`.

use crate::workspace::generated_dir;
use crate::{bad_input, Failure};
use airlight_fit::catalog;
use airlight_shaders::bench::{BenchError, BenchSize};
use airlight_shapes::vocab::CompiledKernel;
use std::path::PathBuf;

pub(crate) fn bench(
    root: Option<PathBuf>,
    kernels: &[CompiledKernel],
    size: BenchSize,
    out: Option<PathBuf>,
) -> Result<(), Failure> {
    let generated = generated_dir(root)?;
    let files = catalog::load(&generated.join("coefficients")).map_err(bad_input)?;
    let bar = indicatif::ProgressBar::new(0);
    let b = airlight_shaders::bench::measure(&generated, &files, kernels, size, &|what, done, total| {
        bar.set_message(what.to_string());
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
    .map_err(|e| match e {
        BenchError::Input(m) => bad_input(m),
        BenchError::Failed(m) => Failure(1, m),
    })?;
    bar.finish_and_clear();
    println!("{}", b.table());
    let path = out.unwrap_or_else(|| generated.join(airlight_shapes::bench::FILE));
    airlight_truth::io::write_atomic(&path, b.to_json().as_bytes())
        .map_err(|e| Failure(1, format!("{}: cannot write: {e}", path.display())))?;
    println!("wrote {}; `airlight generate` puts it into REPORT.md", path.display());
    Ok(())
}

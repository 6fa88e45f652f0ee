//! `airlight plan`: a scene file from anywhere, planned (each candidate model with
//! its declared bound and measured cost, and the pick) and, with `--out`, its
//! kernel written there for each target the scene names — the bytes `generate`
//! writes for a scene of `codegen/scenes/`.

use crate::workspace::{generated_dir, registry};
use crate::{bad_input, Failure};
use airlight_codegen::SceneKernel;
use std::path::{Path, PathBuf};

/// Reads and plans the scene file `file` against the models and the measured
/// costs of the repository at `root` (found from the current directory if
/// `None`). Errors in the file come back as bad input naming its line and field.
pub(crate) fn plan_file(
    file: &Path,
    root: Option<PathBuf>,
) -> Result<(airlight_codegen::scene::Scene, SceneKernel), Failure> {
    let generated = generated_dir(root)?;
    let shown = file.display().to_string();
    let text = std::fs::read_to_string(file).map_err(|e| bad_input(format!("{shown}: cannot read: {e}")))?;
    let scene = airlight_codegen::scene::parse(&shown, &text).map_err(bad_input)?;
    let (_, models) = registry(Some(generated.parent().map(Path::to_path_buf).unwrap_or_default()))?;
    if models.is_empty() {
        return Err(bad_input(format!(
            "{}: no coefficient files; run `airlight regenerate` first",
            generated.join("coefficients").display()
        )));
    }
    let recorded = airlight_codegen::read_recorded(&generated).map_err(bad_input)?;
    let kernel = airlight_codegen::scene_kernel(&scene, &models, &recorded).map_err(|e| match e {
        airlight_codegen::RenderError::Scene(..) => bad_input(e.to_string()),
        _ => Failure(1, format!("{shown}: {e}")),
    })?;
    Ok((scene, kernel))
}

pub(crate) fn plan(file: &Path, out: Option<&Path>, root: Option<PathBuf>) -> Result<(), Failure> {
    let (_, kernel) = plan_file(file, root)?;
    print!("{}", String::from_utf8_lossy(&kernel.plan_file.contents));
    let Some(out) = out else {
        println!("\n(plan only: `--out DIR` writes the kernel's files)");
        return Ok(());
    };
    let mut outputs = kernel.files.clone();
    outputs.push(kernel.plan_file.clone());
    let changed = airlight_codegen::write_all(out, &outputs).map_err(|e| Failure(1, e.to_string()))?;
    println!();
    for o in &outputs {
        println!("wrote {}", out.join(&o.path).display());
    }
    println!("{} file(s), {} changed", outputs.len(), changed.len());
    Ok(())
}

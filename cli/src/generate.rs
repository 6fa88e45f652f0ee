//! `airlight generate` (render `generated/` from the committed inputs, or check
//! it) and `airlight regenerate` (self-check, fit, measure, render, gate).

use crate::check::{gate_gpu, run_gate};
use crate::fit::{build_models, measure, print_fits, run_fits};
use crate::workspace::{delegate, generated_dir, registry, write_outputs};
use crate::{bad_input, Failure};
use airlight_fit::coeffs::ModelFile;
use airlight_shapes::vocab::{CompiledKernel, Domain};
use airlight_truth::selfcheck;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Everything under `generated/`, with the scenes of `codegen/scenes/` (next to `generated/`).
pub(crate) fn render(
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

pub(crate) fn generate(root: Option<PathBuf>, check_only: bool) -> Result<(), Failure> {
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

pub(crate) fn regenerate(root: Option<PathBuf>, kernels: Option<&[CompiledKernel]>) -> Result<(), Failure> {
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

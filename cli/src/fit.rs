//! `airlight fit`: every family's fit, the models assembled and measured, the
//! coefficient files written; with `--family`, one part fitted and printed.

use crate::workspace::{generated_dir, with_progress, write_outputs};
use crate::{bad_input, Failure};
use airlight_fit::catalog;
use airlight_fit::coeffs::{self, ModelFile};
use airlight_fit::family::Fits;
use airlight_truth::selfcheck;
use std::path::PathBuf;
use std::time::Instant;

/// Fits (every family, or the one part named) with a progress bar.
pub(crate) fn run_fits(only: Option<&str>) -> Fits {
    with_progress("fitting families", |progress| Fits::fit(only, progress))
}

/// Assembles and measures every shipped model from the fits (progress bar).
pub(crate) fn build_models(fits: &Fits) -> Result<Vec<ModelFile>, Failure> {
    with_progress("measuring models", |progress| catalog::build(fits, progress)).map_err(|e| Failure(1, e))
}

pub(crate) fn print_fits(fits: &Fits) {
    for line in fits.summary() {
        println!("{line}");
    }
}

pub(crate) fn fit(family: Option<&str>, root: Option<PathBuf>) -> Result<(), Failure> {
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

/// Runs the reference self-check with a progress bar.
pub(crate) fn measure() -> selfcheck::SelfCheck {
    with_progress("reference self-check", selfcheck::run_standard)
}

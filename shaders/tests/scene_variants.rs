//! Scene specialisations that no committed scene exercises — the closed form with
//! surfaces, a baked g, a g range without surfaces, HG without extinction, no
//! backward part — rendered in memory and run on the adapter in WGSL and GLSL
//! against the reference, within their model's declared bound (skipped loudly
//! without an adapter unless `AIRLIGHT_REQUIRE_GPU=1`).

use crate::common;

use airlight_codegen::kernel::{self, Index, KernelSpec};
use airlight_codegen::scene;
use airlight_shaders::gate::project;
use airlight_shaders::{KernelSource, Target};
use airlight_truth::domains::{Domain, VALIDATION_SEED};
use airlight_truth::reference::airlight;
use std::path::Path;

/// A scene file; without extinction the medium is clear (σt = 0), the only one
/// where ignoring extinction meets a budget.
fn scene_text(phase: &str, extinction: bool, surfaces: bool, backscatter: bool, budget: f64) -> String {
    let sigma_t = if extinction { 0.5 } else { 0.0 };
    format!(
        "[medium]\nsigma_t = [0.0, {sigma_t:?}]\n{phase}\nextinction = {extinction}\n\n[lights]\nkind = \"point\"\nmax_distance = 30.0\n\n\
         [ray]\nsurfaces = {surfaces}\nbackscatter = {backscatter}\n\n[accuracy]\nmax_rel_error = {budget}\n\n[output]\ntargets = [\"wgsl\", \"glsl\"]\n"
    )
}

#[test]
fn unexercised_specialisations_compute_within_their_bounds_on_the_gpu() {
    let Some(gpu) = common::open_or_skip("unexercised_specialisations_compute_within_their_bounds_on_the_gpu") else {
        return;
    };
    let models =
        airlight_fit::catalog::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated/coefficients")).unwrap();
    let variants = [
        ("closed form with surfaces", scene_text("phase = \"isotropic\"", false, true, true, 0.01)),
        ("baked g", scene_text("phase = \"hg\"\ng = 0.5", true, true, true, 1.0)),
        ("g range, no surfaces", scene_text("phase = \"hg\"\ng_range = [-0.3, 0.6]", true, false, true, 1.0)),
        ("HG without extinction", scene_text("phase = \"hg\"\ng = -0.4", false, true, true, 1.0)),
        ("no backward part", scene_text("phase = \"isotropic\"", true, true, false, 1.0)),
    ];
    for (what, text) in variants {
        let s = scene::parse("variant.toml", &text).unwrap();
        let plan = scene::plan(&s, &models, None).unwrap();
        let spec = KernelSpec::for_scene(&s, &plan, &models, "variant.toml");
        let outputs = kernel::render(std::slice::from_ref(&spec)).unwrap();
        let index_text = String::from_utf8(kernel::render_index(std::slice::from_ref(&spec)).contents).unwrap();
        let entry = Index::parse("kernels.toml", &index_text).unwrap().kernel.remove(0);
        let declared = match &entry.model {
            None => 0.0,
            Some(_) if !entry.backscatter => 1.0,
            Some(m) => {
                let m = models.iter().find(|f| &f.model.name == m).unwrap();
                entry.domains.iter().map(|&d| m.error(d).unwrap().max_rel).fold(0.0, f64::max)
            }
        };
        let mut pts = Vec::new();
        for d in [Domain::Thin, Domain::Dense] {
            if entry.domains.contains(&d) {
                pts.extend(
                    d.validation_set((entry.g[0], entry.g[1]), 1500, VALIDATION_SEED ^ 0x5CE)
                        .into_iter()
                        .map(|p| project(&entry, p)),
                );
            }
        }
        let exact: Vec<f64> = pts.iter().map(|p| airlight(*p).unwrap()).collect();
        let raw: Vec<[f64; 4]> = pts.iter().map(|p| [p.tau, p.gamma, p.rho, p.g]).collect();
        for (language, file) in [(Target::Wgsl, &entry.wgsl), (Target::Glsl, &entry.glsl)] {
            let file = file.as_ref().unwrap();
            let source = String::from_utf8(outputs.iter().find(|o| &o.path == file).unwrap().contents.clone()).unwrap();
            let src = KernelSource::of(&entry, language, &source);
            let got = gpu.airlight(&src, &raw).unwrap_or_else(|e| panic!("{what} ({}): {e}", language.name()));
            let mut worst = 0.0f64;
            for (i, (&v, &a)) in got.iter().zip(&exact).enumerate() {
                assert!(v.is_finite() && v >= 0.0, "{what} ({}): {v} at {:?}", language.name(), pts[i]);
                if (1e-30..1e30).contains(&a) {
                    worst = worst.max((f64::from(v) - a).abs() / a);
                }
            }
            eprintln!(
                "{what} ({}), model {:?}: max {worst:.2e}, declared {declared:.2e}",
                language.name(),
                entry.model
            );
            assert!(
                worst <= airlight_shapes::vocab::f32_limit(declared),
                "{what} ({}): {worst:.3e} > declared {declared:.3e}",
                language.name()
            );
        }
    }
}

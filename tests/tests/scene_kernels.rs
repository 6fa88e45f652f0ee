//! Scene kernels carry only what their scene needs, and compute what the model
//! (or the exact closed form) computes.

use airlight_codegen::kernel::{self, KernelPhase, KernelSpec};
use airlight_codegen::scene;
use airlight_fit::model::Model;
use airlight_tests::{committed_models, generated_dir, repo_root};
use airlight_truth::reference::{airlight, Point};
use std::f64::consts::PI;

/// A scene file; without extinction the medium is clear (σt = 0), the only one
/// where ignoring extinction meets a budget.
fn scene_text(phase: &str, extinction: bool, surfaces: bool, budget: f64) -> String {
    let sigma_t = if extinction { 0.05 } else { 0.0 };
    format!(
        "[medium]\nsigma_t = [0.0, {sigma_t:?}]\n{phase}\nextinction = {extinction}\n\n[lights]\nkind = \"point\"\nmax_distance = 30.0\n\n\
         [ray]\nsurfaces = {surfaces}\nbackscatter = true\n\n[accuracy]\nmax_rel_error = {budget}\n\n[output]\ntargets = [\"wgsl\", \"glsl\", \"rust\"]\n"
    )
}

/// The scene's kernels as rendered in memory: (path, text).
/// The scene's kernel planned among the split family's models: these tests are
/// about how that family specialises (the baselines and the φ family, which the
/// planner picks where they are cheaper, are planned and rendered in
/// `scene_variants`).
fn render(text: &str) -> (KernelSpec, Vec<(String, String)>) {
    let models: Vec<_> = committed_models().into_iter().filter(|m| m.model.split().is_some()).collect();
    let s = scene::parse("test.toml", text).unwrap();
    let plan = scene::plan(&s, &models, None).unwrap();
    let spec = KernelSpec::for_scene(&s, &plan, &models, "test.toml");
    let out = kernel::render(std::slice::from_ref(&spec)).unwrap();
    let files = out
        .into_iter()
        .filter(|o| o.path.contains("scene-test") || o.path.contains("scene_test"))
        .map(|o| (o.path, String::from_utf8(o.contents).unwrap()))
        .collect();
    (spec, files)
}

/// `glslangValidator` compiles the include as ES 3.00 (fragment) and 4.50 (compute).
fn glslang_compiles(glsl: &str, what: &str) {
    // One directory per call: tests calling this run in parallel threads.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("airlight-scene-glsl-{}-{call}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (ext, src) in [
        ("frag", format!("#version 300 es\n{glsl}\nout highp vec4 c;\nvoid main() {{ c = vec4(0.0); }}\n")),
        ("comp", format!("#version 450\n{glsl}\nlayout(local_size_x = 1) in;\nvoid main() {{}}\n")),
    ] {
        let file = dir.join(format!("k.{ext}"));
        std::fs::write(&file, src).unwrap();
        let out = std::process::Command::new("glslangValidator")
            .arg(&file)
            .output()
            .expect("glslangValidator (glslang-tools)");
        assert!(out.status.success(), "{what} as {ext}: {}", String::from_utf8_lossy(&out.stdout));
    }
    std::fs::remove_dir_all(&dir).ok();
}

fn naga_validates(wgsl: &str) {
    let module = naga::front::wgsl::parse_str(wgsl).unwrap_or_else(|e| panic!("{}", e.emit_to_string(wgsl)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(&module)
        .unwrap();
}

#[test]
fn isotropic_without_surfaces_has_no_phase_or_surface_code() {
    // The committed example, in every target.
    let paths = [
        "wgsl/scene-harbour-fog.wgsl",
        "wgsl/bevy/scene-harbour-fog.wgsl",
        "glsl/scene-harbour-fog.glsl",
        "airlight-kernels/src/scene_harbour_fog.rs",
    ];
    for p in paths {
        let text = std::fs::read_to_string(generated_dir().join(p)).unwrap();
        for word in ["phase", "Phase", "surface", "rho", "ρ", "mirrored", "band"] {
            assert!(!text.contains(word), "{p} contains '{word}'");
        }
    }
    // The general kernel of the same model has both.
    let general = std::fs::read_to_string(generated_dir().join("wgsl/phi-iso-4.wgsl")).unwrap();
    assert!(general.contains("rho") && general.contains("surface"));
    let hg = std::fs::read_to_string(generated_dir().join("wgsl/hg-exp2.wgsl")).unwrap();
    assert!(hg.contains("fn airlight_hg_exp2_phase(g: f32)"));
}

#[test]
fn a_fixed_g_bakes_one_bands_terms_and_a_g_range_keeps_only_its_bands() {
    // HG models' declared bounds are near 100% (REPORT.md), above it with the 25%
    // margin (hg-exp3's band [0.1, 0.3]: 1.2): budgets must allow it.
    let (spec, files) = render(&scene_text("phase = \"hg\"\ng = 0.5", true, true, 1.5));
    assert!(matches!(spec.phase, KernelPhase::Fixed(g) if g == 0.5));
    let (_, wgsl) = files.iter().find(|f| f.0 == "wgsl/scene-test.wgsl").unwrap();
    assert!(wgsl.contains("const airlight_scene_test_PHASE = airlight_scene_test_Phase("), "{wgsl}");
    assert!(!wgsl.contains("_phase(g: f32)") && !wgsl.contains("ga <="), "no band search");
    assert!(wgsl.contains("fn airlight_scene_test_airlight(tau: f32, gamma: f32, rho: f32) -> f32"));
    naga_validates(wgsl);
    let (_, glsl) = files.iter().find(|f| f.0 == "glsl/scene-test.glsl").unwrap();
    glslang_compiles(glsl, "scene-test");

    let (spec, files) = render(&scene_text("phase = \"hg\"\ng_range = [0.1, 0.3]", true, false, 1.5));
    let KernelPhase::Banded(bands) = &spec.phase else { panic!("{:?}", spec.phase) };
    assert_eq!(bands, &[0, 1], "g in [0.1, 0.3] lies in the bands [0, 0.2] and (0.2, 0.4]");
    let (_, wgsl) = files.iter().find(|f| f.0 == "wgsl/scene-test.wgsl").unwrap();
    assert_eq!(wgsl.matches("let x = ga - ").count(), 2, "two bands");
    assert!(wgsl.contains("fn airlight_scene_test_airlight(tau: f32, gamma: f32, g: f32) -> f32"));
    naga_validates(wgsl);
    let (_, glsl) = files.iter().find(|f| f.0 == "glsl/scene-test.glsl").unwrap();
    glslang_compiles(glsl, "scene-test");
}

#[test]
fn hg_without_extinction_drops_tau() {
    let (spec, files) = render(&scene_text("phase = \"hg\"\ng = -0.4", false, true, 1.0));
    assert!(!spec.extinction && spec.model.is_some());
    let (_, wgsl) = files.iter().find(|f| f.0 == "wgsl/scene-test.wgsl").unwrap();
    assert!(wgsl.contains("fn airlight_scene_test_airlight(gamma: f32, rho: f32) -> f32"), "{wgsl}");
    assert!(!wgsl.contains("sigma_t: f32"));
    naga_validates(wgsl);
}

#[test]
fn scene_kernels_compute_their_model_or_the_exact_closed_form() {
    let models = committed_models();
    // The model its plan chose, as the index names it.
    let text = std::fs::read_to_string(generated_dir().join("kernels.toml")).unwrap();
    let index = airlight_shapes::vocab::Index::parse("kernels.toml", &text).unwrap();
    let name = index.get("scene-harbour-fog").unwrap().model.clone().expect("a fitted model");
    let planned = models.iter().find(|m| m.model.name == name).unwrap();
    let harbour = airlight_kernels::kernel("scene-harbour-fog").unwrap();
    assert_eq!(harbour.params, ["tau", "gamma"]);
    let haze = airlight_kernels::kernel("scene-haze-sky").unwrap();
    assert_eq!(haze.params, ["gamma"]);
    let mut worst_model: f64 = 0.0;
    let mut worst_exact: f64 = 0.0;
    for i in 0..400 {
        let gamma = 0.01 + (PI - 0.02) * (i as f64 + 0.5) / 400.0;
        let tau = 12.0 * ((i * 37) % 400) as f64 / 400.0;
        let q = Point { tau: tau as f32 as f64, gamma: gamma as f32 as f64, rho: f64::INFINITY, g: 0.0 };
        let want = planned.model.eval_unchecked(q);
        let got = (harbour.airlight)(tau as f32, gamma as f32, -1.0, 0.0) as f64;
        worst_model = worst_model.max((got - want).abs() / want);
        let exact = airlight(Point { tau: 0.0, ..q }).unwrap();
        let got = (haze.airlight)(0.0, gamma as f32, -1.0, 0.0) as f64;
        worst_exact = worst_exact.max((got - exact).abs() / exact);
    }
    assert!(worst_model < 1e-4, "harbour-fog vs {name}: {worst_model:.2e}");
    assert!(worst_exact < 1e-5, "haze-sky vs the reference: {worst_exact:.2e}");
    // Physical entry: σs·I/D·A with A from the canonical form of the same geometry.
    let (origin, dir, light) = ([1.0f32, 2.0, 3.0], [0.0f32, 0.6, 0.8], [4.0f32, 10.0, 3.0]);
    let l = [3.0f64, 8.0, 0.0];
    let d = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
    let gamma = ((0.6 * l[1] + 0.8 * l[2]) / d).acos();
    let (sigma_t, sigma_s, intensity) = (0.02f64, 0.015f64, 50.0f64);
    let want = sigma_s * intensity / d
        * planned.model.eval_unchecked(Point { tau: sigma_t * d, gamma, rho: f64::INFINITY, g: 0.0 });
    let got = airlight_kernels::scene_harbour_fog::radiance(
        origin,
        dir,
        light,
        intensity as f32,
        sigma_t as f32,
        sigma_s as f32,
    ) as f64;
    assert!(((got - want) / want).abs() < 1e-5, "{got} vs {want}");
}

#[test]
fn example_scene_files_all_plan() {
    let models = committed_models();
    let scenes = scene::load_dir(&repo_root().join("codegen/scenes"), "codegen/scenes").unwrap();
    assert!(scenes.len() >= 4);
    for s in &scenes {
        scene::plan(s, &models, None).unwrap_or_else(|e| panic!("{}", s.plan_error(&e)));
        assert!(generated_dir().join(format!("plans/scene-{}.md", s.name)).exists());
    }
}

/// A scene whose lights cast shadows gets the shafts accumulator in every
/// target, and it compiles (naga, glslang ES 3.00 and 4.50); scenes without
/// shadows carry none of it; shadows need surfaces.
#[test]
fn shadows_bring_the_shafts_accumulator_and_nothing_else_does() {
    let text = std::fs::read_to_string(repo_root().join("codegen/scenes/window-shafts.toml")).unwrap();
    let s = scene::parse("window-shafts.toml", &text).unwrap();
    assert!(s.shadows && s.spot);
    // Planned among every committed model (the split family alone misses its budget).
    let models = committed_models();
    let t = scene::parse("test.toml", &text).unwrap();
    let spec = KernelSpec::for_scene(&t, &scene::plan(&t, &models, None).unwrap(), &models, "test.toml");
    assert!(spec.shafts);
    let files: Vec<(String, String)> = kernel::render(std::slice::from_ref(&spec))
        .unwrap()
        .into_iter()
        .filter(|o| o.path.contains("scene-test") || o.path.contains("scene_test"))
        .map(|o| (o.path, String::from_utf8(o.contents).unwrap()))
        .collect();
    assert!(files.len() >= 3);
    for (path, src) in &files {
        if path.ends_with(".wgsl") && !path.contains("bevy") {
            assert!(src.contains("fn airlight_scene_test_shafts_push_spot("), "{path}");
            naga_validates(src);
        }
        if path.ends_with(".glsl") {
            assert!(
                src.contains("void airlight_scene_test_shafts_push_spot(inout airlight_scene_test_Shafts acc"),
                "{path}"
            );
            glslang_compiles(src, path);
        }
        if path.ends_with(".rs") {
            assert!(src.contains("pub fn push_spot("), "{path}");
        }
    }
    for p in ["wgsl/scene-spot-harbour.wgsl", "glsl/scene-fog-street.glsl", "airlight-kernels/src/scene_hg_fog.rs"] {
        let text = std::fs::read_to_string(generated_dir().join(p)).unwrap();
        assert!(!text.contains("Shafts") && !text.contains("shafts"), "{p} has the shafts accumulator");
    }
    let open = text.replace("surfaces = true", "surfaces = false").replace("kind = \"spot\"", "kind = \"point\"");
    let e = scene::parse("w.toml", &open).unwrap_err().to_string();
    assert!(e.contains("field 'lights.shadows'") && e.contains("surfaces"), "{e}");
}

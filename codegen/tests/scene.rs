//! Scene files and the planner's choice of model, on the committed coefficient files
//! and bench (these tests name models; the planner's code does not).

use airlight_codegen::front::CostMeasure;
use airlight_codegen::scene::*;
use airlight_fit::coeffs::ModelFile;
use airlight_shapes::bench::Bench;
use airlight_shapes::vocab::Target;
use std::path::Path;

fn models() -> Vec<ModelFile> {
    airlight_fit::coeffs::load_dir(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated/coefficients")).unwrap()
}

fn bench() -> Bench {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated/bench.json");
    Bench::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    parse(&path.display().to_string(), &std::fs::read_to_string(&path).unwrap()).unwrap()
}

#[test]
fn example_scenes_get_the_cheapest_model_meeting_their_budget() {
    let models = models();
    // Counted calls rank here (no bench). fog-street's 2% budget is below
    // lite-iso-2's declared 2.5e-2 (its searched 2.0e-2 with the 25% margin).
    for (file, want) in
        [("fog-street.toml", "lite-iso-3"), ("smoke-room.toml", "lite-iso-3"), ("harbour-fog.toml", "lite-iso-2")]
    {
        let s = scene(file);
        let p = plan(&s, &models, None).unwrap();
        let Choice::Model { name, bound, cost } = &p.choice else { panic!("{file}: {:?}", p.choice) };
        assert_eq!(name, want, "{file}");
        assert!(*bound <= s.max_rel_error);
        // Nothing cheaper would have done.
        for m in &models {
            if m.model.cost() < cost.calls && m.model.g_range.0 <= 0.0 && m.model.g_range.1 >= 0.0 {
                let b = p.domains.iter().map(|&d| m.error(d).unwrap().max_rel).fold(0.0, f64::max);
                assert!(b > s.max_rel_error, "{file}: {} (cost {}) meets {b}", m.model.name, m.model.cost());
            }
        }
    }
    assert_eq!(plan(&scene("haze-sky.toml"), &models, None).unwrap().choice, Choice::NoExtinction);
}

/// Issue 37: a plan error says what is wrong in a line a person reads — τ in
/// four digits however far the lights are, and a `g` no model covers by name.
#[test]
fn plan_errors_name_tau_shortly_and_an_uncovered_g() {
    let models = models();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hg-fog.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let far = text.replacen("max_distance = 150.0", "max_distance = 1e300", 1);
    let e = plan(&parse("s.toml", &far).unwrap(), &models, None).unwrap_err().to_string();
    assert!(e.contains("τ = σt·D = ") && e.len() < 200 && !e.contains("0000000000"), "{e}");
    let wide = text.replacen("\ng = 0.8\n", "\ng = 0.995\n", 1);
    let e = plan(&parse("s.toml", &wide).unwrap(), &models, None).unwrap_err().to_string();
    assert!(e.contains("no model covers g = 0.995") && e.contains("[-0.99, 0.99]"), "{e}");
}

/// With the bench, each example scene gets the model that is cheapest by the
/// cost measured where its kernels run (the GPU path for WGSL/GLSL scenes, the
/// CPU for a Rust-only one) among those meeting its budget.
#[test]
fn scenes_rank_by_the_cost_measured_on_their_target() {
    let (models, b) = (models(), bench());
    for file in [
        "fog-street.toml",
        "smoke-room.toml",
        "harbour-fog.toml",
        "hg-fog.toml",
        "backscatter-aerosol.toml",
        "spot-harbour.toml",
    ] {
        for rust_only in [false, true] {
            let mut s = scene(file);
            if rust_only {
                s.targets = vec![Target::Rust];
            }
            let p = plan(&s, &models, Some(&b)).unwrap();
            let Ranking::Measured(measure) = p.ranking else { panic!("{file}: {:?}", p.ranking) };
            assert_eq!(measure == CostMeasure::Cpu, rust_only, "{file}: {measure:?}");
            let Choice::Model { name, bound, cost } = &p.choice else { panic!("{file}: {:?}", p.choice) };
            assert!(*bound <= s.max_rel_error);
            let ns = cost.ns.expect("the chosen model was measured");
            assert_eq!(Some(ns), measure.ns(b.model(name).unwrap()), "{file}: {name}");
            let (g_lo, g_hi) = s.phase.g_range();
            for m in models.iter().filter(|m| m.model.g_range.0 <= g_lo && g_hi <= m.model.g_range.1) {
                let Some(o) = b.model(&m.model.name).and_then(|bm| measure.ns(bm)) else { continue };
                // Cheaper beyond the tie: it must miss the budget.
                if o * (1.0 + COST_TIE) < ns {
                    let baked = if let ScenePhase::Fixed(g) = s.phase { Some(g) } else { None };
                    let bm = p.domains.iter().map(|&d| m.bound_at(d, baked).unwrap()).fold(0.0, f64::max);
                    assert!(
                        bm > s.max_rel_error,
                        "{file}: {} ({o} ns) meets {bm} but {name} ({ns} ns) was chosen",
                        m.model.name
                    );
                }
            }
        }
    }
}

#[test]
fn impossible_scenes_say_why_and_name_the_best_bound() {
    let models = models();
    let mut s = scene("smoke-room.toml");
    s.max_rel_error = 1e-6;
    let e = plan(&s, &models, None).unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with("no model meets max_rel_error = 0.000001; the best achievable for this scene is"), "{msg}");
    assert!(msg.contains("phi-iso-8"), "{msg}");
    s.max_distance = 100.0;
    assert_eq!(plan(&s, &models, None).unwrap_err(), PlanError::OutsideDomains { tau_max: 50.0 });
    let mut hg = scene("fog-street.toml");
    hg.phase = ScenePhase::Fixed(0.9);
    hg.max_rel_error = 1e-6;
    assert!(matches!(plan(&hg, &models, None).unwrap_err(), PlanError::Budget { best: Some(_), .. }));
}

/// `extinction = false` is a modelling error of its own: measured at the
/// scene's optical distances and refused beyond the budget, naming the field.
#[test]
fn ignoring_extinction_must_fit_the_budget() {
    let models = models();
    let mut s = scene("haze-sky.toml");
    assert_eq!(plan(&s, &models, None).unwrap().ignored_extinction, 0.0, "σt = 0: exact");
    // Fog at 2 km: σt·D = 2, where dropping extinction is off by orders of magnitude.
    s.sigma_t = (0.0, 1e-3);
    let e = plan(&s, &models, None).unwrap_err();
    let PlanError::IgnoredExtinction { tau_max, error, .. } = e else { panic!("{e:?}") };
    assert!(tau_max == 2.0 && error > 1.0, "{error}");
    let msg = s.plan_error(&e).to_string();
    assert!(msg.contains("field 'medium.extinction'") && msg.contains("set extinction = true"), "{msg}");
    assert_eq!(s.plan_error(&e).line, s.text.lines().position(|l| l.starts_with("extinction")).unwrap() + 1);
    // Clear air: σt·D = 2e-6 costs a little, which the plan states.
    s.sigma_t = (0.0, 1e-9);
    let p = plan(&s, &models, None).unwrap();
    assert!(p.ignored_extinction > 0.0 && p.ignored_extinction < s.max_rel_error, "{}", p.ignored_extinction);
}

#[test]
fn bad_fields_name_file_line_and_field() {
    let good = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/fog-street.toml")).unwrap();
    let cases = [
        ("phase = \"isotropic\"", "phase = \"mie\"", "field 'medium.phase'"),
        ("max_rel_error = 0.02", "max_rel_error = -1", "field 'accuracy.max_rel_error'"),
        ("kind = \"point\"", "kind = \"area\"", "field 'lights.kind'"),
        ("targets = [\"wgsl\", \"glsl\", \"rust\"]", "targets = [\"hlsl\"]", "field 'output.targets'"),
        ("sigma_t = [0.0, 0.04]", "sigma_t = [0.04, 0.0]", "field 'medium.sigma_t'"),
    ];
    for (from, to, want) in cases {
        let text = good.replacen(from, to, 1);
        assert_ne!(text, good, "{from}");
        let line = text.lines().position(|l| l.contains(to)).unwrap() + 1;
        let e = parse("s.toml", &text).unwrap_err().to_string();
        assert!(e.starts_with(&format!("s.toml:{line}: {want}")), "{e}");
    }
    // An isotropic medium refuses a g it would ignore, on g's own line.
    let text = good.replacen("phase = \"isotropic\"", "phase = \"isotropic\"\ng = 0.5", 1);
    let e = parse("s.toml", &text).unwrap_err().to_string();
    let line = text.lines().position(|l| l == "g = 0.5").unwrap() + 1;
    assert!(e.starts_with(&format!("s.toml:{line}: field 'medium.g'")) && e.contains("isotropic"), "{e}");
    // A spot scene needs surfaces (its cone ends the lit stretch).
    let spot = good.replacen("kind = \"point\"", "kind = \"spot\"", 1);
    assert!(parse("s.toml", &spot).unwrap().spot);
    let text = spot.replacen("surfaces = true", "surfaces = false", 1);
    let line = text.lines().position(|l| l.starts_with("surfaces")).unwrap() + 1;
    let e = parse("s.toml", &text).unwrap_err().to_string();
    assert!(e.starts_with(&format!("s.toml:{line}: field 'ray.surfaces'")), "{e}");
    let e = parse("s.toml", "[medium\n").unwrap_err().to_string();
    assert!(e.starts_with("s.toml:1: field '(syntax)'"), "{e}");
}

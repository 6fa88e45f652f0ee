//! The committed coefficient files: exact round trip, the keys the project
//! promises, and models that stay finite and non-negative at the extremes.

use airlight_fit::coeffs::{parse, render};
use airlight_fit::model::Model;
use airlight_tests::{committed_models, generated_dir};
use airlight_truth::domains::Domain;
use airlight_truth::reference::Point;
use std::f64::consts::PI;

#[test]
fn files_round_trip_exactly_and_carry_the_promised_keys() {
    for m in committed_models() {
        let text = render(&m);
        let back = parse("x.toml", &text).expect("parses");
        assert_eq!(back, m, "{}: parse(render(m)) differs", m.model.name);
        let raw = std::fs::read_to_string(generated_dir().join(format!("coefficients/{}.toml", m.model.name))).unwrap();
        let doc: toml::Table = raw.parse().unwrap();
        for key in ["name", "families", "g_range"] {
            assert!(doc["model"].get(key).is_some(), "{}: [model].{key}", m.model.name);
        }
        for d in ["thin", "dense"] {
            let e = &doc["error"][d];
            for key in ["max_rel", "p99_rel", "worst"] {
                assert!(e.get(key).is_some(), "{}: [error.{d}].{key}", m.model.name);
            }
            assert!(e["points"].as_integer().unwrap() >= 10_000);
        }
        for key in ["reference_rel_tol", "validation_seed", "crate"] {
            assert!(doc["provenance"].get(key).is_some(), "{}: [provenance].{key}", m.model.name);
        }
        // Every hex coefficient's comment is its decimal value.
        for line in raw.lines().filter(|l| l.trim_start().starts_with("\"0x") || l.trim_start().starts_with("\"-0x")) {
            let (hex, comment) = line.split_once("\", #").expect("hex with comment");
            let x = airlight_truth::hexf::parse(hex.trim().trim_start_matches('"')).unwrap();
            let y: f64 = comment.trim().parse().unwrap();
            assert_eq!(x.to_bits(), y.to_bits(), "{line}");
        }
    }
}

#[test]
fn models_are_finite_and_non_negative_at_the_extremes() {
    let mut pts = Domain::Extreme.corners(&[0.0]);
    for tau in [0.0, 1e-8, 2.0, 20.0, 100.0] {
        for gamma in [0.0, 1e-9, 1e-4, 0.01, PI / 2.0, PI - 0.01, PI - 1e-9, PI] {
            for rho in [1e-6, 0.5, 1.0, 1.0 + 1e-9, 1e4, f64::INFINITY] {
                pts.push(Point { tau, gamma, rho, g: 0.0 });
            }
        }
    }
    for m in committed_models() {
        let (lo, hi) = m.model.g_range;
        for p in &pts {
            for g in [lo, 0.5 * (lo + hi), hi] {
                let p = Point { g, ..*p };
                let a = m.model.eval_unchecked(p);
                let on_axis_through_light = p.gamma == 0.0 && p.rho >= 1.0;
                assert!(a >= 0.0 && (a.is_finite() || on_axis_through_light), "{}: A = {a} at {p:?}", m.model.name);
            }
        }
    }
}

#[test]
fn model_geometry_limits() {
    use airlight_truth::reference::airlight;
    let models = committed_models();
    let m = &models.iter().find(|m| m.model.name == "segments-16").unwrap().model;
    // On the axis before the light: exact closed form P(0) e^{-τ} ρ/(1 − ρ).
    let p = Point { tau: 0.7, gamma: 0.0, rho: 0.4, g: 0.0 };
    let exact = airlight(p).unwrap();
    assert!((m.eval_unchecked(p) / exact - 1.0).abs() < 1e-14);
    // Continuous across γ = π/2, where the forward part vanishes and the backward
    // part starts at the foot point.
    for tau in [0.0, 1.0, 10.0] {
        let a = m.eval_unchecked(Point { tau, gamma: PI / 2.0 - 1e-9, rho: 3.0, g: 0.0 });
        let b = m.eval_unchecked(Point { tau, gamma: PI / 2.0 + 1e-9, rho: 3.0, g: 0.0 });
        assert!((a / b - 1.0).abs() < 1e-6, "τ = {tau}: {a} vs {b}");
    }
    // Continuous in ρ across the far part's switch between its local sum and E1 form.
    let gamma: f64 = 3.0; // ua = tan(1.5) ≈ 14.1: the far part starts at u = 16
    let h = gamma.sin();
    let x0 = gamma.cos();
    let rho_at = |u1: f64| {
        // u = (ρ − x0 + t)/h with t = hypot(ρ − x0, h): invert for ρ.
        let d = (u1 * u1 * h * h - h * h) / (2.0 * u1 * h);
        x0 + d
    };
    let r = rho_at(32.0);
    let a = m.eval_unchecked(Point { tau: 2.0, gamma, rho: r * (1.0 - 1e-12), g: 0.0 });
    let b = m.eval_unchecked(Point { tau: 2.0, gamma, rho: r * (1.0 + 1e-12), g: 0.0 });
    assert!((a / b - 1.0).abs() < 1e-3, "{a} vs {b}");
    // The error there is within the declared bound.
    let p = Point { tau: 2.0, gamma, rho: r, g: 0.0 };
    let e = (m.eval_unchecked(p) / airlight(p).unwrap() - 1.0).abs();
    assert!(
        e < 1.5
            * models
                .iter()
                .find(|f| f.model.name == "segments-16")
                .unwrap()
                .error(airlight_shapes::vocab::Domain::Thin)
                .unwrap()
                .max_rel
    );
}

/// Every way a coefficient file can be damaged is refused where it is parsed,
/// with the file, the line and the key.
#[test]
fn damaged_files_are_refused_naming_file_line_and_key() {
    let path = generated_dir().join("coefficients/segments-8.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let first_slope = text.lines().skip_while(|l| !l.starts_with("slopes")).nth(1).unwrap().to_string();
    let thin = text.find("[error.thin]").unwrap();
    let dense = text.find("[error.dense]").unwrap();
    // (what, damaged text, field, words of the message, the line starting with this, or 1)
    let cases: Vec<(&str, String, &str, &str, Option<&str>)> = vec![
        (
            "a coefficient beyond f32",
            text.replacen(&first_slope, "  \"-0x1p+900\", # -8.45e270", 1),
            "forward.slopes",
            "outside f32's range",
            Some("slopes ="),
        ),
        ("[error.thin] deleted", format!("{}{}", &text[..thin], &text[dense..]), "error.thin", "missing table", None),
        (
            "a negative bound",
            text.replacen("max_rel = ", "max_rel = -", 1),
            "error.thin.max_rel",
            ">= 0",
            Some("max_rel = -"),
        ),
        (
            "an unknown key",
            text.replacen("n = 8\n", "n = 8\nsegmnets = 8\n", 1),
            "forward.segmnets",
            "unknown key",
            Some("segmnets"),
        ),
        ("an unknown table", format!("{text}\n[extra]\nx = 1\n"), "extra", "unknown table", Some("[extra]")),
        (
            "another version",
            text.replacen("format_version = 1", "format_version = 2", 1),
            "format_version",
            "reads format_version = 1",
            Some("format_version = 2"),
        ),
        ("no version", text.replacen("format_version = 1\n", "", 1), "format_version", "missing", None),
        (
            "an unknown family",
            text.replacen("kind = \"split\"", "kind = \"splat\"", 1),
            "model.kind",
            "unknown family 'splat'",
            Some("kind = \"splat\""),
        ),
    ];
    for (what, damaged, field, says, at) in cases {
        assert_ne!(damaged, text, "{what}: the damage applies");
        let e = parse("segments-8.toml", &damaged).expect_err(what);
        let msg = e.to_string();
        assert_eq!(e.field, field, "{what}: {msg}");
        assert!(msg.contains(says), "{what}: {msg}");
        assert!(msg.starts_with("segments-8.toml:") && msg.lines().count() == 1, "{what}: {msg}");
        let line = at.map_or(1, |a| damaged.lines().position(|l| l.starts_with(a)).unwrap() + 1);
        assert_eq!(e.line, line, "{what}: {msg}");
    }
}

/// A damaged band bound is refused naming the line in its own `[[error.band]]`.
#[test]
fn damaged_band_bounds_are_refused_at_their_line() {
    let text = std::fs::read_to_string(generated_dir().join("coefficients/phi-4.toml")).unwrap();
    assert!(text.matches("[[error.band]]").count() >= 20, "phi-4 declares its bands");
    // The third band's g reversed, and its thin bound made negative.
    let third = text.match_indices("[[error.band]]").nth(2).unwrap().0;
    let (head, tail) = text.split_at(third);
    let g_line = tail.lines().find(|l| l.starts_with("g = ")).unwrap();
    let inner = g_line.trim_start_matches("g = [").trim_end_matches(']');
    let (lo, hi) = inner.split_once(", ").unwrap();
    let cases = [
        (tail.replacen(g_line, &format!("g = [{hi}, {lo}]"), 1), "error.band.g", "must be [lo, hi]", "g = ["),
        (tail.replacen("max_rel = ", "max_rel = -", 1), "error.band.max_rel", ">= 0", "max_rel = -"),
        (tail.replacen("points = ", "extra = 1\npoints = ", 1), "error.band.extra", "unknown key", "extra"),
    ];
    for (damaged_tail, field, says, at) in cases {
        let damaged = format!("{head}{damaged_tail}");
        let e = parse("phi-4.toml", &damaged).expect_err(field);
        let msg = e.to_string();
        assert_eq!(e.field, field, "{msg}");
        assert!(msg.contains(says) && msg.lines().count() == 1, "{msg}");
        let want = head.lines().count() + damaged_tail.lines().position(|l| l.starts_with(at)).unwrap() + 1;
        assert_eq!(e.line, want, "{field}: {msg}");
    }
}

/// Scene files refuse unknown keys too.
#[test]
fn scene_files_refuse_unknown_keys() {
    let path = airlight_tests::repo_root().join("codegen/scenes/fog-street.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let damaged = text.replacen("extinction = true", "extinction = true\nextintion = true", 1);
    let e = airlight_codegen::scene::parse("fog-street.toml", &damaged).unwrap_err();
    assert_eq!(e.field, "medium.extintion", "{e}");
    let line = damaged.lines().position(|l| l.starts_with("extintion")).unwrap() + 1;
    assert_eq!(e.line, line, "{e}");
    let damaged = format!("{text}\n[fog]\ndensity = 1\n");
    let e = airlight_codegen::scene::parse("fog-street.toml", &damaged).unwrap_err();
    assert_eq!(e.field, "fog", "{e}");
}

//! `generated/` is what `airlight generate` renders now from the committed
//! coefficient files: every output is re-rendered in memory and compared byte for
//! byte with the committed files, and nothing else may sit there.

use airlight_tests::{committed_models, generated_dir};

#[test]
fn generated_matches_a_fresh_rendering() {
    let check = airlight_codegen::read_selfcheck(&generated_dir()).expect("generated/selfcheck.toml reads");
    let models = committed_models();
    assert_eq!(models.len(), airlight_fit::catalog::CATALOG.len(), "one coefficient file per catalog model");
    let scenes =
        airlight_codegen::scene::load_dir(&airlight_tests::repo_root().join("codegen/scenes"), "codegen/scenes")
            .expect("scenes parse");
    let renders = airlight_codegen::read_renders(&generated_dir()).expect("generated/render/ reads");
    let recorded = airlight_codegen::read_recorded(&generated_dir()).expect("recorded measurements parse");
    let outputs = airlight_codegen::render_all(&check, &models, &recorded, &scenes, &renders).expect("renders");
    let diffs = airlight_codegen::check(&generated_dir(), &outputs);
    assert!(
        diffs.is_empty(),
        "generated/ is stale; run `cargo run --release -- regenerate`:\n{}",
        diffs.iter().map(|d| d.to_string()).collect::<Vec<_>>().join("\n")
    );
    // The self-check itself must hold the reference's specification.
    assert_eq!(check.problems(), Vec::<String>::new());
}

/// The committed self-check is what the reference does now: `generate` passes it
/// through, so this is where a change to the reference shows.
#[test]
fn committed_selfcheck_is_current() {
    let committed = airlight_codegen::read_selfcheck(&generated_dir()).expect("generated/selfcheck.toml reads");
    let fresh = airlight_truth::selfcheck::run_standard(&|_, _| {});
    assert!(fresh == committed, "generated/selfcheck.toml is stale; run `cargo run --release -- regenerate`");
}

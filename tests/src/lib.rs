//! End-to-end tests across the airlight crates live in `tests/`; this library
//! holds what they share: where the repository and its committed outputs are.

pub mod calls;

use std::path::PathBuf;

/// The repository root (the workspace directory).
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).parent().expect("tests/ sits in the workspace").to_path_buf()
}

/// The committed `generated/` directory.
pub fn generated_dir() -> PathBuf {
    repo_root().join("generated")
}

/// The package a WESL user imports the kernels' modules from: the Bevy 0.20
/// plugin crate's name, which `load_shader_library!` makes the first component
/// of `embedded://bevy_airlight/<kernel>.wesl`, and Bevy's loader the package.
pub const WESL_PACKAGE: &str = "bevy_airlight";

/// Where the committed WESL modules are: the plugin crate's `src/`.
pub fn wesl_dir() -> PathBuf {
    generated_dir().join("bevy_airlight/src")
}

/// The committed coefficient files, in catalog order.
pub fn committed_models() -> Vec<airlight_fit::coeffs::ModelFile> {
    airlight_fit::catalog::load(&generated_dir().join("coefficients")).expect("committed coefficient files parse")
}

/// `n` independent uniform random points (not the validation sets' Halton
/// sequence) inside `domain` (thin or dense) with `g` uniform in `g`: γ in
/// [0.01, π − 0.01], ρ = ∞ for a tenth, else log-uniform in [0.01, 100].
pub fn random_points(
    domain: airlight_truth::domains::Domain,
    g: (f64, f64),
    n: usize,
    seed: u64,
) -> Vec<airlight_truth::reference::Point> {
    let mut rng = airlight_truth::domains::SplitMix64(seed);
    let (tlo, thi) = domain.tau_range();
    (0..n)
        .map(|_| {
            let tau = tlo + (thi - tlo) * rng.next_f64();
            let gamma = 0.01 + (std::f64::consts::PI - 0.02) * rng.next_f64();
            let rho = if rng.next_f64() < 0.1 { f64::INFINITY } else { 0.01 * 1e4f64.powf(rng.next_f64()) };
            let gv = g.0 + (g.1 - g.0) * rng.next_f64();
            airlight_truth::reference::Point { tau, gamma, rho, g: gv }
        })
        .collect()
}

/// `tests/node/`, where `.ci/run` installs the pinned npm tools (`npm ci`), if
/// `package` is installed there. Without it a test skips, unless the environment
/// requires every tool (`AIRLIGHT_REQUIRE_GPU=1`, as CI sets, or
/// `AIRLIGHT_REQUIRE_NPM=1`): then the test fails.
pub fn npm_tools(package: &str) -> Option<PathBuf> {
    let dir = repo_root().join("tests/node");
    if dir.join("node_modules").join(package).join("package.json").exists() {
        return Some(dir);
    }
    let required =
        ["AIRLIGHT_REQUIRE_GPU", "AIRLIGHT_REQUIRE_NPM"].iter().any(|v| std::env::var(v).is_ok_and(|x| x == "1"));
    assert!(
        !required,
        "npm package {package} not installed in tests/node: run `npm ci --prefix tests/node` (see README)"
    );
    eprintln!("SKIPPED: npm package {package} not installed (npm ci --prefix tests/node; AIRLIGHT_REQUIRE_NPM=1 makes this a failure)");
    None
}

//! Properties every committed model keeps for any valid input up to the `extreme`
//! domain's τ = 100 and far outside the fitted ρ and γ (the GPU gate will count NaN,
//! ∞ and negative values as failures): finite, non-negative, and positive wherever
//! the exact value is.

use airlight_fit::model::Model;
use airlight_tests::committed_models;
use airlight_truth::reference::{airlight, Point};
use proptest::prelude::*;
use std::f64::consts::PI;
use std::sync::OnceLock;

fn models() -> &'static [airlight_fit::coeffs::ModelFile] {
    static MODELS: OnceLock<Vec<airlight_fit::coeffs::ModelFile>> = OnceLock::new();
    MODELS.get_or_init(committed_models)
}

fn point() -> impl Strategy<Value = (f64, f64, f64, f64)> {
    (
        prop_oneof![Just(0.0), 1e-9..1e-3f64, 1e-3..50.0f64, 50.0..100.0f64],
        prop_oneof![1e-9..1e-3f64, 1e-3..PI, (1e-9..1e-3f64).prop_map(|d| PI - d)],
        prop_oneof![Just(f64::INFINITY), 1e-6..1e-2f64, 1e-2..1e2f64, 1e2..1e8f64],
        0.0..1.0f64,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn finite_and_non_negative((tau, gamma, rho, u) in point()) {
        for m in models() {
            let (lo, hi) = m.model.g_range;
            let p = Point { tau, gamma, rho, g: lo + (hi - lo) * u };
            let a = m.model.eval_unchecked(p);
            prop_assert!(a.is_finite() && a >= 0.0, "{}: A = {a} at {p:?}", m.model.name);
            // A baseline may return 0 where A is not (a march whose samples all
            // miss the light): the method's answer, measured by its error.
            if a == 0.0 && !m.model.body.is_baseline() {
                let exact = airlight(p).unwrap();
                prop_assert!(exact == 0.0, "{}: 0 where A = {exact} at {p:?}", m.model.name);
            }
        }
    }
}

/// Every model and the reference are continuous into γ = 0 and ρ → 0: each
/// model at γ = 1e-12 … 1e-200 agrees with its own exact on-axis value at γ = 0
/// (to 1e-8), and so does the reference; `A/ρ` settles as ρ → 0; and no digits
/// are lost on the way: the relative error against the reference at γ = 1e-20
/// (ρ = 1e-20) is that at 1e-8, where the limit is already reached (the defect
/// this guards against was 122% at γ = 1e-16 and exactly 0 beyond). Against
/// γ = 1e-4 the error may differ by the model's own smooth change: hg-exp3 at
/// τ = 0, ρ = 0.999, g = 0.5 goes from 2.1% at 1e-4 through 7.9% at 1e-5 to 9.0%
/// on the axis, far outside the domains its bound covers (γ ≥ 0.01); the Sun
/// table still moves by 3e-10 below 1e-8 (`T = τ h` enters its bilinear lookup
/// linearly), hence the 1e-9 slack.
#[test]
fn continuous_into_gamma_zero_and_rho_zero() {
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    for &(tau, rho) in &[(1.0, 0.5), (0.1, 0.9), (5.0, 0.2), (0.0, 0.999)] {
        for g in [0.0, 0.5, -0.5] {
            let at = |gamma: f64| Point { tau, gamma, rho, g };
            let axis = airlight(at(0.0)).unwrap();
            for gamma in [1e-12, 1e-20, 1e-200] {
                assert!(rel(airlight(at(gamma)).unwrap(), axis) < 1e-12, "reference at {:?}", at(gamma));
            }
            for m in models() {
                let (lo, hi) = m.model.g_range;
                if g < lo || g > hi {
                    continue;
                }
                let own = m.model.eval_unchecked(at(0.0));
                let err = |gamma: f64| rel(m.model.eval_unchecked(at(gamma)), airlight(at(gamma)).unwrap());
                let e8 = err(1e-8);
                for gamma in [1e-12, 1e-16, 1e-20, 1e-200] {
                    let v = m.model.eval_unchecked(at(gamma));
                    assert!(rel(v, own) < 1e-8, "{}: {v} at γ = {gamma}, {own} at 0 ({:?})", m.model.name, at(gamma));
                }
                let e = err(1e-20);
                assert!(
                    e <= 1.01 * e8 + 1e-9,
                    "{}: error {e:.2e} at γ = 1e-20 > {e8:.2e} at 1e-8 ({:?})",
                    m.model.name,
                    at(1e-20)
                );
            }
        }
    }
    for &(tau, gamma) in &[(1.0, 1.0), (1.0, 3.0), (10.0, 2.0), (0.5, 0.01), (2.0, 3.1)] {
        for g in [0.0, 0.5, -0.5] {
            let at = |rho: f64| Point { tau, gamma, rho, g };
            let per = |v: f64, rho: f64| v / rho;
            let r = per(airlight(at(1e-200)).unwrap(), 1e-200);
            assert!(rel(per(airlight(at(1e-20)).unwrap(), 1e-20), r) < 1e-10, "reference A/ρ at {:?}", at(1e-20));
            for m in models() {
                let (lo, hi) = m.model.g_range;
                if g < lo || g > hi {
                    continue;
                }
                if m.model.body.texture().is_some() {
                    // Sun et al.'s method is a difference of two table lookups, which
                    // cancel as the lit stretch shrinks: the baseline as published.
                    continue;
                }
                let lim = per(m.model.eval_unchecked(at(1e-200)), 1e-200);
                for rho in [1e-12, 1e-20] {
                    let v = per(m.model.eval_unchecked(at(rho)), rho);
                    assert!(
                        rel(v, lim) < 1e-8,
                        "{}: A/ρ {v} at ρ = {rho}, {lim} at 1e-200 ({:?})",
                        m.model.name,
                        at(rho)
                    );
                }
                let err = |rho: f64| rel(m.model.eval_unchecked(at(rho)), airlight(at(rho)).unwrap());
                let (e8, e) = (err(1e-8), err(1e-20));
                assert!(
                    e <= 1.01 * e8 + 1e-9,
                    "{}: error {e:.2e} at ρ = 1e-20 > {e8:.2e} at 1e-8 ({:?})",
                    m.model.name,
                    at(1e-20)
                );
            }
        }
    }
}

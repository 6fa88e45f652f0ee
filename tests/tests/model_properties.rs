//! Properties every committed model keeps for any valid input up to the `extreme`
//! domain's τ = 100 and far outside the fitted ρ and γ (the GPU gate will count NaN,
//! ∞ and negative values as failures): finite, non-negative, and positive wherever
//! the exact value is.

use airlight_fit::model::Model;
use airlight_fit::reference::{airlight, Point};
use airlight_tests::committed_models;
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
            if a == 0.0 {
                let exact = airlight(p).unwrap();
                prop_assert!(exact == 0.0, "{}: 0 where A = {exact} at {p:?}", m.model.name);
            }
        }
    }
}

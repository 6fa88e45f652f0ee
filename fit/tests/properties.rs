//! Properties the exact airlight has for every input, checked on random points
//! over the whole domain (proptest shrinks any failure to a minimal point).

use airlight_truth::geometry::PhysicalRay;
use airlight_truth::reference::{airlight, Point};
use proptest::prelude::*;
use std::f64::consts::PI;

fn point_with(rho: impl Strategy<Value = f64>) -> impl Strategy<Value = Point> {
    (
        prop_oneof![Just(0.0), 1e-8..1e-3f64, 1e-3..100.0f64],
        prop_oneof![1e-8..1e-3f64, 1e-3..PI, (1e-8..1e-3f64).prop_map(|d| PI - d)],
        rho,
        prop_oneof![Just(0.0), -0.99..0.99f64],
    )
        .prop_map(|(tau, gamma, rho, g)| Point { tau, gamma, rho, g })
}

fn point() -> impl Strategy<Value = Point> {
    point_with(prop_oneof![Just(f64::INFINITY), 1e-4..1e4f64])
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

    /// Positive integrand: A is finite and > 0 off the axis.
    #[test]
    fn positive_and_finite(p in point()) {
        let a = airlight(p).unwrap();
        prop_assert!(a.is_finite() && a > 0.0, "A = {a}");
    }

    /// More ray (a farther surface) never means less light.
    #[test]
    fn grows_with_the_surface_distance(p in point_with(1e-4..1e4f64), k in 1.0001..10.0f64) {
        let near = airlight(p).unwrap();
        let far = airlight(Point { rho: p.rho * k, ..p }).unwrap();
        prop_assert!(far >= near * (1.0 - 1e-13), "{near} then {far}");
        let open = airlight(Point { rho: f64::INFINITY, ..p }).unwrap();
        prop_assert!(open >= far * (1.0 - 1e-13));
    }

    /// More extinction never means more light.
    #[test]
    fn falls_with_extinction(p in point(), dt in 1e-6..5.0f64) {
        let a = airlight(p).unwrap();
        let b = airlight(Point { tau: p.tau + dt, ..p }).unwrap();
        prop_assert!(b <= a * (1.0 + 1e-13), "{a} then {b}");
    }

    /// Henyey–Greenstein is `P_0 (1 ± 3g cos α + O(g²))` for small `±g`, so the
    /// mean of the `+g` and `−g` airlights equals the isotropic one to second order.
    #[test]
    fn small_g_is_close_to_isotropic(p in point(), g in 1e-6..1e-4f64) {
        let iso = airlight(Point { g: 0.0, ..p }).unwrap();
        let plus = airlight(Point { g, ..p }).unwrap();
        let minus = airlight(Point { g: -g, ..p }).unwrap();
        let mean = 0.5 * (plus + minus);
        prop_assert!(((mean - iso) / iso).abs() < 20.0 * g * g + 1e-13, "{iso} vs {mean}");
    }

    /// Any placement, scale and orientation of the same canonical point gives the
    /// same canonical point back.
    #[test]
    fn geometry_round_trip(p in point(), dist in 1e-4..1e6f64, off in prop::array::uniform3(-1.0..1.0f64)) {
        prop_assume!(p.gamma > 1e-6 && p.gamma < PI - 1e-6);
        let mut ray = PhysicalRay::from_canonical(p, dist, 0.5 * p.tau / dist, 2.0);
        let o = [off[0] * dist, off[1] * dist, off[2] * dist];
        ray.origin = o;
        ray.light = [ray.light[0] + o[0], ray.light[1] + o[1], ray.light[2] + o[2]];
        let c = ray.to_canonical(p.g).unwrap();
        prop_assert!(((c.point.tau - p.tau) / p.tau.max(1e-300)).abs() < 1e-13);
        prop_assert!(((c.point.gamma - p.gamma) / p.gamma).abs() < 1e-9);
        prop_assert!(c.point.rho == p.rho || ((c.point.rho - p.rho) / p.rho).abs() < 1e-13);
    }
}

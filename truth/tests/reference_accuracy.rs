//! The reference against 30-digit public values and against its independent paths.

use airlight_truth::domains::{Domain, VALIDATION_SEED};
use airlight_truth::fixtures;
use airlight_truth::reference::{airlight, airlight_detailed, airlight_e1, airlight_s_form, Point};
use airlight_truth::stats::rel_error;

fn load(name: &str) -> Vec<(Point, f64)> {
    let (_, text) = fixtures::PUBLIC.iter().find(|(n, _)| *n == name).expect("a public fixture");
    fixtures::parse(text)
}

fn check_public(name: &str, tol: f64) {
    let mut worst = (0.0, None);
    for (p, exact) in load(name) {
        let a = airlight(p).unwrap();
        let e = rel_error(a, exact);
        if e > worst.0 {
            worst = (e, Some((p, a, exact)));
        }
    }
    assert!(worst.0 <= tol, "{name}: worst relative error {:e} at {:?}", worst.0, worst.1);
}

#[test]
fn matches_public_30_digit_values() {
    check_public("airlight_public.csv", 1e-12);
}

#[test]
fn matches_public_extreme_values() {
    check_public("airlight_public_extreme.csv", 1e-12);
}

/// Primary (u form, Gauss–Kronrod) vs the s form (tanh–sinh) vs the E1 closed form.
fn cross_check(domain: Domain, g: (f64, f64), n: usize, seed: u64) {
    let mut worst_s = (0.0, None);
    let mut worst_e1 = (0.0, None);
    for p in domain.validation_set(g, n, seed) {
        let ev = airlight_detailed(p).unwrap();
        assert!(ev.converged, "not converged at {p:?}: {ev:?}");
        assert!(ev.value.is_finite() && ev.value >= 0.0, "{p:?}: {ev:?}");
        let s = airlight_s_form(p).unwrap();
        let e = rel_error(ev.value, s);
        if e > worst_s.0 {
            worst_s = (e, Some((p, ev.value, s)));
        }
        if p.g == 0.0 {
            let (v, cond) = airlight_e1(p).unwrap();
            let e = rel_error(ev.value, v) / cond.max(1.0);
            if e > worst_e1.0 {
                worst_e1 = (e, Some((p, ev.value, v, cond)));
            }
        }
    }
    assert!(worst_s.0 < 1e-12, "{domain:?} u vs s form: {:e} at {:?}", worst_s.0, worst_s.1);
    assert!(worst_e1.0 < 1e-12, "{domain:?} u vs E1 form: {:e} at {:?}", worst_e1.0, worst_e1.1);
}

#[test]
fn three_paths_agree_isotropic() {
    for d in Domain::ALL {
        cross_check(d, (0.0, 0.0), 1500, VALIDATION_SEED ^ 0x7E57);
    }
}

#[test]
fn u_and_s_forms_agree_henyey_greenstein() {
    for d in Domain::ALL {
        cross_check(d, (-0.95, 0.95), 1500, VALIDATION_SEED ^ 0x7E58);
    }
    cross_check(Domain::Extreme, (-0.99, 0.99), 0, 1);
}

/// Random points far outside the named domains: grazing angles down to 1e-8 rad
/// on both sides, surfaces from 1e-4 to 1e4 and just around the light's distance,
/// τ from 1e-8 to 100, g up to ±0.99. The u and s forms must agree to 1e-12.
#[test]
fn u_and_s_forms_agree_on_wide_random_points() {
    use airlight_truth::domains::SplitMix64;
    use std::f64::consts::PI;
    let mut r = SplitMix64(0xA1A1_2026);
    let mut worst = (0.0, None);
    for i in 0..3000 {
        let tau = if i % 17 == 0 { 0.0 } else { 10f64.powf(-8.0 + 10.0 * r.next_f64()) };
        let gamma = match i % 3 {
            0 => 10f64.powf(-8.0 + 8.5 * r.next_f64()).min(PI),
            1 => PI - 10f64.powf(-8.0 + 8.0 * r.next_f64()),
            _ => PI * r.next_f64(),
        };
        let rho = if i % 7 == 0 {
            f64::INFINITY
        } else if i % 11 == 0 {
            1.0 + (r.next_f64() - 0.5) * 1e-3
        } else {
            10f64.powf(-4.0 + 8.0 * r.next_f64())
        };
        let g = if i % 2 == 0 { 0.0 } else { (2.0 * r.next_f64() - 1.0) * 0.99 };
        let p = Point::new(tau, gamma, rho, g);
        let ev = airlight_detailed(p).unwrap();
        assert!(ev.converged && ev.value.is_finite() && ev.value > 0.0, "{p:?}: {ev:?}");
        let e = rel_error(ev.value, airlight_s_form(p).unwrap());
        if e > worst.0 {
            worst = (e, Some(p));
        }
        if g == 0.0 {
            let (v, cond) = airlight_e1(p).unwrap();
            let e = rel_error(ev.value, v) / cond.max(1.0);
            assert!(e < 1e-12, "E1 form disagrees by {e:e} at {p:?}");
        }
    }
    assert!(worst.0 < 1e-12, "u vs s form: {:e} at {:?}", worst.0, worst.1);
}

//! The generated Rust kernels (`airlight-kernels`, f32) against the f64 models
//! they were generated from, against the reference within each model's declared
//! bound plus f32 rounding, and at the extremes (finite, non-negative).

use airlight_fit::model::Model;
use airlight_tests::{committed_models, random_points};
use airlight_truth::domains::Domain;
use airlight_truth::reference::Point;
use std::f64::consts::PI;

/// Largest relative difference between an f32 kernel and its f64 model: f32
/// rounding amplified by exponents up to τ = 20, by the 1/h of grazing rays and by
/// the cancelling amplitudes of the 3-term phase fits (measured up to 4e-4).
const PORT_TOLERANCE: f64 = 1e-3;
/// Below this, `A` is not meaningfully representable in f32 (the gate's rule too).
const F32_TINY: f64 = airlight_shapes::vocab::F32_RANGE.0;

fn kernel_at(k: &airlight_kernels::Kernel, p: &Point) -> f64 {
    let rho = if p.rho.is_infinite() { -1.0 } else { p.rho as f32 };
    (k.airlight)(p.tau as f32, p.gamma as f32, rho, p.g as f32) as f64
}

/// The point an f32 kernel sees (its arguments rounded to f32).
fn rounded(p: &Point) -> Point {
    Point { tau: p.tau as f32 as f64, gamma: p.gamma as f32 as f64, rho: p.rho as f32 as f64, g: p.g as f32 as f64 }
}

#[test]
fn every_model_has_a_kernel_and_every_kernel_is_listed() {
    let models = committed_models();
    for m in &models {
        let k = airlight_kernels::kernel(&m.model.name).unwrap_or_else(|| panic!("no kernel for {}", m.model.name));
        let mut want = vec!["tau", "gamma", "rho"];
        if m.model.g_range != (0.0, 0.0) {
            want.push("g");
        }
        if !m.model.body.extinction() {
            // The closed form without extinction takes no τ.
            want.remove(0);
        }
        assert_eq!(k.params, want, "{}", m.model.name);
        assert_eq!(k.thin_max_rel, m.error(Domain::Thin).unwrap().max_rel, "{}: stale kernel crate", m.model.name);
        // Its own f32 bounds, recorded for this code and never below the model's.
        for (f32, f64) in [(k.f32_thin_max_rel, k.thin_max_rel), (k.f32_dense_max_rel, k.dense_max_rel)] {
            let f32 = f32.unwrap_or_else(|| panic!("{}: no f32 bound recorded (airlight check --record)", k.name));
            assert!(f32 >= f64, "{}: f32 bound {f32:e} below the f64 bound {f64:e}", k.name);
        }
    }
    let scenes = airlight_kernels::KERNELS.iter().filter(|k| k.scene).count();
    assert_eq!(airlight_kernels::KERNELS.len(), models.len() + scenes);
}

#[test]
fn every_model_kernel_matches_its_f64_model() {
    let mut failures = Vec::new();
    for m in committed_models() {
        let k = airlight_kernels::kernel(&m.model.name).unwrap();
        let gs = [m.model.g_range.0, 0.0f64.clamp(m.model.g_range.0, m.model.g_range.1), m.model.g_range.1];
        for (domain, seed) in [(Domain::Thin, 0x5EED_0001), (Domain::Dense, 0x5EED_0002), (Domain::Extreme, 0)] {
            let mut pts =
                if domain == Domain::Extreme { Vec::new() } else { random_points(domain, m.model.g_range, 4000, seed) };
            pts.extend(domain.corners(&gs));
            for p in &pts {
                let q = rounded(p);
                let want = m.model.eval_unchecked(q);
                let got = kernel_at(k, p);
                if !(got.is_finite() && got >= 0.0) && want.is_finite() {
                    failures.push(format!(
                        "{} {}: {got} where the model gives {want} at {q:?}",
                        m.model.name,
                        domain.name()
                    ));
                    continue;
                }
                if !(F32_TINY..=airlight_shapes::vocab::F32_RANGE.1).contains(&want) {
                    continue;
                }
                // The Sun table's two lookups cancel towards γ = π, and its f32 kernel
                // interpolates in f32: it is held to its declared bound against the
                // reference (the gate), not to its f64 twin.
                if m.model.body.texture().is_some() {
                    continue;
                }
                let e = (got - want).abs() / want;
                if e.is_nan() || e > PORT_TOLERANCE {
                    failures.push(format!("{} {}: {e:.2e} ({got} vs {want}) at {q:?}", m.model.name, domain.name()));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures[..failures.len().min(20)].join("\n"));
}

/// Held-out points against the reference: the public 30-digit values inside each
/// model's domains, within the kernel's declared f32 bound as the gate holds it
/// ([`airlight_shapes::vocab::f32_domain_limit`]).
#[test]
fn every_model_kernel_holds_its_declared_bound_on_the_public_values() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for m in committed_models() {
        let k = airlight_kernels::kernel(&m.model.name).unwrap();
        for (_, text) in airlight_truth::fixtures::PUBLIC {
            for (p, exact) in airlight_truth::fixtures::parse(text) {
                let domain = match p.tau {
                    t if (0.0..=2.0).contains(&t) => Domain::Thin,
                    t if (2.0..=20.0).contains(&t) => Domain::Dense,
                    _ => continue,
                };
                let inside = (0.01..=PI - 0.01).contains(&p.gamma)
                    && (p.rho.is_infinite() || (0.01..=100.0).contains(&p.rho))
                    && (m.model.g_range.0..=m.model.g_range.1).contains(&p.g);
                if !inside || !exact.is_finite() || exact < F32_TINY {
                    continue;
                }
                checked += 1;
                let e = (kernel_at(k, &p) - exact).abs() / exact;
                // The kernel's own f32 bound, as the gate holds it on thin and dense.
                let declared = match domain {
                    Domain::Thin => k.f32_thin_max_rel,
                    _ => k.f32_dense_max_rel,
                }
                .expect("the committed registry carries f32 bounds (airlight check --record)");
                let limit = airlight_shapes::vocab::f32_domain_limit(declared);
                if e.is_nan() || e > limit {
                    failures.push(format!(
                        "{} {domain}: {e:.3e} at {p:?} > {limit:.3e} (declared f32 bound {declared:.3e})",
                        m.model.name
                    ));
                }
            }
        }
    }
    assert!(checked > 500, "only {checked} public points inside the models' domains");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

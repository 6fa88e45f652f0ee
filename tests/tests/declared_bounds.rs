//! Every committed model's declared error bound holds on points that neither the
//! fits nor the validation sets used: independent uniform random points (not the
//! Halton sequence) inside each domain and the model's g range, against the
//! reference. The check allows the factor 1.5 the project promises.

use airlight_fit::model::Model;
use airlight_tests::{committed_models, random_points};
use airlight_truth::domains::Domain;
use airlight_truth::reference::airlight;
use airlight_truth::stats::rel_error;
use std::f64::consts::PI;

#[test]
fn declared_max_holds_on_fresh_points() {
    let mut failures = Vec::new();
    for m in committed_models() {
        for (domain, seed) in [(Domain::Thin, 0xA11CE), (Domain::Dense, 0xB0B)] {
            let declared = m.error(domain).expect("thin and dense errors are declared").max_rel;
            let pts = random_points(domain, m.model.g_range, 3000, seed);
            let errs = airlight_truth::parallel::map(
                &pts,
                |p| rel_error(m.model.eval_unchecked(*p), airlight(*p).expect("valid")),
                &|_, _| {},
            );
            let (i, worst) = errs.iter().enumerate().fold((0, 0.0), |b, (i, &e)| if e > b.1 { (i, e) } else { b });
            if worst > 1.5 * declared {
                failures.push(format!(
                    "{} {}: {worst:.3e} at {:?} > 1.5 × declared {declared:.3e}",
                    m.model.name,
                    domain.name(),
                    pts[i]
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The public 30-digit values are held-out points too: every one inside a model's
/// domain and g range must respect its declared bound (factor 1.5).
#[test]
fn declared_max_holds_on_the_public_values() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for m in committed_models() {
        for (_, text) in airlight_truth::fixtures::PUBLIC {
            for (p, exact) in airlight_truth::fixtures::parse(text) {
                let domain = if (0.0..=2.0).contains(&p.tau) {
                    Domain::Thin
                } else if (2.0..=20.0).contains(&p.tau) {
                    Domain::Dense
                } else {
                    continue;
                };
                let inside = (0.01..=PI - 0.01).contains(&p.gamma)
                    && (p.rho.is_infinite() || (0.01..=100.0).contains(&p.rho))
                    && (m.model.g_range.0..=m.model.g_range.1).contains(&p.g);
                if !inside || !exact.is_finite() {
                    continue;
                }
                checked += 1;
                let e = rel_error(m.model.eval_unchecked(p), exact);
                let declared = m.error(domain).unwrap().max_rel;
                if e > 1.5 * declared {
                    failures.push(format!(
                        "{} {}: {e:.3e} at {p:?} > 1.5 × {declared:.3e}",
                        m.model.name,
                        domain.name()
                    ));
                }
            }
        }
    }
    assert!(checked > 500, "only {checked} public points inside the models' domains");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

//! The reference's account of itself: its three paths compared on every domain's
//! validation set, and against the public 30-digit values. `airlight regenerate`
//! runs it and writes its figures to `generated/selfcheck.toml` ([`SelfCheck::to_toml`]);
//! `airlight generate` only reads that file back and quotes it in `REPORT.md`.

use crate::domains::{Domain, VALIDATION_POINTS, VALIDATION_SEED};
use crate::fixtures;
use crate::parallel;
use crate::reference::{airlight, airlight_detailed, airlight_e1, airlight_s_form, Point, REFERENCE_REL_TOL};
use crate::stats::{rel_error, ErrorStats};

/// The E1 form subtracts two terms; where their magnitudes exceed the result by
/// more than this factor it cannot certify 1e-13, and the comparison skips it.
pub const E1_MAX_CONDITION: f64 = 10.0;

/// The reference's specification: relative accuracy on every domain.
pub const REFERENCE_SPEC: f64 = 1e-12;

/// g range of the Henyey–Greenstein validation sets.
pub const HG_RANGE: (f64, f64) = (-0.95, 0.95);

/// One domain × phase family.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DomainCheck {
    /// The domain.
    pub domain: Domain,
    /// The g range sampled (`(0, 0)`: isotropic).
    pub g_range: (f64, f64),
    /// Points evaluated (low-discrepancy set plus corners).
    pub points: usize,
    /// Primary path vs the s form.
    pub vs_s_form: ErrorStats,
    /// Primary path vs the complex-E1 closed form (isotropic sets only), on the
    /// points where that form is well conditioned (see [`E1_MAX_CONDITION`]).
    pub vs_e1: Option<ErrorStats>,
    /// Points left out of `vs_e1` because the E1 form's final subtraction would
    /// lose more than one digit there.
    pub e1_ill_conditioned: usize,
    /// Largest a-posteriori relative error estimate of the primary path.
    pub max_estimate: f64,
    /// Mean integrand evaluations per point.
    pub mean_evaluations: f64,
    /// Maximum integrand evaluations at one point.
    pub max_evaluations: usize,
    /// Points where the adaptive quadrature did not meet its tolerance.
    pub unconverged: usize,
    /// Points with a NaN, infinite or negative value.
    pub bad_values: usize,
}

/// Agreement with one public fixture file.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FixtureCheck {
    /// File name.
    pub name: String,
    /// Points with finite exact values.
    pub finite: usize,
    /// Points where the exact value is `inf`, and how many of them the reference
    /// also returned as `inf`.
    pub infinite: (usize, usize),
    /// Relative error on the finite points.
    pub stats: ErrorStats,
}

/// The whole self-check.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SelfCheck {
    /// Quadrature tolerance in force.
    pub tolerance: f64,
    /// Validation seed and points per sampled domain.
    pub seed: u64,
    /// Low-discrepancy points per sampled domain.
    pub points_per_domain: usize,
    /// Per domain and phase family.
    pub domains: Vec<DomainCheck>,
    /// Per public fixture file.
    pub fixtures: Vec<FixtureCheck>,
}

impl DomainCheck {
    /// "isotropic" or "HG", for tables.
    pub fn phase_label(&self) -> &'static str {
        if self.g_range == (0.0, 0.0) {
            "isotropic"
        } else {
            "HG"
        }
    }
}

impl SelfCheck {
    /// Every way the reference misses its specification ([`REFERENCE_SPEC`]):
    /// independent paths disagreeing, unconverged or non-finite values, public
    /// values missed, rays through the light not returned as `inf`. Empty when
    /// the reference holds.
    pub fn problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        for d in &self.domains {
            let label = format!("{} {}", d.domain.name(), d.phase_label());
            let worst = d.vs_s_form.max.max(d.vs_e1.map_or(0.0, |s| s.max));
            if worst >= REFERENCE_SPEC {
                out.push(format!("{label}: independent paths disagree by {worst:.1e} (spec {REFERENCE_SPEC:.0e})"));
            }
            if d.unconverged > 0 || d.bad_values > 0 {
                out.push(format!("{label}: {} unconverged, {} NaN, ∞ or negative", d.unconverged, d.bad_values));
            }
        }
        for f in &self.fixtures {
            if f.stats.max >= REFERENCE_SPEC {
                out.push(format!("{}: off by {:.1e} (spec {REFERENCE_SPEC:.0e})", f.name, f.stats.max));
            }
            if f.infinite.0 != f.infinite.1 {
                out.push(format!(
                    "{}: {} of {} rays through the light not inf",
                    f.name,
                    f.infinite.0 - f.infinite.1,
                    f.infinite.0
                ));
            }
        }
        out
    }

    /// Worst disagreement between independent paths over all domains.
    pub fn worst_path_disagreement(&self) -> f64 {
        self.domains
            .iter()
            .flat_map(|d| std::iter::once(d.vs_s_form.max).chain(d.vs_e1.map(|s| s.max)))
            .fold(0.0, f64::max)
    }
}

/// The file under `generated/` that holds the self-check's figures.
pub const FILE: &str = "selfcheck.toml";

impl SelfCheck {
    /// The figures as `generated/selfcheck.toml`; [`SelfCheck::from_toml`] reads them back exactly.
    pub fn to_toml(&self) -> String {
        let body = toml::to_string(self).expect("a self-check serialises");
        format!(
            "# The reference's self-check, written by `airlight regenerate` (truth/src/selfcheck.rs);\n\
             # `airlight generate` quotes it in REPORT.md without rerunning it. Do not edit.\n{body}"
        )
    }

    /// Reads [`SelfCheck::to_toml`]'s text; an error names the file and line.
    pub fn from_toml(file: &str, text: &str) -> Result<SelfCheck, crate::tomlfile::FieldError> {
        crate::tomlfile::from_str(file, text, "(self-check)")
    }
}

struct PointResult {
    point: Point,
    value: f64,
    estimate: f64,
    evaluations: usize,
    converged: bool,
    s_form: f64,
    e1: Option<(f64, f64)>,
}

/// Runs the self-check with `n` points per sampled domain. `progress` gets
/// `(done, total)` over all points.
pub fn run(n: usize, progress: &(dyn Fn(usize, usize) + Sync)) -> SelfCheck {
    let mut sets = Vec::new();
    for domain in Domain::ALL {
        for g in [(0.0, 0.0), HG_RANGE] {
            sets.push((domain, g, domain.validation_set(g, n, VALIDATION_SEED)));
        }
    }
    let total: usize = sets.iter().map(|s| s.2.len()).sum();
    let mut offset = 0;
    let mut domains = Vec::new();
    for (domain, g_range, pts) in sets {
        let base = offset;
        let results = parallel::map(
            &pts,
            |&p| {
                let ev = airlight_detailed(p).expect("validation points are in the domain");
                PointResult {
                    point: p,
                    value: ev.value,
                    estimate: ev.rel_error,
                    evaluations: ev.evaluations,
                    converged: ev.converged,
                    s_form: airlight_s_form(p).expect("valid"),
                    e1: (p.g == 0.0).then(|| airlight_e1(p).expect("valid")),
                }
            },
            &|d, _| progress(base + d, total),
        );
        offset += pts.len();
        let vs_s_form = ErrorStats::from_errors(results.iter().map(|r| (r.point, rel_error(r.value, r.s_form))));
        let well_conditioned = |r: &&PointResult| r.e1.is_some_and(|(_, cond)| cond <= E1_MAX_CONDITION);
        let vs_e1 = (g_range == (0.0, 0.0)).then(|| {
            ErrorStats::from_errors(
                results
                    .iter()
                    .filter(well_conditioned)
                    .map(|r| (r.point, rel_error(r.value, r.e1.expect("isotropic").0))),
            )
        });
        let e1_ill_conditioned = results.iter().filter(|r| r.e1.is_some()).count() - vs_e1.map_or(0, |s| s.count);
        domains.push(DomainCheck {
            domain,
            g_range,
            points: results.len(),
            vs_s_form,
            vs_e1,
            e1_ill_conditioned,
            max_estimate: results.iter().map(|r| r.estimate).fold(0.0, f64::max),
            mean_evaluations: results.iter().map(|r| r.evaluations as f64).sum::<f64>() / results.len() as f64,
            max_evaluations: results.iter().map(|r| r.evaluations).max().unwrap_or(0),
            unconverged: results.iter().filter(|r| !r.converged).count(),
            bad_values: results.iter().filter(|r| !(r.value.is_finite() && r.value >= 0.0)).count(),
        });
    }
    let fixtures = fixtures::PUBLIC
        .iter()
        .map(|(name, text)| {
            let rows = fixtures::parse(text);
            let inf: Vec<&(Point, f64)> = rows.iter().filter(|r| r.1.is_infinite()).collect();
            let inf_ok = inf.iter().filter(|r| airlight(r.0) == Ok(f64::INFINITY)).count();
            let stats = ErrorStats::from_errors(
                rows.iter()
                    .filter(|r| r.1.is_finite())
                    .map(|&(p, exact)| (p, rel_error(airlight(p).expect("valid"), exact))),
            );
            FixtureCheck { name: name.to_string(), finite: stats.count, infinite: (inf.len(), inf_ok), stats }
        })
        .collect();
    SelfCheck { tolerance: REFERENCE_REL_TOL, seed: VALIDATION_SEED, points_per_domain: n, domains, fixtures }
}

/// [`run`] with the standard validation size.
pub fn run_standard(progress: &(dyn Fn(usize, usize) + Sync)) -> SelfCheck {
    run(VALIDATION_POINTS, progress)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn problems_name_each_miss() {
        let mut check = run(10, &|_, _| {});
        let text = check.to_toml();
        assert_eq!(SelfCheck::from_toml("s.toml", &text).unwrap(), check, "round trip is exact");
        assert_eq!(check.problems(), Vec::<String>::new());
        check.domains[1].vs_s_form.max = 2e-12;
        check.domains[2].bad_values = 1;
        check.fixtures[1].infinite.1 = 0;
        let p = check.problems();
        assert_eq!(p.len(), 3, "{p:?}");
        assert!(p[0].starts_with("thin HG: independent paths disagree by 2.0e-12"), "{}", p[0]);
        assert!(p[1].starts_with("dense isotropic: 0 unconverged, 1 NaN"), "{}", p[1]);
        assert!(p[2].contains("1 of 1 rays through the light not inf"), "{}", p[2]);
    }
}

//! The reference's self-check for the report: its domains' agreement with the
//! independent paths and its agreement with the public 30-digit fixtures.

use airlight_truth::selfcheck::SelfCheck;
use airlight_truth::stats::{fmt_err, fmt_point, ErrorStats};
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct DomainRow {
    domain: &'static str,
    phase: &'static str,
    points: usize,
    s_max: String,
    s_p99: String,
    s_worst: String,
    e1_max: String,
    e1_p99: String,
    e1_skipped: String,
    estimate: String,
    evals: String,
    unconverged: usize,
    bad: usize,
}

#[derive(Serialize)]
pub(super) struct FixtureRow {
    name: String,
    finite: usize,
    max: String,
    p99: String,
    worst: String,
    infinite: String,
}

pub(super) fn worst(s: &ErrorStats) -> String {
    match &s.worst {
        Some(p) => format!("{} at {}", fmt_err(s.max), fmt_point(p)),
        None => "no points".into(),
    }
}

/// The reference's self-check: per domain and phase, the agreement of its
/// independent paths, and the public 30-digit fixtures.
pub(super) fn selfcheck_context(ctx: &mut tera::Context, check: &SelfCheck) {
    let domains: Vec<DomainRow> = check
        .domains
        .iter()
        .map(|d| DomainRow {
            domain: d.domain.name(),
            phase: d.phase_label(),
            points: d.points,
            s_max: fmt_err(d.vs_s_form.max),
            s_p99: fmt_err(d.vs_s_form.p99),
            s_worst: worst(&d.vs_s_form),
            e1_max: d.vs_e1.map_or("—".into(), |s| fmt_err(s.max)),
            e1_p99: d.vs_e1.map_or("—".into(), |s| fmt_err(s.p99)),
            e1_skipped: if d.vs_e1.is_some() { d.e1_ill_conditioned.to_string() } else { "—".into() },
            estimate: fmt_err(d.max_estimate),
            evals: format!("{:.0} / {}", d.mean_evaluations, d.max_evaluations),
            unconverged: d.unconverged,
            bad: d.bad_values,
        })
        .collect();
    let fixtures: Vec<FixtureRow> = check
        .fixtures
        .iter()
        .map(|f| FixtureRow {
            name: f.name.clone(),
            finite: f.finite,
            max: fmt_err(f.stats.max),
            p99: fmt_err(f.stats.p99),
            worst: f.stats.worst.as_ref().map_or("—".into(), fmt_point),
            infinite: format!("{} of {}", f.infinite.1, f.infinite.0),
        })
        .collect();
    ctx.insert("tolerance", &format!("{:.0e}", check.tolerance));
    ctx.insert("seed", &format!("{:#x}", check.seed));
    ctx.insert("points_per_domain", &check.points_per_domain);
    let hg = airlight_truth::selfcheck::HG_RANGE;
    ctx.insert("hg_lo", &hg.0);
    ctx.insert("hg_hi", &hg.1);
    ctx.insert("e1_max_condition", &airlight_truth::selfcheck::E1_MAX_CONDITION);
    ctx.insert("domains", &domains);
    ctx.insert("fixtures", &fixtures);
    ctx.insert("worst_disagreement", &fmt_err(check.worst_path_disagreement()));
}

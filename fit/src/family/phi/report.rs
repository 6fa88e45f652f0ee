//! The φ family's report section (`report.md.tera` here): per member the
//! declared bounds and where they peak, the cost of the worst path, the bench's
//! ns and ratio to the cost floor, and its f32 kernel's largest error per g.

use super::PhiRule;
use airlight_shapes::cost::{PhaseShape, Shape};
use airlight_truth::domains::Domain;
use crate::family::{Family, Member, ReportFloor};
use airlight_truth::stats::{fmt_err, fmt_point};
use airlight_shapes::template::Context;
use serde::Serialize;

#[derive(Serialize)]
struct PhiRow {
    name: String,
    medium: &'static str,
    nodes: String,
    thin: String,
    dense: String,
    worst: String,
    ops: String,
    ns: String,
    ratio: String,
    target: String,
    f32_by_g: String,
}

/// The row of one member; its ratio to the floor, if both were benched.
fn row(m: &Member<'_, PhiRule>, floor: ReportFloor) -> (PhiRow, Option<f64>) {
    let r = m.body;
    let iso = m.g_range == (0.0, 0.0);
    let shape =
        Shape { phase: if iso { PhaseShape::Isotropic } else { PhaseShape::Exact }, backscatter: true, surfaces: true };
    let o = r.ops(shape);
    let e = |d: Domain| m.error(d).map_or("—".into(), |e| fmt_err(e.max_rel));
    let worst = [Domain::Thin, Domain::Dense]
        .iter()
        .filter_map(|&d| m.error(d).map(|e| (e.max_rel, d, e.worst)))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or("—".into(), |(_, d, p)| format!("{d} at {}", fmt_point(&p)));
    // The cost targets: isotropic ≤ 3×, HG ≤ 5× the floor.
    let limit = if iso { 3.0 } else { 5.0 };
    let ratio = m.bench.zip(floor.cpu_ns).map(|(b, c)| b.cpu_ns_per_eval / c);
    let row = PhiRow {
        name: m.name.to_string(),
        medium: if iso { "isotropic" } else { "HG, g at run time" },
        nodes: format!("{} / {} / {}", r.head.x.len(), r.far.x.len(), r.tail.x.len()),
        thin: e(Domain::Thin),
        dense: e(Domain::Dense),
        worst,
        ops: o.describe(),
        ns: m.bench.map_or("—".into(), |b| format!("{:.1}", b.cpu_ns_per_eval)),
        ratio: ratio.map_or("—".into(), |x| format!("{x:.1}×")),
        target: ratio.map_or("—".into(), |x| {
            if x <= limit {
                format!("≤ {limit}×: met")
            } else {
                format!("≤ {limit}×: missed")
            }
        }),
        f32_by_g: m.bench.map_or("—".into(), |b| {
            b.errors.iter().map(|e| format!("{}: {}", e.g, fmt_err(e.max_rel.max()))).collect::<Vec<_>>().join(", ")
        }),
    };
    (row, ratio)
}

/// The section's values.
pub(super) fn context(members: &[Member<'_, PhiRule>], floor: ReportFloor) -> Option<Context> {
    let mut ctx = Context::new();
    let (mut rows, mut ratios) = (Vec::new(), Vec::new());
    for m in members {
        let (r, ratio) = row(m, floor);
        rows.push(r);
        ratios.extend(ratio);
    }
    if !ratios.is_empty() {
        let (lo, hi) = ratios.iter().fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        ctx.insert("phi_ratio_range", &format!("{lo:.1}–{hi:.1}×"));
    }
    ctx.insert("phi_closed_ns", &floor.cpu_ns.map_or("—".into(), |c| format!("{c:.1}")));
    ctx.insert("phi_rows", &rows);
    let prov = |key: &str| {
        members.first().and_then(|m| m.provenance_value("e2.fit", key)).and_then(toml::Value::as_float).map_or("—".into(), fmt_err)
    };
    ctx.insert("e2_max", &prov("max_rel"));
    ctx.insert("e2_series_max", &prov("series_max_rel"));
    Some(ctx)
}

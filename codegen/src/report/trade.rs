//! The report's speed/accuracy section from the bench (`generated/bench.json`):
//! per `g` the headline ratios at every error level and where airlight loses,
//! the smallest ray-march error, what modelling extinction costs over the
//! closed form, every model's row, and the RGB entry against three scalar calls.

use super::KernelIr;
use crate::front::{self, Method};
use airlight_fit::coeffs::ModelFile;
use airlight_fit::roles::roles;
use airlight_shapes::bench::{Bench, BenchModel};
use airlight_shapes::cost::Shape;
use airlight_truth::domains::Domain;
use airlight_truth::stats::fmt_err;
use serde::Serialize;

/// ns/eval as written in tables.
fn ns(x: f64) -> String {
    if x >= 100.0 {
        format!("{x:.0}")
    } else {
        format!("{x:.1}")
    }
}

#[derive(Serialize)]
struct Level {
    measure: &'static str,
    level: String,
    airlight: String,
    baseline: String,
    ratio: String,
    verdict: &'static str,
}

#[derive(Serialize)]
struct MeasureTable {
    title: &'static str,
    plot: String,
    levels: Vec<Level>,
    losses: Vec<String>,
}

#[derive(Serialize)]
struct GSection {
    g: String,
    title: String,
    /// One table per cost measure the bench holds, the CPU's first.
    measures: Vec<MeasureTable>,
    march_best: String,
}

#[derive(Serialize)]
struct TradeRow {
    name: String,
    kind: airlight_shapes::vocab::Role,
    thin_max: String,
    dense_max: String,
    thin_p50: String,
    dense_p50: String,
    ns: String,
    ns_one: String,
    ops: usize,
    ops_every: String,
    transcendentals: usize,
    gpu: String,
    gpu_frame: String,
    bytes: String,
}

#[derive(Serialize)]
struct RgbRow {
    name: String,
    three: String,
    point: String,
    ratio: String,
    hard: String,
    soft: String,
    gpu_three: String,
    gpu_point: String,
    gpu_ratio: String,
}

#[derive(Serialize)]
struct ShaftsRow {
    name: String,
    samples: String,
    calls: String,
    max: String,
    mean: String,
    max_u: String,
    mean_u: String,
    ns: String,
    gpu: String,
    build: String,
}

/// A row of the shadow-map table (`bench.json`'s `shadow_map`).
#[derive(Serialize)]
struct MapRow {
    method: String,
    res: String,
    runs: String,
    steps: String,
    max_u: String,
    mean_u: String,
    leaks: usize,
    ns: String,
    gpu: String,
}

#[derive(Serialize)]
struct NoExt {
    tau: f64,
    error: String,
    fastest: String,
    cost: String,
}

/// A kernel's IR operations as the losses quote them: "every branch (worst path)".
fn ir_ops(ir: &[KernelIr], name: &str) -> Option<String> {
    ir.iter().find(|k| k.name == name).map(|k| format!("{} ({})", k.every.ops, k.worst.ops))
}

/// A kernel's worst path as a CPU loss quotes it: IR operations, transcendental
/// calls and the bytes of any table it reads (`bench.json`).
fn cpu_path(b: &Bench, ir: &[KernelIr], name: &str) -> Option<String> {
    let k = ir.iter().find(|k| k.name == name)?;
    let bytes = b.models.iter().find(|m| m.name == name).map_or(0, |m| m.bytes);
    let table = if bytes > 0 { format!(" and a {} KiB table", bytes / 1024) } else { String::new() };
    Some(format!("`{name}` {} ops, {} transcendental calls{table}", k.worst.ops, k.worst.transcendentals))
}

/// Where airlight loses a level, in words, with what each kernel pays where the
/// cost follows it (the section's "What the cost follows"): on a GPU measure both
/// kernels' IR operations on every branch and on the worst path; on the CPU the
/// worst path's operations, transcendental calls and table bytes.
fn loss(h: &front::Headline, cost: front::CostMeasure, ir: &[KernelIr], b: &Bench) -> String {
    let who = match (&h.airlight, &h.baseline) {
        (Some(a), Some(bl)) => format!(
            "`{}` ({} ns) is {:.2}× faster than airlight's fastest, `{}` ({} ns)",
            bl.name,
            ns(bl.ns),
            a.ns / bl.ns,
            a.name,
            ns(a.ns)
        ),
        (None, Some(bl)) => format!("only baselines reach it; the fastest is `{}` ({} ns)", bl.name, ns(bl.ns)),
        _ => String::new(),
    };
    let why = match (&h.airlight, &h.baseline) {
        (Some(a), Some(bl)) if cost != front::CostMeasure::Cpu => match (ir_ops(ir, &a.name), ir_ops(ir, &bl.name)) {
            (Some(x), Some(y)) => {
                format!(" — IR ops on every branch (worst path): `{}` {x}, `{}` {y}", a.name, bl.name)
            }
            _ => String::new(),
        },
        (Some(a), Some(bl)) => match (cpu_path(b, ir, &a.name), cpu_path(b, ir, &bl.name)) {
            (Some(x), Some(y)) => format!(" — worst path: {x}; {y}"),
            _ => String::new(),
        },
        _ => String::new(),
    };
    format!("{} error {}: {who}{why}", h.measure, fmt_err(h.level))
}

/// One `g`'s headline table on one cost measure, with its losses.
fn measure_table(b: &Bench, g: f64, cost: front::CostMeasure, ir: &[KernelIr]) -> MeasureTable {
    let who = |m: &Option<Method>| m.as_ref().map_or("—".to_string(), |m| format!("`{}` {} ns", m.name, ns(m.ns)));
    let ms = front::methods_by(b, g, cost);
    let hs = front::headlines(&ms);
    let losses = hs.iter().filter(|h| h.verdict().airlight_loses()).map(|h| loss(h, cost, ir, b)).collect();
    let levels = hs
        .iter()
        .map(|h| Level {
            measure: h.measure,
            level: fmt_err(h.level),
            airlight: who(&h.airlight),
            baseline: who(&h.baseline),
            ratio: h.speedup().map_or("—".into(), |r| format!("{r:.2}×")),
            verdict: h.verdict().label(),
        })
        .collect();
    MeasureTable {
        title: cost.title(),
        plot: format!("plots/pareto-{}{}", front::g_label(g), cost.suffix()),
        levels,
        losses,
    }
}

/// One `g`'s headline tables (one per cost measure), losses and best ray march.
fn g_section(b: &Bench, g: f64, ir: &[KernelIr]) -> GSection {
    let ms = front::methods(b, g);
    let label = front::g_label(g);
    let measures =
        front::CostMeasure::ALL.into_iter().filter(|c| c.measured(b)).map(|c| measure_table(b, g, c, ir)).collect();
    let march_best = ms
        .iter()
        .filter(|m| roles().is_march(&m.name))
        .min_by(|a, b| a.max.total_cmp(&b.max))
        .map_or("no raymarch measured".into(), |m| format!("{} (`{}`, {} ns)", fmt_err(m.max), m.name, ns(m.ns)));
    GSection {
        title: if g == 0.0 { "isotropic (g = 0)".into() } else { format!("Henyey–Greenstein, g = {label}") },
        g: label,
        measures,
        march_best,
    }
}

/// Every model's row of the bench.
fn trade_row(m: &BenchModel, ir: &[KernelIr]) -> TradeRow {
    let e = m.at(0.0).or(m.errors.first());
    let f = |x: Option<f64>| x.map_or("—".to_string(), fmt_err);
    TradeRow {
        name: m.name.clone(),
        kind: m.kind,
        thin_max: f(e.map(|e| e.max_rel.thin)),
        dense_max: f(e.map(|e| e.max_rel.dense)),
        thin_p50: f(e.map(|e| e.p50_rel.thin)),
        dense_p50: f(e.map(|e| e.p50_rel.dense)),
        ns: format!("{} ({}–{})", ns(m.cpu_ns_per_eval), ns(m.cpu_ns_range[0]), ns(m.cpu_ns_range[1])),
        ns_one: if m.cpu_ns_one_at_a_time > 0.0 { ns(m.cpu_ns_one_at_a_time) } else { "—".into() },
        ops: m.ops,
        ops_every: ir.iter().find(|k| k.name == m.name).map_or("—".into(), |k| k.every.ops.to_string()),
        transcendentals: m.transcendentals,
        gpu: if m.gpu_evals_per_s > 0.0 { format!("{:.3e}", m.gpu_evals_per_s) } else { "—".into() },
        gpu_frame: if m.gpu_frame_evals_per_s > 0.0 {
            format!("{:.3e}", m.gpu_frame_evals_per_s)
        } else {
            "—".into()
        },
        bytes: if m.bytes > 0 { format!("{} KiB", m.bytes / 1024) } else { "—".into() },
    }
}

/// One model's RGB row: one `spot` call against three `radiance` calls.
fn rgb_row(r: &airlight_shapes::bench::RgbCost) -> RgbRow {
    let rate = |x: f64| if x > 0.0 { format!("{x:.3e}") } else { "—".into() };
    RgbRow {
        name: r.name.clone(),
        three: ns(r.three_scalar_ns),
        point: ns(r.rgb_point_ns),
        ratio: format!("{:.2}", r.rgb_point_ns / r.three_scalar_ns),
        hard: ns(r.rgb_hard_cone_ns),
        soft: ns(r.rgb_soft_cone_ns),
        gpu_three: rate(r.gpu_three_scalar_rays_per_s),
        gpu_point: rate(r.gpu_rgb_point_rays_per_s),
        // Time per RGB ray, spot over three scalar calls (as the CPU ratio).
        gpu_ratio: if r.gpu_three_scalar_rays_per_s > 0.0 && r.gpu_rgb_point_rays_per_s > 0.0 {
            format!("{:.2}", r.gpu_three_scalar_rays_per_s / r.gpu_rgb_point_rays_per_s)
        } else {
            "—".into()
        },
    }
}

/// The cost floor (the closed form without extinction): its error at a few
/// optical distances (measured here with the reference), and what modelling
/// extinction costs over it.
fn no_extinction(ctx: &mut tera::Context, b: &Bench, models: &[ModelFile]) {
    let floor_name = models.iter().find(|m| m.model.body.is_cost_floor()).map(|m| m.model.name.as_str());
    let floor = floor_name.and_then(|n| b.model(n));
    let iso: Vec<Method> = front::methods(b, 0.0);
    let noext: Vec<NoExt> = [0.1, 1.0, 5.0]
        .iter()
        .map(|&tau| {
            let e = airlight_fit::analysis::extinction_error(tau, true, &[0.0]);
            let better = iso
                .iter()
                .filter(|m| Some(m.name.as_str()) != floor_name && m.max < e)
                .min_by(|a, b| a.ns.total_cmp(&b.ns));
            NoExt {
                tau,
                error: fmt_err(e),
                fastest: better.map_or("—".into(), |m| {
                    format!("`{}` ({} max over thin ∪ dense, {} ns)", m.name, fmt_err(m.max), ns(m.ns))
                }),
                cost: match (better, floor) {
                    (Some(m), Some(f)) if f.cpu_ns_per_eval > 0.0 => format!("{:.1}×", m.ns / f.cpu_ns_per_eval),
                    _ => "—".into(),
                },
            }
        })
        .collect();
    ctx.insert("noext", &noext);
    ctx.insert("noext_ns", &floor.map_or("—".into(), |f| ns(f.cpu_ns_per_eval)));
}

/// One row of the cheap tiers' table.
#[derive(Serialize)]
struct TierRow {
    medium: &'static str,
    level: String,
    measure: &'static str,
    kernel: String,
    ratio: String,
    target: String,
}

/// Issue 25's tiers: per medium and max level (the declared bound over `thin` ∪
/// `dense`), airlight's fastest kernel on each cost measure and its cost over the
/// closed form without extinction's on the same measure; the 1e-2 level's target
/// (isotropic ≤ 2×, HG ≤ 3×) met or missed.
fn tiers(b: &Bench, models: &[ModelFile], ir: &[KernelIr]) -> (Vec<TierRow>, Vec<String>) {
    let Some(floor_model) = models.iter().find(|m| m.model.body.is_cost_floor()) else {
        return (Vec::new(), Vec::new());
    };
    let Some(floor) = b.model(&floor_model.model.name) else {
        return (Vec::new(), Vec::new());
    };
    // What a missed target pays: on the CPU the calls on its worst path (the cost
    // the CPU follows), on a GPU path its IR operations with every branch taken.
    let calls = |m: &ModelFile| m.model.body.ops(Shape::general(m.model.body.phase_shape())).describe();
    let every = |name: &str| ir.iter().find(|k| k.name == name).map(|k| k.every.ops.to_string());
    let mut why = Vec::new();
    let declared = |m: &ModelFile| {
        [Domain::Thin, Domain::Dense]
            .iter()
            .map(|&d| m.error(d).map_or(f64::INFINITY, |e| e.max_rel))
            .fold(0.0, f64::max)
    };
    let mut rows = Vec::new();
    for (medium, iso, target) in [("isotropic", true, 2.0), ("HG, g at run time in [−0.99, 0.99]", false, 3.0)] {
        for level in [1e-1, 1e-2, 1e-3] {
            for measure in front::CostMeasure::ALL {
                let Some(f) = measure.ns(floor) else { continue };
                let best = models
                    .iter()
                    .filter(|m| !m.model.body.is_baseline() && !m.model.body.is_cost_floor())
                    .filter(|m| {
                        let (lo, hi) = m.model.g_range;
                        if iso {
                            lo <= 0.0 && hi >= 0.0
                        } else {
                            (lo, hi) == (-0.99, 0.99)
                        }
                    })
                    .filter(|m| declared(m) <= level)
                    .filter_map(|m| Some((m, measure.ns(b.model(&m.model.name)?)?)))
                    .min_by(|a, b| a.1.total_cmp(&b.1));
                let (kernel, ratio, met) = match best {
                    Some((m, ns)) => (
                        format!("`{}` ({} declared)", m.model.name, fmt_err(declared(m))),
                        format!("{:.2}×", ns / f),
                        ns / f <= target,
                    ),
                    None => ("—".into(), "—".into(), false),
                };
                if level == 1e-2 && !met {
                    if let Some((m, ns)) = best {
                        let pays = if measure == front::CostMeasure::Cpu {
                            format!(
                                "its worst path calls {} against the closed form's {}",
                                calls(m),
                                calls(floor_model)
                            )
                        } else {
                            format!(
                                "it runs {} IR operations with every branch taken against the closed form's {}",
                                every(&m.model.name).unwrap_or_else(|| "?".into()),
                                every(&floor_model.model.name).unwrap_or_else(|| "?".into())
                            )
                        };
                        why.push(format!(
                            "{medium}, {}: `{}` at {:.2}× misses ≤ {target}× by {:.2}×; {pays}",
                            measure.title(),
                            m.model.name,
                            ns / f,
                            ns / f / target
                        ));
                    }
                }
                rows.push(TierRow {
                    medium,
                    level: fmt_err(level),
                    measure: measure.title(),
                    kernel,
                    ratio,
                    target: if level == 1e-2 {
                        format!("≤ {target}×: {}", if met { "met" } else { "missed" })
                    } else {
                        "—".into()
                    },
                });
            }
        }
    }
    (rows, why)
}

/// One way of measuring a model: its label and its figure.
type Way = (&'static str, fn(&BenchModel) -> f64);

/// For each pair `(a, z)` that both ways measured: "`a` / `z` r₁× way₁, r₂× way₂",
/// each `r` the ratio of `a`'s figure to `z`'s that way.
fn two_ways(b: &Bench, pairs: &[(String, String)], ways: [Way; 2]) -> Vec<String> {
    pairs
        .iter()
        .filter_map(|(a, z)| {
            let (a, z) = (b.model(a)?, b.model(z)?);
            ways.iter().all(|(_, f)| f(a) > 0.0 && f(z) > 0.0).then(|| {
                let cells: Vec<String> = ways.iter().map(|(what, f)| format!("{:.2}× {what}", f(a) / f(z))).collect();
                format!("`{}` / `{}` {}", a.name, z.name, cells.join(", "))
            })
        })
        .collect()
}

/// One cost measure's row of "What the cost follows".
#[derive(Serialize)]
struct FollowRow {
    measure: &'static str,
    kernels: usize,
    worst_rms: String,
    worst_max: String,
    every_rms: String,
    every_max: String,
    every_line: String,
    /// "every branch" or "worst path": the count that misses less (rms).
    follows: &'static str,
    /// Whether the measure is the GPU path's.
    #[serde(skip)]
    gpu: bool,
}

/// Per cost measure, how well each IR count predicts the measured cost over the
/// bench's kernels that read no table (a texture fetch is not arithmetic):
/// [`airlight_shapes::ircost::fit_cost`] on the worst path's operations and on every
/// branch's.
fn follows(b: &Bench, ir: &[KernelIr]) -> Vec<FollowRow> {
    let pct = |x: f64| format!("{:.1}%", 100.0 * x);
    front::CostMeasure::ALL
        .into_iter()
        .filter(|c| c.measured(b))
        .filter_map(|cost| {
            let pts: Vec<(&KernelIr, f64)> = b
                .models
                .iter()
                .filter(|m| m.bytes == 0)
                .filter_map(|m| Some((ir.iter().find(|k| k.name == m.name)?, cost.ns(m)?)))
                .collect();
            let fit = |f: fn(&KernelIr) -> usize| {
                airlight_shapes::ircost::fit_cost(&pts.iter().map(|(k, ns)| (f(k) as f64, *ns)).collect::<Vec<_>>())
            };
            let (w, e) = (fit(|k| k.worst.ops)?, fit(|k| k.every.ops)?);
            Some(FollowRow {
                measure: cost.title(),
                kernels: pts.len(),
                worst_rms: pct(w.rms),
                worst_max: pct(w.max),
                every_rms: pct(e.rms),
                every_max: pct(e.max),
                every_line: format!("{:.2} + {:.4} × ops", e.intercept, e.slope),
                follows: if e.rms < w.rms { "every branch" } else { "worst path" },
                gpu: cost != front::CostMeasure::Cpu,
            })
        })
        .collect()
}

/// Airlight kernels whose every-branch IR count exceeds their worst path's by the
/// most (the branches a GPU wave may pay for together), as "`name` every (worst,
/// +x%)", largest first.
fn branchy(b: &Bench, ir: &[KernelIr]) -> Vec<String> {
    let mut k: Vec<&KernelIr> = ir
        .iter()
        .filter(|k| b.model(&k.name).is_some_and(|m| m.kind == airlight_shapes::vocab::Role::Airlight))
        .filter(|k| k.every.ops > k.worst.ops)
        .collect();
    let extra = |k: &KernelIr| k.every.ops as f64 / k.worst.ops.max(1) as f64 - 1.0;
    k.sort_by(|a, z| extra(z).total_cmp(&extra(a)).then(a.name.cmp(&z.name)));
    k.iter()
        .take(6)
        .map(|k| format!("`{}` {} ({}, +{:.0}%)", k.name, k.every.ops, k.worst.ops, 100.0 * extra(k)))
        .collect()
}

/// The speed/accuracy section's values.
/// One `g`'s row of the report's opening table: per cost measure, who is fastest
/// at each error level someone reaches.
#[derive(Serialize)]
struct GlanceRow {
    g: String,
    cells: Vec<String>,
}

/// The opening table of the trade: the measures' titles and one row per `g`.
fn glance(b: &Bench) -> (Vec<&'static str>, Vec<GlanceRow>) {
    let measures: Vec<front::CostMeasure> = front::CostMeasure::ALL.into_iter().filter(|c| c.measured(b)).collect();
    let rows = front::gs(b)
        .into_iter()
        .map(|g| GlanceRow {
            g: if g == 0.0 { "isotropic".into() } else { format!("g = {}", front::g_label(g)) },
            cells: measures
                .iter()
                .map(|&c| {
                    let hs = front::headlines(&front::methods_by(b, g, c));
                    let reached: Vec<&front::Headline> =
                        hs.iter().filter(|h| h.verdict() != front::Verdict::Nobody).collect();
                    let won = reached.iter().filter(|h| !h.verdict().airlight_loses()).count();
                    let lost: Vec<String> = reached
                        .iter()
                        .filter(|h| h.verdict().airlight_loses())
                        .map(|h| {
                            let who = h.baseline.as_ref().map_or(String::new(), |m| format!(" (`{}`)", m.name));
                            format!("{} {}{who}", h.measure, fmt_err(h.level))
                        })
                        .collect();
                    if lost.is_empty() {
                        format!("airlight at all {won}")
                    } else {
                        format!("airlight at {won} of {}; a baseline at {}", reached.len(), lost.join(", "))
                    }
                })
                .collect(),
        })
        .collect();
    (measures.iter().map(|c| c.title()).collect(), rows)
}

pub(super) fn context(ctx: &mut tera::Context, b: &Bench, models: &[ModelFile], ir: &[KernelIr]) {
    let (glance_measures, glance_rows) = glance(b);
    ctx.insert("glance_measures", &glance_measures);
    ctx.insert("glance_rows", &glance_rows);
    let sections: Vec<GSection> = front::gs(b).into_iter().map(|g| g_section(b, g, ir)).collect();
    ctx.insert("trade", &sections);
    ctx.insert("trade_rows", &b.models.iter().map(|m| trade_row(m, ir)).collect::<Vec<_>>());
    let follow_rows = follows(b, ir);
    // Whether some GPU-path measure follows every branch (the report then says what
    // that means for the branchy kernels).
    let gpu_every = follow_rows.iter().any(|f| f.gpu && f.follows == "every branch");
    ctx.insert("gpu_follows_every", &gpu_every);
    ctx.insert("follows", &follow_rows);
    ctx.insert("branchy", &branchy(b, ir));
    let flat: Vec<String> = roles()
        .report
        .flat
        .iter()
        .filter_map(|n| ir.iter().find(|k| k.name == *n))
        .map(|k| format!("`{}` {} ({})", k.name, k.every.ops, k.worst.ops))
        .collect();
    ctx.insert("flat", &flat);
    let lite_flat: Vec<String> = ir
        .iter()
        .filter(|k| roles().report.flat_prefixes.iter().any(|p| k.name.starts_with(p.as_str())))
        .map(|k| format!("`{}` {} ({})", k.name, k.every.ops, k.worst.ops))
        .collect();
    ctx.insert("lite_flat", &lite_flat);
    // The CPU cost ratios that depend on how a short kernel is called, and the
    // GPU-path rate ratios, random and frame-coherent.
    let cpu_two_ways = two_ways(
        b,
        &roles().report.cpu_two_ways,
        [("in the loop", |m| m.cpu_ns_per_eval), ("one call at a time", |m| m.cpu_ns_one_at_a_time)],
    );
    ctx.insert("cpu_two_ways", &cpu_two_ways);
    let gpu_two_ways = two_ways(
        b,
        &roles().report.gpu_two_ways,
        [("on random points", |m| m.gpu_evals_per_s), ("frame-coherent", |m| m.gpu_frame_evals_per_s)],
    );
    ctx.insert("gpu_two_ways", &gpu_two_ways);
    let (tier_rows, tier_why) = tiers(b, models, ir);
    ctx.insert("tiers", &tier_rows);
    ctx.insert("tier_why", &tier_why);
    ctx.insert("rgb_rows", &b.rgb.iter().map(rgb_row).collect::<Vec<_>>());
    shafts_context(ctx, b);
    ctx.insert("fprime_res", &airlight_truth::shafts::FPRIME_RES);
    ctx.insert("fprime_kernel", &airlight_truth::shafts::FPRIME_KERNEL);
    ctx.insert("spot_edge_nodes", &crate::kernel::SPOT_EDGE_NODES);
    ctx.insert("spot_edge_pieces", &(crate::kernel::SPOT_EDGE_PIECES.len() - 1));
    ctx.insert("bench_adapter", &b.adapter);
    ctx.insert("bench_cpu", &b.cpu);
    ctx.insert("bench_points", &b.error_points);
    ctx.insert("bench_batch", &b.cost_batch);
    ctx.insert("bench_repeats", &b.repeats);
    ctx.insert("bench_gs", &front::gs(b).iter().map(|g| front::g_label(*g)).collect::<Vec<_>>().join(", "));
    no_extinction(ctx, b, models);
}

/// The light-shafts table (`bench.json`'s `shafts`) and where the headline
/// accumulator (`fit/src/roles.toml`) loses to the march on the same samples.
fn shafts_context(ctx: &mut tera::Context, b: &Bench) {
    let shafts: Vec<ShaftsRow> = b
        .shafts
        .iter()
        .map(|r| ShaftsRow {
            name: r.name.clone(),
            samples: if r.samples == 0 { "exact intervals".into() } else { r.samples.to_string() },
            calls: format!("{:.2}", r.calls_per_ray),
            max: fmt_err(r.max_rel),
            mean: fmt_err(r.mean_rel),
            max_u: fmt_err(r.max_of_unshadowed),
            mean_u: fmt_err(r.mean_of_unshadowed),
            ns: ns(r.cpu_ns_per_ray),
            gpu: if r.gpu_rays_per_s > 0.0 { format!("{:.3e}", r.gpu_rays_per_s) } else { "—".into() },
            build: match (r.build_cpu_ms > 0.0, r.build_gpu_ms > 0.0) {
                (false, _) => "—".into(),
                (true, false) => format!("{:.1} ms CPU", r.build_cpu_ms),
                (true, true) => format!("{:.1} ms CPU, {:.3} ms GPU", r.build_cpu_ms, r.build_gpu_ms),
            },
        })
        .collect();
    ctx.insert("shafts_rows", &shafts);
    // Where the headline accumulator loses to the march on the same samples.
    let mut losses = Vec::new();
    let roles = roles();
    for r in b.shafts.iter().filter(|r| r.name == roles.shafts.headline && r.samples > 0) {
        let Some(m) = b.shafts.iter().find(|m| m.name == roles.march(r.samples)) else { continue };
        let mut lost = Vec::new();
        for (what, a, x) in [
            ("max relative", r.max_rel, m.max_rel),
            ("mean relative", r.mean_rel, m.mean_rel),
            ("max of unshadowed", r.max_of_unshadowed, m.max_of_unshadowed),
            ("mean of unshadowed", r.mean_of_unshadowed, m.mean_of_unshadowed),
            ("CPU ns", r.cpu_ns_per_ray, m.cpu_ns_per_ray),
        ] {
            if a > x {
                lost.push(format!("{what} ({} against {})", fmt_err(a), fmt_err(x)));
            }
        }
        if r.gpu_rays_per_s > 0.0 && m.gpu_rays_per_s > 0.0 && r.gpu_rays_per_s < m.gpu_rays_per_s {
            lost.push(format!("GPU rays/s ({:.3e} against {:.3e})", r.gpu_rays_per_s, m.gpu_rays_per_s));
        }
        if !lost.is_empty() {
            losses.push(format!("at {} samples: {}", r.samples, lost.join(", ")));
        }
    }
    ctx.insert("shafts_losses", &losses);
    let maps: Vec<MapRow> = b
        .shadow_map
        .iter()
        .map(|r| MapRow {
            method: r.method.clone(),
            res: if r.res == 0 { format!("{} look-ups (analytic)", r.samples) } else { format!("{0}²", r.res) },
            runs: format!("{:.1}", r.runs_per_ray),
            steps: if r.res == 0 {
                "—".into()
            } else {
                format!("{:.0} (max {:.0}, {} truncated)", r.steps_mean, r.steps_max, r.truncated)
            },
            max_u: fmt_err(r.max_of_unshadowed),
            mean_u: fmt_err(r.mean_of_unshadowed),
            leaks: r.leaks,
            ns: ns(r.cpu_ns_per_ray),
            gpu: if r.gpu_rays_per_s > 0.0 { format!("{:.3e}", r.gpu_rays_per_s) } else { "—".into() },
        })
        .collect();
    ctx.insert("map_rows", &maps);
    ctx.insert("map_alone", &b.shadow_map_alone);
}

#[cfg(test)]
mod tests {
    use super::*;
    use airlight_shapes::ircost::IrCost;

    fn method(name: &str, baseline: bool, ns: f64) -> Method {
        Method {
            name: name.into(),
            baseline,
            ns,
            max: 1.0,
            median: 1e-3,
            dominated_max: false,
            dominated_median: false,
        }
    }

    fn model(name: &str, bytes: usize) -> BenchModel {
        BenchModel {
            name: name.into(),
            kind: airlight_shapes::vocab::Role::Baseline,
            g_range: [0.0, 0.0],
            errors: Vec::new(),
            cpu_ns_per_eval: 1.0,
            cpu_ns_range: [1.0, 1.0],
            cpu_ns_one_at_a_time: 1.0,
            ops: 0,
            transcendentals: 0,
            gpu_evals_per_s: 0.0,
            gpu_frame_evals_per_s: 0.0,
            bytes,
        }
    }

    #[test]
    fn a_loss_says_what_each_kernel_pays_where_the_cost_follows_it() {
        let bench = Bench {
            adapter: "none".into(),
            cpu: "none".into(),
            error_points: 1,
            cost_batch: 1,
            repeats: 1,
            models: vec![model("cheap", 0), model("table", 262_144)],
            rgb: Vec::new(),
            shafts: Vec::new(),
            shadow_map: Vec::new(),
            shadow_map_alone: None,
        };
        let ir = |name: &str, worst: usize, every: usize, calls: usize| KernelIr {
            name: name.into(),
            worst: IrCost { ops: worst, transcendentals: calls },
            every: IrCost { ops: every, transcendentals: calls },
        };
        let ir = vec![ir("cheap", 265, 273, 9), ir("table", 198, 198, 2)];
        let h = front::Headline {
            measure: "median",
            level: 1e-2,
            airlight: Some(method("cheap", false, 70.0)),
            baseline: Some(method("table", true, 50.0)),
        };
        let cpu = loss(&h, front::CostMeasure::Cpu, &ir, &bench);
        assert!(cpu.contains("`table` (50.0 ns) is 1.40× faster"), "{cpu}");
        assert!(
            cpu.contains(
                "`cheap` 265 ops, 9 transcendental calls; `table` 198 ops, 2 transcendental calls and a 256 KiB table"
            ),
            "{cpu}"
        );
        let gpu = loss(&h, front::CostMeasure::GpuRandom, &ir, &bench);
        assert!(gpu.contains("IR ops on every branch (worst path): `cheap` 273 (265), `table` 198 (198)"), "{gpu}");
        assert!(!gpu.contains("KiB"), "{gpu}");
    }
}

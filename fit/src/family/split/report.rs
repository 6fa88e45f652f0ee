//! The split family's report section (`report.md.tera` here: the paper,
//! reproduced and refit) and its figures: the forward kernel's error, the phase
//! against HG, the backscatter ratio's error, and the error against `N`.
//!
//! The section is about particular members of the catalog (the published model,
//! its refit, `segments-N`, `hg-expN`), so it picks them by name; a member that is
//! not there leaves its cells `—` and its figure undrawn.

use super::phase_exp::PAPER_BANDS;
use super::ratio::Ratio;
use super::segments::Segments;
use super::{expsum, PhaseModel, Split};
use super::ratio::exact_backward;
use super::segments::exact_forward;
use crate::analysis::{linspace, logspace, math_grid_error};
use airlight_truth::domains::Domain;
use crate::family::{Family, Member};
use airlight_shapes::figure::{Figure, Heatmap, Line, Lines, Panel};
use airlight_truth::stats::fmt_err;
use airlight_shapes::template::Context;
use airlight_truth::Phase;
use serde::Serialize;
use std::f64::consts::{FRAC_PI_2, PI};

#[derive(Serialize)]
struct KernelRow {
    name: String,
    kernel: String,
    rms: String,
    max: String,
    iterations: String,
    termination: String,
}

#[derive(Serialize)]
struct BandRow {
    band: String,
    paper: String,
    k1: String,
    k2: String,
    k3: String,
}

#[derive(Serialize)]
struct FactRow {
    model: String,
    cells: Vec<String>,
}

type M<'a, 'b> = &'a Member<'b, Split>;

fn get<'a, 'b>(members: &'a [Member<'b, Split>], name: &str) -> Option<M<'a, 'b>> {
    members.iter().find(|m| m.name == name)
}

fn prov_f(m: M, table: &str, key: &str) -> String {
    m.provenance_value(table, key).and_then(toml::Value::as_float).map_or("—".into(), fmt_err)
}

fn prov_s(m: M, table: &str, key: &str) -> String {
    m.provenance_value(table, key).map_or("—".into(), |v| v.as_str().map_or_else(|| v.to_string(), str::to_string))
}

fn by_band(m: M, key: &str) -> Vec<f64> {
    m.provenance_value("phase.fit", key)
        .and_then(toml::Value::as_array)
        .map(|a| a.iter().filter_map(toml::Value::as_float).collect())
        .unwrap_or_default()
}

/// The forward kernels' fits: the published one and each `segments-N` refit.
fn forward(ctx: &mut Context, members: &[Member<'_, Split>]) {
    let kernel_row = |name: String, m: M| KernelRow {
        name,
        kernel: prov_f(m, "forward.fit", "kernel_max_abs_error"),
        rms: prov_f(m, "forward.fit", "forward_integral_rms_rel"),
        max: prov_f(m, "forward.fit", "forward_integral_max_rel"),
        iterations: prov_s(m, "forward.fit", "iterations"),
        termination: prov_s(m, "forward.fit", "termination"),
    };
    let mut kernels = Vec::new();
    if let Some(m) = get(members, "paper") {
        kernels.push(kernel_row("paper (3)".into(), m));
        ctx.insert("forward_targets", &prov_s(m, "forward.fit", "targets"));
    } else {
        ctx.insert("forward_targets", "—");
    }
    for m in members.iter().filter(|m| m.name.starts_with("segments-")) {
        kernels.push(kernel_row(format!("refit ({})", m.body.forward.n()), m));
    }
    ctx.insert("kernels", &kernels);
    ctx.insert("paper_end", &format!("{:.4}", Segments::paper().eval(FRAC_PI_2)));
}

/// The phase's fits per band: the paper's table and 1–3 exponentials.
fn phase(ctx: &mut Context, members: &[Member<'_, Split>]) {
    let pair = |m: Option<M>| m.map(|m| (by_band(m, "a_rms_rel_by_band"), by_band(m, "a_max_rel_by_band")));
    let paper = pair(get(members, "paper-hg")).unwrap_or_default();
    let k = |n: usize| pair(get(members, &format!("hg-exp{n}"))).unwrap_or_default();
    let (k1, k2, k3) = (k(1), k(2), k(3));
    let cell = |v: &(Vec<f64>, Vec<f64>), i: usize| match (v.0.get(i), v.1.get(i)) {
        (Some(a), Some(b)) => format!("{} / {}", fmt_err(*a), fmt_err(*b)),
        _ => "—".into(),
    };
    let bands: Vec<BandRow> = PAPER_BANDS
        .iter()
        .enumerate()
        .map(|(i, (lo, hi))| BandRow {
            band: format!("[{lo}, {hi}]"),
            paper: cell(&paper, i),
            k1: cell(&k1, i),
            k2: cell(&k2, i),
            k3: cell(&k3, i),
        })
        .collect();
    ctx.insert("bands", &bands);
    let hg = get(members, "hg-exp1");
    ctx.insert("phase_points", &hg.map_or("—".into(), |m| prov_s(m, "phase.fit", "targets_per_band")));
    ctx.insert("node_rule", "162");
    ctx.insert("node_error", &hg.map_or("—".into(), |m| prov_f(m, "phase.fit", "node_rule_max_rel_error")));
}

/// The backscatter ratio's and the backward sums' fits.
fn backward(ctx: &mut Context, members: &[Member<'_, Split>]) {
    // The least-squares ratio is `paper-refit-hg`'s (`paper-refit`'s is fitted
    // with its segments for dominance, [`dominance`]).
    let (pp, pr) = (get(members, "paper"), get(members, "paper-refit-hg"));
    ctx.insert("ratio_targets", &pr.map_or("—".into(), |m| prov_s(m, "backscatter.fit", "targets")));
    for (name, m, key) in [
        ("ratio_paper_rms", pp, "backward_integral_rms_rel"),
        ("ratio_paper_max", pp, "backward_integral_max_rel"),
        ("ratio_refit_rms", pr, "backward_integral_rms_rel"),
        ("ratio_refit_max", pr, "backward_integral_max_rel"),
    ] {
        ctx.insert(name, &m.map_or("—".into(), |m| prov_f(m, "backscatter.fit", key)));
    }
    let es = members.first();
    let t = "backscatter.expsum_fit";
    ctx.insert("near_terms", &es.map_or(0, |m| m.body.expsum.near.c.len()));
    ctx.insert("local_terms", &es.map_or(0, |m| m.body.expsum.local.c.len()));
    ctx.insert("near_error", &es.map_or("—".into(), |m| prov_f(m, t, "near_max_rel")));
    ctx.insert("local_error", &es.map_or("—".into(), |m| prov_f(m, t, "local_max_rel")));
    ctx.insert("split", &expsum::SPLIT);
}

#[derive(Serialize)]
struct DominanceRow {
    figure: String,
    paper: String,
    refit: String,
}

/// `paper-refit` against `paper`: the fit's figures on its own points, and the
/// declared (held-out) bounds of both.
fn dominance(ctx: &mut Context, members: &[Member<'_, Split>]) {
    ctx.insert("dominance_fit", &Vec::<DominanceRow>::new());
    ctx.insert("dominance_declared", &Vec::<DominanceRow>::new());
    ctx.insert("dominance_points", "—");
    ctx.insert("dominance_ratio", "—");
    let (Some(pp), Some(pr)) = (get(members, "paper"), get(members, "paper-refit")) else { return };
    let floats = |key: &str| -> Vec<f64> {
        pr.provenance_value("forward.fit", key)
            .and_then(toml::Value::as_array)
            .map(|a| a.iter().filter_map(toml::Value::as_float).collect())
            .unwrap_or_default()
    };
    let (refit, paper) = (floats("figures_refit"), floats("figures_paper"));
    let fit_rows: Vec<DominanceRow> = super::dominant::FIGURES
        .iter()
        .zip(refit.iter().zip(&paper))
        .map(|(n, (r, p))| DominanceRow { figure: n.to_string(), paper: fmt_err(*p), refit: fmt_err(*r) })
        .collect();
    let mut declared = Vec::new();
    for d in [Domain::Thin, Domain::Dense] {
        if let (Some(a), Some(b)) = (pp.error(d), pr.error(d)) {
            for (what, x, y) in [("max", a.max_rel, b.max_rel), ("p99", a.p99_rel, b.p99_rel)] {
                declared.push(DominanceRow { figure: format!("{} {what}", d.name()), paper: fmt_err(x), refit: fmt_err(y) });
            }
        }
    }
    ctx.insert("dominance_fit", &fit_rows);
    ctx.insert("dominance_declared", &declared);
    ctx.insert("dominance_points", &prov_s(pr, "forward.fit", "points"));
    ctx.insert("dominance_ratio", &prov_f(pr, "forward.fit", "worst_ratio"));
}

/// The section's values.
pub(super) fn context(members: &[Member<'_, Split>]) -> Option<Context> {
    let mut ctx = Context::new();
    let fact_taus = [0.5, 1.0, 2.0, 5.0, 10.0];
    let facts: Vec<FactRow> = ["paper-as-printed", "paper", "paper-refit", "segments-3", "segments-8"]
        .iter()
        .filter_map(|n| get(members, n))
        .map(|m| FactRow {
            model: m.name.to_string(),
            cells: fact_taus.iter().map(|&t| fmt_err(math_grid_error(&|p| m.body.eval(p), t))).collect(),
        })
        .collect();
    ctx.insert("fact_taus", &fact_taus);
    ctx.insert("facts", &facts);
    forward(&mut ctx, members);
    phase(&mut ctx, members);
    backward(&mut ctx, members);
    dominance(&mut ctx, members);
    Some(ctx)
}

/// Relative error of `∫₀^θ e^{−T k̂}` over the grid `ts × thetas` (row per T),
/// as in the paper's Fig. 4 (its `θ` is `π/2 − γ`).
pub fn forward_error_grid(seg: &Segments, ts: &[f64], thetas: &[f64]) -> Vec<Vec<f64>> {
    let cells: Vec<(f64, f64)> = ts.iter().flat_map(|&t| thetas.iter().map(move |&th| (t, th))).collect();
    let errs = airlight_truth::parallel::map(
        &cells,
        |&(t, th)| (seg.integrate(0.0, th, t, 0.0, 0.0) / exact_forward(t, 0.0, th) - 1.0).abs(),
        &|_, _| {},
    );
    errs.chunks(thetas.len()).map(<[f64]>::to_vec).collect()
}

/// Relative error of the backward integral `ratio(θ1, κ) · ∫₀^{π/2} e^{−κ(sec − tan)}`
/// against `∫₀^{θ1} e^{−κ(sec + tan)}`, per `θ1` (rows) and `κ` (columns).
pub fn ratio_error_grid(r: &Ratio, theta1s: &[f64], kappas: &[f64]) -> Vec<Vec<f64>> {
    theta1s
        .iter()
        .map(|&th| {
            kappas
                .iter()
                .map(|&k| {
                    let approx = r.eval(th, k) * exact_forward(k, 0.0, FRAC_PI_2);
                    (approx / exact_backward(k, 0.0, th) - 1.0).abs()
                })
                .collect()
        })
        .collect()
}

/// Forward-kernel error over `(T, θ)`: the paper's Fig. 4, paper against refit.
fn forward_figure(members: &[Member<'_, Split>]) -> Option<Figure> {
    let (refit, s16) = (get(members, "paper-refit")?, get(members, "segments-16")?);
    let ts = linspace(0.25, 19.75, 40);
    let thetas = linspace(FRAC_PI_2 / 80.0, FRAC_PI_2 * 79.0 / 80.0, 40);
    let panel = |title: &str, s: &Segments| {
        Panel::Heatmap(Heatmap {
            title: title.to_string(),
            x_desc: "θ = π/2 − γ (rad)".into(),
            y_desc: "T = τ sin γ".into(),
            x_range: (0.0, FRAC_PI_2),
            y_range: (0.0, 20.0),
            x: thetas.clone(),
            y: ts.clone(),
            values: forward_error_grid(s, &ts, &thetas),
            log10_range: (-6.0, 0.0),
        })
    };
    Some(Figure {
        file: "forward-error".into(),
        panels: vec![
            panel("paper, 3 segments: log10 |error|", &Segments::paper()),
            panel("refit, 3 segments", &refit.body.forward),
            panel("refit, 16 segments", &s16.body.forward),
        ],
    })
}

/// HG against its approximations at three `g` (the paper's Figs. 6–8).
fn phase_figure(members: &[Member<'_, Split>]) -> Figure {
    let alphas = linspace(0.0, PI, 181);
    let exp = |name: &str| match get(members, name).map(|m| &m.body.phase) {
        Some(PhaseModel::Exp(e)) => Some(e.clone()),
        _ => None,
    };
    let paper_hg = exp("paper-hg");
    let fits: Vec<_> = (1..=3).filter_map(|k| exp(&format!("hg-exp{k}")).map(|e| (format!("refit, {k} exp"), e))).collect();
    let panels = [0.1, 0.7, 0.97]
        .iter()
        .map(|&g| {
            let curve = |f: &dyn Fn(f64) -> f64| alphas.iter().map(|&a| (a, f(a))).collect::<Vec<_>>();
            let mut series =
                vec![Line { name: "Henyey-Greenstein".into(), points: curve(&|a| Phase::from_g(g).eval(a)), colour: 0 }];
            if let Some(p) = &paper_hg {
                series.push(Line { name: "paper table".into(), points: curve(&|a| p.terms(g).eval(a)), colour: 1 });
            }
            for (i, (name, e)) in fits.iter().enumerate() {
                series.push(Line { name: name.clone(), points: curve(&|a| e.terms(g).eval(a)), colour: 2 + i });
            }
            let ymax = series[0].points.iter().map(|p| p.1).fold(0.0, f64::max) * 3.0;
            let ymin = series[0].points.iter().map(|p| p.1).fold(f64::INFINITY, f64::min) / 10.0;
            Panel::Lines(Lines {
                title: format!("g = {g}"),
                x_desc: "α (rad)".into(),
                y_desc: "P(α) (1/sr)".into(),
                x_range: (0.0, PI),
                y_range: (ymin, ymax),
                x_log: false,
                series,
            })
        })
        .collect();
    Figure { file: "phase".into(), panels }
}

/// The backscatter ratio's error (the paper's Fig. 11): paper against refit.
fn backscatter_figure(members: &[Member<'_, Split>]) -> Figure {
    let kappas = logspace(0.01, 20.0, 60);
    let theta1s = [0.2, 0.8, FRAC_PI_2];
    let refit = get(members, "paper-refit").and_then(|m| m.body.ratio.clone());
    let mut series = Vec::new();
    let ratios = std::iter::once(("paper", Ratio::paper(), [1, 3, 4])).chain(refit.map(|r| ("refit", r, [2, 5, 0])));
    for (label, r, palette) in ratios {
        for (i, row) in ratio_error_grid(&r, &theta1s, &kappas).iter().enumerate() {
            series.push(Line {
                name: format!("{label}, θ1 = {:.2}", theta1s[i]),
                points: kappas.iter().copied().zip(row.iter().copied()).collect(),
                colour: palette[i],
            });
        }
    }
    Figure {
        file: "backscatter-error".into(),
        panels: vec![Panel::Lines(Lines {
            title: "backward integral: |relative error| of the ratio form".into(),
            x_desc: "κ = T".into(),
            y_desc: "|error|".into(),
            x_range: (0.01, 20.0),
            y_range: (1e-4, 1e3),
            x_log: true,
            series,
        })],
    }
}

/// The error of `A` and of the forward integral against `N` for `segments-N`.
fn error_vs_n_figure(members: &[Member<'_, Split>]) -> Option<Figure> {
    let mut pts: Vec<(usize, M)> = members
        .iter()
        .filter_map(|m| m.name.strip_prefix("segments-").and_then(|n| n.parse().ok()).map(|n| (n, m)))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    pts.sort_by_key(|p| p.0);
    let get = |d: Domain, f: &dyn Fn(&airlight_truth::domains::DomainErrors) -> f64| -> Vec<(f64, f64)> {
        pts.iter().filter_map(|(n, m)| m.error(d).map(|e| (*n as f64, f(e)))).collect()
    };
    let fwd: Vec<(f64, f64)> = pts
        .iter()
        .filter_map(|(n, m)| {
            m.provenance_value("forward.fit", "forward_integral_max_rel").and_then(|v| v.as_float()).map(|v| (*n as f64, v))
        })
        .collect();
    let line = |name: &str, points: Vec<(f64, f64)>, colour: usize| Line { name: name.into(), points, colour };
    Some(Figure {
        file: "error-vs-n".into(),
        panels: vec![Panel::Lines(Lines {
            title: "segments-N: relative error vs number of segments".into(),
            x_desc: "N".into(),
            y_desc: "relative error".into(),
            x_range: (2.0, 16.0),
            y_range: (1e-4, 1.0),
            x_log: false,
            series: vec![
                line("A, thin: max", get(Domain::Thin, &|e| e.max_rel), 2),
                line("A, thin: p99", get(Domain::Thin, &|e| e.p99_rel), 3),
                line("A, dense: max", get(Domain::Dense, &|e| e.max_rel), 1),
                line("A, dense: p99", get(Domain::Dense, &|e| e.p99_rel), 5),
                line("forward integral alone: max (fit targets)", fwd, 0),
            ],
        })],
    })
}

/// Every figure the family draws from its members.
pub(super) fn figures(members: &[Member<'_, Split>]) -> Vec<Figure> {
    let mut out: Vec<Figure> = forward_figure(members).into_iter().collect();
    out.push(phase_figure(members));
    out.push(backscatter_figure(members));
    out.extend(error_vs_n_figure(members));
    out
}

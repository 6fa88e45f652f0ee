//! The models for the report: a row per model and per generated kernel, and the
//! plain-language advice computed from the measured table.

use crate::kernel::KernelSpec;
use airlight_fit::coeffs::ModelFile;
use airlight_shapes::bench::Bench;
use airlight_shapes::vocab::Domain;
use airlight_truth::domains::DomainErrors;
use airlight_truth::stats::{fmt_err, fmt_point};
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct ModelRow {
    name: String,
    g_range: String,
    thin_max: String,
    thin_p99: String,
    dense_max: String,
    dense_p99: String,
    extreme_max: String,
    thin_worst: String,
    dense_worst: String,
    cost: usize,
    families: String,
}

pub(super) fn err_cell(e: Option<&DomainErrors>, f: impl Fn(&DomainErrors) -> f64) -> String {
    e.map_or("—".into(), |e| fmt_err(f(e)))
}

/// Both maxima of a model over thin and dense.
pub(super) fn worst_of(m: &ModelFile) -> f64 {
    [Domain::Thin, Domain::Dense].iter().filter_map(|&d| m.error(d)).map(|e| e.max_rel).fold(0.0, f64::max)
}

/// The published model against the same forms refit (`fit/src/roles.toml`).
pub(super) fn published_advice(models: &[ModelFile]) -> Option<String> {
    let get = |n: &str| models.iter().find(|m| m.model.name == n);
    let roles = &airlight_fit::roles::roles().report;
    if let (Some(p), Some(r)) = (get(&roles.published), get(&roles.published_refit)) {
        let e = |m: &ModelFile, d: Domain| m.error(d).map_or(f64::NAN, |e| e.max_rel);
        return Some(format!(
            "The published isotropic model (`{}`) has max error {} on `thin` and {} on `dense`; the same forms refit (`{}`) reach {} and {}.",
            roles.published,
            fmt_err(e(p, Domain::Thin)),
            fmt_err(e(p, Domain::Dense)),
            roles.published_refit,
            fmt_err(e(r, Domain::Thin)),
            fmt_err(e(r, Domain::Dense))
        ));
    }
    None
}

/// Plain-language advice computed from the measured table.
/// `f32_of(name)`: the f32 bound over `thin` and `dense` of a model's kernel, where
/// the gate record measured these kernels.
pub(super) fn advice(models: &[ModelFile], bench: Option<&Bench>, f32_of: &dyn Fn(&str) -> Option<f64>) -> Vec<String> {
    let mut out = Vec::new();
    out.extend(published_advice(models));
    let ns_of = |m: &ModelFile| -> Option<f64> {
        bench?.models.iter().find(|b| b.name == m.model.name).map(|b| b.cpu_ns_per_eval)
    };
    // Speed: the bench's ns where it measured the model, else the op count (as ns-like rank).
    let speed = |m: &ModelFile| ns_of(m).unwrap_or(m.model.cost() as f64 * 1e6);
    let own: Vec<&ModelFile> = models.iter().filter(|m| !m.model.body.is_baseline()).collect();
    let serves = |m: &ModelFile, iso: bool| {
        if iso {
            m.model.g_range.0 <= 0.0 && m.model.g_range.1 >= 0.0
        } else {
            m.model.g_range == (-0.99, 0.99)
        }
    };
    // A model is dominated for a medium when another of airlight's is at least as
    // fast (bench) and at least as accurate (declared bound over thin and dense).
    let dominator = |m: &ModelFile, iso: bool| -> Option<&ModelFile> {
        own.iter()
            .filter(|o| o.model.name != m.model.name && serves(o, iso))
            .find(|o| crate::front::beats((speed(o), worst_of(o)), (speed(m), worst_of(m))))
            .copied()
    };
    for (label, iso) in [("isotropic media", true), ("Henyey–Greenstein media (g at run time, −0.99 … 0.99)", false)]
    {
        for budget in [1e-1, 1e-2, 1e-3, 1e-4, 1e-5] {
            let best = own
                .iter()
                .filter(|m| {
                    serves(m, iso)
                        && (iso || m.model.g_range != (0.0, 0.0))
                        && worst_of(m) <= budget
                        && dominator(m, iso).is_none()
                })
                .min_by(|a, b| speed(a).total_cmp(&speed(b)));
            out.push(match best {
                Some(m) => format!(
                    "{label}, max error ≤ {} on both `thin` and `dense`: `{}` ({}cost {}, declared max {}{}).",
                    fmt_err(budget),
                    m.model.name,
                    ns_of(m).map_or(String::new(), |n| format!("{n:.0} ns/eval in the bench, ")),
                    m.model.cost(),
                    fmt_err(worst_of(m)),
                    f32_of(&m.model.name).map_or(String::new(), |e| format!(
                        "; its f32 kernels {}{}",
                        fmt_err(e),
                        if e > budget { ", above this level" } else { "" }
                    ))
                ),
                None => format!("{label}, max error ≤ {}: no model here meets it.", fmt_err(budget)),
            });
        }
    }
    // Retired from the recommendations: a split-family model some other of
    // airlight's models covering its g range beats in both bench speed and bound
    // (the fastest such is named).
    let retired: Vec<String> = own
        .iter()
        .filter(|m| m.model.split().is_some())
        .filter_map(|m| {
            own.iter()
                .filter(|o| {
                    o.model.name != m.model.name
                        && o.model.g_range.0 <= m.model.g_range.0
                        && o.model.g_range.1 >= m.model.g_range.1
                        && crate::front::beats((speed(o), worst_of(o)), (speed(m), worst_of(m)))
                })
                .min_by(|a, b| speed(a).total_cmp(&speed(b)))
                .map(|d| format!("`{}` (by `{}`)", m.model.name, d.model.name))
        })
        .collect();
    if !retired.is_empty() {
        out.push(format!(
            "Not recommended, kept in the registry as the paper reproduced and refit: {} — each is at least as slow in the bench and less accurate than the model named.",
            retired.join(", ")
        ));
    }
    let baselines: Vec<String> =
        models.iter().filter(|m| m.model.body.is_baseline()).map(|m| format!("`{}`", m.model.name)).collect();
    if !baselines.is_empty() {
        out.push(format!(
            "The baselines ({}) are what a renderer would use instead, listed for comparison. The march and the equiangular rules take g at run time, so their bounds here hold over g ∈ [−0.99, 0.99] at once: their figures per g, and every model's cost in ns, are in \"Speed and accuracy: the trade\" below, which says where they beat airlight's models.",
            baselines.join(", ")
        ));
    }
    out
}

#[derive(Serialize)]
pub(super) struct GeneratedKernel {
    name: String,
    model: String,
    targets: String,
    specialised: String,
    ops: String,
    bound: String,
    f32_bound: String,
}

/// The model table's row of `m`.
pub(super) fn model_row(m: &ModelFile) -> ModelRow {
    let worst =
        |d: Domain| m.error(d).map_or("—".into(), |e| format!("{} at {}", fmt_err(e.max_rel), fmt_point(&e.worst)));
    ModelRow {
        name: m.model.name.clone(),
        g_range: format!("[{}, {}]", m.model.g_range.0, m.model.g_range.1),
        thin_max: err_cell(m.error(Domain::Thin), |e| e.max_rel),
        thin_p99: err_cell(m.error(Domain::Thin), |e| e.p99_rel),
        dense_max: err_cell(m.error(Domain::Dense), |e| e.max_rel),
        dense_p99: err_cell(m.error(Domain::Dense), |e| e.p99_rel),
        extreme_max: err_cell(m.error(Domain::Extreme), |e| e.max_rel),
        thin_worst: worst(Domain::Thin),
        dense_worst: worst(Domain::Dense),
        cost: m.model.cost(),
        families: m.families.join("; "),
    }
}

/// The table of generated kernels' row of `k`.
pub(super) fn generated_kernel(k: &KernelSpec) -> GeneratedKernel {
    let o = k.op_count();
    GeneratedKernel {
        name: k.name.clone(),
        model: k.model.as_ref().map_or("closed form".into(), |m| format!("`{}`", m.model.name)),
        targets: k.targets.iter().map(|t| t.name()).collect::<Vec<_>>().join(", "),
        specialised: crate::kernel::specialisations(k),
        ops: format!("{} / {} / {} / {}", o.exp, o.log, o.atan, o.div),
        bound: k
            .model
            .as_ref()
            .map_or("exact".into(), |m| crate::kernel::spec::domain_bound(m, k.domains(), k.g_range)),
        f32_bound: if k.f32.is_empty() {
            "not recorded for these sources".into()
        } else {
            k.f32.iter().map(|(d, e)| format!("{d} {}", fmt_err(*e))).collect::<Vec<_>>().join(", ")
        },
    }
}

//! The φ family's fits — `eˣE₂`'s rational, and each member's split points (the
//! head's cut `L`, the far region's start `X` and reach, the far correction's cut,
//! the short-interval threshold) by minimax against the reference — and the
//! assembly of a member from its tier. The rules are Gauss's; node counts are the
//! tier's.

use super::{E2Fit, PhiRule, E2_DEGREE, EIN_TERMS};
use crate::fitset::{self, Set, SetSpec};
use crate::family::{phase_label, Assembled, Family};
use crate::lsq::{self, Outcome, OUTER_SOLVER};
use airlight_truth::reference::Point;
use airlight_truth::tomlfile::value::{f, hex_seed, i, kv, s};
use toml::Value;

/// The part `airlight fit --family phi` names.
pub const PART: &str = "phi";

/// The parameters of one member of the φ family (`fit/src/family/phi/`): its head
/// node count (the member's name), the most far-correction and tail nodes the
/// node-count search may give it, and the split its fit starts from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhiTier {
    /// Head nodes (Gauss–Legendre in φ).
    pub head: usize,
    /// At most this many far-correction nodes (Gauss–Legendre in `v = 1/u`).
    pub far: usize,
    /// At most this many tail nodes (Gauss–Laguerre).
    pub tail: usize,
    /// `L`, the head's transmittance cut, where the split fit starts.
    pub cut: f64,
    /// The far correction's transmittance cut, where the split fit starts.
    pub far_cut: f64,
}

/// A node-count choice counts as good as the best when its check-set max is
/// within this factor of the best's: the search then takes the one with the
/// fewest far and tail nodes (the cheaper kernel).
pub const NODES_WITHIN: f64 = 1.25;

/// The node counts of a member, searched: every far-correction count `1..=t.far`
/// and tail count `1..=t.tail`, each with its split fitted ([`fit_split`]); the
/// check set decides ([`NODES_WITHIN`]).
#[derive(Debug, Clone, PartialEq)]
pub struct NodeSearch {
    /// `(far, tail, check-set max with its fitted split)` for every count tried.
    pub tried: Vec<(usize, usize, f64)>,
    /// The chosen far and tail counts.
    pub chosen: (usize, usize),
    /// The chosen counts' split fit.
    pub split: SplitFit,
}

/// Searches `t`'s far and tail node counts over `g_range` ([`NodeSearch`]).
pub fn search_nodes(t: PhiTier, g_range: (f64, f64), e2: &super::ExpE2) -> NodeSearch {
    let mut fits = Vec::new();
    for far in 1..=t.far {
        for tail in 1..=t.tail {
            let rule = PhiRule::new(t.head, far, tail, t.cut, t.far_cut, e2.clone());
            let f = fit_split(&rule, g_range);
            fits.push((far, tail, f));
        }
    }
    let best = fits.iter().map(|f| f.2.check_max.0.min(f.2.check_max.1)).fold(f64::INFINITY, f64::min);
    let (far, tail, split) = fits
        .iter()
        .filter(|f| f.2.check_max.0.min(f.2.check_max.1) <= NODES_WITHIN * best)
        .min_by_key(|f| (f.0 + f.1, f.1))
        .cloned()
        .expect("the best is within its own factor");
    NodeSearch {
        tried: fits.iter().map(|f| (f.0, f.1, f.2.check_max.0.min(f.2.check_max.1))).collect(),
        chosen: (far, tail),
        split,
    }
}

/// The split parameters the fit moves, in order, with the box it keeps them in.
pub const SPLIT_KEYS: [&str; 5] = ["cut", "far_from", "far_tmax", "far_cut", "short"];
/// The box: `L` ∈ [1, 8], `X/max(1, κ)` ∈ [1.5, 6], `T X` ∈ [1, 10], the far cut
/// ∈ [2, 12], the short threshold ∈ [0.05, 1].
pub const SPLIT_BOX: [(f64, f64); 5] = [(1.0, 8.0), (1.5, 6.0), (1.0, 10.0), (2.0, 12.0), (0.05, 1.0)];
/// Seed of the split fit's points (the validation and its held-out rounds use their own).
pub const SPLIT_FIT_SEED: u64 = 0xF17_0000_0000_0006;
/// Seed of the split fit's check set, which decides between the tier's split
/// and the fitted one.
pub const SPLIT_CHECK_SEED: u64 = 0xF17_0000_0000_0007;
/// Low-discrepancy points per domain in the fitting set.
pub const SPLIT_FIT_POINTS: usize = 2500;
/// Face grid per domain (`n × n` per face at the ends of the g range and 0).
pub const SPLIT_FACES: usize = 12;
/// Points per domain in the check set.
pub const SPLIT_CHECK_POINTS: usize = 2000;
/// Nelder–Mead iterations.
pub const SPLIT_ITERS: u64 = 300;

/// The split points of one member, fitted: what the search found, and which of
/// the tier's and the fitted split the check set kept.
#[derive(Debug, Clone, PartialEq)]
pub struct SplitFit {
    /// The tier's split ([`SPLIT_KEYS`] order): the search's start.
    pub start: [f64; 5],
    /// The search's result.
    pub fitted: [f64; 5],
    /// The one kept (the smaller max on the check set; the tier's on a tie).
    pub kept: [f64; 5],
    /// Max relative error on the fitting set: tier's, fitted.
    pub fit_max: (f64, f64),
    /// Max relative error on the check set: tier's, fitted.
    pub check_max: (f64, f64),
    /// What the search did.
    pub outcome: Outcome,
    /// Points in the fitting set and in the check set.
    pub points: (usize, usize),
}

fn split_of(r: &PhiRule) -> [f64; 5] {
    [r.cut, r.far_from, r.far_tmax, r.far_cut, r.short]
}

/// `r` with split `x`, each clamped into [`SPLIT_BOX`].
fn with_split(r: &PhiRule, x: &[f64]) -> PhiRule {
    let c = |j: usize| x[j].clamp(SPLIT_BOX[j].0, SPLIT_BOX[j].1);
    PhiRule { cut: c(0), far_from: c(1), far_tmax: c(2), far_cut: c(3), short: c(4), ..r.clone() }
}

/// The split fit's sets over `g_range` ([`crate::fitset`]).
fn sets(g_range: (f64, f64)) -> (Set, Set) {
    fitset::sets(SetSpec {
        g_range,
        fit_points: SPLIT_FIT_POINTS,
        fit_seed: SPLIT_FIT_SEED,
        faces: SPLIT_FACES,
        check_points: SPLIT_CHECK_POINTS,
        check_seed: SPLIT_CHECK_SEED,
    })
}

/// The largest relative error of `r` on `set`.
fn max_on(r: &PhiRule, set: &[(Point, f64)]) -> f64 {
    fitset::max_on(&|p| r.eval(p), set)
}

/// Fits `rule`'s split points over `g_range`: minimax (the largest relative error
/// of `A` over the fitting set) by Nelder–Mead from the tier's split; the check
/// set (points of its own seed) then keeps whichever of the two is smaller there.
pub fn fit_split(rule: &PhiRule, g_range: (f64, f64)) -> SplitFit {
    let (fit_set, check_set) = sets(g_range);
    let start = split_of(rule);
    let cost = |x: &[f64]| max_on(&with_split(rule, x), &fit_set);
    let step = [0.5, 0.5, 1.0, 1.0, 0.1];
    let outcome = lsq::nelder_mead(&cost, &start, &step, 1e-9, SPLIT_ITERS);
    let fitted = split_of(&with_split(rule, &outcome.param));
    let fit_max = (max_on(rule, &fit_set), max_on(&with_split(rule, &fitted), &fit_set));
    let check_max = (max_on(rule, &check_set), max_on(&with_split(rule, &fitted), &check_set));
    let kept = if check_max.1 < check_max.0 { fitted } else { start };
    SplitFit { start, fitted, kept, fit_max, check_max, outcome, points: (fit_set.len(), check_set.len()) }
}

/// The split fit's provenance table.
fn split_provenance(fit: &SplitFit) -> airlight_truth::tomlfile::Provenance {
    let arr = |x: &[f64; 5]| Value::Array(x.iter().map(|&v| f(v)).collect());
    (
        "split.fit".into(),
        kv(vec![
                ("objective", s("minimax: the largest relative error of A over the fitting set (f64 model)")),
                ("parameters", Value::Array(SPLIT_KEYS.iter().map(|k| s(k)).collect())),
                ("box", s("cut in [1, 8], far_from in [1.5, 6], far_tmax in [1, 10], far_cut in [2, 12], short in [0.05, 1]")),
                (
                    "points_from",
                    s(&format!(
                        "{SPLIT_FIT_POINTS} low-discrepancy points inside thin and inside dense each over the g range, and {SPLIT_FACES}x{SPLIT_FACES} grids on each domain's faces at its ends and 0 (seed below)"
                    )),
                ),
                ("points_seed", hex_seed(SPLIT_FIT_SEED)),
                ("points", i(fit.points.0)),
                ("solver", s(&format!("{OUTER_SOLVER}, from the tier's split"))),
                ("iterations", i(fit.outcome.iterations)),
                ("termination", s(&fit.outcome.termination)),
                ("start", arr(&fit.start)),
                ("fitted", arr(&fit.fitted)),
                ("fit_max_rel_start", f(fit.fit_max.0)),
                ("fit_max_rel_fitted", f(fit.fit_max.1)),
                ("check", s(&format!("{SPLIT_CHECK_POINTS} points inside thin and inside dense each, a seed of their own (below): the split with the smaller max there is kept"))),
                ("check_seed", hex_seed(SPLIT_CHECK_SEED)),
                ("check_points", i(fit.points.1)),
                ("check_max_rel_start", f(fit.check_max.0)),
                ("check_max_rel_fitted", f(fit.check_max.1)),
                ("kept", s(if fit.kept == fit.fitted && fit.kept != fit.start { "fitted" } else { "start" })),
        ]),
    )
}

/// The node-count search's provenance table.
fn nodes_provenance(n: &NodeSearch, t: PhiTier) -> airlight_truth::tomlfile::Provenance {
    let col = |f: &dyn Fn(&(usize, usize, f64)) -> Value| Value::Array(n.tried.iter().map(f).collect());
    (
        "head.fit".into(),
        kv(vec![
            ("objective", s(&format!("far-correction nodes 1..={} and tail nodes 1..={}, each with its split fitted (see [split.fit]); of the counts whose check-set max is within {NODES_WITHIN} of the best, the fewest far + tail nodes", t.far, t.tail))),
            ("head", i(t.head)),
            ("far_tried", col(&|x| i(x.0))),
            ("tail_tried", col(&|x| i(x.1))),
            ("check_max_rel_tried", col(&|x| f(x.2))),
            ("far", i(n.chosen.0)),
            ("tail", i(n.chosen.1)),
        ]),
    )
}

/// A member of the φ family (errors not yet measured): the rules are Gauss's,
/// `eˣE₂` fitted, the split points fitted from the tier's ([`fit_split`]).
pub fn assemble(t: PhiTier, g_range: (f64, f64), fit: Option<&E2Fit>) -> Result<Assembled<PhiRule>, String> {
    let fit = fit.ok_or("the phi family's e^x E2 was not fitted")?;
    let nodes = search_nodes(t, g_range, &fit.e2);
    let (far, tail) = nodes.chosen;
    let rule = with_split(&PhiRule::new(t.head, far, tail, t.cut, t.far_cut, fit.e2.clone()), &nodes.split.kept);
    let split = &nodes.split;
    let families = vec![
        format!(
            "phi-{} ({}-point Gauss-Legendre head, {far}-point far correction, {tail}-point Gauss-Laguerre tail)",
            t.head, t.head
        ),
        phase_label(g_range),
    ];
    let provenance = vec![
        e2_provenance(fit),
        split_provenance(split),
        nodes_provenance(&nodes, t),
    ];
    Ok(Assembled {
        body: rule,
        families,
        provenance,
        method: kv(vec![
            ("method", s("whole A in the u form: Gauss-Legendre head in the HG variable phi (u past X or on short intervals) to the transmittance cut e^-L, Gauss-Laguerre tail from both ends; for small T X, C/u^2 exactly through e^x E2 and the rest by Gauss-Legendre in v = 1/u (fit/src/family/phi/)")),
            ("fitted", s("e^x E2's rational (see [e2.fit]) and the split points (see [split.fit]); node counts are the tier's")),
        ]),
    })
}

/// The provenance table of `eˣE₂`'s fit (`[e2.fit]`), for every family that integrates with it.
fn e2_provenance(fit: &E2Fit) -> airlight_truth::tomlfile::Provenance {
(
        "e2.fit".into(),
        kv(vec![
            ("source", s("this project: e^x E2(x) = 1 - x e^x E1(x); Ein's Taylor series below x = 1, a rational in t = 1/x beyond")),
            ("target", s("e^x E2(x), x >= 1, through the reference complex E1 (truth/src/e1.rs, about 1e-15)")),
            ("form", s(&format!("t P(t)/Q(t), P, Q of degree {E2_DEGREE} with unit constant terms; Ein to x^{EIN_TERMS}"))),
            ("objective", s("relative error, linearised (Sanathanan-Koerner): each step linear least squares by SVD (nalgebra 0.34), weighted by the previous denominator")),
            ("points", i(fit.points)),
            ("points_from", s("Chebyshev points of t = 1/x in (0, 1]")),
            ("iterations", i(fit.iterations)),
            ("max_rel", f(fit.max_rel.0)),
            ("max_rel_at_x", f(fit.max_rel.1)),
            ("series_max_rel", f(fit.series_max_rel.0)),
            ("series_max_rel_at_x", f(fit.series_max_rel.1)),
        ]),
    )
}

/// What `airlight fit --family phi` prints.
pub fn summary(fit: &E2Fit) -> String {
    format!(
        "phi e^x E2 (x >= 1): t P(t)/Q(t), degree {E2_DEGREE}/{E2_DEGREE}, {} Chebyshev points, {} Sanathanan-Koerner iterations: max rel {:.2e} at x = {:.4}; Ein series to x^{EIN_TERMS} below 1: max rel {:.2e} at x = {:.4}",
        fit.points, fit.iterations, fit.max_rel.0, fit.max_rel.1, fit.series_max_rel.0, fit.series_max_rel.1
    )
}

//! The lite family's fit: each member's nodes, weights, `α` and `σ` (and an HG
//! member's fade `b`) together, by minimax against the reference (the largest
//! relative error of `A` over a fitting set; the median members: the largest median,
//! [`Objective`]), Nelder–Mead restarted from `n`-point Gauss–Legendre; a check set of its
//! own seed keeps whichever of the start and the fitted rule is better there. The
//! declared bound is then measured like every model's, on points neither saw.

use super::LiteRule;
use crate::family::Family;
use super::e2::{self, LogE2, LogE2Fit};
use crate::family::{phase_label, Assembled};
use crate::fitset::{self, SetSpec};
use crate::lsq::{self, Outcome, OUTER_SOLVER};
use airlight_truth::tomlfile::value::{f, hex_seed, i, kv, s};
use toml::Value;

/// The part `airlight fit --family lite` names.
pub const PART: &str = "lite";
/// Seed of the fitting set (the validation and its held-out rounds use their own).
pub const FIT_SEED: u64 = 0xF17_0000_0000_0011;
/// Seed of the check set.
pub const CHECK_SEED: u64 = 0xF17_0000_0000_0012;
/// Low-discrepancy points per domain in the fitting set.
pub const FIT_POINTS: usize = 3000;
/// HG members: `g` is one more dimension, so their fitting set is denser.
pub const FIT_POINTS_HG: usize = 9000;
/// Face grid per domain.
pub const FACES: usize = 16;
/// Points per domain in the check set.
pub const CHECK_POINTS: usize = 3000;
/// Nelder–Mead iterations per run, and restarts.
pub const ITERS: u64 = 4000;
/// Restarts of Nelder–Mead from its own best point.
pub const RESTARTS: usize = 6;
/// The box `α ∈ [0.05, 4]`, `σ ∈ [0.01, 1]`; nodes inside (0, 1) through a logistic map.
pub const ALPHA_BOX: (f64, f64) = (0.05, 4.0);
/// See [`ALPHA_BOX`].
pub const SHORT_BOX: (f64, f64) = (0.01, 1.0);
/// HG members: the fade `b ∈ [1e-3, 10]`, from 0.3.
pub const FADE_BOX: (f64, f64) = (1e-3, 10.0);
/// See [`FADE_BOX`].
pub const FADE_START: f64 = 0.3;

/// A member's recipe: its node count and what its fit minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LiteTier {
    /// The number of nodes.
    pub nodes: usize,
    /// The fit's objective.
    pub objective: Objective,
}

/// What a member's fit minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Objective {
    /// The largest relative error (minimax): the members of the max levels.
    Max,
    /// The largest median relative error over the domains and bands of `g`
    /// ([`fitset::median_on`]): the members of the median levels.
    Median,
}

impl Objective {
    /// Its value for `eval` on `set` (a non-finite value counts as the largest).
    fn on(self, eval: &(dyn Fn(airlight_truth::reference::Point) -> f64 + Sync), set: &[(airlight_truth::reference::Point, f64)]) -> f64 {
        let m = match self {
            Objective::Max => fitset::max_on(eval, set),
            Objective::Median => fitset::median_on(eval, set),
        };
        if m.is_finite() {
            m
        } else {
            f64::MAX
        }
    }

    /// The provenance keys' word for it.
    fn word(self) -> &'static str {
        match self {
            Objective::Max => "max",
            Objective::Median => "median",
        }
    }
}

/// What the fit found.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeFit {
    /// The start and the fitted rule.
    pub start: LiteRule,
    /// The fitted rule.
    pub fitted: LiteRule,
    /// The one kept.
    pub kept: LiteRule,
    /// The objective on the fitting set: start, fitted.
    pub fit_max: (f64, f64),
    /// The objective on the check set: start, fitted.
    pub check_max: (f64, f64),
    /// The objective.
    pub objective: Objective,
    /// What the search did.
    pub outcome: Outcome,
    /// Points in the fitting set and in the check set.
    pub points: (usize, usize),
}

/// Whether a member of this g range (its ends) is an HG member (the isotropic ones
/// have the range `(0, 0)`): the one place the family decides, for its fit and for
/// reading its coefficient file.
pub(super) fn is_hg(g_range: &[f64]) -> bool {
    g_range.iter().any(|&g| g != 0.0)
}

/// Points per domain in the fitting set of an isotropic or an HG member.
fn fit_points(hg: bool) -> usize {
    if hg {
        FIT_POINTS_HG
    } else {
        FIT_POINTS
    }
}

fn spec(g_range: (f64, f64)) -> SetSpec {
    SetSpec {
        g_range,
        fit_points: fit_points(is_hg(&[g_range.0, g_range.1])),
        fit_seed: FIT_SEED,
        faces: FACES,
        check_points: CHECK_POINTS,
        check_seed: CHECK_SEED,
    }
}

/// The search's parameters: `logit x_i`, `w_i`, `ln α`, `σ` (and `ln b`).
fn params(r: &LiteRule) -> Vec<f64> {
    let mut p: Vec<f64> = r.x.iter().map(|x| (x / (1.0 - x)).ln()).collect();
    p.extend(&r.w);
    p.push(r.alpha.ln());
    p.push(r.short);
    p.extend(r.fade.map(f64::ln));
    p
}

/// The rule at parameters `p` (nodes sorted, `α` and `σ` clamped into their box).
fn rule_at(start: &LiteRule, p: &[f64]) -> LiteRule {
    let n = start.x.len();
    let mut nodes: Vec<(f64, f64)> = (0..n).map(|j| (1.0 / (1.0 + (-p[j]).exp()), p[n + j])).collect();
    nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Weights summing to 1 (summed in node order): a constant integrand (the
    // shortest intervals) is exact.
    let total: f64 = nodes.iter().map(|q| q.1).sum();
    LiteRule::from_nodes(
        nodes.into_iter().map(|(x, w)| (x, w / total)).collect(),
        p[2 * n].exp().clamp(ALPHA_BOX.0, ALPHA_BOX.1),
        p[2 * n + 1].clamp(SHORT_BOX.0, SHORT_BOX.1),
        start.fade.map(|_| p[2 * n + 2].exp().clamp(FADE_BOX.0, FADE_BOX.1)),
        start.e2.clone(),
    )
}

/// Fits the member of `tier` ([`NodeFit`]).
pub fn fit_nodes(tier: LiteTier, g_range: (f64, f64), e2: &LogE2) -> NodeFit {
    let (n, objective) = (tier.nodes, tier.objective);
    let (fit_set, check_set) = fitset::sets(spec(g_range));
    let hg = is_hg(&[g_range.0, g_range.1]);
    let start = LiteRule::start(n, hg.then_some(FADE_START), e2.clone());
    let max_on = |r: &LiteRule, set: &[(airlight_truth::reference::Point, f64)]| objective.on(&|p| r.eval(p), set);
    let cost = |p: &[f64]| max_on(&rule_at(&start, p), &fit_set);
    let p0 = params(&start);
    let mut step: Vec<f64> = vec![0.3; n];
    step.extend(start.w.iter().map(|w| 0.1 * w));
    step.push(0.3);
    step.push(0.05);
    if hg {
        step.push(0.3);
    }
    let outcome = lsq::nelder_mead_restarted(&cost, &p0, &step, 1e-10, ITERS, RESTARTS);
    let fitted = rule_at(&start, &outcome.param);
    let fit_max = (max_on(&start, &fit_set), max_on(&fitted, &fit_set));
    let check_max = (max_on(&start, &check_set), max_on(&fitted, &check_set));
    let kept = if check_max.1 < check_max.0 { fitted.clone() } else { start.clone() };
    NodeFit { start, fitted, kept, fit_max, check_max, objective, outcome, points: (fit_set.len(), check_set.len()) }
}

/// The node fit's provenance table.
fn provenance(fit: &NodeFit) -> airlight_truth::tomlfile::Provenance {
    let arr = |x: &[f64]| Value::Array(x.iter().map(|&v| f(v)).collect());
    // The boxes as `rule_at` clamps to them.
    let (a, sh, fb) = (ALPHA_BOX, SHORT_BOX, FADE_BOX);
    let (fade_param, fade_box, phase) = match fit.start.fade {
        None => (String::new(), String::new(), "isotropic"),
        Some(b) => (", ln fade".to_string(), format!(", fade in [{}, {}] from {b}", fb.0, fb.1), "g over the member's range"),
    };
    let parameters = format!(
        "nodes x (through logit), weights w (normalised to sum 1, so that the shortest intervals are exact), ln alpha, short{fade_param}; nodes sorted, alpha in [{}, {}], short in [{}, {}]{fade_box}",
        a.0, a.1, sh.0, sh.1
    );
    let objective = match fit.objective {
        Objective::Max => "minimax: the largest relative error of A over the fitting set (f64 model)".to_string(),
        Objective::Median => format!(
            "the largest median relative error of A over the fitting set's domains (thin, dense) and bands of g (edges {:?}), f64 model",
            fitset::MEDIAN_G_EDGES
        ),
    };
    let w = fit.objective.word();
    let (fs, ff, cs, cf) =
        (format!("fit_{w}_rel_start"), format!("fit_{w}_rel_fitted"), format!("check_{w}_rel_start"), format!("check_{w}_rel_fitted"));
    let mut table = vec![
            ("objective", s(&objective)),
            ("parameters", s(&parameters)),
            (
                "points_from",
                s(&format!(
                    "{} low-discrepancy points inside thin and inside dense each ({phase}), and {FACES}x{FACES} grids on each domain's faces (seed below)",
                    fit_points(fit.start.fade.is_some())
                )),
            ),
            ("points_seed", hex_seed(FIT_SEED)),
            ("points", i(fit.points.0)),
            ("solver", s(&format!("{OUTER_SOLVER}, restarted up to {RESTARTS} times, {ITERS} iterations a run, from Gauss-Legendre nodes on [0, 1], alpha 0.5, short 0.1"))),
            ("iterations", i(fit.outcome.iterations)),
            ("termination", s(&fit.outcome.termination)),
            ("start_x", arr(&fit.start.x)),
            ("start_w", arr(&fit.start.w)),
            ("fitted_x", arr(&fit.fitted.x)),
            ("fitted_w", arr(&fit.fitted.w)),
            ("fitted_alpha", f(fit.fitted.alpha)),
            ("fitted_short", f(fit.fitted.short)),
    ];
    // HG members' fade (isotropic ones have none).
    table.extend(fit.fitted.fade.map(|b| ("fitted_fade", f(b))));
    table.extend([
            (fs.as_str(), f(fit.fit_max.0)),
            (ff.as_str(), f(fit.fit_max.1)),
            ("check", s(&format!("{CHECK_POINTS} points inside thin and inside dense each, a seed of their own (below): the rule with the smaller {w} there is kept"))),
            ("check_seed", hex_seed(CHECK_SEED)),
            ("check_points", i(fit.points.1)),
            (cs.as_str(), f(fit.check_max.0)),
            (cf.as_str(), f(fit.check_max.1)),
            ("kept", s(if fit.kept == fit.fitted && fit.kept != fit.start { "fitted" } else { "start" })),
    ]);
    ("nodes.fit".into(), kv(table))
}

/// A member of the lite family (errors not yet measured): `eˣE₂` fitted, nodes,
/// weights and split fitted ([`fit_nodes`]).
pub fn assemble(tier: LiteTier, g_range: (f64, f64), fit: Option<&LogE2Fit>) -> Result<Assembled<LiteRule>, String> {
    let fit = fit.ok_or("the lite family's e^x E2 was not fitted")?;
    let nodes = fit_nodes(tier, g_range, &fit.e2);
    let n = tier.nodes;
    let med = if tier.objective == Objective::Median { "med-" } else { "" };
    let hg = is_hg(&[g_range.0, g_range.1]);
    let (family, method, fitted) = if hg {
        (
            format!("lite-{med}{n} (e^x E2 of a faded C/(kappa+u)^2, {n} fitted nodes for the rest, HG at each)"),
            "whole A in the u form, one path: w(u) = C sqrt(1+u^2)/(kappa^2+u^2)^(3/2); beta C/(kappa+u)^2 exactly through e^x E2 (one log, no branch) at both ends, beta = 1/(1 + fade T m), m = kappa + ua; the rest w - beta C/(kappa+u)^2 by fitted nodes in s, u = ua + lambda s/(1-s); short intervals take w at the same nodes (fit/src/family/lite/)",
            "e^x E2's form (see [e2.fit]); the nodes, weights, alpha, short and fade together (see [nodes.fit])",
        )
    } else {
        (
            format!("lite-{med}{n} (e^x E2 of 1/(1+u)^2, {n} fitted nodes for the rest)"),
            "whole A in the u form, one path: 1/(1+u)^2 exactly through e^x E2 (one log, no branch) at both ends, the rest k(u) = 2u/((1+u^2)(1+u)^2) by fitted nodes in s, u = ua + lambda s/(1-s); short intervals take 1/(1+u^2) at the same nodes (fit/src/family/lite/)",
            "e^x E2's form (see [e2.fit]); the nodes, weights, alpha and short together (see [nodes.fit])",
        )
    };
    Ok(Assembled {
        body: nodes.kept.clone(),
        families: vec![family, phase_label(g_range)],
        provenance: vec![e2::provenance(fit), provenance(&nodes)],
        method: kv(vec![("method", s(method)), ("fitted", s(fitted))]),
    })
}

//! The lite family: the cheap isotropic tiers, one straight-line rule with no
//! head, far or tail branch, so that the lanes of a GPU wave take the same path.
//!
//! In the u form (docs/MATH.md §3), `A = (2 e^{−τ}/h) P I`, `P = 1/(4π)`,
//! `I = ∫_{ua}^{ub} e^{−T(u−ua)}/(1 + u²) du`, `T = τ h`. With `m = 1 + ua`,
//! `Δ = ub − ua`:
//!
//! * `1/(1 + u²) = 1/(1 + u)² + k(u)`, `k(u) = 2u/((1 + u²)(1 + u)²) ≥ 0`, which
//!   falls like `2/u³`. The first part carries the `u⁻²` tail and with it the
//!   `T ln T` non-analyticity (docs/MATH.md §6): it is integrated exactly,
//!   `J₀ = E(T m)/m − e^{−TΔ} E(T(m + Δ))/(m + Δ)`, `E(x) = eˣE₂(x)` by a fitted form
//!   with one `log` and no branch ([`e2::LogE2`]).
//! * `k` by `n` fitted nodes in the rational map `u = ua + λ r`, `r = s/(1 − s)`,
//!   `s ∈ [0, s_b]`, `λ = m/(1 + α T m)`, `s_b = Δ/(λ + Δ)` (1 on an open ray):
//!   `λ` is the scale of `k` (about `m`) where the medium is thin and the
//!   transmittance's `1/T` where it is dense, so that `e^{−Tλr}` stays a gentle
//!   function of `s` in both.
//! * A short interval (`Δ < σ m`) takes `1/(1 + u²)` itself at the same nodes and no
//!   `J₀` (the difference of two `E` would cancel there).
//!
//! Henyey–Greenstein members (`g` at run time) take the same rule with `w(u)` for
//! `1/(1 + u²)`: with `κ = (1 − g)/(1 + g)`, `C = (1 − g)/(4π (1 + g)²)`,
//! `w = C √(1 + u²)/(κ² + u²)^{3/2}`, which is `C/(1 + u²)` at `g = 0`, flat for
//! `u ≲ κ` (the forward peak when `g > 0`, the backward lobe up to `u ≈ κ` when
//! `g < 0`) and `C/u²` beyond `max(1, κ)`. The exact part is `β C/(κ + u)²`
//! and the scale `m = κ + ua`; `β = 1/(1 + b T m)` fades it where the medium is
//! dense on the scale of `w`. Any `β` leaves the split exact; without the fade the
//! nodes would cancel an exact part up to `κ` times larger than `A` when `g → −1`
//! (`C/κ²` against `w(0) = C/κ³`), which amplified their error to 100% and more.
//!
//! Nodes `x_i`, weights `w_i`, `α`, `σ` (and `b`) are fitted together against the
//! reference, by minimax or, for the median members, for the largest median ([`fit`]).

pub mod e2;
pub mod fit;

use airlight_shapes::cost::{Cost, PhaseShape, Shape};
use crate::family::uform::{on_axis, u_geometry};
use e2::{LogE2, LogE2Fit};
use crate::family::{Assembled, Family, Role};
use airlight_truth::reference::Point;
use airlight_shapes::template::{lit, lits, Context, KernelView, Templates};
use airlight_truth::tomlfile::{FieldError, Reader};
use std::f64::consts::PI;
use std::fmt::Write as _;
use toml::Table;

/// A member: its fitted nodes, weights and split, and `eˣE₂`.
#[derive(Debug, Clone, PartialEq)]
pub struct LiteRule {
    /// Nodes `x_i ∈ (0, 1)`: `s = s_b x_i`.
    pub x: Vec<f64>,
    /// Weights.
    pub w: Vec<f64>,
    /// `α` of the scale `λ = m/(1 + α T m)`.
    pub alpha: f64,
    /// `σ`: an interval with `Δ < σ m` is short.
    pub short: f64,
    /// Henyey–Greenstein members: `b` of the fade `β = 1/(1 + b T m)`; `None`: isotropic.
    pub fade: Option<f64>,
    /// `eˣE₂`.
    pub e2: LogE2,
}

/// `k(u) = 1/(1 + u²) − 1/(1 + u)²`, cancellation-free.
pub fn k_of_u(u: f64) -> f64 {
    2.0 * u / ((1.0 + u * u) * (1.0 + u) * (1.0 + u))
}

impl LiteRule {
    /// `n` Gauss–Legendre nodes on `[0, 1]`, `α = 1/2`, `σ = 0.1`: where the fit starts.
    /// HG members (`fade`) start from `b = 0.3`.
    pub fn start(n: usize, fade: Option<f64>, e2: LogE2) -> LiteRule {
        let (x, w) = airlight_truth::quad::gauss_legendre(n);
        LiteRule::from_nodes(x.iter().zip(&w).map(|(x, w)| (0.5 * (1.0 + x), 0.5 * w)).collect(), 0.5, 0.1, fade, e2)
    }

    /// The rule with nodes `(x_i, w_i)` (any order: sorted by `x`, as the coefficient
    /// file requires).
    pub fn from_nodes(mut nodes: Vec<(f64, f64)>, alpha: f64, short: f64, fade: Option<f64>, e2: LogE2) -> LiteRule {
        nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
        LiteRule { x: nodes.iter().map(|q| q.0).collect(), w: nodes.iter().map(|q| q.1).collect(), alpha, short, fade, e2 }
    }

    /// `I/C` of an HG member (`w/C` integrated) from `T`, `ua`, `Δ` and `κ`.
    pub fn integral_hg(&self, t: f64, ua: f64, du: f64, kappa: f64) -> f64 {
        let m = kappa + ua;
        let short = du < self.short * m;
        let beta = if short { 0.0 } else { 1.0 / (1.0 + self.fade.unwrap_or(0.0) * t * m) };
        let sum = if short { 0.0 } else { self.ends(t, m, du) * beta };
        self.add_nodes(sum, t, ua, du, m, |u| {
            let iq = 1.0 / (kappa * kappa + u * u);
            ((1.0 + u * u) * iq).sqrt() * iq - beta / ((kappa + u) * (kappa + u))
        })
    }

    /// `I` (without `2 e^{−τ} P/h`) from `T`, `ua` and `Δ` (`∞`: open).
    pub fn integral(&self, t: f64, ua: f64, du: f64) -> f64 {
        let m = 1.0 + ua;
        let short = du < self.short * m;
        let sum = if short { 0.0 } else { self.ends(t, m, du) };
        self.add_nodes(sum, t, ua, du, m, |u| if short { 1.0 / (1.0 + u * u) } else { k_of_u(u) })
    }

    /// The exact part, `1/(c + u)²` from both ends with `m = c + ua`:
    /// `E(T m)/m − e^{−TΔ} E(T(m + Δ))/(m + Δ)` (the second term 0 on an open ray).
    fn ends(&self, t: f64, m: f64, du: f64) -> f64 {
        let mut sum = self.e2.eval(t * m) / m;
        if du.is_finite() {
            let mb = m + du;
            sum -= (-t * du).exp() * self.e2.eval(t * mb) / mb;
        }
        sum
    }

    /// `sum` plus the nodes' `∫ f(u) e^{−T(u−ua)} du` over `[ua, ua + Δ]`, in the map of
    /// scale `m`.
    fn add_nodes(&self, mut sum: f64, t: f64, ua: f64, du: f64, m: f64, f: impl Fn(f64) -> f64) -> f64 {
        let lam = m / (1.0 + self.alpha * t * m);
        let sb = if du.is_finite() { du / (lam + du) } else { 1.0 };
        for (&x, &w) in self.x.iter().zip(&self.w) {
            // s = s_b x, v = 1/(1 − s) = 1 + r, r = s/(1 − s) (1 − s ≥ 1 − x: no cancellation).
            let v = 1.0 / (1.0 - sb * x);
            let r = sb * x * v;
            let u = ua + lam * r;
            sum += w * sb * lam * v * v * f(u) * (-t * lam * r).exp();
        }
        sum
    }
}

impl Family for LiteRule {
    const KIND: &'static str = "lite";
    const DIR: &'static str = "lite";
    const ROLE: Role = Role::Airlight;
    const ON_THE_MENU: bool = true;
    const TABLES: &'static [&'static str] = &["nodes", "split", "e2"];
    const TEMPLATES: Templates = airlight_shapes::core_templates!();
    const FIT_PARTS: &'static [&'static str] = &[fit::PART];
    /// The number of nodes and the fit's objective.
    type Recipe = fit::LiteTier;
    type Fit = Option<LogE2Fit>;

    fn fit(_parts: &[&str], _progress: &(dyn Fn(usize, usize) + Sync)) -> Option<LogE2Fit> {
        Some(LogE2::fit())
    }

    fn fit_summary(fit: &Option<LogE2Fit>) -> Vec<String> {
        fit.iter()
            .map(|f| {
                format!(
                    "lite e^x E2 (one log, no branch): {} iterations, {}: max rel {:.2e} at x = {:.4}",
                    f.outcome.iterations, f.outcome.termination, f.max_rel.0, f.max_rel.1
                )
            })
            .collect()
    }

    fn assemble(t: fit::LiteTier, g_range: (f64, f64), fit: &Option<LogE2Fit>) -> Result<Assembled<LiteRule>, String> {
        fit::assemble(t, g_range, fit.as_ref())
    }

    /// Isotropic (`1/(4π)` folded in), or HG exact at each node.
    fn phase_shape(&self) -> PhaseShape {
        if self.fade.is_some() {
            PhaseShape::Exact
        } else {
            PhaseShape::Isotropic
        }
    }

    fn kernel_context(&self, k: &KernelView) -> Context {
        let mut ctx = Context::quadrature(k);
        ctx.insert("nodes", &lits(&self.x));
        ctx.insert("weights", &lits(&self.w));
        ctx.insert("alpha", &lit(self.alpha));
        ctx.insert("short", &lit(self.short));
        ctx.insert("hg", &self.fade.is_some());
        ctx.insert("fade", &lit(self.fade.unwrap_or(0.0)));
        ctx.insert("e2_n1", &lits(&self.e2.n1));
        ctx.insert("e2_n2", &lits(&self.e2.n2));
        ctx.insert("e2_d", &lits(&self.e2.d));
        ctx
    }

    /// `A` at a valid point (isotropic members do not read `g`).
    fn eval(&self, p: Point) -> f64 {
        let g = if self.fade.is_some() { p.g.clamp(-0.999, 0.999) } else { 0.0 };
        let (h, ua, du, _) = u_geometry(p.gamma, p.rho);
        if h <= 0.0 {
            return on_axis(p, g, &|q| self.eval(q));
        }
        let t = p.tau * h;
        if self.fade.is_none() {
            return 2.0 * (-p.tau).exp() * self.integral(t, ua, du) / (4.0 * PI * h);
        }
        let c = (1.0 - g) / (4.0 * PI * (1.0 + g) * (1.0 + g));
        2.0 * (-p.tau).exp() * c * self.integral_hg(t, ua, du, (1.0 - g) / (1.0 + g)) / h
    }

    /// One path for every ray: the geometry (the canonical entry's `sin_cos`, the
    /// surface's `sqrt` and divisions), `λ`, `s_b`, two `eˣE₂` (a `log` and two
    /// divisions each) with `e^{−TΔ}` and the ends' divisions; per node `exp` and three
    /// divisions. HG adds `κ`, `C` and `β` (three divisions) and per node a `sqrt`; its
    /// `1/(κ² + u²)`, used twice, takes the place of the isotropic `1/(1 + u²)`.
    fn ops(&self, shape: Shape) -> Cost {
        let s = usize::from(shape.surfaces);
        let n = self.x.len();
        let hg = usize::from(self.fade.is_some());
        Cost { exp: 2 + n, log: 2, atan: 0, sqrt: s + hg * n, div: 3 + 2 * s + 2 + 6 + 3 * n + hg * 3, sincos: 1 }
    }

    fn render_toml(&self, _g_range: (f64, f64), o: &mut String, prov: &dyn Fn(&mut String, &str)) {
        o.push_str("\n[nodes]\nrule = \"fitted\"\n");
        let m = if self.fade.is_some() { "kappa + ua" } else { "1 + ua" };
        let _ = writeln!(
            o,
            "variable = \"s in [0, s_b]: u = ua + lambda s/(1 - s), lambda = m/(1 + alpha T m), m = {m}, s_b = du/(lambda + du) (1 open); s = s_b x\""
        );
        let _ = writeln!(o, "nodes = {}", self.x.len());
        airlight_truth::tomlfile::hex_list(o, "x", &self.x);
        airlight_truth::tomlfile::hex_list(o, "w", &self.w);
        prov(o, "nodes.fit");
        o.push_str("\n[split]\n");
        let _ = writeln!(o, "alpha = {:?}", self.alpha);
        let _ = writeln!(o, "short = {:?}", self.short);
        if let Some(b) = self.fade {
            let _ = writeln!(o, "fade = {b:?}");
        }
        self.e2.render_toml(o, prov);
    }

    /// Reads its tables: nodes inside (0, 1) and increasing, a finite positive split.
    fn parse_toml(r: &Reader, doc: &Table, g_range: &[f64]) -> Result<LiteRule, FieldError> {
        let t = r.table(doc, "nodes")?;
        r.deny(t, "nodes", &["rule", "variable", "nodes", "x", "w", "fit"])?;
        r.expect_str(t, "nodes", "rule", "fitted")?;
        let n = r.uint(t, "nodes", "nodes")?;
        if !(1..=16).contains(&n) {
            return Err(r.err("nodes", "nodes", "must be 1..=16"));
        }
        let x = r.hexes(t, "nodes", "x", Some(n))?;
        if x.iter().any(|&x| !(x > 0.0 && x < 1.0)) || x.windows(2).any(|p| p[0] >= p[1]) {
            return Err(r.err("nodes", "x", "must increase strictly inside (0, 1)"));
        }
        let w = r.hexes(t, "nodes", "w", Some(n))?;
        if w.iter().any(|w| !w.is_finite()) {
            return Err(r.err("nodes", "w", "must be finite"));
        }
        let s = r.table(doc, "split")?;
        r.deny(s, "split", &["alpha", "short", "fade", "fit"])?;
        let pos = |key: &str| -> Result<f64, FieldError> {
            let v = r.float(s, "split", key)?;
            if !(v.is_finite() && v > 0.0) {
                return Err(r.err("split", key, "must be finite and positive"));
            }
            Ok(v)
        };
        let (alpha, short) = (pos("alpha")?, pos("short")?);
        // HG members (a g range beyond 0) carry the fade; isotropic ones must not.
        let fade = if fit::is_hg(g_range) {
            Some(pos("fade")?)
        } else {
            if s.contains_key("fade") {
                return Err(r.err("split", "fade", "only Henyey-Greenstein members (a g range beyond 0) have a fade"));
            }
            None
        };
        Ok(LiteRule { x, w, alpha, short, fade, e2: LogE2::parse_toml(r, doc)? })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use airlight_truth::reference;

    #[test]
    fn the_split_weight_is_the_isotropic_weight() {
        for u in [0.0, 1e-3, 0.5, 1.0, 7.0, 1e4] {
            let direct = 1.0 / (1.0 + u * u) - 1.0 / ((1.0 + u) * (1.0 + u));
            assert!((k_of_u(u) - direct).abs() <= 1e-15 * (1.0 / (1.0 + u * u)), "u {u}");
        }
    }

    #[test]
    fn many_nodes_converge_to_the_reference() {
        // The map is exact in the limit: 24 Gauss–Legendre nodes, the start's split;
        // what is left is eˣE₂'s fitted form (a few 1e-5).
        let r = LiteRule::start(24, None, LogE2::fit().e2);
        for &(tau, gamma, rho) in
            &[(0.5, 1.0, 3.0), (3.0, 2.0, f64::INFINITY), (1e-3, 0.3, f64::INFINITY), (15.0, 3.1, 0.02), (8.0, 0.2, 40.0)]
        {
            let p = Point { tau, gamma, rho, g: 0.0 };
            let exact = reference::airlight(p).unwrap();
            let e = r.eval(p);
            assert!((e / exact - 1.0).abs() < 1e-4, "{p:?}: {e} vs {exact}");
        }
    }

    #[test]
    fn the_hg_rule_converges_for_any_fade() {
        // Any β constant along the ray leaves the split exact: with 32 Gauss–Legendre
        // nodes both a weak and a strong fade reach the reference, for g near both
        // ends of the range, where the forward peak and the backward lobe are.
        let e2 = LogE2::fit().e2;
        for fade in [0.01, 3.0] {
            let r = LiteRule::start(32, Some(fade), e2.clone());
            for &(tau, gamma, rho, g) in &[
                (0.5, 1.0, 3.0, 0.9),
                (3.0, 2.0, f64::INFINITY, -0.9),
                (1e-3, 0.3, f64::INFINITY, 0.95),
                (15.0, 3.1, 0.02, -0.5),
                (8.0, 0.2, 40.0, -0.95),
                (0.05, 0.05, f64::INFINITY, 0.0),
            ] {
                let p = Point { tau, gamma, rho, g };
                let exact = reference::airlight(p).unwrap();
                let e = r.eval(p);
                assert!((e / exact - 1.0).abs() < 1e-4, "fade {fade}, {p:?}: {e} vs {exact}");
            }
        }
    }
}

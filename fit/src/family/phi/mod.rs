//! The φ family: the whole of `A` for isotropic and Henyey–Greenstein media,
//! `g` a run-time argument, with an error that does not grow with optical depth.
//!
//! In the u form (docs/MATH.md §3), `A = (2 e^{−τ}/h) I`, `I = ∫_{ua}^{ub} w(u) e^{−T(u−ua)} du`,
//! `w = (1 − g²) √(1 + u²) / (4π (a² + b² u²)^{3/2})`, `a = 1 − g`, `b = 1 + g`, `κ = a/b`.
//! Each of the integral's scales (docs/MATH.md §6.6) goes to the piece that takes it
//! exactly:
//!
//! * **head** `[ua, ua + ℓ]`: Gauss–Legendre in the HG variable `φ`
//!   (`η = (1 + g cos φ)/(1 − g²)`, docs/MATH.md §6.6), where `w du` is a smooth bounded
//!   weight times `dφ` for every `g`; `ℓ` ends where the transmittance has fallen by
//!   `e^{−L}` (`L = cut`), at the far region, or at the surface. Past every HG
//!   feature (`ua ≥ X`) or on a short interval the nodes are taken in `u` itself, so
//!   that exponent offsets `T(u − ua)` stay exact in f32.
//! * **tail** `[ua + L/T, ub]`: Gauss–Laguerre in `T(u − ua − L/T)`, minus the same
//!   from `ub` weighted by `e^{−T(ub − ua − L/T)}`.
//! * **far** `[X, ub]`, `X = far_from · max(1, κ)`, when `T X` is small (the `T ln T`
//!   non-analyticity): `w = C/u² + Δ`, `C = (1 − g)/(4π b²)`; `C/u²` is integrated
//!   exactly through `eˣE₂(x)` (a fitted rational beyond `x = 1`, `Ein`'s series
//!   below), `Δ = C r(v)`, `v = 1/u`, `r = O(v²)` in closed, cancellation-free form,
//!   by Gauss–Legendre in `v` up to where the transmittance has fallen by `e^{−far_cut}`.
//!
//! The f32 kernels (`codegen/templates/kernels/phi.*.tera`) are this function line
//! for line.

pub mod fit;
mod report;

use airlight_shapes::cost::{Cost, PhaseShape, Shape};
use crate::family::{Assembled, Family, Member, ReportFloor, Role};
use crate::lsq;
use airlight_shapes::template::{lit, lits, Context, KernelView, Templates};
use serde::Serialize;
use airlight_truth::reference::Point;
use airlight_truth::tomlfile::{FieldError, Reader};
use std::f64::consts::PI;
use crate::family::uform::{exp_e2_exact, horner1, on_axis, u_geometry};
use std::fmt::Write as _;
use toml::Table;

/// Euler's constant.
pub const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;
/// Terms of `Ein(x) = Σ_{k≥1} (−1)^{k+1} x^k/(k·k!)` kept below `x = 1`.
pub const EIN_TERMS: usize = 10;
/// Degree of numerator and denominator of the fitted `eˣE₂(x)` beyond `x = 1`.
pub const E2_DEGREE: usize = 4;

/// `eˣE₂(x)` for `x ≥ 0`: `1 + x eˣ(ln x + γ − Ein(x))` below 1, `t P(t)/Q(t)`
/// in `t = 1/x` beyond (`P, Q` of degree [`E2_DEGREE`] with unit constant terms).
#[derive(Debug, Clone, PartialEq)]
pub struct ExpE2 {
    /// `Ein`'s coefficients `c_k` of `x^k`, `k = 1 ..= EIN_TERMS` (the series).
    pub ein: Vec<f64>,
    /// `p_1 … p_d` of `P(t) = 1 + Σ p_k t^k`.
    pub p: Vec<f64>,
    /// `q_1 … q_d` of `Q(t) = 1 + Σ q_k t^k`.
    pub q: Vec<f64>,
}

/// How the rational part of [`ExpE2`] was fitted.
#[derive(Debug, Clone, PartialEq)]
pub struct E2Fit {
    /// The approximation.
    pub e2: ExpE2,
    /// Sanathanan–Koerner iterations run.
    pub iterations: usize,
    /// Points fitted.
    pub points: usize,
    /// Largest relative error over `x ≥ 1` (dense check grid) and where.
    pub max_rel: (f64, f64),
    /// Largest relative error of the series branch on `[0, 1]` and where.
    pub series_max_rel: (f64, f64),
}

impl ExpE2 {
    /// Writes the `[e2]` table of a coefficient file (its provenance `e2.fit` by `prov`).
    pub fn render_toml(&self, o: &mut String, prov: &dyn Fn(&mut String, &str)) {
        o.push_str("\n[e2]\nform = \"e^x E2(x): 1 + x e^x (ln x + Euler gamma - Ein(x)) for x < 1, Ein(x) = sum ein_k x^k; t P(t)/Q(t), t = 1/x, P = 1 + sum p_k t^k, Q = 1 + sum q_k t^k beyond\"\n");
        airlight_truth::tomlfile::hex_list(o, "ein", &self.ein);
        airlight_truth::tomlfile::hex_list(o, "p", &self.p);
        airlight_truth::tomlfile::hex_list(o, "q", &self.q);
        prov(o, "e2.fit");
    }

    /// Reads the `[e2]` table of a coefficient file.
    pub fn parse_toml(r: &Reader, doc: &Table) -> Result<ExpE2, FieldError> {
        let e = r.table(doc, "e2")?;
        r.deny(e, "e2", &["form", "ein", "p", "q", "fit"])?;
        let ein = r.hexes(e, "e2", "ein", Some(EIN_TERMS))?;
        let p = r.hexes(e, "e2", "p", Some(E2_DEGREE))?;
        let q = r.hexes(e, "e2", "q", Some(E2_DEGREE))?;
        Ok(ExpE2 { ein, p, q })
    }

    /// What the shared template `e2.*.tera` needs: `euler`, `ein`, `e2p`, `e2q`, `e2_rev`.
    pub fn insert_context(&self, ctx: &mut Context) {
        ctx.insert("euler", &lit(EULER_GAMMA));
        ctx.insert("ein", &lits(&self.ein));
        ctx.insert("e2p", &lits(&self.p));
        ctx.insert("e2q", &lits(&self.q));
        let rev: Vec<E2Term> = self.p.iter().zip(&self.q).rev().map(|(&p, &q)| E2Term { p: lit(p), q: lit(q) }).collect();
        ctx.insert("e2_rev", &rev);
    }

    /// Evaluates it.
    pub fn eval(&self, x: f64) -> f64 {
        if x < 1.0 {
            let mut ein = 0.0;
            for c in self.ein.iter().rev() {
                ein = (ein + c) * x;
            }
            // x ln x → 0 at x = 0.
            let lx = if x > 0.0 { x.ln() } else { 0.0 };
            1.0 + x * x.exp() * (lx + EULER_GAMMA - ein)
        } else {
            let t = 1.0 / x;
            t * horner1(&self.p, t) / horner1(&self.q, t)
        }
    }

    /// Fits the rational branch by linearised least squares (Sanathanan–Koerner:
    /// each step an SVD solve weighted by the previous denominator), relative
    /// error on Chebyshev points of `t = 1/x ∈ (0, 1]`.
    pub fn fit() -> E2Fit {
        let ein: Vec<f64> = (1..=EIN_TERMS)
            .map(|k| {
                let fact: f64 = (1..=k).map(|j| j as f64).product();
                let s = if k % 2 == 1 { 1.0 } else { -1.0 };
                s / (k as f64 * fact)
            })
            .collect();
        const N: usize = 400;
        let ts: Vec<f64> = (0..N).map(|j| 0.5 * (1.0 + (PI * (j as f64 + 0.5) / N as f64).cos())).collect();
        let fs: Vec<f64> = ts.iter().map(|&t| exp_e2_exact(1.0 / t) / t).collect();
        let d = E2_DEGREE;
        // One linearised step: unknowns p_1..p_d, q_1..q_d in
        // (P(t) − f Q(t)) / (f Q_prev(t)) = 0.
        let step = |q: &[f64]| -> Vec<f64> {
            let a = nalgebra::DMatrix::from_fn(N, 2 * d, |j, k| {
                let (t, f) = (ts[j], fs[j]);
                let wgt = 1.0 / (f * horner1(q, t));
                if k < d {
                    wgt * t.powi(k as i32 + 1)
                } else {
                    -wgt * f * t.powi((k - d) as i32 + 1)
                }
            });
            let b = nalgebra::DVector::from_fn(N, |j, _| (fs[j] - 1.0) / (fs[j] * horner1(q, ts[j])));
            lsq::solve(a, &b).expect("the e^x E2 fit is well posed").as_slice().to_vec()
        };
        let mut sol = step(&vec![0.0; d]);
        let mut iterations = 1;
        while iterations < 12 {
            sol = step(&sol[d..]);
            iterations += 1;
        }
        let e2 = ExpE2 { ein, p: sol[..d].to_vec(), q: sol[d..].to_vec() };
        let check = |lo: f64, hi: f64, n: usize, inv: bool| {
            let mut worst = (0.0f64, lo);
            for j in 0..=n {
                let s = lo + (hi - lo) * j as f64 / n as f64;
                let x = if inv { 1.0 / s } else { s };
                let e = (e2.eval(x) / exp_e2_exact(x) - 1.0).abs();
                if e > worst.0 {
                    worst = (e, x);
                }
            }
            worst
        };
        let max_rel = check(1e-6, 1.0, 4000, true);
        let series_max_rel = check(0.0, 0.999_999, 4000, false);
        E2Fit { e2, iterations, points: N, max_rel, series_max_rel }
    }
}

/// A quadrature rule on a reference interval.
#[derive(Debug, Clone, PartialEq)]
pub struct Rule {
    /// Nodes.
    pub x: Vec<f64>,
    /// Weights.
    pub w: Vec<f64>,
}

/// Nodes and weights of the `n`-point Gauss–Laguerre rule (weight `e^{−y}` on
/// `[0, ∞)`), by Newton on the Laguerre recurrence.
pub fn gauss_laguerre(n: usize) -> Rule {
    let mut x = Vec::with_capacity(n);
    let mut w = Vec::with_capacity(n);
    let nf = n as f64;
    let mut z = 0.0f64;
    for i in 0..n {
        z = if i == 0 {
            3.0 / (1.0 + 2.4 * nf)
        } else if i == 1 {
            z + 15.0 / (1.0 + 2.5 * nf)
        } else {
            let ai = (i - 1) as f64;
            z + (1.0 + 2.55 * ai) / (1.9 * ai) * (z - x[i - 2])
        };
        let mut pp = 0.0;
        for _ in 0..100 {
            let (mut p1, mut p2) = (1.0, 0.0);
            for j in 0..n {
                let p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j as f64 + 1.0 - z) * p2 - j as f64 * p3) / (j as f64 + 1.0);
            }
            pp = nf * (p1 - p2) / z;
            let dz = p1 / pp;
            z -= dz;
            if dz.abs() <= 1e-15 * z.abs() {
                break;
            }
        }
        // w = x / ((n+1)² L_{n+1}(x)²) = 1 / (x L_n'(x)²).
        x.push(z);
        w.push(1.0 / (z * pp * pp));
    }
    Rule { x, w }
}

/// One member of the family.
#[derive(Debug, Clone, PartialEq)]
pub struct PhiRule {
    /// Head rule (Gauss–Legendre on `[−1, 1]`).
    pub head: Rule,
    /// `L`: the head ends where the transmittance has fallen by `e^{−L}`.
    pub cut: f64,
    /// `X = far_from · max(1, κ)`: where the far region starts.
    pub far_from: f64,
    /// The far region is used while `T X < far_tmax`.
    pub far_tmax: f64,
    /// Far correction rule (Gauss–Legendre in `v = 1/u` on `[−1, 1]`).
    pub far: Rule,
    /// The far correction ends where the transmittance has fallen by `e^{−far_cut}`.
    pub far_cut: f64,
    /// An interval is short when `ub − ua < short · (ua + min(1, κ))`.
    pub short: f64,
    /// Tail rule (Gauss–Laguerre).
    pub tail: Rule,
    /// `eˣE₂(x)`.
    pub e2: ExpE2,
}

impl PhiRule {
    /// The member with `n` head nodes, `nf` far nodes, `nt` tail nodes and these splits.
    pub fn new(n: usize, nf: usize, nt: usize, cut: f64, far_cut: f64, e2: ExpE2) -> PhiRule {
        let (x, w) = airlight_truth::quad::gauss_legendre(n);
        let (fx, fw) = airlight_truth::quad::gauss_legendre(nf);
        PhiRule {
            head: Rule { x, w },
            cut,
            far_from: 3.0,
            far_tmax: 4.0,
            far: Rule { x: fx, w: fw },
            far_cut,
            short: 0.25,
            tail: gauss_laguerre(nt),
            e2,
        }
    }

}

impl Family for PhiRule {
    const KIND: &'static str = "phi";
    const DIR: &'static str = "phi";
    const ROLE: Role = Role::Airlight;
    const ON_THE_MENU: bool = true;
    const TABLES: &'static [&'static str] = &["head", "split", "far", "tail", "e2"];
    const TEMPLATES: Templates = airlight_shapes::core_templates!();
    const REPORT: Option<&'static str> = Some(include_str!("report.md.tera"));
    const FIT_PARTS: &'static [&'static str] = &[fit::PART];
    type Recipe = fit::PhiTier;
    type Fit = Option<E2Fit>;

    fn fit(_parts: &[&str], _progress: &(dyn Fn(usize, usize) + Sync)) -> Option<E2Fit> {
        Some(ExpE2::fit())
    }

    fn fit_summary(fit: &Option<E2Fit>) -> Vec<String> {
        fit.iter().map(fit::summary).collect()
    }

    fn assemble(t: fit::PhiTier, g_range: (f64, f64), fit: &Option<E2Fit>) -> Result<Assembled<PhiRule>, String> {
        fit::assemble(t, g_range, fit.as_ref())
    }

    /// `g` at run time, exact at each node.
    fn phase_shape(&self) -> PhaseShape {
        PhaseShape::Exact
    }

    fn kernel_context(&self, k: &KernelView) -> Context {
        kernel_context(self, k)
    }

    fn report(members: &[Member<'_, PhiRule>], floor: ReportFloor) -> Option<Context> {
        report::context(members, floor)
    }

    /// `A` at a valid point.
    fn eval(&self, p: Point) -> f64 {
        let g = p.g.clamp(-0.999, 0.999);
        let (h, ua, du, ub) = u_geometry(p.gamma, p.rho);
        if h <= 0.0 {
            return on_axis(p, g, &|q| self.eval(q));
        }
        let t = p.tau * h;
        let (a, b) = (1.0 - g, 1.0 + g);
        let kappa = a / b;
        let xf = self.far_from * kappa.max(1.0);
        let lcut = if t > 0.0 { self.cut / t } else { f64::INFINITY };
        let m = ua.max(xf);
        let short = du < self.short * (ua + kappa.min(1.0));
        let far = !short && ub > m && t * (m - ua) < self.cut && t * m < self.far_tmax;
        let len = if far { m - ua } else { du.min(lcut) };
        let mut sum = 0.0;
        if len > 0.0 {
            // Nodes in u where the piece is short against the scale of w or past
            // every HG feature: the exponent offsets are then exact.
            if len < self.short * (ua + kappa.min(1.0)) || ua >= xf {
                // Nodes in u: exact offsets.
                let half = 0.5 * len;
                for (x, wt) in self.head.x.iter().zip(&self.head.w) {
                    let d = half * (1.0 + x);
                    sum += wt * half * w_u(ua + d, g) * (-t * d).exp();
                }
            } else {
                // φ/2 and its complement (π − φ)/2 at both ends, each where it is
                // the smaller, so that nodes near φ = π keep their digits.
                let ((pa, ca), (pb, cb)) = (phi_and_complement(ua, g), phi_and_complement(ua + len, g));
                let hl = 0.5 * if ca < 0.5 * PI { ca - cb } else { pb - pa };
                let mut s = 0.0;
                for (x, wt) in self.head.x.iter().zip(&self.head.w) {
                    let beta = 0.5 * pa + 0.5 * hl * (1.0 + x);
                    let co = 0.5 * ca - 0.5 * hl * (1.0 + x);
                    let (sn, cs) = beta.min(co).max(0.0).sin_cos();
                    let (s2, c2) = if beta <= co { (sn, cs) } else { (cs, sn) };
                    let (u, wp) = u_and_weight(s2, c2, g);
                    s += wt * wp * (-t * (u - ua)).exp();
                }
                sum += s * hl / (4.0 * PI * a * b);
            }
        }
        if far {
            let c = (1.0 - g) / (4.0 * PI * b * b);
            let em = (-t * (m - ua)).exp();
            let mut f = self.e2.eval(t * m) / m;
            if ub.is_finite() {
                f -= (-t * (ub - m)).exp() * self.e2.eval(t * ub) / ub;
            }
            let ue = if t > 0.0 { m + self.far_cut / t } else { f64::INFINITY };
            let (va, vb) = (1.0 / ub.min(ue), 1.0 / m);
            let half = 0.5 * (vb - va);
            let mut s = 0.0;
            for (x, wt) in self.far.x.iter().zip(&self.far.w) {
                let v = va + half * (1.0 + x);
                s += wt * r_of_v(v, kappa) * (-t * (1.0 / v - m)).exp();
            }
            sum += c * em * (f + s * half);
        } else if du > lcut {
            // The tail beyond the cut, Gauss–Laguerre from both ends.
            let ue = ua + lcut;
            let lag =
                |u0: f64| -> f64 { self.tail.x.iter().zip(&self.tail.w).map(|(y, wt)| wt * w_u(u0 + y / t, g)).sum() };
            let mut s = lag(ue);
            if ub.is_finite() {
                s -= (-t * (du - lcut)).exp() * lag(ub);
            }
            sum += (-self.cut).exp() / t * s;
        }
        2.0 * (-p.tau).exp() * sum / h
    }

    /// Operations on the worst path, counted from the f32 kernel: the geometry,
    /// then the worse head (in φ or in u) and the worse of the far part and the
    /// tail. `sin_cos` counts the canonical entry's and the head's octant ones.
    fn ops(&self, shape: Shape) -> Cost {
        let (n, nf, nt) = (self.head.x.len(), self.far.x.len(), self.tail.x.len());
        let hg = usize::from(shape.phase != PhaseShape::Isotropic);
        let c = |exp: usize, log: usize, atan: usize, sqrt: usize, div: usize, sincos: usize| Cost {
            exp,
            log,
            atan,
            sqrt,
            div,
            sincos,
        };
        // sin_cos(γ); ua, κ, L/T; the surface: one sqrt, two divisions; e^{−τ}, /h.
        let s = usize::from(shape.surfaces);
        let geo = c(1, 0, 0, s, 3 + 2 * s + 1 + hg, 1);
        // w(u): a division for the isotropic weight, two sqrt and two for HG.
        let w = c(0, 0, 0, 2 * hg, 1 + hg, 0);
        // Head in φ: per end (ψ: two sqrt and two divisions for HG) an atan of ψ
        // or 1/ψ; per node sin_cos, exp, s2/c2 (HG: one sqrt, two more divisions).
        let end = c(0, 0, 1, 2 * hg, 1 + 2 * hg, 0);
        let node = c(1, 0, 0, hg, 1 + 2 * hg, 1);
        let mut head_phi = end.add(&end);
        for _ in 0..n {
            head_phi = head_phi.add(&node);
        }
        let mut head_u = Cost::default();
        for _ in 0..n {
            head_u = head_u.add(&w).add(&c(1, 0, 0, 0, 0, 0));
        }
        // Far: two e^x E2 (exp and log below 1), their exp and divisions, the cut;
        // per node r(v) (HG: two sqrt), 1/v and an exp.
        let mut far = c(2 + 2, 2, 0, 0, 6, 0);
        for _ in 0..nf {
            far = far.add(&c(1, 0, 0, 2 * hg, 2, 0));
        }
        // Tail: w at both ends per node, one exp, L/T.
        let mut tail = c(1, 0, 0, 0, 1, 0);
        for _ in 0..2 * nt {
            tail = tail.add(&w);
        }
        geo.add(&head_phi.max(&head_u)).add(&far.max(&tail))
    }

    /// Writes its tables.
    fn render_toml(&self, _g_range: (f64, f64), o: &mut String, prov: &dyn Fn(&mut String, &str)) {
        o.push_str("\n[head]\nrule = \"gauss-legendre\"\n");
        o.push_str("variable = \"φ: η = (1 + g cos φ)/(1 − g²), η the HG variable (1 + g² − 2g cos α)^(-1/2); u itself past X or on short intervals\"\n");
        let _ = writeln!(o, "nodes = {}", self.head.x.len());
        airlight_truth::tomlfile::hex_list(o, "x", &self.head.x);
        airlight_truth::tomlfile::hex_list(o, "w", &self.head.w);
        prov(o, "head.fit");
        o.push_str("\n[split]\n");
        let _ = writeln!(o, "cut = {:?}", self.cut);
        let _ = writeln!(o, "far_from = {:?}", self.far_from);
        let _ = writeln!(o, "far_tmax = {:?}", self.far_tmax);
        let _ = writeln!(o, "far_cut = {:?}", self.far_cut);
        let _ = writeln!(o, "short = {:?}", self.short);
        prov(o, "split.fit");
        o.push_str("\n[far]\nrule = \"gauss-legendre\"\nvariable = \"v = 1/u\"\n");
        let _ = writeln!(o, "nodes = {}", self.far.x.len());
        airlight_truth::tomlfile::hex_list(o, "x", &self.far.x);
        airlight_truth::tomlfile::hex_list(o, "w", &self.far.w);
        o.push_str("\n[tail]\nrule = \"gauss-laguerre\"\n");
        let _ = writeln!(o, "nodes = {}", self.tail.x.len());
        airlight_truth::tomlfile::hex_list(o, "x", &self.tail.x);
        airlight_truth::tomlfile::hex_list(o, "w", &self.tail.w);
        self.e2.render_toml(o, prov);
    }

    /// Reads its tables; the rules must be the Gauss rules they name.
    fn parse_toml(r: &Reader, doc: &Table, _g_range: &[f64]) -> Result<PhiRule, FieldError> {
        let rule = |sec: &str, kind: &str, laguerre: bool| -> Result<Rule, FieldError> {
            let t = r.table(doc, sec)?;
            r.deny(t, sec, &["rule", "variable", "nodes", "x", "w", "fit"])?;
            r.expect_str(t, sec, "rule", kind)?;
            let n = r.uint(t, sec, "nodes")?;
            if !(1..=64).contains(&n) {
                return Err(r.err(sec, "nodes", "must be 1..=64"));
            }
            let x = r.hexes(t, sec, "x", Some(n))?;
            let w = r.hexes(t, sec, "w", Some(n))?;
            let want = if laguerre {
                gauss_laguerre(n)
            } else {
                let (x, w) = airlight_truth::quad::gauss_legendre(n);
                Rule { x, w }
            };
            for (key, got, want) in [("x", &x, &want.x), ("w", &w, &want.w)] {
                if got.iter().zip(want).any(|(a, b)| (a - b).abs() > 1e-12 * b.abs().max(1.0)) {
                    return Err(r.err(sec, key, &format!("is not the {n}-point {kind} rule")));
                }
            }
            Ok(Rule { x, w })
        };
        let head = rule("head", "gauss-legendre", false)?;
        let far = rule("far", "gauss-legendre", false)?;
        let tail = rule("tail", "gauss-laguerre", true)?;
        let s = r.table(doc, "split")?;
        r.deny(s, "split", &["cut", "far_from", "far_tmax", "far_cut", "short", "fit"])?;
        let pos = |key: &str| -> Result<f64, FieldError> {
            let v = r.float(s, "split", key)?;
            if !(v.is_finite() && v > 0.0) {
                return Err(r.err("split", key, "must be finite and positive"));
            }
            Ok(v)
        };
        let (cut, far_from, far_tmax, far_cut, short) =
            (pos("cut")?, pos("far_from")?, pos("far_tmax")?, pos("far_cut")?, pos("short")?);
        let e2 = ExpE2::parse_toml(r, doc)?;
        Ok(PhiRule { head, cut, far_from, far_tmax, far, far_cut, short, tail, e2 })
    }
}

/// `w(u) = (1 − g²) √(1 + u²) / (4π (a² + b² u²)^{3/2})`.
pub fn w_u(u: f64, g: f64) -> f64 {
    let (a, b) = (1.0 - g, 1.0 + g);
    let d = a * a + b * b * u * u;
    (1.0 - g * g) * (1.0 + u * u).sqrt() / (4.0 * PI * d * d.sqrt())
}

/// `ψ² = tan²(φ/2)` at `u`: `d = b u² − a`, `ψ² = (b/(2a))(d + √(d² + 4u²))`
/// (`= 2 b u² / (a (√(d² + 4u²) − d))` when `d < 0`).
pub fn psi2_of_u(u: f64, g: f64) -> f64 {
    let (a, b) = (1.0 - g, 1.0 + g);
    let d = b * u * u - a;
    let r = (d * d + 4.0 * u * u).sqrt();
    if d >= 0.0 {
        b / (2.0 * a) * (d + r)
    } else {
        2.0 * b * u * u / (a * (r - d))
    }
}

/// `(φ, π − φ)` at `u`, the smaller of the two from its own `atan` (`2 atan ψ` or
/// `2 atan(1/ψ)`).
pub fn phi_and_complement(u: f64, g: f64) -> (f64, f64) {
    let psi = psi2_of_u(u, g).sqrt();
    if psi <= 1.0 {
        let p = 2.0 * psi.atan();
        (p, PI - p)
    } else {
        let c = 2.0 * (1.0 / psi).atan();
        (PI - c, c)
    }
}

/// `u(φ)` and the head's weight `(1 + g c)² / √((2 + g c)² − g²)` (`c = cos φ`)
/// from `s2 = sin(φ/2)`, `c2 = cos(φ/2)`, every factor in a form that does not
/// cancel: `2 ± g + g c = 2(1 + g c2²), 2(a + g c2²)` for `g ≥ 0`, `2(b − g s2²),
/// 2(1 − g s2²)` below; `u = (a/b) (s2/c2) √(num/den)`, weight `q²/(2√(num·den))`.
pub fn u_and_weight(s2: f64, c2: f64, g: f64) -> (f64, f64) {
    let (a, b) = (1.0 - g, 1.0 + g);
    let (num, den, q) = if g >= 0.0 {
        (1.0 + g * c2 * c2, a + g * c2 * c2, a + 2.0 * g * c2 * c2)
    } else {
        (b - g * s2 * s2, 1.0 - g * s2 * s2, b - 2.0 * g * s2 * s2)
    };
    let r = (num * den).sqrt();
    (a / b * (s2 / c2) * (r / den), q * q / (2.0 * r))
}

/// `r(v) = u² w / C − 1 = √(1 + v²)(1 + κ² v²)^{−3/2} − 1`, without cancellation:
/// `v² (1 − 3κ² − 3κ⁴ v² − κ⁶ v⁴) / ((q + p√p) p√p)`, `p = 1 + κ² v²`, `q = √(1 + v²)`.
pub fn r_of_v(v: f64, kappa: f64) -> f64 {
    let (k2, v2) = (kappa * kappa, v * v);
    let p = 1.0 + k2 * v2;
    let pp = p * p.sqrt();
    let q = (1.0 + v2).sqrt();
    v2 * (1.0 - 3.0 * k2 - k2 * k2 * v2 * (3.0 + k2 * v2)) / ((q + pp) * pp)
}

#[derive(Serialize)]
struct E2Term {
    p: String,
    q: String,
}

/// What the φ family's core templates need: its rules, splits and `eˣE₂`.
fn kernel_context(r: &PhiRule, k: &KernelView) -> Context {
    let mut ctx = Context::quadrature(k);
    ctx.insert("head_x", &lits(&r.head.x));
    ctx.insert("head_w", &lits(&r.head.w));
    ctx.insert("far_x", &lits(&r.far.x));
    ctx.insert("far_w", &lits(&r.far.w));
    ctx.insert("tail_x", &lits(&r.tail.x));
    ctx.insert("tail_w", &lits(&r.tail.w));
    ctx.insert("cut", &lit(r.cut));
    ctx.insert("cut_doc", &r.cut);
    ctx.insert("exp_neg_cut", &lit((-r.cut).exp()));
    ctx.insert("far_cut", &lit(r.far_cut));
    ctx.insert("far_tmax", &lit(r.far_tmax));
    ctx.insert("short", &lit(r.short));
    ctx.insert("far_from", &lit(r.far_from));
    r.e2.insert_context(&mut ctx);
    ctx
}


#[cfg(test)]
mod tests {
    use super::*;
    use airlight_truth::reference;

    #[test]
    fn the_variable_and_its_inverse_agree() {
        for g in [-0.95, -0.3, 0.0, 0.5, 0.95] {
            for u in [0.001, 0.03, 0.5, 1.0, 4.0, 100.0] {
                let (s2, c2) = (0.5 * phi_and_complement(u, g).0).sin_cos();
                let (back, _) = u_and_weight(s2, c2, g);
                assert!((back / u - 1.0).abs() < 1e-12, "g {g} u {u}: {back}");
            }
        }
    }

    #[test]
    fn the_far_correction_is_the_weight_minus_its_tail() {
        for g in [-0.9, 0.0, 0.7] {
            let (a, b) = (1.0 - g, 1.0 + g);
            let c = (1.0 - g) / (4.0 * PI * b * b);
            for u in [3.0, 40.0, 1e3] {
                let direct = u * u * w_u(u, g) / c - 1.0;
                let r = r_of_v(1.0 / u, a / b);
                assert!((r - direct).abs() < 1e-12 * direct.abs().max(1e-3), "g {g} u {u}: {r} vs {direct}");
            }
        }
    }

    #[test]
    fn laguerre_integrates_polynomials() {
        let r = gauss_laguerre(3);
        for k in 0..6 {
            let got: f64 = r.x.iter().zip(&r.w).map(|(x, w)| w * x.powi(k)).sum();
            let fact: f64 = (1..=k).map(f64::from).product();
            assert!((got / fact - 1.0).abs() < 1e-13, "k {k}: {got}");
        }
    }

    #[test]
    fn the_exp_e2_fit_reaches_single_precision() {
        let f = ExpE2::fit();
        assert!(f.max_rel.0 < 2e-7, "{:?}", f.max_rel);
        assert!(f.series_max_rel.0 < 3e-7, "{:?}", f.series_max_rel);
    }

    #[test]
    fn the_members_converge_to_the_reference() {
        let e2 = ExpE2::fit().e2;
        let r = PhiRule::new(8, 4, 3, 5.0, 8.0, e2);
        for &(tau, gamma, rho, g) in &[
            (0.5, 1.0, 3.0, 0.0),
            (3.0, 2.0, f64::INFINITY, 0.0),
            (1.0, 0.7, 10.0, 0.9),
            (2.0, 2.5, 5.0, -0.5),
            (1e-3, 0.3, f64::INFINITY, -0.95),
            (15.0, 3.1, 0.02, 0.95),
        ] {
            let p = Point { tau, gamma, rho, g };
            let exact = reference::airlight(p).unwrap();
            let e = r.eval(p);
            assert!((e / exact - 1.0).abs() < 2e-5, "{p:?}: {e} vs {exact}");
        }
    }
}

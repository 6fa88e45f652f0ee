//! The split family: `A` as a forward part plus a backward part, assembled from
//! the three families of the paper (forward kernel, phase, backscatter),
//! generalised to every geometry of the domains.
//!
//! With `θa = γ − π/2`, `θb = atan((ρ − cos γ)/sin γ)` and `T = τ sin γ`
//! (docs/MATH.md §3, angle form):
//!
//! * **forward part** (`θ < 0`, written `θ' = −θ ∈ [max(0, −θb), −θa]`): the
//!   piecewise-linear kernel makes `P(π/2 − θ') e^{−τ cos γ − T k̂(θ')}` a sum of
//!   exponentials of linear functions, integrated exactly per segment. A surface
//!   before the foot point simply raises the lower end.
//! * **backward part** (`θ ∈ [max(0, θa), θb]`), one of two families:
//!   - the paper's ratio, `R(θb, T) · F̂(T)` with the model's own whole forward
//!     integral `F̂`. It is defined only from the foot point (`γ ≤ π/2`); beyond it
//!     (`γ > π/2`) it could only be used as a difference `R(θb) − R(θa)`, which
//!     cancels catastrophically (measured: relative errors up to 1e17 in `dense`),
//!     so models that use it switch to the exponential sum there;
//!   - the exponential sum of the backward weight in the u form
//!     ([`expsum`]): positive terms, no differences, any geometry.
//!
//!   The phase enters the backward part at a mean angle: of the whole part for the
//!   ratio (mean offset `L/(2 + κ L)` from its start, `κ` the decay rate there), of
//!   each term for the exponential sum; exact for a uniform weight and for a fast
//!   exponential one.
//!
//! `γ = 0` uses the exact on-axis value; `γ` within 1e-7 of π is evaluated at
//! `π − 1e-7` (A is flat in γ there).

use airlight_truth::tomlfile::{dec, hex_list, quad_rows};
use airlight_shapes::cost::{Cost, PhaseShape, Shape};
pub mod dominant;
pub mod expsum;
pub mod fit;
mod kernel;
pub mod phase_exp;
pub mod ratio;
mod report;
pub mod segments;

use crate::family::{Assembled, Family, Member, ReportFloor, Role};
use airlight_shapes::figure::Figure;
use airlight_shapes::template::{Context, KernelPhase, KernelView, Templates, WantPhase};
use expsum::{Backward, ExpSum};
use phase_exp::{sec_plus_tan, Band, ExpPhase, Terms};
use ratio::Ratio;
use segments::Segments;
use airlight_truth::hexf;
use airlight_truth::reference::Point;
use airlight_truth::tomlfile::{FieldError, Reader};
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt::Write;
use toml::Table;

/// How a model represents the phase function.
#[derive(Debug, Clone, PartialEq)]
pub enum PhaseModel {
    /// `1/(4π)`; the model takes only `g = 0`.
    Isotropic,
    /// Banded exponential sums.
    Exp(ExpPhase),
}

impl PhaseModel {
    /// The terms at `g`.
    pub fn terms(&self, g: f64) -> Terms {
        match self {
            PhaseModel::Isotropic => Terms::isotropic(),
            PhaseModel::Exp(e) => e.terms(g),
        }
    }
}

/// A forward part plus a backward part, assembled from families.
#[derive(Debug, Clone, PartialEq)]
pub struct Split {
    /// Forward kernel.
    pub forward: Segments,
    /// Phase function.
    pub phase: PhaseModel,
    /// Backscatter ratio, used for `γ ≤ π/2` where present.
    pub ratio: Option<Ratio>,
    /// Exponential sum of the backward weight: `γ > π/2`, and everywhere without a ratio.
    pub expsum: Backward,
    /// Whether the forward part carries `e^{−τ cos γ}` (the paper's `e^{−β d1}`,
    /// lost in its printed `L1`).
    pub forward_attenuation: bool,
}

/// Largest γ evaluated as is; beyond it, A is taken at this angle.
const GAMMA_MAX: f64 = PI - 1e-7;

impl Split {
    /// The forward and backward parts of `A` at `p` (their sum is the model's `A`).
    pub fn parts(&self, p: Point) -> (f64, f64) {
        let gamma = p.gamma.min(GAMMA_MAX);
        let terms = self.phase.terms(p.g);
        if gamma == 0.0 {
            // On the axis towards the light: s + t = 1, α = 0.
            // The limit γ → 0 of the model itself: its forward part carries
            // e^{−τ cos γ} → e^{−τ} only where it has the attenuation.
            let att = if self.forward_attenuation { (-p.tau).exp() } else { 1.0 };
            let v = if p.rho >= 1.0 { f64::INFINITY } else { terms.eval(0.0) * att * p.rho / (1.0 - p.rho) };
            return (v, 0.0);
        }
        let (h, x0) = (gamma.sin(), gamma.cos());
        let t = p.tau * h;
        let theta_a = gamma - FRAC_PI_2;
        let theta_b = if p.rho.is_infinite() { FRAC_PI_2 } else { (p.rho - x0).atan2(h) };
        let mut forward = 0.0;
        if theta_a < 0.0 {
            let (lo, hi) = ((-theta_b).max(0.0), -theta_a);
            // The length as an angle between vectors (at the light: from the
            // viewer to the surface, or to the foot point), never as `hi − lo`,
            // which cancels when γ → 0 or ρ → 0.
            let len = if theta_b < 0.0 { (h * p.rho).atan2(1.0 - x0 * p.rho) } else { x0.atan2(h) };
            let att = if self.forward_attenuation { -p.tau * x0 } else { 0.0 };
            let dir = if terms.mirrored { -1.0 } else { 1.0 };
            for &(c, beta) in &terms.terms {
                forward += c * self.forward.integrate_span(lo, hi, len, t, att - beta * FRAC_PI_2, dir * beta);
            }
            // The terms of a phase that is ≥ 0 can only cancel below rounding.
            forward = forward.max(0.0) / h;
        }
        let mut backward = 0.0;
        let theta_lo = theta_a.max(0.0);
        // Past the foot point (γ > π/2: any surface; else one beyond it), decided on
        // ρ itself: the angles agree to the last digit as ρ → 0.
        if if x0 < 0.0 { p.rho > 0.0 } else { p.rho > x0 } {
            backward = match (&self.ratio, theta_a <= 0.0) {
                (Some(ratio), true) => {
                    let r = ratio.eval(theta_b, t);
                    let whole = self.forward.integrate(0.0, FRAC_PI_2, t, 0.0, 0.0);
                    let len = theta_b - theta_lo;
                    let kappa = t * sec_plus_tan(theta_lo) / theta_lo.cos();
                    let mean = theta_lo + len / (2.0 + kappa * len);
                    (-p.tau * x0).exp() * terms.eval(FRAC_PI_2 + mean) * r.max(0.0) * whole / h
                }
                _ => self.backward_expsum(p.tau, h, x0, p.rho, &terms),
            };
        }
        (forward, backward)
    }
}

impl Split {
    /// The backward part from the exponential sum (u form, docs/MATH.md §3).
    fn backward_expsum(&self, tau: f64, h: f64, x0: f64, rho: f64, terms: &Terms) -> f64 {
        let t = tau * h;
        // u = tan(γ/2), written without cancellation on either side of π/2.
        let ua = if x0 >= 0.0 { h / (1.0 + x0) } else { (1.0 - x0) / h };
        let u0 = ua.max(1.0);
        // The length `ub − u0`, formed without cancellation: for γ > π/2 the
        // interval starts at `ua` and `ub − ua = 2ρ(d + r)/((ρ + r + 1) h)` with
        // `d = ρ − cos γ > 0`, `r = √(d² + h²)` (docs/MATH.md §3), which stays exact
        // as ρ → 0.
        let len = if rho.is_infinite() {
            f64::INFINITY
        } else {
            let d = rho - x0; // ≥ 0 here: the surface is past the foot point
            let r = d.hypot(h);
            if x0 < 0.0 {
                2.0 * rho * (d + r) / ((rho + r + 1.0) * h)
            } else {
                (d + r) / h - u0
            }
        };
        if len.is_nan() || len <= 0.0 {
            return 0.0;
        }
        // The phase varies slowly against each term's exponential: taken at the
        // term's mean point, α = 2 atan u.
        let e = self.expsum.integrate(u0, len, t, -tau - t * (u0 - ua), |u| terms.eval(2.0 * u.atan()));
        2.0 / h * e
    }
}

impl Family for Split {
    const KIND: &'static str = "split";
    const DIR: &'static str = "split";
    const ROLE: Role = Role::Airlight;
    const TABLES: &'static [&'static str] = &["forward", "phase", "backscatter"];
    const TEMPLATES: Templates = airlight_shapes::core_templates!();
    const FIT_PARTS: &'static [&'static str] = &[fit::SEGMENTS, fit::PHASE, fit::BACKSCATTER];
    const REPORT: Option<&'static str> = Some(include_str!("report.md.tera"));
    type Recipe = fit::Recipe;
    type Fit = fit::SplitFits;

    fn fit(parts: &[&str], progress: &(dyn Fn(usize, usize) + Sync)) -> fit::SplitFits {
        fit::fit(parts, progress)
    }

    fn fit_summary(fits: &fit::SplitFits) -> Vec<String> {
        fit::summary(fits)
    }

    fn assemble(r: fit::Recipe, g_range: (f64, f64), fits: &fit::SplitFits) -> Result<Assembled<Split>, String> {
        fit::assemble(r, g_range, fits)
    }

    fn kernel_phase(&self, _g_range: (f64, f64), want: WantPhase) -> KernelPhase {
        kernel::kernel_phase(self, want)
    }

    fn kernel_context(&self, k: &KernelView) -> Context {
        kernel::context(self, k)
    }

    fn report(members: &[Member<'_, Split>], _floor: ReportFloor) -> Option<Context> {
        report::context(members)
    }

    fn figures(members: &[Member<'_, Split>]) -> Vec<Figure> {
        report::figures(members)
    }
    /// How the phase function costs: isotropic, or `k` exponentials per band.
    fn phase_shape(&self) -> PhaseShape {
        match &self.phase {
            PhaseModel::Isotropic => PhaseShape::Isotropic,
            PhaseModel::Exp(e) => PhaseShape::Exp { terms: e.k() },
        }
    }

    /// Worst-case operation count of one f32 kernel evaluation of this family in
    /// `shape` (the generated kernels' loops: all N segments, every term).
    fn ops(&self, shape: Shape) -> Cost {
        let (k, phase_evals) = match shape.phase {
            PhaseShape::Isotropic => (1, 0),
            PhaseShape::Exp { terms } => (terms, terms),
            PhaseShape::Exact => (1, 1),
        };
        let n = self.forward.n();
        // Forward: at most two segments' exp + exprel per term, but the loop is over all N.
        let mut c = Cost { exp: 2 * n * k, log: 0, atan: 3, sqrt: 0, div: 3, sincos: 1 };
        if shape.backscatter {
            let near = self.expsum.near.c.len();
            let local = self.expsum.local.c.len();
            let expsum_exp = near * (2 + phase_evals) + (local * (2 + phase_evals)).max(4 + phase_evals);
            let expsum_atan = if phase_evals > 0 { near + local } else { 0 };
            let expsum = Cost {
                exp: expsum_exp,
                log: 1,
                atan: expsum_atan,
                sqrt: usize::from(shape.surfaces),
                div: 12,
                sincos: 0,
            };
            let back = if self.ratio.is_some() {
                let ratio = Cost { exp: 3 + 2 * n + phase_evals, log: 1, atan: 1, sqrt: 0, div: 1, sincos: 0 };
                ratio.max(&expsum)
            } else {
                expsum
            };
            c = c.add(&back);
        }
        c.exp += phase_evals; // on-axis phase
        c
    }


    /// Its tables of a coefficient file (the `coeffs` module renders the rest); `prov(out,
    /// table)` writes the provenance table `table` where it belongs.
    fn render_toml(&self, g_range: (f64, f64), o: &mut String, prov: &dyn Fn(&mut String, &str)) {
        o.push_str("\n[forward]\nfamily = \"segments\"\n");
        let _ = writeln!(o, "attenuation = {}", self.forward_attenuation);
        let _ = writeln!(o, "n = {}", self.forward.n());
        hex_list(o, "breakpoints", &self.forward.breakpoints);
        hex_list(o, "slopes", &self.forward.slopes);
        hex_list(o, "intercepts", &self.forward.intercepts);
        prov(o, "forward.fit");
        o.push_str("\n[phase]\n");
        match &self.phase {
            PhaseModel::Isotropic => o.push_str("family = \"isotropic\"\n"),
            PhaseModel::Exp(e) => {
                o.push_str("family = \"exp-sum\"\n");
                let _ = writeln!(o, "terms = {}", e.k());
                let _ = writeln!(o, "scale = \"{}\" # {}", hexf::format(e.scale), dec(e.scale));
                let neg = if g_range.0 < 0.0 { "mirror" } else { "unsupported" };
                let _ = writeln!(o, "negative_g = \"{neg}\"");
                for b in &e.bands {
                    o.push_str("\n[[phase.band]]\n");
                    let _ = writeln!(o, "g = [{}, {}]", dec(b.g_lo), dec(b.g_hi));
                    quad_rows(o, "a", &b.a);
                    quad_rows(o, "b", &b.b);
                }
            }
        }
        prov(o, "phase.fit");
        o.push_str("\n[backscatter]\n");
        if let Some(r) = &self.ratio {
            o.push_str("family = \"ratio+expsum\" # ratio for γ ≤ π/2, exponential sum beyond\n");
            let _ = writeln!(o, "# ratio f(θ1) e^(-g(θ1) κ^h(θ1)), cubics in θ1 (θ1³, θ1², θ1, 1)");
            hex_list(o, "f", &r.f);
            hex_list(o, "g", &r.g);
            hex_list(o, "h", &r.h);
        } else {
            o.push_str("family = \"expsum\"\n");
        }
        let _ = writeln!(
            o,
            "# backward weight: near 1/(1 + u²) ≈ Σ c e^(-s u) on [1, 16]; beyond, exact 1/u² integral via E1,"
        );
        let _ =
            writeln!(o, "# or for far parts with u1 < 2 u0: local 1/y² ≈ Σ c e^(-s y) on [1, 2], y = u/max(u0, 16)");
        hex_list(o, "near_c", &self.expsum.near.c);
        hex_list(o, "near_s", &self.expsum.near.s);
        hex_list(o, "local_c", &self.expsum.local.c);
        hex_list(o, "local_s", &self.expsum.local.s);
        prov(o, "backscatter.fit");
        prov(o, "backscatter.expsum_fit");
    }

    /// Reads its tables of a coefficient file (`g_range` from `[model]`).
    fn parse_toml(r: &Reader, doc: &Table, g_range: &[f64]) -> Result<Split, FieldError> {
        let fwd = r.table(doc, "forward")?;
        r.deny(fwd, "forward", &["family", "attenuation", "n", "breakpoints", "slopes", "intercepts", "fit"])?;
        r.expect_str(fwd, "forward", "family", "segments")?;
        let forward_attenuation = r.boolean(fwd, "forward", "attenuation")?;
        let n = r.uint(fwd, "forward", "n")?;
        if !(1..=64).contains(&n) {
            return Err(r.err("forward", "n", "must be 1..=64"));
        }
        let breakpoints = r.hexes(fwd, "forward", "breakpoints", Some(n + 1))?;
        if breakpoints.windows(2).any(|w| w[1] <= w[0]) || breakpoints[0] != 0.0 {
            return Err(r.err("forward", "breakpoints", "must increase from 0"));
        }
        let forward = Segments {
            breakpoints,
            slopes: r.hexes(fwd, "forward", "slopes", Some(n))?,
            intercepts: r.hexes(fwd, "forward", "intercepts", Some(n))?,
        };

        let ph = r.table(doc, "phase")?;
        r.deny(ph, "phase", &["family", "terms", "scale", "negative_g", "band", "fit"])?;
        let family = r.string(ph, "phase", "family")?;
        let phase = match family.as_str() {
            "isotropic" => {
                if g_range != [0.0, 0.0] {
                    return Err(r.err("model", "g_range", "an isotropic model takes only [0.0, 0.0]"));
                }
                PhaseModel::Isotropic
            }
            "exp-sum" => {
                let k = r.uint(ph, "phase", "terms")?;
                let scale = r.hex(ph, "phase", "scale")?;
                let bands = r.array(ph, "phase", "band")?;
                let mut out = Vec::new();
                for b in bands {
                    let b = b.as_table().ok_or_else(|| r.err("phase.band", "band", "must be tables"))?;
                    r.deny(b, "phase.band", &["g", "a", "b"])?;
                    let g = r.floats(b, "[phase.band]", "g", Some(2))?;
                    if !(g[0] <= g[1] && g[0] >= 0.0 && g[1] < 1.0) {
                        return Err(r.err("[phase.band]", "g", "must be [lo, hi] with 0 <= lo <= hi < 1"));
                    }
                    let rows = |key: &str| -> Result<Vec<[f64; 3]>, FieldError> {
                        let arr = r.array(b, "[phase.band]", key)?;
                        if arr.len() != k {
                            return Err(r.err("[phase.band]", key, &format!("needs {k} rows, one per term")));
                        }
                        arr.iter()
                            .map(|row| {
                                let row = row.as_array().filter(|r| r.len() == 3).ok_or_else(|| {
                                    r.err("[phase.band]", key, "rows are [g², g, 1] hexadecimal floats")
                                })?;
                                let mut c = [0.0; 3];
                                for (ci, v) in c.iter_mut().zip(row) {
                                    *ci = r.hex_value(v, "[phase.band]", key)?;
                                }
                                Ok(c)
                            })
                            .collect()
                    };
                    out.push(Band { g_lo: g[0], g_hi: g[1], a: rows("a")?, b: rows("b")? });
                }
                if out.is_empty() {
                    return Err(r.err("phase", "band", "at least one band"));
                }
                PhaseModel::Exp(ExpPhase { bands: out, scale })
            }
            other => return Err(r.err("phase", "family", &format!("unknown family '{other}' (isotropic, exp-sum)"))),
        };

        let bs = r.table(doc, "backscatter")?;
        r.deny(
            bs,
            "backscatter",
            &["family", "f", "g", "h", "near_c", "near_s", "local_c", "local_s", "fit", "expsum_fit"],
        )?;
        let four = |k: &str| -> Result<[f64; 4], FieldError> {
            let v = r.hexes(bs, "backscatter", k, Some(4))?;
            Ok([v[0], v[1], v[2], v[3]])
        };
        let ratio = match r.string(bs, "backscatter", "family")?.as_str() {
            "ratio+expsum" => Some(Ratio { f: four("f")?, g: four("g")?, h: four("h")? }),
            "expsum" => None,
            other => {
                return Err(r.err("backscatter", "family", &format!("unknown family '{other}' (ratio+expsum, expsum)")))
            }
        };
        let sum = |which: &str| -> Result<ExpSum, FieldError> {
            let c = r.hexes(bs, "backscatter", &format!("{which}_c"), None)?;
            let key = format!("{which}_s");
            let rates = r.hexes(bs, "backscatter", &key, Some(c.len()))?;
            if c.is_empty() || rates.iter().any(|&x| x <= 0.0) {
                return Err(r.err("backscatter", &key, "needs at least one positive rate per amplitude"));
            }
            Ok(ExpSum { c, s: rates })
        };
        let expsum = Backward { near: sum("near")?, local: sum("local")? };
        Ok(Split { forward, phase, ratio, expsum, forward_attenuation })
    }

    fn eval(&self, p: Point) -> f64 {
        let (f, b) = self.parts(p);
        f + b
    }
}

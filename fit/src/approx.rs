//! Fitted models: complete evaluators of `A(τ, γ, ρ; g)` assembled from the three
//! families of the paper, generalised to every geometry of the domains.
//!
//! With `θa = γ − π/2`, `θb = atan((ρ − cos γ)/sin γ)` and `T = τ sin γ`
//! (MATH.md §3, angle form):
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
//!     ([`crate::family::expsum`]): positive terms, no differences, any geometry.
//!
//!   The phase enters the backward part at a mean angle: of the whole part for the
//!   ratio (mean offset `L/(2 + κ L)` from its start, `κ` the decay rate there), of
//!   each term for the exponential sum; exact for a uniform weight and for a fast
//!   exponential one.
//!
//! `γ = 0` uses the exact on-axis value; `γ` within 1e-7 of π is evaluated at
//! `π − 1e-7` (A is flat in γ there).

use crate::family::expsum::Backward;
use crate::family::phase_exp::{sec_plus_tan, ExpPhase, Terms};
use crate::family::ratio::Ratio;
use crate::family::segments::Segments;
use crate::model::Model;
use crate::reference::Point;
use std::f64::consts::{FRAC_PI_2, PI};

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

/// A model assembled from families.
#[derive(Debug, Clone, PartialEq)]
pub struct Approximation {
    /// Name on the command line and in file names.
    pub name: String,
    /// One line for tables.
    pub summary: String,
    /// Supported `g`.
    pub g_range: (f64, f64),
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

impl Approximation {
    /// The forward and backward parts of `A` at `p` (their sum is the model's `A`).
    pub fn parts(&self, p: Point) -> (f64, f64) {
        let gamma = p.gamma.min(GAMMA_MAX);
        let terms = self.phase.terms(p.g);
        if gamma == 0.0 {
            // On the axis towards the light: s + t = 1, α = 0.
            let v = if p.rho >= 1.0 { f64::INFINITY } else { terms.eval(0.0) * (-p.tau).exp() * p.rho / (1.0 - p.rho) };
            return (v, 0.0);
        }
        let (h, x0) = (gamma.sin(), gamma.cos());
        let t = p.tau * h;
        let theta_a = gamma - FRAC_PI_2;
        let theta_b = if p.rho.is_infinite() { FRAC_PI_2 } else { (p.rho - x0).atan2(h) };
        let mut forward = 0.0;
        if theta_a < 0.0 && theta_b > theta_a {
            let (lo, hi) = ((-theta_b).max(0.0), -theta_a);
            let att = if self.forward_attenuation { -p.tau * x0 } else { 0.0 };
            let dir = if terms.mirrored { -1.0 } else { 1.0 };
            for &(c, beta) in &terms.terms {
                forward += c * self.forward.integrate(lo, hi, t, att - beta * FRAC_PI_2, dir * beta);
            }
            forward /= h;
        }
        let mut backward = 0.0;
        let theta_lo = theta_a.max(0.0);
        if theta_b > theta_lo {
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

impl Approximation {
    /// Worst-case number of transcendental calls (exp, expm1, pow, atan) per
    /// evaluation in this f64 form: a rough cost to compare models by.
    pub fn cost(&self) -> usize {
        let k = match &self.phase {
            PhaseModel::Isotropic => 1,
            PhaseModel::Exp(e) => e.k(),
        };
        let n = self.forward.n();
        let forward = 2 * n * k;
        let expsum = self.expsum.near.c.len() * (2 + k + 1) + (self.expsum.local.c.len() * 2).max(6) + k + 1;
        let ratio = self.ratio.as_ref().map_or(0, |_| 3 + 2 * n + k);
        forward + expsum.max(ratio) + 3
    }

    /// The backward part from the exponential sum (u form, MATH.md §3).
    fn backward_expsum(&self, tau: f64, h: f64, x0: f64, rho: f64, terms: &Terms) -> f64 {
        let t = tau * h;
        // u = tan(γ/2), written without cancellation on either side of π/2.
        let ua = if x0 >= 0.0 { h / (1.0 + x0) } else { (1.0 - x0) / h };
        let ub = if rho.is_infinite() {
            f64::INFINITY
        } else {
            let d = rho - x0; // ≥ 0 here: the surface is past the foot point
            (d + d.hypot(h)) / h
        };
        let u0 = ua.max(1.0);
        if ub <= u0 {
            return 0.0;
        }
        // The phase varies slowly against each term's exponential: taken at the
        // term's mean point, α = 2 atan u.
        let e = self.expsum.integrate(u0, ub, t, -tau - t * (u0 - ua), |u| terms.eval(2.0 * u.atan()));
        2.0 / h * e
    }
}

impl Model for Approximation {
    fn name(&self) -> &str {
        &self.name
    }
    fn summary(&self) -> &str {
        &self.summary
    }
    fn g_range(&self) -> (f64, f64) {
        self.g_range
    }
    fn eval_unchecked(&self, p: Point) -> f64 {
        let (f, b) = self.parts(p);
        f + b
    }
}

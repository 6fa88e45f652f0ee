//! The reference airlight `A(τ, γ, ρ; P)` of docs/MATH.md §2, in f64, to ≤ 1e-12
//! relative.
//!
//! Primary path: the u form of docs/MATH.md §3 split at the foot of the perpendicular
//! (`u = 1`). The forward half is integrated in `x = u − ua`, the backward half in
//! `v = 1/u` (the substitution maps `du/(1+u²)` to `dv/(1+v²)`, so the infinite
//! range `ρ = ∞` becomes `v → 0`). Every quantity that could cancel — `ub − ua`,
//! `s + t − cos γ`, `1 ± cos α` — is formed in a cancellation-free way.
//! Adaptive Gauss–Kronrod with breakpoints at the scales where the integrand has
//! structure: `1/T` (extinction), the Henyey–Greenstein peak `1 − |g|`.
//!
//! Independent paths, used by the tests and the self-check:
//! [`airlight_s_form`] (tanh–sinh in the distance `s` along the ray, §2) and
//! [`airlight_e1`] (isotropic only; exact complex-E1 closed form, §3).

use crate::e1::isotropic_kernel_integral;
use crate::phase::Phase;
use crate::quad::{gauss_kronrod, tanh_sinh, Quadrature};
use std::f64::consts::PI;
use std::fmt;

/// Relative tolerance handed to the adaptive quadrature (on the pessimistic
/// `|K21 − G10|` estimate; the returned Kronrod value is far better).
pub const REFERENCE_REL_TOL: f64 = 1e-13;
/// Subinterval budget per half of the u form.
pub const MAX_INTERVALS: usize = 2000;

/// A point of the canonical domain: `τ = σt·D`, `γ` the angle between the view ray
/// and the direction to the light, `ρ = Dp/D` (∞ when no surface), `g` the
/// Henyey–Greenstein asymmetry (0: isotropic).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Point {
    /// Optical distance from viewer to light, `σt · D`.
    pub tau: f64,
    /// Angle between the view ray and the direction to the light, radians, `[0, π]`.
    pub gamma: f64,
    /// Distance to the first surface in units of `D`; `f64::INFINITY` for none.
    pub rho: f64,
    /// Henyey–Greenstein asymmetry parameter, `(−1, 1)`; 0 is isotropic.
    pub g: f64,
}

/// Which parameter of a [`Point`] is out of its domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Param {
    /// `τ`
    Tau,
    /// `γ`
    Gamma,
    /// `ρ`
    Rho,
    /// `g`
    G,
}

impl Param {
    /// The column name used in CSV files and messages.
    pub fn name(self) -> &'static str {
        match self {
            Param::Tau => "tau",
            Param::Gamma => "gamma",
            Param::Rho => "rho",
            Param::G => "g",
        }
    }
}

/// An input outside the domain of `A`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamError {
    /// The offending parameter.
    pub param: Param,
    /// Its value.
    pub value: f64,
    /// The `g` range of the model that refused it, when narrower than `(−1, 1)`.
    pub allowed: Option<(f64, f64)>,
}

impl ParamError {
    /// `param = value` outside the domain of `A` itself.
    pub fn new(param: Param, value: f64) -> ParamError {
        ParamError { param, value, allowed: None }
    }
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = self.param.name();
        let need = match (self.param, self.allowed) {
            (_, Some((lo, hi))) if lo == hi => {
                format!("{}: the model or kernel takes only {name} = {}", num(lo), num(lo))
            }
            (_, Some((lo, hi))) => format!("in [{}, {}], the range of the model or kernel", num(lo), num(hi)),
            (Param::Tau, None) => "a finite number ≥ 0".to_string(),
            (Param::Gamma, None) => "an angle in [0, π] radians".to_string(),
            (Param::Rho, None) => "a number > 0, or inf for no surface".to_string(),
            (Param::G, None) => "in (−1, 1)".to_string(),
        };
        write!(f, "{} = {} is out of range: it must be {need}", self.param.name(), num(self.value))
    }
}

impl std::error::Error for ParamError {}

/// A float for a message: exact and short (`-2`, `0.5`, `1e300`; never 301 digits).
fn num(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 20 {
        plain
    } else {
        format!("{x:e}")
    }
}

impl Point {
    /// A point; see [`Point::validate`].
    pub fn new(tau: f64, gamma: f64, rho: f64, g: f64) -> Point {
        Point { tau, gamma, rho, g }
    }

    /// Checks the domain: `τ ∈ [0, ∞)`, `γ ∈ [0, π]`, `ρ ∈ (0, ∞]`, `|g| < 1`, no NaN.
    pub fn validate(&self) -> Result<(), ParamError> {
        let err = |param, value| Err(ParamError::new(param, value));
        if !self.tau.is_finite() || self.tau < 0.0 {
            return err(Param::Tau, self.tau);
        }
        if !(0.0..=PI).contains(&self.gamma) {
            return err(Param::Gamma, self.gamma);
        }
        if self.rho.is_nan() || self.rho <= 0.0 {
            return err(Param::Rho, self.rho);
        }
        if self.g.is_nan() || self.g.abs() >= 1.0 {
            return err(Param::G, self.g);
        }
        Ok(())
    }

    /// The point with a surface beyond [`RHO_OPEN`] taken as none (`ρ = ∞`):
    /// equal to f64 precision, and no `ρ²` or `ρ·q` overflows on the way.
    pub fn open_far(self) -> Point {
        Point { rho: if self.rho >= RHO_OPEN { f64::INFINITY } else { self.rho }, ..self }
    }

    /// The phase function this point uses.
    pub fn phase(&self) -> Phase {
        Phase::from_g(self.g)
    }
}

/// A surface farther than this (in units of the viewer–light distance) is no
/// surface. What lies beyond `ρ` is at most `P_max ∫_ρ^∞ ds/(s − 1)² = P_max/(ρ − 1)`
/// (its transmittance `e^{−τ(2ρ−1)}` only shrinks it), while `A ≥ P_min e^{−3τ}/4`
/// from the stretch `s ∈ [0, 1]`; `P_max/P_min = ((1 + |g|)/(1 − |g|))³ < 7e48` for
/// every f64 `|g| < 1`, so the part dropped is below `3e-51 A`. Below it every
/// product the evaluators form (`ρ²`, `ρ q`) stays finite.
pub const RHO_OPEN: f64 = 1e100;

/// A reference value with the quadrature's own account of itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    /// `A(τ, γ, ρ; g)`; `+∞` when the ray passes through the light.
    pub value: f64,
    /// Estimated relative error (the pessimistic Gauss–Kronrod estimate; 0 for
    /// closed forms).
    pub rel_error: f64,
    /// Integrand evaluations spent.
    pub evaluations: usize,
    /// Whether the adaptive quadrature met its tolerance on every part.
    pub converged: bool,
}

/// Quantities of the u form shared by every path (docs/MATH.md §3).
#[derive(Debug, Clone, Copy)]
struct Geometry {
    /// `sin γ`
    h: f64,
    /// `1 − cos γ = 2 sin²(γ/2)`
    one_minus_c: f64,
    /// `ua = tan(γ/2)`
    ua: f64,
    /// `ub = (ρ + t(ρ) − cos γ)/sin γ`, ∞ for ρ = ∞
    ub: f64,
    /// `1/ub`
    vb: f64,
    /// `ub − ua`, without cancellation
    delta: f64,
}

/// `s − cos γ + t(s)` ≥ 0 without cancellation, with `t = √((s − c)² + h²)`.
#[inline]
fn s_minus_c_plus_t(r: f64, t: f64, h: f64) -> f64 {
    // r = s − c. If r < 0, t − |r| = h² / (t + |r|).
    if r >= 0.0 {
        r + t
    } else {
        h * h / (t - r)
    }
}

/// `s − cos γ` to full precision even when `cos γ` rounds to 1: for `γ < π/2`
/// it is `(s − 1) + (1 − cos γ)`, where `s − 1` is exact for `s ∈ [½, 2]` (the
/// only place the difference can be small) and `1 − cos γ = 2 sin²(γ/2)`.
#[inline]
fn offset_from_foot(s: f64, c: f64, one_minus_c: f64) -> f64 {
    if c > 0.0 {
        (s - 1.0) + one_minus_c
    } else {
        s - c
    }
}

impl Geometry {
    fn new(gamma: f64, rho: f64) -> Geometry {
        let h = gamma.sin();
        let c = gamma.cos();
        let half = (0.5 * gamma).sin();
        let one_minus_c = 2.0 * half * half;
        let ua = (0.5 * gamma).tan();
        if rho.is_infinite() {
            return Geometry { h, one_minus_c, ua, ub: f64::INFINITY, vb: 0.0, delta: f64::INFINITY };
        }
        let r = offset_from_foot(rho, c, one_minus_c);
        let t = r.hypot(h);
        let q = s_minus_c_plus_t(r, t, h);
        // u(ρ) − ua = (ρ + t − 1)/h = 2ρ q / ((ρ + t + 1) h); for r < 0, q = h²/(t − r)
        // and the h cancels first, so nothing underflows as γ → 0.
        let delta =
            if r >= 0.0 { 2.0 * rho * q / ((rho + t + 1.0) * h) } else { 2.0 * rho * (h / (t - r)) / (rho + t + 1.0) };
        // ub = q/h; 1/ub = h/q, written so that neither over- nor underflows early.
        let (ub, vb) = if r >= 0.0 { (q / h, h / q) } else { (h / (t - r), (t - r) / h) };
        Geometry { h, one_minus_c, ua, ub, vb, delta }
    }
}

/// Validates and evaluates the reference airlight. The main entry point.
///
/// Returns `+∞` only for a ray through the light (`γ = 0`, `ρ ≥ 1`). The value
/// carries the factor `e^{−τ}`, so it underflows to 0 beyond τ ≈ 745; it is
/// never NaN or negative.
pub fn airlight(p: Point) -> Result<f64, ParamError> {
    airlight_detailed(p).map(|e| e.value)
}

/// The forward half of the u form, `u = ua + x`, `x ∈ [0, min(ub, 1) − ua]`
/// (only when `ua < 1`, `γ < π/2`).
fn forward_half(geo: &Geometry, phase: Phase, t_ext: f64, width: f64) -> Quadrature {
    let x_end = if geo.ub <= 1.0 { geo.delta } else { 1.0 - geo.ua };
    let mut bps = vec![0.0, x_end];
    add_scales(&mut bps, x_end, &[1.0 / t_ext]);
    // The forward HG peak at u = 0 is algebraic: powers of 4 up to the end
    // (from where a breakpoint is still distinct from 0 at the end's scale,
    // so the loop is bounded however small the width).
    let mut x = (0.5 * width / 16.0).max(x_end * f64::EPSILON);
    while x < x_end {
        bps.push(x);
        x *= 4.0;
    }
    gauss_kronrod(
        |x| {
            let u = geo.ua + x;
            let w = 1.0 / (1.0 + u * u);
            phase.eval_half(u * u * w, w) * w * (-t_ext * x).exp()
        },
        &finish(bps),
        REFERENCE_REL_TOL,
        MAX_INTERVALS,
    )
}

/// The backward half of the u form, `v = 1/u = v0 − y` from `v0 = min(1, 1/ua)`
/// down to `vb` (only when `ub > 1`).
fn backward_half(geo: &Geometry, tau: f64, phase: Phase, t_ext: f64, width: f64) -> Quadrature {
    let (v0, k0, e0) = if geo.ua < 1.0 {
        // T(1/v − ua) = T·y/v + T(1 − ua)
        (1.0, t_ext, t_ext * (1.0 - geo.ua))
    } else {
        // T/va = τ (1 − cos γ); T(1/v − ua) = τ(1 − c) y / v
        (1.0 / geo.ua, tau * geo.one_minus_c, 0.0)
    };
    let y_end = if geo.ua < 1.0 {
        1.0 - geo.vb
    } else if geo.ub.is_infinite() {
        v0
    } else {
        geo.delta / (geo.ua * geo.ub)
    };
    let mut bps = vec![0.0, y_end];
    // Near y = 0 the decay scale is v0²/k0 (T large).
    add_scales(&mut bps, y_end, &[v0 * v0 / k0]);
    // Towards v = 0: the cut-off e^{−T/v} at v ~ T, whose 1 − e^{−T/v} ≈ T/v
    // tail reaches every scale up to v0, and the backward HG peak, algebraic
    // on the same terms. Breakpoints at every power of 4 keep each
    // subinterval well away from that structure.
    for s in [t_ext, 0.5 * width] {
        if s.is_finite() && s > 0.0 {
            // Bounded: `v0 − v` rounds to `v0` below `v0·ε`, and `s / 16`
            // underflows to 0 when `T` is subnormal (it never grew then).
            let mut v = (s / 16.0).max(v0 * f64::EPSILON);
            while v < v0 {
                if v > geo.vb {
                    bps.push(v0 - v);
                }
                v *= 4.0;
            }
        }
    }
    gauss_kronrod(
        |y| {
            let v = v0 - y;
            if v <= 0.0 {
                return 0.0;
            }
            let w = 1.0 / (1.0 + v * v);
            let e = if k0 == 0.0 { e0 } else { k0 * (y / v) + e0 };
            phase.eval_half(w, v * v * w) * w * (-e).exp()
        },
        &finish(bps),
        REFERENCE_REL_TOL,
        MAX_INTERVALS,
    )
}

/// [`airlight`] with the quadrature's diagnostics.
pub fn airlight_detailed(p: Point) -> Result<Evaluation, ParamError> {
    p.validate()?;
    let p = p.open_far();
    let phase = p.phase();
    if let Some(v) = on_axis(p, phase) {
        return Ok(Evaluation { value: v, rel_error: 0.0, evaluations: 0, converged: true });
    }
    let geo = Geometry::new(p.gamma, p.rho);
    let t_ext = p.tau * geo.h; // T = τ sin γ
    let width = phase.peak_width();
    let mut evaluations = 0;
    let mut err = 0.0;
    let mut total = 0.0;
    let mut converged = true;
    let halves = [
        (geo.ua < 1.0).then(|| forward_half(&geo, phase, t_ext, width)),
        (geo.ub > 1.0).then(|| backward_half(&geo, p.tau, phase, t_ext, width)),
    ];
    for q in halves.into_iter().flatten() {
        total += q.value;
        err += q.error;
        evaluations += q.evaluations;
        converged &= q.converged;
    }
    // A = 2 e^{−τ} I / h; the order keeps it from ever forming 0·∞.
    let value = 2.0 * (-p.tau).exp() * total / geo.h;
    let rel_error = if total > 0.0 { err / total } else { 0.0 };
    Ok(Evaluation { value, rel_error, evaluations, converged })
}

/// `γ = 0`: the ray looks straight at the light. `α = 0` before it, so
/// `A = P(0) e^{−τ} ρ/(1 − ρ)` for `ρ < 1` and `+∞` when the ray reaches the light.
fn on_axis(p: Point, phase: Phase) -> Option<f64> {
    if p.gamma != 0.0 {
        return None;
    }
    Some(if p.rho < 1.0 { phase.eval_half(0.0, 1.0) * (-p.tau).exp() * p.rho / (1.0 - p.rho) } else { f64::INFINITY })
}

/// Breakpoints at `s·4^k` inside `(0, end)` for each finite, positive scale `s`.
fn add_scales(bps: &mut Vec<f64>, end: f64, scales: &[f64]) {
    for &s in scales {
        if s.is_finite() && s > 0.0 {
            for k in [-2, -1, 0, 1, 2, 3] {
                let x = s * 4f64.powi(k);
                if x > 0.0 && x < end {
                    bps.push(x);
                }
            }
        }
    }
}

fn finish(mut bps: Vec<f64>) -> Vec<f64> {
    bps.sort_by(|a, b| a.total_cmp(b));
    bps.dedup();
    bps
}

/// Independent path: tanh–sinh quadrature of the s form (docs/MATH.md §2), split
/// geometrically around the foot of the perpendicular and at the extinction
/// length; the tail to `ρ = ∞` is mapped by `s = S/w`. Every breakpoint is kept as
/// the pair `(s, r = s − cos γ)`, and each node is placed from its nearer
/// breakpoint, so neither `s` near 0 nor `r` near the foot loses digits.
pub fn airlight_s_form(p: Point) -> Result<f64, ParamError> {
    p.validate()?;
    let p = p.open_far();
    let phase = p.phase();
    if let Some(v) = on_axis(p, phase) {
        return Ok(v);
    }
    let h = p.gamma.sin();
    let c = p.gamma.cos();
    let one_minus_c = 2.0 * (0.5 * p.gamma).sin().powi(2);
    let tau = p.tau;
    // Integrand at distance s, with r = s − c supplied accurately; e^{−τ} factored out.
    let f = |s: f64, r: f64| -> f64 {
        let t = r.hypot(h);
        let q = s_minus_c_plus_t(r, t, h); // = 2 t sin²(α/2)
        let s2 = 0.5 * q / t;
        let c2 = if r <= 0.0 { 0.5 * (t - r) / t } else { 0.5 * h * h / ((t + r) * t) };
        let excess = 2.0 * s * q / (s + t + 1.0); // s + t − 1 ≥ 0
        phase.eval_half(s2, c2) * (-tau * excess).exp() / (t * t)
    };
    let tail_start = if p.rho.is_infinite() { (c.max(0.0) + 1.0) * 4.0 } else { p.rho };
    // Breakpoints as (s, r): the ends, the foot, and geometric offsets from the foot.
    let mut bps: Vec<(f64, f64)> = vec![(0.0, -c), (tail_start, offset_from_foot(tail_start, c, one_minus_c))];
    let mut scales = vec![h];
    if tau > 0.0 {
        scales.push(1.0 / tau);
    }
    for sc in scales {
        for k in 0..60 {
            let d = sc * 4f64.powi(k);
            if d > 4.0 * (tail_start + 1.0) {
                break;
            }
            for r in [d, -d, 0.0] {
                let s = c + r;
                if s > 0.0 && s < tail_start {
                    bps.push((s, r));
                }
            }
        }
    }
    bps.sort_by(|a, b| a.0.total_cmp(&b.0));
    bps.dedup_by(|a, b| a.0 == b.0);
    let mut total = 0.0;
    for w in bps.windows(2) {
        let ((sa, ra), (sb, rb)) = (w[0], w[1]);
        // The width from whichever coordinate is smaller here, hence exact.
        let width = if ra.abs().max(rb.abs()) < sa.abs().max(sb.abs()) { rb - ra } else { sb - sa };
        total +=
            tanh_sinh(|da, db| if da <= db { f(sa + da, ra + da) } else { f(sb - db, rb - db) }, width, 1e-14).value;
    }
    if p.rho.is_infinite() {
        let big_s = tail_start;
        // s = S/w, ds = S/w² dw, w ∈ (0, 1].
        total += tanh_sinh(
            |w, _| {
                let s = big_s / w;
                f(s, offset_from_foot(s, c, one_minus_c)) * big_s / (w * w)
            },
            1.0,
            1e-14,
        )
        .value;
    }
    Ok((-tau).exp() * total)
}

/// `A(0, γ, ρ)` for isotropic scattering, in closed form (docs/MATH.md §3): the
/// angle the lit part of the ray subtends at the light over `4π h`; on the axis its
/// limits (divergent through the light).
pub fn no_extinction(gamma: f64, rho: f64) -> f64 {
    let (h, c) = (gamma.sin(), gamma.cos());
    if h == 0.0 {
        return if c > 0.0 && rho >= 1.0 {
            f64::INFINITY
        } else if c > 0.0 {
            rho / (4.0 * PI * (1.0 - rho))
        } else if rho.is_infinite() {
            1.0 / (4.0 * PI)
        } else {
            rho / (4.0 * PI * (1.0 + rho))
        };
    }
    let angle = if rho.is_infinite() { PI - gamma } else { (h * rho).atan2(1.0 - rho * c) };
    angle / (4.0 * PI * h)
}

/// Independent path for isotropic media: the exact complex-E1 closed form of
/// docs/MATH.md §3. Returns the value and the condition number of its final
/// subtraction (digits lost ≈ log10 of it). `g` must be 0.
pub fn airlight_e1(p: Point) -> Result<(f64, f64), ParamError> {
    p.validate()?;
    if p.g != 0.0 {
        return Err(ParamError::new(Param::G, p.g));
    }
    let p = p.open_far();
    if let Some(v) = on_axis(p, Phase::Isotropic) {
        return Ok((v, 1.0));
    }
    let geo = Geometry::new(p.gamma, p.rho);
    let (i, cond) = isotropic_kernel_integral(p.tau * geo.h, geo.ua, geo.ub, geo.delta);
    Ok((2.0 * (-p.tau).exp() * i / (4.0 * PI) / geo.h, cond))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_input_names_the_parameter() {
        let cases = [
            (Point::new(-1.0, 1.0, 1.0, 0.0), Param::Tau),
            (Point::new(f64::NAN, 1.0, 1.0, 0.0), Param::Tau),
            (Point::new(f64::INFINITY, 1.0, 1.0, 0.0), Param::Tau),
            (Point::new(1.0, -0.1, 1.0, 0.0), Param::Gamma),
            (Point::new(1.0, 3.2, 1.0, 0.0), Param::Gamma),
            (Point::new(1.0, f64::NAN, 1.0, 0.0), Param::Gamma),
            (Point::new(1.0, 1.0, 0.0, 0.0), Param::Rho),
            (Point::new(1.0, 1.0, f64::NAN, 0.0), Param::Rho),
            (Point::new(1.0, 1.0, 1.0, 1.0), Param::G),
            (Point::new(1.0, 1.0, 1.0, -1.0), Param::G),
            (Point::new(1.0, 1.0, 1.0, f64::NAN), Param::G),
        ];
        for (p, param) in cases {
            assert_eq!(airlight(p).unwrap_err().param, param, "{p:?}");
        }
    }

    #[test]
    fn looking_at_the_light() {
        let p0 = Phase::Isotropic.eval(0.0);
        let a = airlight(Point::new(0.5, 0.0, 0.5, 0.0)).unwrap();
        assert!((a - p0 * (-0.5f64).exp()).abs() < 1e-16);
        assert_eq!(airlight(Point::new(0.5, 0.0, 1.0, 0.0)).unwrap(), f64::INFINITY);
        assert_eq!(airlight(Point::new(0.5, 0.0, f64::INFINITY, 0.3)).unwrap(), f64::INFINITY);
        // Continuity: a tiny angle approaches the on-axis value.
        let near = airlight(Point::new(0.5, 1e-9, 0.5, 0.0)).unwrap();
        assert!(((near - a) / a).abs() < 1e-12, "{near} vs {a}");
    }

    #[test]
    fn looking_away_from_the_light() {
        // γ = π: α = π all along, t = 1 + s, so A = P(π) e^{−τ} ∫₀^ρ e^{−2τs}/(1+s)² ds,
        // which is P(π) ρ/(1+ρ) at τ = 0 and P(π) e^{−τ} (1 − 2τ e^{2τ} E1(2τ)) at ρ = ∞.
        // (π as an f64 is 1.2e-16 short of π; A moves by far less than 1e-15.)
        for g in [0.0, 0.6, -0.6] {
            let back = Phase::from_g(g).eval(PI);
            let a = airlight(Point::new(0.0, PI, 3.0, g)).unwrap();
            assert!(((a - back * 0.75) / a).abs() < 1e-14, "g = {g}: {a}");
            // e^{1} E1(1) = 0.596347362323194074341…
            let a = airlight(Point::new(0.5, PI, f64::INFINITY, g)).unwrap();
            let want = back * (-0.5f64).exp() * (1.0 - 0.596_347_362_323_194_1);
            assert!(((a - want) / want).abs() < 1e-13, "g = {g}: {a} vs {want}");
        }
    }

    #[test]
    fn never_nan_far_outside_the_domains() {
        for tau in [0.0, 1e-300, 1e-8, 100.0, 700.0, 1e4] {
            for gamma in [1e-300, 1e-12, 1e-4, 1.0, PI - 1e-12, PI] {
                for rho in [1e-300, 1e-4, 0.999_999_999, 1.0, 1e4, 1e300, f64::INFINITY] {
                    for g in [0.0, 0.999, -0.999] {
                        let a = airlight(Point::new(tau, gamma, rho, g)).unwrap();
                        assert!(a >= 0.0, "A({tau}, {gamma}, {rho}; {g}) = {a}");
                    }
                }
            }
        }
    }

    #[test]
    fn messages_name_the_range_that_refused_and_print_numbers_short() {
        let iso = ParamError { param: Param::G, value: 0.5, allowed: Some((0.0, 0.0)) };
        assert_eq!(iso.to_string(), "g = 0.5 is out of range: it must be 0: the model or kernel takes only g = 0");
        let hg = ParamError { param: Param::G, value: 0.995, allowed: Some((-0.99, 0.99)) };
        assert_eq!(
            hg.to_string(),
            "g = 0.995 is out of range: it must be in [-0.99, 0.99], the range of the model or kernel"
        );
        assert_eq!(
            ParamError::new(Param::Tau, -1e300).to_string(),
            "tau = -1e300 is out of range: it must be a finite number ≥ 0"
        );
        assert_eq!(
            ParamError::new(Param::Rho, 0.0).to_string(),
            "rho = 0 is out of range: it must be a number > 0, or inf for no surface"
        );
    }

    /// A subnormal optical depth once made a breakpoint loop spin forever; the
    /// value is then `A` at τ = 0 (to the reference's tolerance).
    #[test]
    fn vanishing_optical_depth_returns_and_is_continuous() {
        for &(tau, gamma, rho, g) in &[
            (5e-324, 1.0, f64::INFINITY, 0.0),
            (4e-323, 1.0, 2.0, 0.0),
            (1e-310, 0.5, f64::INFINITY, 0.9),
            (1e-300, 2.5, 3.0, -0.7),
            (5e-324, 3.0, f64::INFINITY, 0.5),
        ] {
            let at = |tau| airlight(Point { tau, gamma, rho, g }).unwrap();
            let (a, a0) = (at(tau), at(0.0));
            assert!((a - a0).abs() <= 1e-11 * a0, "τ = {tau:e}, γ {gamma}, ρ {rho}, g {g}: {a} vs {a0} at τ = 0");
        }
    }

    #[test]
    fn no_extinction_closed_form() {
        // τ = 0, isotropic: A = (2/h)(atan ub − atan ua)/(4π) (seed 003).
        for (gamma, rho) in [(0.3, 2.0), (2.5, f64::INFINITY), (1.0, 0.01)] {
            let geo = Geometry::new(gamma, rho);
            let exact = 2.0 * (geo.ub.atan() - geo.ua.atan()) / (4.0 * PI * geo.h);
            let a = airlight(Point::new(0.0, gamma, rho, 0.0)).unwrap();
            assert!(((a - exact) / exact).abs() < 1e-13, "{a} vs {exact}");
        }
    }
}

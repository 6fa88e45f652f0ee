//! Phase family: Henyey–Greenstein approximated by a sum of `K` exponentials in
//! the scattering angle, `P_g(α) ≈ Σ_k a_k(g) e^{−b_k(g) α}` (α in radians, `P`
//! normalised over the sphere as in docs/MATH.md), with `a_k` and `b_k` quadratic in `g`
//! inside each band of `g`. `K = 1` is the paper's form (appendix table, seven bands
//! over `[0, 0.99]`).
//!
//! Negative `g` is mirrored: `P_g(α) = P_{−g}(π − α)`, so one table serves
//! `[−0.99, 0.99]` where a model declares it.
//!
//! The fit minimises the least-squares relative error of `A` itself, with the
//! exact kernel: each fit point's `A` is written as a fixed quadrature
//! `Σ_i w_i P(α_i)` (graded Gauss–Legendre panels), so for fixed `b` the
//! coefficients of `a` solve a linear least-squares problem (SVD), and the
//! coefficients of `b` are moved by Nelder–Mead.

use airlight_truth::domains::Domain;
use crate::lsq::{self, Outcome};
use airlight_truth::quad::gauss_legendre;
use airlight_truth::reference::{self, Point};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::{FRAC_PI_2, PI};

/// The paper's seven bands of `g`.
pub const PAPER_BANDS: [(f64, f64); 7] =
    [(0.0, 0.2), (0.2, 0.4), (0.4, 0.6), (0.6, 0.8), (0.8, 0.9), (0.9, 0.95), (0.95, 0.99)];

/// One band: for each term, `a = a[0] g² + a[1] g + a[2]`, `b` likewise.
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    /// Lower end of the band's `|g|`.
    pub g_lo: f64,
    /// Upper end of the band's `|g|`.
    pub g_hi: f64,
    /// Amplitude coefficients per term (`g²`, `g`, 1).
    pub a: Vec<[f64; 3]>,
    /// Decay coefficients per term (`g²`, `g`, 1), per radian.
    pub b: Vec<[f64; 3]>,
}

fn quad_in(c: &[f64; 3], g: f64) -> f64 {
    (c[0] * g + c[1]) * g + c[2]
}

/// A banded `K`-term exponential phase approximation.
#[derive(Debug, Clone, PartialEq)]
pub struct ExpPhase {
    /// Bands in increasing `g`, contiguous.
    pub bands: Vec<Band>,
    /// Factor applied to every amplitude: `1/(4π)` for the paper's table (which is
    /// read as `4π·P`, the only reading under which its `g = 0` row is isotropic),
    /// 1 for refits.
    pub scale: f64,
}

/// `P(α) ≈ Σ c_k e^{−β_k α'}` at one `g`, where `α' = α`, or `π − α` if `mirrored`.
#[derive(Debug, Clone, PartialEq)]
pub struct Terms {
    /// `(c_k, β_k)`.
    pub terms: Vec<(f64, f64)>,
    /// Whether the angle is measured from the back (`g < 0`).
    pub mirrored: bool,
}

impl Terms {
    /// The isotropic phase `1/(4π)`.
    pub fn isotropic() -> Terms {
        Terms { terms: vec![(1.0 / (4.0 * PI), 0.0)], mirrored: false }
    }

    /// The approximate `P(α)`.
    pub fn eval(&self, alpha: f64) -> f64 {
        let a = if self.mirrored { PI - alpha } else { alpha };
        self.terms.iter().map(|&(c, b)| c * (-b * a).exp()).sum()
    }
}

impl ExpPhase {
    /// The paper's appendix table, read as `4π·P(α) ≈ a e^{−bα}`, α in radians.
    pub fn paper() -> ExpPhase {
        let rows: [([f64; 3], [f64; 3]); 7] = [
            ([-0.8470, 0.6117, 1.0004], [0.7218, 2.2603, 0.0009]),
            ([-0.3199, 0.4128, 1.0197], [3.1063, 1.2475, 0.1109]),
            ([-0.2697, 0.3865, 1.0223], [9.4069, -4.0092, 1.2134]),
            ([-0.3067, 0.4298, 1.0096], [46.9285, -51.3639, 16.1729]),
            ([-1.1784, 1.8440, 0.4358], [369.6793, -573.3485, 227.3450]),
            ([-7.5, 13.3, -4.7], [2829.9, -5022.1, 2238.6]),
            ([-50.0, 90.0, -40.0], [78630.0, -150550.0, 72090.0]),
        ];
        ExpPhase {
            bands: PAPER_BANDS
                .iter()
                .zip(rows)
                .map(|(&(g_lo, g_hi), (a, b))| Band { g_lo, g_hi, a: vec![a], b: vec![b] })
                .collect(),
            scale: 1.0 / (4.0 * PI),
        }
    }

    /// Number of exponential terms.
    pub fn k(&self) -> usize {
        self.bands[0].a.len()
    }

    /// The band holding `|g|` (the first whose upper end reaches it).
    pub fn band(&self, g: f64) -> &Band {
        let ga = g.abs();
        self.bands.iter().find(|b| ga <= b.g_hi).unwrap_or(self.bands.last().expect("at least one band"))
    }

    /// The terms at `g` (mirrored for `g < 0`).
    pub fn terms(&self, g: f64) -> Terms {
        let ga = g.abs();
        let band = self.band(g);
        Terms {
            terms: band.a.iter().zip(&band.b).map(|(a, b)| (self.scale * quad_in(a, ga), quad_in(b, ga))).collect(),
            mirrored: g < 0.0,
        }
    }
}

/// One fit point, its `A` written as `Σ w_i P(α_i)` with the weights already
/// divided by the reference `A` (so a perfect `P` gives 1).
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseSample {
    /// The point.
    pub point: Point,
    /// `(α_i, w_i / A_ref)`.
    pub nodes: Vec<(f64, f64)>,
}

/// `sec θ + tan θ` for θ ∈ (−π/2, π/2), without cancellation on either side.
pub fn sec_plus_tan(theta: f64) -> f64 {
    if theta <= 0.0 {
        theta.cos() / (1.0 - theta.sin())
    } else {
        (1.0 + theta.sin()) / theta.cos()
    }
}

/// Panels of the node rule: geometric towards the start of the ray's angle range
/// (the forward peak and the fast decay of `e^{−T(sec θ + tan θ)}` live there).
const PANEL_LEVELS: i32 = 14;
const NODES_PER_PANEL: usize = 6;

/// Quadrature nodes for `A(p) = (1/h) ∫ P(π/2 + θ) e^{−τ cos γ − T (sec θ + tan θ)} dθ`
/// over `[γ − π/2, θ_b]`: `(α_i, w_i)` with `A ≈ Σ w_i P(α_i)`.
pub fn nodes(p: &Point) -> Vec<(f64, f64)> {
    let (h, x0) = (p.gamma.sin(), p.gamma.cos());
    let ta = p.gamma - FRAC_PI_2;
    let tb = if p.rho.is_infinite() { FRAC_PI_2 } else { (p.rho - x0).atan2(h) };
    let (gx, gw) = gauss_legendre(NODES_PER_PANEL);
    let len = tb - ta;
    // Graded towards both ends (the forward peak and the start of the decay at
    // θa; the e^{−2T/(π/2 − θ)} tail at θb = π/2), with a cut at the foot point.
    let mut cuts: Vec<f64> = vec![0.0, 1.0];
    for k in 1..PANEL_LEVELS {
        let x = 0.5f64.powi(k);
        cuts.push(x);
        cuts.push(1.0 - x);
    }
    if ta < 0.0 && tb > 0.0 {
        cuts.push(-ta / len);
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let t = p.tau * h;
    let mut out = Vec::with_capacity(cuts.len() * NODES_PER_PANEL);
    for w in cuts.windows(2) {
        let (a, b) = (ta + len * w[0], ta + len * w[1]);
        let half = 0.5 * (b - a);
        for (x, wt) in gx.iter().zip(&gw) {
            let th = a + half * (1.0 + x);
            let e = -p.tau * x0 - t * sec_plus_tan(th);
            out.push((FRAC_PI_2 + th, wt * half * e.exp() / h));
        }
    }
    out
}

/// `n` fit points from each of `thin` and `dense` with `g` uniform in `[g_lo, g_hi]`,
/// with their node rules normalised by the reference `A`.
pub fn phase_samples(g_lo: f64, g_hi: f64, n: usize, seed: u64) -> Vec<PhaseSample> {
    let mut pts = Vec::new();
    for d in [Domain::Thin, Domain::Dense] {
        pts.extend(d.validation_set((g_lo, g_hi), n, seed).into_iter().take(n));
    }
    airlight_truth::parallel::map(
        &pts,
        |p| {
            let a = reference::airlight(*p).expect("sampled inside the domain");
            PhaseSample { point: *p, nodes: nodes(p).into_iter().map(|(al, w)| (al, w / a)).collect() }
        },
        &|_, _| {},
    )
}

/// Largest relative error of the node rule itself (exact HG phase) on `samples`:
/// how far the fit's view of `A` is from the reference.
pub fn node_rule_error(samples: &[PhaseSample]) -> f64 {
    samples
        .iter()
        .map(|s| {
            let ph = s.point.phase();
            (s.nodes.iter().map(|&(al, w)| w * ph.eval(al)).sum::<f64>() - 1.0).abs()
        })
        .fold(0.0, f64::max)
}

/// Relative errors of `A` on `samples` when `P` is replaced by `terms(g)`.
pub fn a_errors(terms: impl Fn(f64) -> Terms, samples: &[PhaseSample]) -> Vec<f64> {
    samples
        .iter()
        .map(|s| {
            let t = terms(s.point.g);
            s.nodes.iter().map(|&(al, w)| w * t.eval(al)).sum::<f64>() - 1.0
        })
        .collect()
}

/// Result of fitting one band.
#[derive(Debug, Clone, PartialEq)]
pub struct BandFit {
    /// The fitted band.
    pub band: Band,
    /// What the search over `b` did.
    pub outcome: Outcome,
    /// Fit points.
    pub samples: usize,
    /// RMS relative error of `A` on the fit points.
    pub rms_rel: f64,
    /// Largest relative error of `A` on the fit points.
    pub max_rel: f64,
}

/// Quadratic through values at `g_lo, g_mid, g_hi` as monomial coefficients (`g²`, `g`, 1).
fn quad_through(gs: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    // Newton form, then expanded.
    let d01 = (v[1] - v[0]) / (gs[1] - gs[0]);
    let d12 = (v[2] - v[1]) / (gs[2] - gs[1]);
    let c2 = (d12 - d01) / (gs[2] - gs[0]);
    let c1 = d01 - c2 * (gs[0] + gs[1]);
    let c0 = v[0] - d01 * gs[0] + c2 * gs[0] * gs[1];
    [c2, c1, c0]
}

/// For fixed decay coefficients, the amplitude coefficients minimising the
/// relative error of `A` (SVD), and the mean squared error.
fn solve_amplitudes(b: &[[f64; 3]], gm: f64, samples: &[PhaseSample]) -> Option<(Vec<[f64; 3]>, f64)> {
    let k = b.len();
    let mut m = DMatrix::<f64>::zeros(samples.len(), 3 * k);
    for (i, s) in samples.iter().enumerate() {
        let g = s.point.g;
        let dg = g - gm;
        for (t, bt) in b.iter().enumerate() {
            let beta = quad_in(bt, g);
            let col: f64 = s.nodes.iter().map(|&(al, w)| w * (-beta * al).exp()).sum();
            m[(i, 3 * t)] = dg * dg * col;
            m[(i, 3 * t + 1)] = dg * col;
            m[(i, 3 * t + 2)] = col;
        }
    }
    let rhs = DVector::<f64>::from_element(samples.len(), 1.0);
    let x = lsq::solve(m.clone(), &rhs)?;
    let r = &m * &x - rhs;
    let mse = r.norm_squared() / samples.len() as f64;
    // Centred (g − gm) basis to monomials in g.
    let a = (0..k)
        .map(|t| {
            let (c2, c1, c0) = (x[3 * t], x[3 * t + 1], x[3 * t + 2]);
            [c2, c1 - 2.0 * c2 * gm, c2 * gm * gm - c1 * gm + c0]
        })
        .collect();
    Some((a, mse))
}

/// Fits one band with `k` terms. The decay of each term is parametrised by its
/// values at the band's ends and middle; `start` gives one decay per term.
pub fn fit_band(g_lo: f64, g_hi: f64, start: &[f64], samples: &[PhaseSample]) -> BandFit {
    let k = start.len();
    let gs = [g_lo, 0.5 * (g_lo + g_hi), g_hi];
    let gm = gs[1];
    let to_b = |x: &[f64]| -> Vec<[f64; 3]> {
        (0..k).map(|t| quad_through(gs, [x[3 * t], x[3 * t + 1], x[3 * t + 2]])).collect()
    };
    let cost = |x: &[f64]| solve_amplitudes(&to_b(x), gm, samples).map_or(f64::INFINITY, |(_, mse)| mse);
    let x0: Vec<f64> = start.iter().flat_map(|&b| [b, b, b]).collect();
    let step: Vec<f64> = x0.iter().map(|b| 0.25 * b.abs() + 0.1).collect();
    let c0 = cost(&x0);
    let outcome = lsq::nelder_mead_restarted(&cost, &x0, &step, c0 * 1e-10, 400 * k as u64 + 400, 2);
    let b = to_b(&outcome.param);
    let (a, mse) = solve_amplitudes(&b, gm, samples).expect("the search ended at a finite cost");
    let band = Band { g_lo, g_hi, a, b };
    let errs = a_errors(|g| ExpPhase { bands: vec![band.clone()], scale: 1.0 }.terms(g), samples);
    BandFit { band, outcome, samples: samples.len(), rms_rel: mse.sqrt(), max_rel: airlight_truth::stats::rms_max(&errs).1 }
}

/// Starting decays for a `k`-term fit of a band: the paper's `b` at the band's
/// middle, spread by factors of 3 for further terms.
pub fn start_decays(band: usize, k: usize) -> Vec<f64> {
    let paper = ExpPhase::paper();
    let b = &paper.bands[band];
    let mid = 0.5 * (b.g_lo + b.g_hi);
    let b0 = quad_in(&b.b[0], mid).max(0.05);
    match k {
        1 => vec![b0],
        2 => vec![3.0 * b0, b0 / 3.0],
        _ => (0..k).map(|i| b0 * 3f64.powf(1.0 - 2.0 * i as f64 / (k - 1) as f64)).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_through_three_values() {
        let c = quad_through([0.2, 0.3, 0.4], [1.0, 4.0, 2.0]);
        for (g, v) in [(0.2, 1.0), (0.3, 4.0), (0.4, 2.0)] {
            assert!((quad_in(&c, g) - v).abs() < 1e-12);
        }
    }

    #[test]
    fn node_rule_reproduces_the_reference() {
        let s = phase_samples(0.0, 0.99, 60, 77);
        let e = node_rule_error(&s);
        assert!(e < 1e-6, "node rule error {e}");
    }

    #[test]
    fn mirror_and_paper_reading() {
        let p = ExpPhase::paper();
        let t = p.terms(0.0);
        assert!((t.eval(0.3) * 4.0 * PI - 1.0004 * (-0.0009f64 * 0.3).exp()).abs() < 1e-12);
        let pos = p.terms(0.7).eval(0.4);
        let neg = p.terms(-0.7).eval(PI - 0.4);
        assert!((pos - neg).abs() < 1e-15);
    }
}

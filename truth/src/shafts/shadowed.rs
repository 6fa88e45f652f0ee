//! The shadowed reference (`∫ v dC` over the exact lit intervals) and the shafts
//! accumulator in f64, run by run (the generated kernels carry the same in f32).

use super::*;
use crate::geometry::{cross, dot, norm, sub, Cone, GeometryError, PhysicalRay, Vec3};
use crate::reference::Point;

/// The in-scattering over the stretch `[a, b]` of `ray` (`b = ∞`: to infinity)
/// from a spot light of cone `cone` or a point light (`None`), `A` by `f`: the
/// viewer moved to `a`, times the transmittance `e^{−σt a}` of the part skipped.
pub fn run_radiance(
    ray: &PhysicalRay,
    cone: Option<&Cone>,
    g: f64,
    a: f64,
    b: f64,
    f: &dyn Fn(Point) -> f64,
) -> Result<f64, GeometryError> {
    if b.is_nan() || b <= a {
        return Ok(0.0);
    }
    let (moved, t) = ray.stretch(a, b);
    if t == 0.0 {
        return Ok(0.0);
    }
    let v = moved.light_radiance(cone, g, f)?;
    Ok(if v.is_infinite() { v } else { t * v })
}

/// The shadowed in-scattering of `ray` lit over `lit` (from [`lit_intervals`]):
/// the sum of the lit stretches' own in-scattering, `A` by `f` (the reference, or
/// a model).
pub fn shadowed_radiance(
    ray: &PhysicalRay,
    cone: Option<&Cone>,
    g: f64,
    lit: &[(f64, f64)],
    f: &dyn Fn(Point) -> f64,
) -> Result<f64, GeometryError> {
    let mut sum = 0.0;
    for &(a, b) in lit {
        sum += run_radiance(ray, cone, g, a, b, f)?;
    }
    Ok(sum)
}

/// A change of visibility not yet placed: between `lo` and `hi`, from `before`
/// to `after`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// The last sample before the change.
    pub lo: f64,
    /// The first sample after it.
    pub hi: f64,
    /// Visibility before.
    pub before: f64,
    /// Visibility after.
    pub after: f64,
}

/// The shafts accumulator, in f64 (the generated kernels' `Shafts` is the same in
/// f32): push `(s, v)` samples in increasing `s`; optionally refine each pending
/// change by bisection on the caller's visibility; finish at the ray's end.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Accumulator {
    /// Start of the current run of constant visibility.
    start: f64,
    /// Its visibility (`None` before the first sample).
    v: Option<f64>,
    /// The last sample's distance.
    s: f64,
    /// A change seen but not yet placed.
    pending: Option<Edge>,
    /// The runs' sum so far.
    sum: f64,
    /// Kernel evaluations so far (one per lit run).
    pub calls: usize,
}

impl Accumulator {
    /// An empty accumulator.
    pub fn new() -> Accumulator {
        Accumulator::default()
    }

    /// Adds the sample `(s, v)`; `run(a, b)` is the in-scattering of the stretch `[a, b]`.
    pub fn push(&mut self, s: f64, v: f64, run: &mut dyn FnMut(f64, Option<f64>) -> f64) {
        self.place(run);
        match self.v {
            None => self.v = Some(v),
            Some(cur) if v != cur => self.pending = Some(Edge { lo: self.s, hi: s, before: cur, after: v }),
            Some(_) => {}
        }
        self.s = s;
    }

    /// Where the caller should look up visibility to refine the pending change,
    /// if there is one.
    pub fn probe(&self) -> Option<f64> {
        self.pending.map(|e| 0.5 * (e.lo + e.hi))
    }

    /// Halves the pending change's bracket by the visibility `v` at [`probe`](Self::probe):
    /// the change lies on the side whose visibility differs more from `v`.
    pub fn refine(&mut self, v: f64) {
        if let Some(e) = self.pending.as_mut() {
            let m = 0.5 * (e.lo + e.hi);
            if (v - e.before).abs() <= (v - e.after).abs() {
                e.lo = m;
            } else {
                e.hi = m;
            }
        }
    }

    /// Places a pending change at its bracket's midpoint, closing the run before it.
    fn place(&mut self, run: &mut dyn FnMut(f64, Option<f64>) -> f64) {
        if let Some(e) = self.pending.take() {
            let m = 0.5 * (e.lo + e.hi);
            self.close(Some(m), e.before, run);
            self.start = m;
            self.v = Some(e.after);
        }
    }

    fn close(&mut self, end: Option<f64>, v: f64, run: &mut dyn FnMut(f64, Option<f64>) -> f64) {
        if v > 0.0 {
            self.sum += v * run(self.start, end);
            self.calls += 1;
        }
    }

    /// The shadowed in-scattering to the ray's end (`None`: an open ray, the last
    /// sample's visibility holding to infinity). Without samples: unshadowed.
    pub fn finish(mut self, end: Option<f64>, run: &mut dyn FnMut(f64, Option<f64>) -> f64) -> (f64, usize) {
        self.place(run);
        let v = self.v.unwrap_or(1.0);
        self.close(end, v, run);
        (self.sum, self.calls)
    }
}

/// The single-scattering integrand at distance `s` (unit direction `d`).
pub fn integrand(ray: &PhysicalRay, d: Vec3, g: f64, s: f64) -> f64 {
    let x = along(ray.origin, d, s);
    let r = sub(ray.light, x);
    let t = norm(r);
    if t == 0.0 {
        return f64::INFINITY;
    }
    // cos α = d · (light − x)/t: forward scattering looking at the light.
    let proj = dot(d, r);
    let h = norm(cross(d, r));
    let (om, op) = crate::phase::one_minus_plus_cos(proj, h, t);
    ray.sigma_s * ray.intensity * crate::phase::hg(g, om, op) * (-ray.sigma_t * (s + t)).exp() / (t * t)
}

//! Visibility sources: where a shadow map's samples fall along a view ray, the
//! exact boundaries, the engines' march with visibility, how the accumulator is
//! fed each of them ([`Feed`]), and the seed's per-frame table `F'`.

use super::*;
use crate::geometry::{cross, dot, norm, sub, Cone, GeometryError, PhysicalRay, Vec3};
use crate::reference::Point;

/// The samples a shadow map's look-ups give at the midpoints of `n` equal steps
/// to `len`: `(s_i, v_i)`.
pub fn samples(ray: &PhysicalRay, occluders: &[Occluder], n: usize, len: f64) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let s = (i as f64 + 0.5) * len / n as f64;
            (s, if visible(ray, occluders, s) { 1.0 } else { 0.0 })
        })
        .collect()
}

/// The samples that feed the accumulator the exact lit intervals: a sample on
/// each side of every boundary, at the boundary itself, so that each change is
/// placed exactly there.
pub fn exact_samples(ray: &PhysicalRay, lit: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let end = ray.surface_distance.unwrap_or(f64::INFINITY);
    let mut out = vec![(0.0, if lit.first().is_some_and(|&(a, _)| a <= 0.0) { 1.0 } else { 0.0 })];
    for &(a, b) in lit {
        if a > 0.0 {
            out.push((a, 0.0));
            out.push((a, 1.0));
        }
        if b < end {
            out.push((b, 1.0));
            out.push((b, 0.0));
        }
    }
    out
}

/// How far a march goes: the surface, or on an open ray the raymarch family's
/// stated cut-off ([`crate::geometry::march_end`], in light distances).
pub fn march_length(ray: &PhysicalRay, g: f64) -> Result<f64, GeometryError> {
    if let Some(s) = ray.surface_distance {
        return Ok(s);
    }
    let c = ray.to_canonical(g)?;
    Ok(crate::geometry::march_end(c.point.tau, c.point.gamma.cos()) * c.distance)
}

/// The engines' march with visibility: `Σ v_i W_i f(s_i) Δ_i` over the samples,
/// with `f` the exact single-scattering integrand (Henyey–Greenstein `g`), `W_i`
/// the cone's weight there (1 for a point light), and `Δ_i` the step each sample
/// stands for (`s_i` the midpoint of its step).
pub fn march(ray: &PhysicalRay, cone: Option<&Cone>, g: f64, samples: &[(f64, f64)]) -> f64 {
    let (d, _) = unit_and_end(ray);
    let mut sum = 0.0;
    let mut prev_end = 0.0;
    for &(s, v) in samples {
        let step = 2.0 * (s - prev_end);
        prev_end += step;
        let w = cone.map_or(1.0, |c| c.weight(sub(along(ray.origin, d, s), ray.light)));
        if v > 0.0 && w > 0.0 {
            sum += v * w * integrand(ray, d, g, s) * step;
        }
    }
    sum
}

/// How a shadowed ray's visibility reaches the accumulator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feed {
    /// The exact lit intervals ([`exact_samples`]).
    Exact,
    /// `n` shadow-map look-ups at the midpoints of `n` equal steps to the surface,
    /// or to the march's cut-off on an open ray ([`march_length`]), between the
    /// two visibilities a renderer already has ([`with_ends`]): the viewer's (one
    /// look-up per frame, the same for every pixel) and the surface's own (its
    /// direct light's shadow test). How the accumulator is fed.
    Samples(usize),
    /// The `n` look-ups alone: how `raymarch-N` looks visibility up at its own
    /// steps (its midpoint rule has no use for the ends), and the accumulator
    /// without the ends, for comparison.
    LookUps(usize),
}

/// The `(s, v)` samples of `feed` for `ray` among `occluders`.
pub fn feed(ray: &PhysicalRay, occluders: &[Occluder], g: f64, feed: Feed) -> Result<Vec<(f64, f64)>, GeometryError> {
    Ok(match feed {
        Feed::Exact => exact_samples(ray, &lit_intervals(ray, occluders)),
        Feed::Samples(n) => with_ends(ray, occluders, &samples(ray, occluders, n, march_length(ray, g)?)),
        Feed::LookUps(n) => samples(ray, occluders, n, march_length(ray, g)?),
    })
}

/// `samples` between the visibility at the viewer (`s = 0`) and, on a ray with a
/// surface, at the surface (taken a relative 1e-9 in front of it, as a shadow
/// test's bias would, so that the surface does not shadow itself). In dense
/// media most of the in-scattering lies within a free path of the viewer, before
/// the first look-up; without these two the accumulator extends the first and
/// the last look-up's visibility over it.
pub fn with_ends(ray: &PhysicalRay, occluders: &[Occluder], samples: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let v = |s: f64| if visible(ray, occluders, s) { 1.0 } else { 0.0 };
    let mut out = Vec::with_capacity(samples.len() + 2);
    out.push((0.0, v(0.0)));
    out.extend(samples.iter().copied().filter(|&(s, _)| s > 0.0));
    if let Some(end) = ray.surface_distance {
        if end > 0.0 {
            out.push((end, v(end * (1.0 - 1e-9))));
        }
    }
    out
}

/// The shadowed radiance of `ray` from `samples` in f64: the accumulator over the
/// lit runs with `A` by `f` (a model, or the reference), or — `march` — the
/// engines' march at the samples (each the midpoint of its step). Also returns the
/// kernel evaluations it took.
pub fn evaluate(
    ray: &PhysicalRay,
    cone: Option<&Cone>,
    g: f64,
    samples: &[(f64, f64)],
    f: &dyn Fn(Point) -> f64,
    march_rule: bool,
) -> Result<(f64, usize), GeometryError> {
    // The ray must define an in-scattering at all (the errors of `radiance`).
    ray.radiance(g, &|_| 0.0)?;
    if march_rule {
        return Ok((march(ray, cone, g, samples), samples.iter().filter(|x| x.1 > 0.0).count()));
    }
    let failed = std::cell::Cell::new(None);
    let mut run = |a: f64, b: Option<f64>| {
        run_radiance(ray, cone, g, a, b.unwrap_or(f64::INFINITY), f).unwrap_or_else(|e| {
            failed.set(Some(e));
            f64::NAN
        })
    };
    let mut acc = Accumulator::new();
    for &(s, v) in samples {
        acc.push(s, v, &mut run);
    }
    let out = acc.finish(ray.surface_distance, &mut run);
    match failed.get() {
        Some(e) => Err(e),
        None => Ok(out),
    }
}

/// Texels per side of the seed's per-frame table in the bench (its authors' 256²).
pub const FPRIME_RES: usize = 256;

/// The kernel that fills the seed's table in the bench.
pub const FPRIME_KERNEL: &str = "phi-6";

/// The seed's method (Wyman & Ramsey 2008, seed 004): a per-frame table
/// `F'(cos γ, x)` of the in-scattering from the viewer to distance `x` along a ray
/// at angle γ to the light, for one viewer and one light, `res × res` texels over
/// `cos γ ∈ [−1, 1]` and `x ∈ [0, x_max]`, filled by any evaluation of the
/// unshadowed in-scattering (a compute pass over an airlight kernel) and read
/// bilinearly; a ray's shadowed in-scattering is then `Σ v_i [F'(c, x_{i+1}) −
/// F'(c, x_i)]` over its steps — the difference form the seed itself notes is
/// unstable for small steps.
#[derive(Debug, Clone, PartialEq)]
pub struct FPrimeTable {
    /// Texels per side.
    pub res: usize,
    /// The far end of the `x` axis.
    pub x_max: f64,
    /// Row-major: row `j` at `x_j = x_max j/(res − 1)`, column `i` at
    /// `cos γ_i = −1 + 2 i/(res − 1)`.
    pub texels: Vec<f32>,
}

impl FPrimeTable {
    /// Builds the table for `viewer`, with `c(direction, x)` the unshadowed
    /// in-scattering of the ray from the viewer along `direction` to distance `x`
    /// (the frame's light, medium and phase inside it); `light` fixes γ.
    pub fn build(res: usize, viewer: Vec3, light: Vec3, x_max: f64, c: &dyn Fn(Vec3, f64) -> f64) -> FPrimeTable {
        let l = sub(light, viewer);
        let ln = norm(l);
        let lu = l.map(|v| v / ln);
        // A unit vector across the direction to the light.
        let helper = if lu[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
        let p = cross(lu, helper);
        let pn = norm(p);
        let pu = p.map(|v| v / pn);
        let mut texels = vec![0.0f32; res * res];
        for i in 0..res {
            let ci = -1.0 + 2.0 * i as f64 / (res - 1) as f64;
            let si = (1.0 - ci * ci).max(0.0).sqrt();
            let d = [0, 1, 2].map(|k| ci * lu[k] + si * pu[k]);
            for j in 0..res {
                let x = x_max * j as f64 / (res - 1) as f64;
                texels[j * res + i] = if j == 0 { 0.0 } else { c(d, x) as f32 };
            }
        }
        FPrimeTable { res, x_max, texels }
    }

    /// `F'(c, x)`, bilinear, clamped to the table.
    pub fn lookup(&self, c: f64, x: f64) -> f64 {
        let n = (self.res - 1) as f64;
        let u = ((c + 1.0) * 0.5 * n).clamp(0.0, n);
        let w = (x / self.x_max * n).clamp(0.0, n);
        let (i, j) = ((u.floor() as usize).min(self.res - 2), (w.floor() as usize).min(self.res - 2));
        let (tu, tw) = (u - i as f64, w - j as f64);
        let t = |i: usize, j: usize| f64::from(self.texels[j * self.res + i]);
        let lo = t(i, j) + tu * (t(i + 1, j) - t(i, j));
        let hi = t(i, j + 1) + tu * (t(i + 1, j + 1) - t(i, j + 1));
        lo + tw * (hi - lo)
    }

    /// The shadowed in-scattering of `ray` (from the table's viewer) with the
    /// visibility `samples` at the midpoints of equal steps: each step's
    /// visibility times the table's difference over the step.
    pub fn shadowed(&self, ray: &PhysicalRay, samples: &[(f64, f64)]) -> f64 {
        let (d, _) = unit_and_end(ray);
        let l = sub(ray.light, ray.origin);
        let c = dot(d, l) / norm(l);
        let mut sum = 0.0;
        let mut prev = 0.0;
        for &(s, v) in samples {
            let end = prev + 2.0 * (s - prev);
            if v > 0.0 {
                sum += v * (self.lookup(c, end) - self.lookup(c, prev));
            }
            prev = end;
        }
        sum
    }
}

//! Light shafts: the in-scattering along a view ray when opaque occluders stand
//! between the light and the medium (docs/MATH.md §8).
//!
//! With the visibility `v(s) ∈ [0, 1]` of the light from the point at distance `s`
//! along the ray, the shadowed in-scattering is `∫ v dC`, `C(s)` the unshadowed
//! in-scattering from the viewer to `s`. Visibility sampled at `s₁ < … < s_N` is
//! taken as constant between changes, each change placed between the samples
//! that straddle it (their midpoint, or where a bisection of the caller's
//! visibility puts it), so `∫ v dC = Σ_runs v_run · C[a, b]` over the runs of
//! constant visibility — the summation by parts `v_N C(end) + Σ (v_i − v_{i+1}) C(m_i)`
//! of the same sum, evaluated run by run. Each `C[a, b]` is the family's own
//! in-scattering of a ray whose viewer is moved to `a` (the phase angle at a point
//! does not depend on where the viewer stands), times `e^{−σt a}`: no difference
//! of two integrals is ever formed, dark runs cost nothing, and the result's
//! error is at most the family's bound times `C(end)` — with no growth in the
//! number of changes. This module holds the exact geometry (analytic occluders
//! and their lit intervals, found to double precision), the shadowed reference,
//! the accumulator in f64 (the generated kernels carry the same in f32), where a
//! shadow map's samples fall, and the engines' march with visibility.

use crate::geometry::{cross, dot, norm, sub, Cone, GeometryError, PhysicalRay, Vec3};
use crate::reference::Point;

fn along(o: Vec3, d: Vec3, s: f64) -> Vec3 {
    [o[0] + s * d[0], o[1] + s * d[1], o[2] + s * d[2]]
}

/// An opaque occluder.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Occluder {
    /// A ball.
    Sphere {
        /// Its centre.
        center: Vec3,
        /// Its radius (> 0).
        radius: f64,
    },
    /// An axis-aligned box.
    Cuboid {
        /// Its lowest corner.
        min: Vec3,
        /// Its highest corner.
        max: Vec3,
    },
}

impl Occluder {
    /// Whether the segment from `x` to `light` passes through the occluder's
    /// interior (grazing its boundary does not block).
    pub fn blocks(&self, x: Vec3, light: Vec3) -> bool {
        let e = sub(light, x);
        match *self {
            Occluder::Sphere { center, radius } => ball_blocks(center, radius, x, light),
            Occluder::Cuboid { min, max } => {
                let (mut lo, mut hi) = (0.0f64, 1.0f64);
                for i in 0..3 {
                    if e[i] == 0.0 {
                        if !(x[i] > min[i] && x[i] < max[i]) {
                            return false;
                        }
                    } else {
                        let (a, b) = ((min[i] - x[i]) / e[i], (max[i] - x[i]) / e[i]);
                        lo = lo.max(a.min(b));
                        hi = hi.min(a.max(b));
                    }
                }
                lo < hi
            }
        }
    }

    /// Whether `q` lies in the occluder (its boundary included).
    pub fn contains(&self, q: Vec3) -> bool {
        match *self {
            Occluder::Sphere { center, radius } => norm(sub(q, center)) <= radius,
            Occluder::Cuboid { min, max } => (0..3).all(|a| q[a] >= min[a] && q[a] <= max[a]),
        }
    }

    /// Where the ray `o + s d` (`d` a unit vector) first enters the occluder ahead
    /// of `o`, if it does.
    pub fn enters(&self, o: Vec3, d: Vec3) -> Option<f64> {
        match *self {
            Occluder::Sphere { center, radius } => {
                let (near, _) = ball_crossings(center, radius, o, d)?;
                (near > 0.0).then_some(near)
            }
            Occluder::Cuboid { min, max } => {
                let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
                for a in 0..3 {
                    if d[a] == 0.0 {
                        if o[a] <= min[a] || o[a] >= max[a] {
                            return None;
                        }
                    } else {
                        let (t1, t2) = ((min[a] - o[a]) / d[a], (max[a] - o[a]) / d[a]);
                        lo = lo.max(t1.min(t2));
                        hi = hi.min(t1.max(t2));
                    }
                }
                (lo < hi && lo > 0.0).then_some(lo)
            }
        }
    }

    /// Distances along the ray `o + s d` (`d` a unit vector) at which [`blocks`](Self::blocks)
    /// can change: a superset of the shadow's boundaries on the ray. A ball's
    /// shadow is bounded by the cone of tangents from the light and by the ball
    /// itself; a box's by the planes through the light and each of its 12 edges and
    /// by its 6 faces.
    pub fn candidates(&self, o: Vec3, d: Vec3, light: Vec3, out: &mut Vec<f64>) {
        match *self {
            Occluder::Sphere { center, radius } => {
                if let Some((a, b)) = ball_crossings(center, radius, o, d) {
                    out.extend([a, b]);
                }
                tangent_cone_cuts(center, radius, o, d, light, out);
            }
            Occluder::Cuboid { min, max } => {
                for i in 0..3 {
                    if d[i] != 0.0 {
                        out.push((min[i] - o[i]) / d[i]);
                        out.push((max[i] - o[i]) / d[i]);
                    }
                }
                let corner = |k: usize| [0, 1, 2].map(|i| if k >> i & 1 == 1 { max[i] } else { min[i] });
                for k in 0..8usize {
                    for i in 0..3 {
                        if k >> i & 1 == 0 {
                            let (p, q) = (corner(k), corner(k | 1 << i));
                            let n = cross(sub(p, light), sub(q, light));
                            let nd = dot(n, d);
                            if nd != 0.0 {
                                out.push(dot(n, sub(light, o)) / nd);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// `x · 2^k`, exactly wherever the result is a normal double.
fn ldexp(mut x: f64, mut k: i32) -> f64 {
    let step = |k: i32| f64::from_bits(((k + 1023) as u64) << 52);
    while k > 1000 {
        x *= step(1000);
        k -= 1000;
    }
    while k < -1000 {
        x *= step(-1000);
        k += 1000;
    }
    x * step(k)
}

/// The `k` with `m · 2^{−k}` in `[0.5, 1)`, for a finite `m > 0` (0 otherwise).
fn binade(m: f64) -> i32 {
    if !(m > 0.0 && m.is_finite()) {
        0
    } else if m < f64::MIN_POSITIVE {
        binade(m * ldexp(1.0, 600)) - 600
    } else {
        ((m.to_bits() >> 52) & 0x7ff) as i32 - 1022
    }
}

fn scaled(v: Vec3, k: i32) -> Vec3 {
    v.map(|x| ldexp(x, -k))
}

/// `a b − c d` to a few ulps even where the products cancel (Kahan's algorithm).
fn diff_of_products(a: f64, b: f64, c: f64, d: f64) -> f64 {
    let w = c * d;
    let err = (-c).mul_add(d, w);
    a.mul_add(b, -w) + err
}

/// `a × b` to a few ulps per component, however nearly parallel `a` and `b` are.
fn cross_accurate(a: Vec3, b: Vec3) -> Vec3 {
    [
        diff_of_products(a[1], b[2], a[2], b[1]),
        diff_of_products(a[2], b[0], a[0], b[2]),
        diff_of_products(a[0], b[1], a[1], b[0]),
    ]
}

/// Where the line `o + s d` (`d` a unit vector) meets the ball, `(near, far)`.
/// Worked in a frame scaled by a power of two, so that no square overflows or
/// underflows at any finite size.
fn ball_crossings(center: Vec3, radius: f64, o: Vec3, d: Vec3) -> Option<(f64, f64)> {
    let w = sub(o, center);
    let k = binade(norm(w).max(radius));
    let (w, r) = (scaled(w, k), ldexp(radius, -k));
    let b = dot(w, d);
    let nw = norm(w);
    let disc = b * b - (nw - r) * (nw + r);
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let q = -(b + b.signum() * disc.sqrt());
    let (x, y) = if q == 0.0 { (0.0, 0.0) } else { (q, (nw - r) * (nw + r) / q) };
    Some((ldexp(x.min(y), k), ldexp(x.max(y), k)))
}

/// Whether the segment from `x` to `light` passes through the ball's interior
/// (touching its surface does not block; a light or a point inside it is blocked).
/// Decided where it is well conditioned: a thin shadow cone (ball small against its
/// distance) by the cross product `|u × e| < r |e|` (each factor scaled by a power of
/// two, the cross product free of cancellation), a wide one (light near or on the
/// surface) by `(u·ê)² > (|u| − r)(|u| + r)`, which is exact in its sign when the
/// light is on the surface.
fn ball_blocks(center: Vec3, radius: f64, x: Vec3, light: Vec3) -> bool {
    let u = sub(center, light);
    let du = norm(u);
    if du < radius || norm(sub(x, center)) < radius {
        return true;
    }
    let e = sub(x, light);
    let de = norm(e);
    if de == 0.0 {
        return false;
    }
    let (ku, ke) = (binade(du), binade(de));
    let (us, rs, dus) = (scaled(u, ku), ldexp(radius, -ku), ldexp(du, -ku));
    let (es, des) = (scaled(e, ke), ldexp(de, -ke));
    // u·ê in the scaled frame of u: the foot of the perpendicular from the centre.
    let foot = dot(us, es) / des;
    if !(foot > 0.0 && foot < ldexp(des, ke - ku)) {
        return false; // the closest point is an end, and both ends are outside
    }
    if rs < 0.5 * dus {
        norm(cross_accurate(us, es)) < rs * des
    } else {
        foot * foot > (dus - rs) * (dus + rs)
    }
}

/// The cuts of a ball's tangent cone from the light on the ray `o + s d`: the roots
/// of `(|u|² − r²) |P × u|² = r² (P·u)²`, `P` the ray's point from the light and
/// `u` the light-to-centre vector — both nappes, so a superset. Formed from
/// cancellation-free cross products in power-of-two-scaled frames, so that a
/// ball 1e-12 of its distance across keeps its cone, and a light on the surface
/// (`|u| = r`) gives the tangent plane `P·u = 0`. Where the discriminant is
/// negative the ray's closest approach is pushed instead (a harmless extra cut).
fn tangent_cone_cuts(center: Vec3, radius: f64, o: Vec3, d: Vec3, light: Vec3, out: &mut Vec<f64>) {
    let u = sub(center, light);
    let du = norm(u);
    if du.is_nan() || du < radius {
        return; // the light is inside: the ball's own surface bounds the shadow
    }
    let ku = binade(du);
    let (u, r, du) = (scaled(u, ku), ldexp(radius, -ku), ldexp(du, -ku));
    let w = sub(o, light);
    let kw = binade(norm(w));
    let w = scaled(w, kw);
    let (c, s) = ((du - r) * (du + r), r * r);
    let (x0, x1) = (cross_accurate(w, u), cross_accurate(d, u));
    let (y0, y1) = (dot(w, u), dot(d, u));
    let a = c * dot(x1, x1) - s * y1 * y1;
    let b = c * dot(x0, x1) - s * y0 * y1;
    let cc = c * dot(x0, x0) - s * y0 * y0;
    let disc = b * b - a * cc;
    if disc.is_nan() || disc < 0.0 {
        if a != 0.0 {
            out.push(ldexp(-b / a, kw));
        }
        return;
    }
    let q = -(b + b.signum() * disc.sqrt());
    if a != 0.0 {
        out.push(ldexp(q / a, kw));
    }
    if q != 0.0 {
        out.push(ldexp(cc / q, kw));
    }
}

/// Reads occluders written as `cx cy cz r` quadruples (balls) separated by `;`;
/// empty for none. The error names the quadruple (1-based) and what is wrong.
pub fn parse_spheres(text: &str) -> Result<Vec<Occluder>, String> {
    let mut out = Vec::new();
    for (k, item) in text.split(';').enumerate() {
        if item.trim().is_empty() {
            if text.trim().is_empty() {
                continue;
            }
            return Err(format!("sphere {} is empty (write cx cy cz r; separated by ';')", k + 1));
        }
        let v: Vec<&str> = item.split_whitespace().collect();
        if v.len() != 4 {
            return Err(format!("sphere {} '{}' has {} numbers, not 4 (cx cy cz r)", k + 1, item.trim(), v.len()));
        }
        let mut x = [0.0; 4];
        for (j, t) in v.iter().enumerate() {
            x[j] = t
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("sphere {}: '{t}' is not a finite number", k + 1))?;
        }
        if x[3] <= 0.0 {
            return Err(format!("sphere {}: radius {} must be > 0", k + 1, v[3]));
        }
        out.push(Occluder::Sphere { center: [x[0], x[1], x[2]], radius: x[3] });
    }
    Ok(out)
}

/// Writes balls as [`parse_spheres`] reads them (round-trip precision).
pub fn render_spheres(occluders: &[Occluder]) -> String {
    occluders
        .iter()
        .filter_map(|o| match o {
            Occluder::Sphere { center: c, radius: r } => Some(format!("{:?} {:?} {:?} {:?}", c[0], c[1], c[2], r)),
            Occluder::Cuboid { .. } => None,
        })
        .collect::<Vec<_>>()
        .join(";")
}

/// The unit direction and the far end (`∞` without a surface) of a ray.
fn unit_and_end(ray: &PhysicalRay) -> (Vec3, f64) {
    let n = norm(ray.direction);
    (ray.direction.map(|x| x / n), ray.surface_distance.unwrap_or(f64::INFINITY))
}

/// Whether the light is visible from the point at distance `s` along `ray`.
pub fn visible(ray: &PhysicalRay, occluders: &[Occluder], s: f64) -> bool {
    let (d, _) = unit_and_end(ray);
    let x = along(ray.origin, d, s);
    !occluders.iter().any(|o| o.blocks(x, ray.light))
}

/// The lit intervals `[a, b]` of `ray` between the viewer and its surface (`b = ∞`
/// on an open ray), in order and disjoint. The candidates of every occluder cut
/// the ray into pieces of constant visibility, each classified at its midpoint;
/// every boundary between a lit and a dark piece is then bisected on the exact
/// visibility test to adjacent doubles.
pub fn lit_intervals(ray: &PhysicalRay, occluders: &[Occluder]) -> Vec<(f64, f64)> {
    let (d, end) = unit_and_end(ray);
    let mut cuts = Vec::new();
    for o in occluders {
        o.candidates(ray.origin, d, ray.light, &mut cuts);
    }
    cuts.retain(|&s| s.is_finite() && s > 0.0 && s < end);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let far = cuts.last().map_or(1.0, |&c| 2.0 * c + 1.0);
    let mut edges = vec![0.0];
    edges.extend(&cuts);
    edges.push(end);
    let mid = |a: f64, b: f64| if b.is_finite() { 0.5 * (a + b) } else { far.max(a + 1.0) };
    let lit: Vec<bool> = edges.windows(2).map(|w| visible(ray, occluders, mid(w[0], w[1]))).collect();
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut start: Option<f64> = None;
    for (i, w) in edges.windows(2).enumerate() {
        if lit[i] && start.is_none() {
            start = Some(if i == 0 { 0.0 } else { boundary(ray, occluders, mid(edges[i - 1], w[0]), mid(w[0], w[1])) });
        }
        let closes = lit[i] && (i + 1 == lit.len() || !lit[i + 1]);
        if closes {
            let b = if i + 1 == lit.len() {
                end
            } else {
                boundary(ray, occluders, mid(w[0], w[1]), mid(w[1], edges[i + 2]))
            };
            out.push((start.take().unwrap_or(0.0), b));
        }
    }
    out.retain(|&(a, b)| b > a);
    out
}

/// The point between `a` and `b` where visibility changes, to adjacent doubles.
fn boundary(ray: &PhysicalRay, occluders: &[Occluder], mut a: f64, mut b: f64) -> f64 {
    let va = visible(ray, occluders, a);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if visible(ray, occluders, m) == va {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference;

    fn ray(surface: Option<f64>) -> PhysicalRay {
        PhysicalRay {
            origin: [0.0, 0.0, 0.0],
            direction: [1.0, 0.05, 0.0],
            surface_distance: surface,
            light: [6.0, 2.0, 0.5],
            intensity: 3.0,
            sigma_t: 0.12,
            sigma_s: 0.08,
        }
    }

    fn scene() -> Vec<Occluder> {
        vec![
            Occluder::Sphere { center: [3.0, 1.2, 0.3], radius: 0.35 },
            Occluder::Sphere { center: [7.0, 1.6, 0.4], radius: 0.25 },
            Occluder::Cuboid { min: [9.0, 1.0, -0.5], max: [9.4, 1.5, 1.5] },
        ]
    }

    #[test]
    fn boundaries_are_where_visibility_changes() {
        let r = ray(Some(25.0));
        let lit = lit_intervals(&r, &scene());
        assert!(lit.len() >= 2 && lit[0].0 > 0.0, "{lit:?}");
        for &(a, b) in &lit {
            assert!(visible(&r, &scene(), 0.5 * (a + b)));
            for &x in &[a, b] {
                if x > 0.0 && x < 25.0 {
                    let eps = 1e-12 * x.max(1.0);
                    assert_ne!(visible(&r, &scene(), x - eps), visible(&r, &scene(), x + eps), "boundary at {x}");
                }
            }
        }
    }

    #[test]
    fn sampled_feeds_add_the_viewers_and_the_surfaces_visibility() {
        // A ball over the viewer's end of the ray: dark from 0, lit later.
        let occ = vec![Occluder::Sphere { center: [0.6, 0.4, 0.0], radius: 0.3 }];
        let r = ray(Some(25.0));
        let look = feed(&r, &occ, 0.0, Feed::LookUps(8)).unwrap();
        let fed = feed(&r, &occ, 0.0, Feed::Samples(8)).unwrap();
        assert_eq!(look.len(), 8);
        assert_eq!(fed.len(), 10);
        assert_eq!(&fed[1..9], &look[..]);
        assert_eq!(fed[0], (0.0, if visible(&r, &occ, 0.0) { 1.0 } else { 0.0 }));
        assert_eq!(fed[9], (25.0, 1.0));
        // An open ray has no surface to add.
        let open = feed(&ray(None), &occ, 0.0, Feed::Samples(8)).unwrap();
        assert_eq!(open.len(), 9);
        assert_eq!(open[0].0, 0.0);
    }

    /// Against an independent evaluation: adaptive quadrature of `v(s) f(s)` over
    /// the ray with the boundaries as breakpoints.
    #[test]
    fn the_reference_is_the_integral_of_visibility_times_the_integrand() {
        let a = |p: Point| reference::airlight(p).unwrap();
        for g in [0.0, 0.6, -0.4] {
            for surface in [Some(25.0), None] {
                let r = ray(surface);
                let occ = scene();
                let lit = lit_intervals(&r, &occ);
                let want = shadowed_radiance(&r, None, g, &lit, &a).unwrap();
                let (d, _) = unit_and_end(&r);
                let far = surface.unwrap_or(400.0);
                let mut breaks = vec![0.0];
                for &(x, y) in &lit {
                    breaks.push(x);
                    breaks.push(y.min(far));
                }
                breaks.push(far);
                breaks.sort_by(f64::total_cmp);
                let q = crate::quad::gauss_kronrod(
                    |s| if visible(&r, &occ, s) { integrand(&r, d, g, s) } else { 0.0 },
                    &breaks,
                    1e-12,
                    4000,
                );
                assert!(((q.value - want) / want).abs() < 1e-9, "g {g}, {surface:?}: {} vs {want}", q.value);
                // The accumulator fed the exact intervals is the same sum.
                let mut acc = Accumulator::new();
                let mut run =
                    |x: f64, y: Option<f64>| run_radiance(&r, None, g, x, y.unwrap_or(f64::INFINITY), &a).unwrap();
                for (s, v) in exact_samples(&r, &lit) {
                    acc.push(s, v, &mut run);
                }
                let (got, calls) = acc.finish(surface, &mut run);
                assert!(((got - want) / want).abs() < 1e-13, "{got} vs {want}");
                assert_eq!(calls, lit.len());
            }
        }
    }

    #[test]
    fn refinement_places_a_change_by_bisection() {
        let r = ray(Some(25.0));
        let occ = scene();
        let lit = lit_intervals(&r, &occ);
        let a = |p: Point| reference::airlight(p).unwrap();
        let want = shadowed_radiance(&r, None, 0.3, &lit, &a).unwrap();
        let mut run = |x: f64, y: Option<f64>| run_radiance(&r, None, 0.3, x, y.unwrap_or(f64::INFINITY), &a).unwrap();
        let err = |k: usize, run: &mut dyn FnMut(f64, Option<f64>) -> f64| {
            let mut acc = Accumulator::new();
            for (s, v) in samples(&r, &occ, 16, 25.0) {
                acc.push(s, v, run);
                for _ in 0..k {
                    let Some(m) = acc.probe() else { break };
                    acc.refine(if visible(&r, &occ, m) { 1.0 } else { 0.0 });
                }
            }
            ((acc.finish(Some(25.0), run).0 - want) / want).abs()
        };
        let (e0, e20) = (err(0, &mut run), err(20, &mut run));
        assert!(e20 < 1e-5 && e20 < e0 / 10.0, "unrefined {e0:.2e}, refined {e20:.2e}");
    }

    /// The seed's table reproduces the reference where it is fine enough, and
    /// its error is the table's (interpolation), not the sampling's.
    #[test]
    fn the_seeds_table_is_the_in_scattering_it_was_built_from() {
        let a = |p: Point| reference::airlight(p).unwrap();
        let r = ray(Some(25.0));
        let g = 0.3;
        let fill =
            |d: Vec3, x: f64| PhysicalRay { direction: d, surface_distance: Some(x), ..r }.radiance(g, &a).unwrap();
        let table = FPrimeTable::build(256, r.origin, r.light, 25.0, &fill);
        let occ = scene();
        let exact = shadowed_radiance(&r, None, g, &lit_intervals(&r, &occ), &a).unwrap();
        let s = samples(&r, &occ, 64, 25.0);
        let (acc, _) = evaluate(&r, None, g, &s, &a, false).unwrap();
        let via_table = table.shadowed(&r, &s);
        // Same samples, same edges: the table adds only its interpolation error.
        assert!(((via_table - acc) / acc).abs() < 2e-2, "table {via_table}, accumulator {acc}, exact {exact}");
        let unshadowed = r.radiance(g, &a).unwrap();
        assert!(
            ((table.lookup(dot(unit_and_end(&r).0, sub(r.light, r.origin)) / norm(sub(r.light, r.origin)), 25.0)
                - unshadowed)
                / unshadowed)
                .abs()
                < 2e-2
        );
    }

    #[test]
    fn spheres_parse_and_refuse() {
        let s = parse_spheres("1 2 3 0.5; -1e3 0 2.5 4").unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(parse_spheres(&render_spheres(&s)).unwrap(), s);
        assert!(parse_spheres("").unwrap().is_empty());
        assert!(parse_spheres("1 2 3").unwrap_err().contains("4"));
        assert!(parse_spheres("1 2 3 -1").unwrap_err().contains("radius"));
        assert!(parse_spheres("1 2 3 x").unwrap_err().contains("'x'"));
        assert!(parse_spheres("1 2 3 1;;").unwrap_err().contains("empty"));
    }

    /// Issue 37's rays: `(origin, direction, light, σt, g, ball, mpmath's value)`;
    /// σs = σt, intensity 1, no surface.
    type Probe = (Vec3, Vec3, Vec3, f64, f64, (Vec3, f64), f64);
    const PROBES: [Probe; 6] = [
        // The light on the ball's surface (tangent plane x = 0).
        ([-1.0, 5.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3], 0.1, 0.0, ([1.0, 0.0, 0.0], 1.0), 1.80666e-4),
        ([-1.0, 5.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3], 0.1, 0.5, ([3.0, 0.0, 4.0], 5.0), 1.10352e-4),
        // Tiny occluders 1e6 away (r/d = 1e-9, 1e-10): lit edges at 499.745 and 1500.755.
        ([1000010.0, 0.002, 0.0], [1.0, -2e-6, 0.0], [0.0; 3], 1e-4, 0.0, ([1e6, 0.0, 0.0], 1e-3), 1.22181e-57),
        ([1000010.0, 0.002, 0.0], [1.0, -2e-6, 0.0], [0.0; 3], 1e-4, 0.0, ([1e6, 0.0, 0.0], 1e-4), 1.43990e-57),
        // r² beyond f64's range: the viewer inside a ball 2e200 across; a light inside one 1e-300 across.
        ([0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0.1, 0.0, ([1.9e200, 0.0, 0.0], 2e200), 0.0),
        ([0.0; 3], [1.0, 0.0, 0.0], [5.0, 1.0, 0.0], 0.1, 0.0, ([5.0, 1.0, 0.0], 1e-300), 0.0),
    ];

    #[test]
    fn lights_on_surfaces_and_balls_of_any_size_cast_their_shadows() {
        for (o, d, l, st, g, (c, r), want) in PROBES {
            let ray = PhysicalRay {
                origin: o,
                direction: d,
                surface_distance: None,
                light: l,
                intensity: 1.0,
                sigma_t: st,
                sigma_s: st,
            };
            let occ = [Occluder::Sphere { center: c, radius: r }];
            let lit = lit_intervals(&ray, &occ);
            let got = shadowed_radiance(&ray, None, g, &lit, &|p| reference::airlight(p).unwrap()).unwrap();
            let err = if want == 0.0 { got } else { (got / want - 1.0).abs() };
            assert!(err < 1e-5, "ball {c:?} r {r}: {got:e} against {want:e} (lit {lit:?})");
        }
    }

    #[test]
    fn a_ball_blocks_exactly_what_its_tangent_cone_holds() {
        // A light on the surface shadows the whole half-space behind its tangent
        // plane, to within a few ulps of the plane.
        let (c, r, l) = ([3.0, 0.0, 4.0], 5.0, [0.0; 3]);
        let ball = Occluder::Sphere { center: c, radius: r };
        for x in [1e-6, 1e-3, 1.0, 1e6] {
            // n = c / 5 is the plane's normal; p ⟂ n.
            let p = [4.0, 7.0, -3.0];
            let side = |t: f64| [p[0] + t * 0.6, p[1], p[2] + t * 0.8];
            assert!(ball.blocks(side(x), l), "{x}");
            assert!(!ball.blocks(side(-x), l), "{x}");
        }
        // A ball 1e-12 of its distance across: its shadow's radius to 1e-9 relative.
        let (c, r) = ([1e6, 0.0, 0.0], 1e-6);
        let ball = Occluder::Sphere { center: c, radius: r };
        let x = 3e6; // 3 light distances behind: the shadow's radius is 3 r / sqrt(1 − (r/d)²).
        let edge = 3.0 * r;
        assert!(ball.blocks([x, edge * (1.0 - 1e-9), 0.0], [0.0; 3]));
        assert!(!ball.blocks([x, edge * (1.0 + 1e-9), 0.0], [0.0; 3]));
    }
}

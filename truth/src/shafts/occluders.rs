//! The exact geometry of light shafts: analytic occluders (balls, cones), whether
//! one blocks the segment from a point to the light, and the lit intervals of a
//! view ray, found to double precision (docs/MATH.md §8).

use crate::geometry::{cross, dot, norm, sub, PhysicalRay, Vec3};

pub(crate) fn along(o: Vec3, d: Vec3, s: f64) -> Vec3 {
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
    /// Whether the segment from `x` to `light` crosses the occluder's boundary:
    /// the occluder is a closed opaque surface, as a renderer's closed mesh is
    /// (docs/MATH.md §8). A point and a light both inside it see each other (a
    /// lamp in a room); one inside and one outside do not; a light on the
    /// surface lights the inside and the outside in front of its tangent plane;
    /// grazing the boundary does not block.
    pub fn blocks(&self, x: Vec3, light: Vec3) -> bool {
        let (xin, lin) = (self.strictly_inside(x), self.strictly_inside(light));
        if xin || lin {
            // From inside, the segment leaves through the boundary iff the other
            // end is strictly outside (a convex occluder).
            return xin != lin && !self.contains(if xin { light } else { x });
        }
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

    /// Whether `q` lies in the occluder's interior (its boundary excluded).
    pub fn strictly_inside(&self, q: Vec3) -> bool {
        match *self {
            Occluder::Sphere { center, radius } => norm(sub(q, center)) < radius,
            Occluder::Cuboid { min, max } => (0..3).all(|a| q[a] > min[a] && q[a] < max[a]),
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
                let (lo, _) = box_crossings(min, max, o, d, false)?;
                (lo > 0.0).then_some(lo)
            }
        }
    }

    /// Where the ray `o + s d` (`d` a unit vector) first crosses the occluder's
    /// boundary ahead of `o` (`s > 0`), entering or leaving: what a depth pass
    /// without face culling records for a light at `o` — the far side when the
    /// light is on the surface or inside, so that neither lets light out.
    pub fn boundary_ahead(&self, o: Vec3, d: Vec3) -> Option<f64> {
        let first = |near: f64, far: f64| {
            if near > 0.0 {
                Some(near)
            } else {
                (far > 0.0).then_some(far)
            }
        };
        match *self {
            Occluder::Sphere { center, radius } => {
                let (near, far) = ball_crossings(center, radius, o, d)?;
                first(near, far)
            }
            Occluder::Cuboid { min, max } => {
                let (lo, hi) = box_crossings(min, max, o, d, true)?;
                first(lo, hi)
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
pub(crate) fn ldexp(mut x: f64, mut k: i32) -> f64 {
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
pub(crate) fn binade(m: f64) -> i32 {
    if !(m > 0.0 && m.is_finite()) {
        0
    } else if m < f64::MIN_POSITIVE {
        binade(m * ldexp(1.0, 600)) - 600
    } else {
        ((m.to_bits() >> 52) & 0x7ff) as i32 - 1022
    }
}

pub(crate) fn scaled(v: Vec3, k: i32) -> Vec3 {
    v.map(|x| ldexp(x, -k))
}

/// `a b − c d` to a few ulps even where the products cancel (Kahan's algorithm).
pub(crate) fn diff_of_products(a: f64, b: f64, c: f64, d: f64) -> f64 {
    let w = c * d;
    let err = (-c).mul_add(d, w);
    a.mul_add(b, -w) + err
}

/// `a × b` to a few ulps per component, however nearly parallel `a` and `b` are.
pub(crate) fn cross_accurate(a: Vec3, b: Vec3) -> Vec3 {
    [
        diff_of_products(a[1], b[2], a[2], b[1]),
        diff_of_products(a[2], b[0], a[0], b[2]),
        diff_of_products(a[0], b[1], a[1], b[0]),
    ]
}

/// Where the line `o + s d` meets the box, `(near, far)` (slab by slab; `near`
/// may be behind `o`). A line parallel to a pair of faces and lying in one of
/// their planes meets the box if `touching`, and misses it otherwise.
fn box_crossings(min: Vec3, max: Vec3, o: Vec3, d: Vec3, touching: bool) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for a in 0..3 {
        if d[a] == 0.0 {
            let outside = if touching { o[a] < min[a] || o[a] > max[a] } else { o[a] <= min[a] || o[a] >= max[a] };
            if outside {
                return None;
            }
        } else {
            let (t1, t2) = ((min[a] - o[a]) / d[a], (max[a] - o[a]) / d[a]);
            lo = lo.max(t1.min(t2));
            hi = hi.min(t1.max(t2));
        }
    }
    (lo < hi).then_some((lo, hi))
}

/// Where the line `o + s d` (`d` a unit vector) meets the ball, `(near, far)`.
/// Worked in a frame scaled by a power of two, so that no square overflows or
/// underflows at any finite size.
pub(crate) fn ball_crossings(center: Vec3, radius: f64, o: Vec3, d: Vec3) -> Option<(f64, f64)> {
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

/// Whether the segment from `x` to `light`, both outside the ball's interior,
/// passes through it (touching its surface does not block).
/// Decided where it is well conditioned: a thin shadow cone (ball small against its
/// distance) by the cross product `|u × e| < r |e|` (each factor scaled by a power of
/// two, the cross product free of cancellation), a wide one (light near or on the
/// surface) by `(u·ê)² > (|u| − r)(|u| + r)`, which is exact in its sign when the
/// light is on the surface.
pub(crate) fn ball_blocks(center: Vec3, radius: f64, x: Vec3, light: Vec3) -> bool {
    let u = sub(center, light);
    let du = norm(u);
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
pub(crate) fn tangent_cone_cuts(center: Vec3, radius: f64, o: Vec3, d: Vec3, light: Vec3, out: &mut Vec<f64>) {
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
pub(crate) fn unit_and_end(ray: &PhysicalRay) -> (Vec3, f64) {
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
    let mid = |a: f64, b: f64| if b.is_finite() { a + 0.5 * (b - a) } else { far.max(a + 1.0) };
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

/// The point between `a` and `b` (`0 ≤ a < b`, finite) where visibility changes,
/// to adjacent doubles: bisected on the doubles' ordering (their bit patterns),
/// so that it ends in at most 64 steps at any scale — a surface at 1e300 as at 20.
pub(crate) fn boundary(ray: &PhysicalRay, occluders: &[Occluder], a: f64, b: f64) -> f64 {
    let va = visible(ray, occluders, a);
    let (mut lo, mut hi) = (a.max(0.0).to_bits(), b.max(0.0).to_bits());
    while hi > lo + 1 {
        let m = lo + (hi - lo) / 2;
        if visible(ray, occluders, f64::from_bits(m)) == va {
            lo = m;
        } else {
            hi = m;
        }
    }
    let (x, y) = (f64::from_bits(lo), f64::from_bits(hi));
    x + 0.5 * (y - x)
}

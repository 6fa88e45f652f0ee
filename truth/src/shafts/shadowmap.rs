//! A shadow map as a renderer has one, and its exact lit runs along a view ray:
//! the reference the generated traversal (`shafts/shadowmap.*.tera`) is held to.
//!
//! A map is one perspective face (a spot light) or six 90° faces (a point light's
//! cube map, in the OpenGL face order and orientation). A face has rows
//! `right/tan_half`, `up/tan_half`, `forward`: a point `p` maps to
//! `(X, Y, Z) = M (p − light)`, its map coordinates are `(X/Z, Y/Z) ∈ [−1, 1]²`
//! and its depth is the linear `Z` (distance along the face's axis). Each texel
//! stores the depth of the first occluder along its centre ray (`f32::MAX`: none),
//! and the nearest-texel test says a point is lit iff `Z ≤ depth + bias`.
//!
//! Along a view ray `p(t) = o + t d` the face coordinates are affine in `t`, so the
//! map coordinates are fractional-linear (monotone) and `Z` is affine: inside one
//! texel the test flips at most once, at `t* = (depth + bias − Z(o))/Z'`.
//! [`ShadowMap::lit_runs`] finds every texel the ray crosses (every texel
//! boundary's crossing, solved directly), classifies each piece by its texel and
//! splits it at its flip: the exact runs of the map's own visibility, in f64.
//! The traversal of the min-max [`Pyramid`] in the kernels finds the same runs
//! by skipping whole nodes; only f32 rounding of the crossings differs.

use super::Occluder;
use crate::geometry::{cross, dot, norm, sub, PhysicalRay, Vec3};
use std::fmt;

/// No occluder along a texel's centre ray.
pub const NO_OCCLUDER: f32 = f32::MAX;

/// The largest map side the traversal takes (2¹³ texels).
pub const MAX_RES: usize = 8192;

/// The cube map's faces (+X, −X, +Y, −Y, +Z, −Z) as `(right, up, forward)`, the
/// orientation of OpenGL's cube map (`s = −z, t = −y` on +X, and so on).
pub const CUBE_FACES: [[Vec3; 3]; 6] = [
    [[0.0, 0.0, -1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]],
    [[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [-1.0, 0.0, 0.0]],
    [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, -1.0, 0.0]],
    [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]],
    [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
];

/// A map that cannot be made.
#[derive(Debug, Clone, PartialEq)]
pub struct MapError(pub String);

impl fmt::Display for MapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for MapError {}

/// One perspective face: `rows = [right/tan_half, up/tan_half, forward]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Face {
    /// The rows of `M`.
    pub rows: [Vec3; 3],
}

impl Face {
    fn new(right: Vec3, up: Vec3, forward: Vec3, tan_half: f64) -> Face {
        Face { rows: [right.map(|x| x / tan_half), up.map(|x| x / tan_half), forward] }
    }

    /// `M q`.
    pub fn apply(&self, q: Vec3) -> Vec3 {
        [dot(self.rows[0], q), dot(self.rows[1], q), dot(self.rows[2], q)]
    }

    /// The stretch of `t ∈ [t0, t1]` where `Z ≥ |X|` and `Z ≥ |Y|` (inside the
    /// face's frustum) for the face coordinates `a + t b`; `None` if empty.
    pub fn clip(&self, a: Vec3, b: Vec3, t0: f64, t1: f64) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (t0, t1);
        for (s, k) in [(1.0, 0), (-1.0, 0), (1.0, 1), (-1.0, 1)] {
            // Z − s·X_k ≥ 0, affine in t: c0 + t c1.
            let (c0, c1) = (a[2] - s * a[k], b[2] - s * b[k]);
            if c1 == 0.0 {
                if c0 < 0.0 {
                    return None;
                }
            } else if c1 > 0.0 {
                lo = lo.max(-c0 / c1);
            } else {
                hi = hi.min(-c0 / c1);
            }
        }
        (lo < hi).then_some((lo, hi))
    }
}

/// A shadow map: its faces, `res × res` depths per face, row-major (`j` the row,
/// from map coordinate −1), and the depth bias of its test.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadowMap {
    /// The light's position.
    pub light: Vec3,
    /// One face (spot) or six (cube).
    pub faces: Vec<Face>,
    /// Texels per side, a power of two.
    pub res: usize,
    /// `faces × res × res` depths.
    pub depth: Vec<f32>,
    /// The test's bias, in depth units.
    pub bias: f64,
}

impl ShadowMap {
    /// A point light's cube map of `res²` texels per face among `occluders`.
    pub fn cube(light: Vec3, res: usize, occluders: &[Occluder], bias: f64) -> Result<ShadowMap, MapError> {
        let faces = CUBE_FACES.iter().map(|f| Face::new(f[0], f[1], f[2], 1.0)).collect();
        ShadowMap::cast(light, faces, res, occluders, bias)
    }

    /// A map whose faces have the given rows of `M` (`right/tan_half`,
    /// `up/tan_half`, `forward`): a renderer's own orientation of its faces, so
    /// that its rasterised map can be held texel by texel against this one. Six
    /// faces make a cube map ([`ShadowMap::is_cube`]: give them in
    /// [`CUBE_FACES`]' order).
    pub fn from_rows(
        light: Vec3,
        rows: &[[Vec3; 3]],
        res: usize,
        occluders: &[Occluder],
        bias: f64,
    ) -> Result<ShadowMap, MapError> {
        if rows.len() != 1 && rows.len() != 6 {
            return Err(MapError(format!("shadow map: {} faces; give one (a spot) or six (a cube)", rows.len())));
        }
        ShadowMap::cast(light, rows.iter().map(|&rows| Face { rows }).collect(), res, occluders, bias)
    }

    /// A spot light's map: one face along `axis` with half-angle `atan(tan_half)`.
    pub fn spot(
        light: Vec3,
        axis: Vec3,
        tan_half: f64,
        res: usize,
        occluders: &[Occluder],
        bias: f64,
    ) -> Result<ShadowMap, MapError> {
        let n = norm(axis);
        if !(n > 0.0 && n.is_finite()) {
            return Err(MapError(format!("spot map: axis {axis:?} has no direction")));
        }
        if !(tan_half > 0.0 && tan_half.is_finite()) {
            return Err(MapError(format!("spot map: tan_half {tan_half} is not a positive number")));
        }
        let forward = axis.map(|x| x / n);
        let (right, up) = basis(forward);
        ShadowMap::cast(light, vec![Face::new(right, up, forward, tan_half)], res, occluders, bias)
    }

    fn cast(
        light: Vec3,
        faces: Vec<Face>,
        res: usize,
        occluders: &[Occluder],
        bias: f64,
    ) -> Result<ShadowMap, MapError> {
        if !res.is_power_of_two() || res > MAX_RES {
            return Err(MapError(format!("shadow map: {res} texels per side; give a power of two up to {MAX_RES}")));
        }
        if !(bias >= 0.0 && bias.is_finite()) {
            return Err(MapError(format!("shadow map: bias {bias} is not a finite number >= 0")));
        }
        // Each occluder is cast only over the texels its bounding box covers.
        let rects: Vec<Vec<[usize; 4]>> =
            faces.iter().map(|f| occluders.iter().map(|o| texel_rect(f, light, o, res)).collect()).collect();
        let rows: Vec<(usize, usize)> = (0..faces.len()).flat_map(|f| (0..res).map(move |j| (f, j))).collect();
        let cast_row = |&(f, j): &(usize, usize)| -> Result<Vec<f32>, MapError> {
            let mut row = vec![f64::INFINITY; res];
            for (o, r) in occluders.iter().zip(&rects[f]) {
                if j < r[2] || j > r[3] {
                    continue;
                }
                for (i, d) in row.iter_mut().enumerate().take(r[1] + 1).skip(r[0]) {
                    *d = d.min(texel_depth(light, &faces[f], res, i, j, std::slice::from_ref(o)));
                }
            }
            row.into_iter().map(stored_depth).collect()
        };
        let depth = crate::parallel::map(&rows, cast_row, &|_, _| {}).into_iter().collect::<Result<Vec<_>, _>>()?;
        Ok(ShadowMap { light, faces, res, depth: depth.concat(), bias })
    }

    /// The depth of texel `(i, j)` of face `f`.
    pub fn texel(&self, f: usize, i: usize, j: usize) -> f32 {
        self.depth[(f * self.res + j) * self.res + i]
    }

    /// Whether the map has six faces.
    pub fn is_cube(&self) -> bool {
        self.faces.len() == 6
    }

    /// The min-max pyramid of the depths.
    pub fn pyramid(&self) -> Pyramid {
        Pyramid::build(self.res, self.faces.len(), &self.depth)
    }

    /// The texel of map coordinate `x ∈ [−1, 1]` (clamped to the map).
    fn cell(&self, x: f64) -> usize {
        (((x + 1.0) * 0.5 * self.res as f64).floor().max(0.0) as usize).min(self.res - 1)
    }

    /// The lit runs `[a, b]` of `ray` under the map's nearest-texel test, in order
    /// and disjoint (`b = ∞` on an open ray); outside a spot map's frustum, lit.
    pub fn lit_runs(&self, ray: &PhysicalRay) -> Vec<(f64, f64)> {
        let len = norm(ray.direction);
        let d = ray.direction.map(|x| x / len);
        let end = ray.surface_distance.unwrap_or(f64::INFINITY);
        let q0 = sub(ray.origin, self.light);
        let mut pieces: Vec<(f64, f64, bool)> = Vec::new();
        for (f, face) in self.faces.iter().enumerate() {
            let (a, b) = (face.apply(q0), face.apply(d));
            if let Some((ta, tb)) = face.clip(a, b, 0.0, end) {
                self.face_pieces(f, a, b, ta, tb, &mut pieces);
            }
        }
        pieces.sort_by(|x, y| x.0.total_cmp(&y.0));
        // Stretches no face covers: outside a spot map, lit.
        let mut runs: Vec<(f64, f64)> = Vec::new();
        let mut t = 0.0;
        let push = |a: f64, b: f64, runs: &mut Vec<(f64, f64)>| {
            if b <= a {
                return;
            }
            match runs.last_mut() {
                Some(last) if last.1 >= a => last.1 = last.1.max(b),
                _ => runs.push((a, b)),
            }
        };
        for &(a, b, lit) in &pieces {
            if a > t && !self.is_cube() {
                push(t, a, &mut runs);
            }
            if lit {
                push(a, b, &mut runs);
            }
            t = t.max(b);
        }
        if t < end && !self.is_cube() {
            push(t, end, &mut runs);
        }
        runs
    }

    /// The pieces of face `f` over `[ta, tb]` for the face coordinates `a + t b`:
    /// cut at every texel boundary's crossing, each classified by its texel and
    /// split where the test flips.
    fn face_pieces(&self, f: usize, a: Vec3, b: Vec3, ta: f64, tb: f64, out: &mut Vec<(f64, f64, bool)>) {
        let n = self.res;
        let mut cuts = vec![ta, tb];
        for axis in 0..2 {
            for k in 0..=n {
                // X_axis(t) = c Z(t), c the boundary's map coordinate.
                let c = 2.0 * k as f64 / n as f64 - 1.0;
                let den = b[axis] - c * b[2];
                if den != 0.0 {
                    let t = (c * a[2] - a[axis]) / den;
                    if t > ta && t < tb {
                        cuts.push(t);
                    }
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        for w in cuts.windows(2) {
            let (t0, t1) = (w[0], w[1]);
            let m = if t1.is_finite() { 0.5 * (t0 + t1) } else { 2.0 * t0 + 1.0 };
            let z = a[2] + m * b[2];
            let (i, j) = (self.cell((a[0] + m * b[0]) / z), self.cell((a[1] + m * b[1]) / z));
            let depth = self.texel(f, i, j);
            if depth == NO_OCCLUDER {
                out.push((t0, t1, true));
                continue;
            }
            let thr = f64::from(depth) + self.bias;
            // Z(t) ≤ thr, Z affine: lit on one side of t*.
            let lit_at = |t: f64| if t.is_finite() { a[2] + t * b[2] <= thr } else { b[2] <= 0.0 };
            let (l0, l1) = (lit_at(t0), lit_at(t1));
            if l0 == l1 {
                out.push((t0, t1, l0));
            } else {
                let ts = ((thr - a[2]) / b[2]).clamp(t0, t1);
                out.push((t0, ts, l0));
                out.push((ts, t1, l1));
            }
        }
    }
}

/// A right and an up vector for the unit `forward`: up is the world's +Y made
/// orthogonal (+X where `forward` is nearly vertical). The kernels' callers pass
/// their own light matrix; this one is the reference scenes'.
pub fn basis(forward: Vec3) -> (Vec3, Vec3) {
    let helper = if forward[1].abs() < 0.99 { [0.0, 1.0, 0.0] } else { [1.0, 0.0, 0.0] };
    let r = cross(helper, forward);
    let right = r.map(|x| x / norm(r));
    (right, cross(forward, right))
}

/// The texels `[i0, i1, j0, j1]` (inclusive) of face `face` whose centre rays can
/// meet `o`: its bounding box's corners projected (the whole face where a corner
/// is not in front of the light), widened by a texel.
fn texel_rect(face: &Face, light: Vec3, o: &Occluder, res: usize) -> [usize; 4] {
    let (lo, hi) = match *o {
        Occluder::Sphere { center, radius } => (center.map(|c| c - radius), center.map(|c| c + radius)),
        Occluder::Cuboid { min, max } => (min, max),
    };
    let full = [0, res - 1, 0, res - 1];
    let corners: Vec<Vec3> = (0..8)
        .map(|k| {
            let corner = [
                if k & 1 == 0 { lo[0] } else { hi[0] },
                if k & 2 == 0 { lo[1] } else { hi[1] },
                if k & 4 == 0 { lo[2] } else { hi[2] },
            ];
            face.apply(sub(corner, light))
        })
        .collect();
    // Every corner outside one plane of the frustum (Z ∓ X ≥ 0, Z ∓ Y ≥ 0): the
    // box is outside the face.
    for (s, a) in [(1.0, 0), (-1.0, 0), (1.0, 1), (-1.0, 1)] {
        if corners.iter().all(|c| c[2] - s * c[a] < 0.0) {
            return [1, 0, 1, 0];
        }
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for c in corners {
        if c[2].is_nan() || c[2] <= 0.0 {
            return full;
        }
        let (x, y) = (c[0] / c[2], c[1] / c[2]);
        if !(x.is_finite() && y.is_finite()) {
            return full;
        }
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let texel = |v: f64| ((v + 1.0) * 0.5 * res as f64).floor();
    let clamp = |t: f64| t.clamp(0.0, (res - 1) as f64) as usize;
    if texel(x1) < 0.0 || texel(y1) < 0.0 || texel(x0) >= res as f64 || texel(y0) >= res as f64 {
        // Outside this face: an empty range.
        return [1, 0, 1, 0];
    }
    [clamp(texel(x0) - 1.0), clamp(texel(x1) + 1.0), clamp(texel(y0) - 1.0), clamp(texel(y1) + 1.0)]
}

/// The depth (`Z`) of the first occluder along the centre ray of texel `(i, j)`:
/// its first boundary ahead of the light, entering or leaving (a light on an
/// occluder's surface or inside it is shadowed by its far side, as a depth pass
/// without face culling draws it), in f64 (`∞`: none); [`stored_depth`] rounds it
/// to the map's f32.
fn texel_depth(light: Vec3, face: &Face, res: usize, i: usize, j: usize, occluders: &[Occluder]) -> f64 {
    let xc = 2.0 * (i as f64 + 0.5) / res as f64 - 1.0;
    let yc = 2.0 * (j as f64 + 0.5) / res as f64 - 1.0;
    // M w = (xc, yc, 1): w = forward + xc·right·tan_half + yc·up·tan_half.
    let rows = face.rows;
    let s2 = |r: Vec3| 1.0 / dot(r, r);
    let w: Vec3 = std::array::from_fn(|k| rows[2][k] + xc * rows[0][k] * s2(rows[0]) + yc * rows[1][k] * s2(rows[1]));
    let w2 = dot(w, w);
    // A ball is met only inside its cone of tangents from the light: a cheap
    // test before the exact crossing.
    let misses = |o: &Occluder| match *o {
        Occluder::Sphere { center, radius } => {
            let c = sub(center, light);
            let (cw, c2) = (dot(c, w), dot(c, c));
            c2 > radius * radius && (cw <= 0.0 || cw * cw < (c2 - radius * radius) * w2 * (1.0 - 1e-9))
        }
        Occluder::Cuboid { .. } => false,
    };
    let len = w2.sqrt();
    let u = w.map(|x| x / len);
    let hit = occluders
        .iter()
        .filter(|o| !misses(o))
        .filter_map(|o| o.boundary_ahead(light, u))
        .fold(f64::INFINITY, f64::min);
    // Z = s/|w| (w has Z = 1).
    hit / len
}

/// A texel's depth `z` (`∞`: no occluder) as the map stores it, an f32 below
/// [`NO_OCCLUDER`]; a depth f32 cannot hold (beyond 3.4e38, or a positive depth
/// that rounds to 0) is refused: stored as infinity or 0 it would light or
/// darken everything behind it (docs/MATH.md §9).
pub fn stored_depth(z: f64) -> Result<f32, MapError> {
    if z == f64::INFINITY {
        return Ok(NO_OCCLUDER);
    }
    let x = z as f32;
    if x.is_finite() && x < NO_OCCLUDER && (x > 0.0 || z <= 0.0) {
        Ok(x)
    } else {
        Err(MapError(format!(
            "an occluder at depth {z:e} from the light is outside the range of the map's f32 depths \
             (1.4e-45 to 3.4e38): scale the scene"
        )))
    }
}

/// A min-max pyramid: per face, level `k` has `(res >> k)²` nodes `[min, max]`
/// of the depths under them, up to one node.
#[derive(Debug, Clone, PartialEq)]
pub struct Pyramid {
    /// Texels per side of level 0.
    pub res: usize,
    /// Faces.
    pub faces: usize,
    /// `levels[face][k]`: row-major nodes of level `k`.
    pub levels: Vec<Vec<Vec<[f32; 2]>>>,
}

impl Pyramid {
    /// The pyramid of `faces × res × res` depths.
    pub fn build(res: usize, faces: usize, depth: &[f32]) -> Pyramid {
        let levels = (0..faces)
            .map(|f| {
                let mut out =
                    vec![depth[f * res * res..(f + 1) * res * res].iter().map(|&d| [d, d]).collect::<Vec<_>>()];
                let mut n = res;
                while n > 1 {
                    let prev = out.last().expect("level 0");
                    let h = n / 2;
                    let next = (0..h * h)
                        .map(|k| {
                            let (x, y) = (2 * (k % h), 2 * (k / h));
                            let q = [
                                prev[y * n + x],
                                prev[y * n + x + 1],
                                prev[(y + 1) * n + x],
                                prev[(y + 1) * n + x + 1],
                            ];
                            [
                                q.iter().map(|v| v[0]).fold(f32::MAX, f32::min),
                                q.iter().map(|v| v[1]).fold(f32::MIN, f32::max),
                            ]
                        })
                        .collect();
                    out.push(next);
                    n = h;
                }
                out
            })
            .collect();
        Pyramid { res, faces, levels }
    }

    /// Levels, level 0 included.
    pub fn level_count(&self) -> usize {
        self.levels.first().map_or(0, Vec::len)
    }

    /// Node `(x, y)` of `level` on `face`.
    pub fn node(&self, face: usize, level: usize, x: usize, y: usize) -> [f32; 2] {
        let n = self.res >> level;
        self.levels[face][level][y * n + x]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(surface: Option<f64>) -> PhysicalRay {
        PhysicalRay {
            origin: [-4.0, 0.3, 0.2],
            direction: [1.0, 0.02, 0.01],
            surface_distance: surface,
            light: [0.5, 1.5, 0.3],
            intensity: 1.0,
            sigma_t: 0.1,
            sigma_s: 0.05,
        }
    }

    fn balls() -> Vec<Occluder> {
        vec![
            Occluder::Sphere { center: [0.0, 1.0, 0.25], radius: 0.2 },
            Occluder::Sphere { center: [2.0, 1.0, 0.3], radius: 0.3 },
            Occluder::Cuboid { min: [-1.6, 1.1, -0.2], max: [-1.4, 1.3, 0.8] },
        ]
    }

    /// Away from the map's own resolution, its runs are the analytic ones: every
    /// boundary within a few texels' footprint of an analytic boundary.
    #[test]
    fn map_runs_approach_the_analytic_runs() {
        for surface in [Some(8.0), None] {
            let r = ray(surface);
            let exact = super::super::lit_intervals(&r, &balls());
            let map = ShadowMap::cube(r.light, 1024, &balls(), 1e-4).unwrap();
            let runs = map.lit_runs(&r);
            assert_eq!(runs.len(), exact.len(), "{runs:?} vs {exact:?}");
            for (x, y) in runs.iter().zip(&exact) {
                for (p, q) in [(x.0, y.0), (x.1, y.1)] {
                    assert!(p == q || (p - q).abs() < 0.005 * (1.0 + q), "{runs:?} vs {exact:?}");
                }
            }
        }
    }

    /// A light on an occluder's surface, or inside it, is shadowed by the
    /// occluder's far side: the map agrees with the analytic visibility away from
    /// the shadow's edge, and lets no light out of a sealed ball or box.
    #[test]
    fn a_light_on_or_inside_an_occluder_is_shadowed() {
        let light = [0.5, 1.5, 0.3];
        let cases = [
            ("on a ball", Occluder::Sphere { center: [0.5, 1.5, 0.8], radius: 0.5 }),
            ("inside a ball", Occluder::Sphere { center: [0.6, 1.4, 0.3], radius: 0.5 }),
            ("on a box's face", Occluder::Cuboid { min: [0.5, 1.0, -0.2], max: [1.5, 2.0, 0.8] }),
            ("inside a box", Occluder::Cuboid { min: [0.0, 1.0, -0.2], max: [1.5, 2.0, 0.8] }),
        ];
        for (what, occ) in cases {
            let map = ShadowMap::cube(light, 256, std::slice::from_ref(&occ), 0.0).unwrap();
            let sealed = what.starts_with("inside");
            let mut disagree = 0;
            let mut n = 0;
            for k in 0..400 {
                // Points on a sphere of radius 3 about the light (outside the occluder).
                let (a, b) = (k as f64 * 2.399_963, 1.0 - 2.0 * (k as f64 + 0.5) / 400.0);
                let q = (1.0 - b * b).sqrt();
                let x = [light[0] + 3.0 * q * a.cos(), light[1] + 3.0 * b, light[2] + 3.0 * q * a.sin()];
                let dir = sub(x, [0.0, 0.0, -5.0]);
                let len = norm(dir);
                let ray = PhysicalRay {
                    origin: [0.0, 0.0, -5.0],
                    direction: dir.map(|v| v / len),
                    surface_distance: Some(len * (1.0 + 1e-9)),
                    light,
                    intensity: 1.0,
                    sigma_t: 0.1,
                    sigma_s: 0.05,
                };
                if occ.contains(ray.origin) {
                    continue;
                }
                let lit_at_x = map.lit_runs(&ray).iter().any(|&(s0, s1)| s0 < len && s1 > len * (1.0 - 1e-6));
                let blocked = occ.blocks(x, light);
                n += 1;
                disagree += usize::from(lit_at_x == blocked);
                if sealed {
                    assert!(!lit_at_x, "{what}: light escapes at {x:?}");
                }
            }
            // Only points within a texel's footprint of the shadow's edge may differ.
            assert!(disagree * 50 <= n, "{what}: {disagree} of {n} points disagree with the analytic visibility");
        }
    }

    #[test]
    fn every_piece_is_classified_by_its_own_texel() {
        let r = ray(Some(8.0));
        let map = ShadowMap::cube(r.light, 256, &balls(), 0.0).unwrap();
        let runs = map.lit_runs(&r);
        // Probe points inside runs and between them with the test itself.
        let lit = |t: f64| {
            let p: Vec3 = std::array::from_fn(|k| r.origin[k] + t * r.direction[k] / norm(r.direction));
            let q = sub(p, map.light);
            map.faces.iter().enumerate().any(|(f, face)| {
                let c = face.apply(q);
                if !(c[2] >= c[0].abs() && c[2] >= c[1].abs() && c[2] > 0.0) {
                    return false;
                }
                let d = map.texel(f, map.cell(c[0] / c[2]), map.cell(c[1] / c[2]));
                c[2] <= f64::from(d) + map.bias
            })
        };
        for k in 1..2000 {
            let t = 8.0 * k as f64 / 2000.0;
            let inside = runs.iter().any(|&(a, b)| t > a && t < b);
            let near = runs.iter().any(|&(a, b)| (t - a).abs() < 1e-9 || (t - b).abs() < 1e-9);
            if !near {
                assert_eq!(inside, lit(t), "t {t}: {runs:?}");
            }
        }
    }

    #[test]
    fn casting_by_bounding_rectangles_changes_no_texel() {
        let light = [0.5, 1.5, 0.3];
        for map in [
            ShadowMap::cube(light, 64, &balls(), 0.0).unwrap(),
            ShadowMap::spot(light, [1.0, -0.5, 0.0], 2.0, 64, &balls(), 0.0).unwrap(),
        ] {
            for f in 0..map.faces.len() {
                for j in 0..64 {
                    for i in 0..64 {
                        let brute = stored_depth(texel_depth(light, &map.faces[f], 64, i, j, &balls())).unwrap();
                        assert_eq!(map.texel(f, i, j), brute, "face {f} texel {i},{j}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_pyramid_bounds_every_texel_and_bad_maps_are_refused() {
        let map = ShadowMap::spot([0.0, 2.0, 0.0], [0.0, -1.0, 0.2], 0.8, 64, &balls(), 0.0).unwrap();
        let p = map.pyramid();
        assert_eq!(p.level_count(), 7);
        assert_eq!(p.levels[0][6].len(), 1);
        let top = p.node(0, 6, 0, 0);
        for &d in &map.depth {
            assert!(top[0] <= d && d <= top[1]);
        }
        assert!(ShadowMap::cube([0.0; 3], 100, &balls(), 0.0).is_err());
        assert!(ShadowMap::cube([0.0; 3], 64, &balls(), -1.0).is_err());
        assert!(ShadowMap::spot([0.0; 3], [0.0; 3], 1.0, 64, &balls(), 0.0).is_err());
    }

    /// Issue 60 (5): the map and the exact model agree on occluders as closed
    /// surfaces — a viewer and a light inside a ball lit to the far wall, a light
    /// on a ball's surface lighting the inside.
    #[test]
    fn the_map_lights_the_inside_of_a_closed_occluder_as_the_exact_model_does() {
        let inside = Occluder::Sphere { center: [2.5, 1.0, 0.0], radius: 10.0 };
        let r = PhysicalRay {
            origin: [0.0; 3],
            direction: [1.0, 0.0, 0.0],
            // The far wall is at x = 2.5 + √(100 − 1): a surface short of it by
            // more than a texel's change in the wall's depth.
            surface_distance: Some((2.5 + 99f64.sqrt()) * 0.95),
            light: [1.0, 1.0, 0.0],
            intensity: 1.0,
            sigma_t: 0.1,
            sigma_s: 0.1,
        };
        for res in [64, 1024] {
            let map = ShadowMap::cube(r.light, res, &[inside], 0.0).unwrap();
            assert_eq!(map.lit_runs(&r), super::super::lit_intervals(&r, &[inside]), "{res}");
        }
        let on = Occluder::Sphere { center: [1.0, 0.0, 0.0], radius: 1.0 };
        let r = PhysicalRay { origin: [-1.0, 0.5, 0.0], light: [0.0; 3], surface_distance: None, ..r };
        let exact = super::super::lit_intervals(&r, &[on]);
        let mut last = f64::INFINITY;
        for res in [256, 1024, 4096] {
            let runs = ShadowMap::cube(r.light, res, &[on], 0.0).unwrap().lit_runs(&r);
            assert_eq!(runs.len(), exact.len(), "{res}: {runs:?} vs {exact:?}");
            let err =
                runs.iter().zip(&exact).map(|(x, y)| (x.0 - y.0).abs().max((x.1 - y.1).abs())).fold(0.0, f64::max);
            assert!(err < 8.0 / res as f64 && err <= last, "{res}: {runs:?} vs {exact:?}");
            last = err;
        }
    }

    /// Issue 60 (7): a depth the map's f32 texels cannot hold is refused, not
    /// stored as "no occluder".
    #[test]
    fn depths_beyond_f32_are_refused() {
        for scale in [1e39, 1e100, 1e-50] {
            let light = [0.5 * scale, 1.5 * scale, 0.3 * scale];
            let occ: Vec<Occluder> = balls()
                .iter()
                .map(|o| match *o {
                    Occluder::Sphere { center, radius } => {
                        Occluder::Sphere { center: center.map(|c| c * scale), radius: radius * scale }
                    }
                    Occluder::Cuboid { min, max } => {
                        Occluder::Cuboid { min: min.map(|c| c * scale), max: max.map(|c| c * scale) }
                    }
                })
                .collect();
            let e = ShadowMap::cube(light, 64, &occ, 0.0).unwrap_err();
            assert!(e.0.contains("f32") && e.0.contains("scale the scene"), "{scale}: {e}");
        }
        assert!(stored_depth(1e-44).is_ok() && stored_depth(3e38).is_ok() && stored_depth(f64::INFINITY).is_ok());
    }
}

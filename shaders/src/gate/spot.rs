//! The spot entry's rays for the gate: cones placed around chosen canonical points,
//! on a grid of outer and inner angles.

use super::*;
use airlight_shapes::vocab::IndexEntry;
use airlight_truth::reference::{self, Point};

/// One spot ray of the gate.
#[derive(Debug, Clone, Copy)]
pub struct SpotCase {
    /// The ray, light and medium.
    pub ray: crate::SpotRay,
    /// The canonical point its error is held at (the lit stretch's).
    pub point: Point,
    /// The reference RGB radiance.
    pub reference: [f64; 3],
    /// The largest relative change of the reference when the cone's cosines, or
    /// one coordinate of the light, the viewer or the direction, move by one f32
    /// ulp: how much of the answer the f32 inputs alone leave undetermined.
    pub ulp_change: f64,
}

/// Spot rays whose answer changes by more than this when the cone's cosines, or a
/// coordinate of the light, the viewer or the direction, move by one f32 ulp
/// (narrow cones, rays grazing an edge, a cone's cut near a light the ray passes
/// close by) are ill-conditioned in f32
/// itself: there an f32 kernel is held to its limit plus [`SPOT_ULP_FACTOR`] times
/// that change, and its error enters the row's statistics only if it breaks that.
pub const SPOT_ULP_CHANGE: f64 = 1e-5;

/// How many one-ulp changes of the cone's cosines an f32 kernel's spot error may
/// add on ill-conditioned rays (measured: at most 20 on 4,500 rays of three kernels).
pub const SPOT_ULP_FACTOR: f64 = 32.0;

/// Spot rays per kernel with a spot entry.
pub const SPOT_RAYS: usize = 224;

/// The outer half-angles (degrees) of the gate's grid of cones (issue 23: the
/// cones renderers use).
pub const SPOT_GRID_OUTER: [f64; 7] = [5.0, 10.0, 20.0, 30.0, 45.0, 60.0, 80.0];

/// The inner half-angles of the grid, as shares of the outer: from a hard edge
/// (equal) to a quarter.
pub const SPOT_GRID_INNER: [f64; 4] = [1.0, 0.75, 0.5, 0.25];

/// Spot-light rays for kernel `k`'s spot entry: the placements of
/// [`physical_rays`], each light made a spot light aimed at a random point of the
/// ray (or beside it): every fourth the next cone of the grid [`SPOT_GRID_OUTER`] ×
/// [`SPOT_GRID_INNER`] (every eighth turned so that the ray leaves through its
/// penumbra), the others outer half-angle 2°…80° log-uniform, every other one with a
/// smooth edge (inner half-angle 20…95% of the outer), every 16th a point light
/// (`cos_outer = −1`); σt and σs per channel the ray's scaled by 0.4…1; then
/// [`NEAR_LIGHT_RAYS`] rays passing close by the light
/// ([`near_light_spot_rays`]) and 28 on the line through the light and beside it. Returns
/// the rays with the canonical point of their unclipped red channel and the
/// reference RGB radiance (through [`crate::SpotRay::reference`]).
pub fn spot_rays(k: &IndexEntry, n: usize, seed: u64) -> Result<Vec<SpotCase>, GateError> {
    let base = placements(k, n, seed)?;
    let mut rays = sampled_spot_rays(k, &base, seed);
    rays.extend(near_light_spot_rays(k, &base, seed));
    hold_at_lit_stretch(k, &mut rays);
    rays.extend(line_spot_rays(k, &base));
    spot_references(k, rays)
}

/// A placement's viewer, unit direction and distance to its light (f64).
fn ray_frame(r: &crate::Ray) -> ([f64; 3], [f64; 3], f64) {
    let o = r.origin.map(f64::from);
    let l = r.light.map(f64::from);
    let dn = {
        let d = r.dir.map(f64::from);
        let m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        d.map(|x| x / m)
    };
    let dist = ((l[0] - o[0]).powi(2) + (l[1] - o[1]).powi(2) + (l[2] - o[2]).powi(2)).sqrt();
    (o, dn, dist)
}

/// `u` less its part along the unit `dn`, and that remainder's length.
fn across(u: [f64; 3], dn: [f64; 3]) -> ([f64; 3], f64) {
    let dot = u[0] * dn[0] + u[1] * dn[1] + u[2] * dn[2];
    let q: [f64; 3] = std::array::from_fn(|j| u[j] - dot * dn[j]);
    (q, (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt())
}

/// One spot ray per placement: cones of 2°–80° aimed near the ray, every fourth
/// from the renderers' grid (every eighth leaving through the penumbra), every
/// sixteenth a point light; RGB media scaled from the placement's.
fn sampled_spot_rays(k: &IndexEntry, base: &[(crate::Ray, Point, f64)], seed: u64) -> Vec<(crate::SpotRay, Point)> {
    let n = base.len();
    let mut rng = airlight_truth::domains::SplitMix64(seed ^ 0x5907);
    let mut rays = Vec::with_capacity(n);
    for (i, (r, p, _)) in base.iter().enumerate() {
        let (o, dn, dist) = ray_frame(r);
        let l = r.light.map(f64::from);
        let s = 2.0 * dist * rng.next_f64();
        let jitter = 0.3 * dist * rng.next_f64();
        let u = [rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5];
        let mut axis: [f64; 3] = std::array::from_fn(|j| o[j] + s * dn[j] + jitter * u[j] - l[j]);
        let outer = (2.0f64 * 40f64.powf(rng.next_f64())).to_radians();
        let inner = outer * (0.2 + 0.75 * rng.next_f64());
        // Every fourth ray: the next cone of the grid renderers use.
        let (grid_outer, grid_inner) = {
            let j = i / 4;
            let o = SPOT_GRID_OUTER[j % SPOT_GRID_OUTER.len()];
            (o.to_radians(), (o * SPOT_GRID_INNER[(j / SPOT_GRID_OUTER.len()) % SPOT_GRID_INNER.len()]).to_radians())
        };
        if i % 8 == 0 {
            // Every other grid ray leaves through the penumbra: the axis turned from
            // the ray's direction by an angle between the inner and outer half-angles,
            // so that the far end of the ray (ω → π, the backscatter peak and the
            // tail) lies in the smooth edge.
            let frac = 0.2 + 0.6 * rng.next_f64();
            let a = grid_inner + frac * (grid_outer - grid_inner);
            let (q, qn) = across(u, dn);
            if qn > 0.0 {
                axis = std::array::from_fn(|j| a.cos() * dn[j] + a.sin() * q[j] / qn);
            }
        }
        let (cos_outer, cos_inner) = if i % 16 == 15 {
            (-1.0, -1.0)
        } else if i % 4 == 0 {
            (grid_outer.cos(), grid_inner.cos())
        } else if i % 2 == 0 {
            (outer.cos(), inner.cos())
        } else {
            (outer.cos(), outer.cos())
        };
        let f = [1.0, 0.4 + 0.6 * rng.next_f64(), 0.4 + 0.6 * rng.next_f64()];
        // A kernel that does not take σt (no extinction) is checked in a medium without it:
        // ignoring the transmittance to a stretch is not bounded by its bound on A.
        let takes_sigma_t = k.spot_params.contains(&airlight_shapes::vocab::Arg::SigmaTRgb);
        let sigma_t = if takes_sigma_t { f.map(|x| (x * f64::from(r.sigma_t)) as f32) } else { [0.0; 3] };
        let sigma_s = f.map(|x| (x * f64::from(r.sigma_s)) as f32);
        rays.push((
            crate::SpotRay {
                origin: r.origin,
                dir: r.dir,
                surface: r.surface,
                light: r.light,
                axis: axis.map(|x| x as f32),
                cos_outer: cos_outer as f32,
                cos_inner: cos_inner as f32,
                intensity: r.intensity,
                sigma_t,
                sigma_s,
                g: r.g,
            },
            *p,
        ));
    }
    rays
}

/// Rays passing close by a spot light whose cone's cut crosses them near it.
pub const NEAR_LIGHT_RAYS: usize = 24;

/// [`NEAR_LIGHT_RAYS`] rays that pass a spot light at 1e-3 … 5e-2 of its distance,
/// the cone (20°–60° outer half-angle, a hard edge or an inner cone of 40% or
/// 70% of it) aimed within a few of those offsets of the light's foot, so that
/// its cut crosses the ray where the glow gathers: found by a held-out probe
/// (a 60°/42.5° cone, the light 0.1 m off a ray 9.5 m away: 2.3e-4 in f32 on
/// every family, where moving the light by one f32 ulp moves the answer by
/// about as much; kept as the last ray). Open rays and the placements' surfaces,
/// every other one.
fn near_light_spot_rays(k: &IndexEntry, base: &[(crate::Ray, Point, f64)], seed: u64) -> Vec<(crate::SpotRay, Point)> {
    let mut rng = airlight_truth::domains::SplitMix64(seed ^ 0x4EA2);
    let takes_sigma_t = k.spot_params.contains(&airlight_shapes::vocab::Arg::SigmaTRgb);
    let mut rays = Vec::with_capacity(NEAR_LIGHT_RAYS);
    for i in 0..NEAR_LIGHT_RAYS.min(base.len()) {
        let (r, p, _) = &base[i];
        let (o, dn, dist) = ray_frame(r);
        // The light's foot on the ray, ahead of the viewer, and a direction across the ray.
        let foot: [f64; 3] = std::array::from_fn(|j| o[j] + dist * dn[j]);
        let u = [rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5];
        let (q, qn) = across(u, dn);
        let qn = qn.max(1e-12);
        let h = dist * 1e-3 * 50f64.powf(rng.next_f64());
        let light: [f64; 3] = std::array::from_fn(|j| foot[j] + h * q[j] / qn);
        let s = h * 4.0 * (rng.next_f64() - 0.5);
        let axis: [f64; 3] = std::array::from_fn(|j| foot[j] + s * dn[j] - light[j]);
        let outer = [20.0f64, 30.0, 45.0, 60.0][i % 4].to_radians();
        let inner = outer * [1.0, 0.7, 0.4][(i / 4) % 3];
        let f = [1.0, 0.5 + 0.5 * rng.next_f64(), 0.5 + 0.5 * rng.next_f64()];
        let sigma_t = if takes_sigma_t { f.map(|x| (x * f64::from(r.sigma_t)) as f32) } else { [0.0; 3] };
        rays.push((
            crate::SpotRay {
                origin: r.origin,
                dir: r.dir,
                surface: if i % 2 == 0 { -1.0 } else { r.surface },
                light: light.map(|x| x as f32),
                axis: axis.map(|x| x as f32),
                cos_outer: outer.cos() as f32,
                cos_inner: inner.cos() as f32,
                intensity: r.intensity,
                sigma_t,
                sigma_s: f.map(|x| (x * f64::from(r.sigma_s)) as f32),
                g: r.g,
            },
            *p,
        ));
    }
    // The held-out probe's ray, kept (its g the first placement's where the
    // kernel's g range leaves out 0.3, no σt where it takes none): 2.25e-4 in f32
    // on phi-6 at these f32 inputs, where one ulp of one coordinate moves the
    // answer by 3.9e-4 and one ulp of the cone's cosines by 4.7e-6 only.
    if let Some((r, p, _)) = base.first() {
        let f = |v: [f64; 3]| v.map(|x| x as f32);
        let takes_g = k.g[0] <= 0.3 && 0.3 <= k.g[1];
        rays.push((
            crate::SpotRay {
                origin: f([0.9833530783653259, 2.7297496795654297, 2.6016733646392822]),
                dir: f([0.20472407341003418, 0.6763367652893066, 0.7075709104537964]),
                surface: 27.827672958374023f64 as f32,
                light: f([2.8405532836914062, 9.191301345825195, 9.288833618164062]),
                axis: f([-0.06457164883613586, -0.8368364572525024, 0.5436315536499023]),
                cos_outer: 0.4931713044643402f64 as f32,
                cos_inner: 0.7374817132949829f64 as f32,
                intensity: 82.15552520751953f64 as f32,
                sigma_t: if takes_sigma_t {
                    f([0.08611420542001724, 0.08064102381467819, 0.06574349850416183])
                } else {
                    [0.0; 3]
                },
                sigma_s: f([0.06136471778154373, 0.027940144762396812, 0.03974611684679985]),
                g: if takes_g { 0.3 } else { r.g },
            },
            *p,
        ));
    }
    rays
}

/// Rays on the line through the light (issue 23), held at γ brought into the sampled hull.
fn line_spot_rays(k: &IndexEntry, base: &[(crate::Ray, Point, f64)]) -> Vec<(crate::SpotRay, Point)> {
    // The line through the light (issue 23): the light on the ray's line ahead and
    // off it by 1e-9 and 1e-5 of its distance, behind on it and off it by 1e-30 …
    // 1e-7, a smooth 30°/20° and a hard 30° cone aimed along the line either way,
    // surfaces before the light and none. On the line the value is the point
    // light's times the line's weight, and the edge regime holds the point light
    // to the bound at γ = 0 and π exactly: these are held at γ brought into the
    // sampled hull.
    let mut line = Vec::new();
    let mut cases = Vec::new();
    for smooth in [true, false] {
        for toward in [true, false] {
            // Ahead, the cone's cut falls within `h cot ω` of the light's foot; the f64
            // reference places it in distances, which hold `h` from about 1e-9 up.
            for off in [0.0, 1e-9, 1e-5] {
                cases.push((true, off, smooth, toward, toward && off == 0.0));
            }
            for off in [0.0, 1e-30, 1e-12, 1e-7] {
                cases.push((false, off, smooth, toward, false));
            }
        }
    }
    for (i, &(ahead, off, smooth, toward, with_surface)) in cases.iter().enumerate() {
        let (r, p, _) = &base[i % base.len()];
        let (_, _, dist) = ray_frame(r);
        let side = if ahead { 1.0 } else { -1.0 };
        let co = 30f64.to_radians().cos();
        let ci = if smooth { 20f64.to_radians().cos() } else { co };
        let surface = if with_surface { (0.5 * dist) as f32 } else { -1.0 };
        let takes_sigma_t = k.spot_params.contains(&airlight_shapes::vocab::Arg::SigmaTRgb);
        let sigma_t = if takes_sigma_t { [r.sigma_t, 0.7 * r.sigma_t, 0.4 * r.sigma_t] } else { [0.0; 3] };
        let ray = crate::SpotRay {
            origin: [0.0; 3],
            dir: [1.0, 0.0, 0.0],
            surface,
            light: [(side * dist) as f32, (off * dist) as f32, 0.0],
            axis: [if toward { -side as f32 } else { side as f32 }, 0.0, 0.0],
            cos_outer: co as f32,
            cos_inner: ci as f32,
            intensity: r.intensity,
            sigma_t,
            sigma_s: [r.sigma_s, 0.8 * r.sigma_s, 0.6 * r.sigma_s],
            g: r.g,
        };
        let q = Point { gamma: if ahead { 1e-4 } else { std::f64::consts::PI - 1e-4 }, ..*p };
        line.push((ray, q));
    }
    line
}

/// Moves each sampled ray's held point to its lit stretch's own canonical point.
fn hold_at_lit_stretch(k: &IndexEntry, rays: &mut [(crate::SpotRay, Point)]) {
    // The canonical point each error is held at: the lit stretch's own (the
    // viewer moved to where the outer cone begins), where the family's bound applies.
    for (r, p) in rays.iter_mut() {
        let Some(cone) = r.cone() else { continue };
        let ray = r.physical(0);
        if let Some((s0, s1)) = cone.lit(&ray, cone.cos_outer) {
            if let Ok(c) = ray.stretch(s0, s1).0.to_canonical(f64::from(r.g)) {
                *p = project(k, c.point);
            }
        }
    }
}

/// The f64 reference of every ray per channel, and its f32 conditioning.
fn spot_references(k: &IndexEntry, rays: Vec<(crate::SpotRay, Point)>) -> Result<Vec<SpotCase>, GateError> {
    let refs = airlight_truth::parallel::map(
        &rays,
        |(r, _)| -> Result<([f64; 3], f64), String> {
            let a = |q: Point| reference::airlight(project(k, q)).unwrap_or(f64::NAN);
            let mut out = [0.0; 3];
            for (c, v) in out.iter_mut().enumerate() {
                *v = r.reference(c, &a).map_err(|e| e.to_string())?;
            }
            // The problem's own f32 conditioning: the largest change when the
            // cone's cosines, or one coordinate of the light, the viewer or the
            // direction, move by one f32 ulp either way (a light near the ray moves
            // the cone's cut across the near stretch, where the glow gathers).
            let mut change = 0.0;
            if r.cone().is_some() {
                for step in [-1.0f32, 1.0] {
                    let ulp = |x: f32| x + step * x.abs().max(f32::MIN_POSITIVE) * f32::EPSILON;
                    let mut moved = Vec::with_capacity(1 + 3 * 3);
                    let mut q = *r;
                    q.cos_outer = ulp(r.cos_outer);
                    q.cos_inner = ulp(r.cos_inner);
                    moved.push(q);
                    for j in 0..3 {
                        for which in 0..3 {
                            let mut q = *r;
                            let v = match which {
                                0 => &mut q.light,
                                1 => &mut q.origin,
                                _ => &mut q.dir,
                            };
                            v[j] = ulp(v[j]);
                            moved.push(q);
                        }
                    }
                    for q in moved {
                        let v = q.reference(0, &a).map_err(|e| e.to_string())?;
                        change = f64::max(change, (v - out[0]).abs() / out[0].max(f64::MIN_POSITIVE));
                    }
                }
            }
            Ok((out, change))
        },
        &|_, _| {},
    );
    rays.into_iter()
        .zip(refs)
        .map(|((ray, point), v)| {
            v.map(|(reference, change)| SpotCase { ray, point, reference, ulp_change: change })
                .map_err(|e| GateError::Input(format!("{}: spot ray: {e}", k.name)))
        })
        .collect()
}

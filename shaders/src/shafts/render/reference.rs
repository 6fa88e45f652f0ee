//! The reference frame: each pixel's first surface and its fog over the exact lit
//! intervals among the analytic occluders, in f64.

use super::*;
use airlight_truth::geometry::PhysicalRay;
use airlight_truth::shafts::{self, Occluder};

/// The outward normal of object `id` at `p` (f64; the shader's `sc_normal`).
pub(crate) fn normal(stage: &Stage, id: usize, p: [f64; 3]) -> [f64; 3] {
    match id {
        0 => [0.0, 1.0, 0.0],
        1 => [0.0, -1.0, 0.0],
        2 => [1.0, 0.0, 0.0],
        3 => [-1.0, 0.0, 0.0],
        4 => [0.0, 0.0, -1.0],
        5 => [0.0, 0.0, 1.0],
        _ => {
            let b = &stage.boxes;
            if id >= 6 + b.len() {
                let c = stage.ball.0.map(f64::from);
                let v = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
                let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                return v.map(|x| x / n);
            }
            let (mn, mx, _) = b[id - 6];
            let mut best = (f64::INFINITY, [0.0; 3]);
            for a in 0..3 {
                for (dist, sign) in [((p[a] - f64::from(mn[a])).abs(), -1.0), ((f64::from(mx[a]) - p[a]).abs(), 1.0)] {
                    if dist < best.0 {
                        let mut n = [0.0; 3];
                        n[a] = sign;
                        best = (dist, n);
                    }
                }
            }
            best.1
        }
    }
}

pub(crate) fn albedo(stage: &Stage, id: usize) -> [f64; 3] {
    let b = &stage.boxes;
    let a = match id {
        0..=5 => stage.room_albedo[id],
        i if i < 6 + b.len() => b[i - 6].2,
        _ => stage.ball.2,
    };
    a.map(f64::from)
}

/// The distance from the camera along the unit `dir` to the first surface:
/// the room's walls from inside, or an occluder (f64).
pub fn first_surface(stage: &Stage, dir: [f64; 3]) -> f64 {
    let cam = stage.camera.map(f64::from);
    let exit = (0..3)
        .filter(|&a| dir[a] != 0.0)
        .map(|a| {
            let (lo, hi) = (f64::from(stage.room[0][a]), f64::from(stage.room[1][a]));
            ((lo - cam[a]) / dir[a]).max((hi - cam[a]) / dir[a])
        })
        .fold(f64::INFINITY, f64::min);
    stage.occluders().iter().filter_map(|o| o.enters(cam, dir)).fold(exit, f64::min)
}

/// The reference fog of pixel `i`'s ray from the camera along `dir`, ending at
/// `end`: the reference in-scattering per channel over the ray's exact lit
/// intervals among the analytic occluders (the spot's cone, if any).
fn fog_of(stage: &Stage, occ: &[Occluder], dir: [f64; 3], end: f64) -> [f64; 3] {
    let a = |q: airlight_truth::reference::Point| airlight_truth::reference::airlight(q).unwrap_or(f64::INFINITY);
    let cone = stage.cone();
    let ray = |c: usize| PhysicalRay {
        origin: stage.camera.map(f64::from),
        direction: dir,
        // A negative distance: no surface, the ray runs on to infinity.
        surface_distance: (end >= 0.0).then_some(end),
        light: stage.light.map(f64::from),
        intensity: f64::from(stage.intensity) * f64::from(stage.colour[c]),
        sigma_t: f64::from(stage.sigma_t[c]),
        sigma_s: f64::from(stage.sigma_s[c]),
    };
    let lit = shafts::lit_intervals(&ray(0), occ);
    std::array::from_fn(|c| {
        shafts::shadowed_radiance(&ray(c), cone.as_ref(), f64::from(stage.g), &lit, &a).unwrap_or(f64::NAN)
    })
}

/// The reference fog along the unit directions `dirs` from the stage's camera,
/// each ray ending on the surface at `ends[i]`: over the exact lit intervals
/// among the stage's occluders when `shadowed`, else over the whole ray (a
/// light without shadows).
pub fn reference_fog_along(stage: &Stage, dirs: &[[f64; 3]], ends: &[f64], shadowed: bool) -> Vec<[f64; 3]> {
    let occ = if shadowed { stage.occluders() } else { Vec::new() };
    let rays: Vec<usize> = (0..dirs.len()).collect();
    airlight_truth::parallel::map(&rays, |&i| fog_of(stage, &occ, dirs[i], ends[i]), &|_, _| {})
}

/// The reference fog of each pixel of `view`, its ray ending at `ends[i]`.
pub fn reference_fog(stage: &Stage, view: &ShaftsView, ends: &[f64]) -> Vec<[f64; 3]> {
    let basis = stage.camera_basis();
    let dirs: Vec<[f64; 3]> = (0..view.width * view.height)
        .map(|i| view.dir_from(basis, i % view.width, i / view.width).map(f64::from))
        .collect();
    reference_fog_along(stage, &dirs, ends, true)
}

/// The reference frame for the GPU frame `gpu` (its surface distances and
/// object ids): the fog by the reference over the exact lit intervals, and the
/// composite with surfaces lit under exact visibility. Per pixel RGB (f64).
pub fn reference(stage: &Stage, view: &ShaftsView, gpu: &Frame) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let occ = stage.occluders();
    let cone = stage.cone();
    let (st, light, cam) = (stage.sigma_t, stage.light.map(f64::from), stage.camera.map(f64::from));
    let basis = stage.camera_basis();
    let pixels: Vec<u32> = (0..view.width * view.height).collect();
    let out = airlight_truth::parallel::map(
        &pixels,
        |&i| {
            let dir = view.dir_from(basis, i % view.width, i / view.width).map(f64::from);
            let end = f64::from(gpu.fog[i as usize][3]);
            let id = gpu.color[i as usize][3] as usize;
            let fog = fog_of(stage, &occ, dir, end);
            let p: [f64; 3] = std::array::from_fn(|q| cam[q] + end * dir[q]);
            let n = normal(stage, id, p);
            let off: [f64; 3] = std::array::from_fn(|q| p[q] + 1e-3 * n[q]);
            let v = if occ.iter().any(|o| o.blocks(off, light)) { 0.0 } else { 1.0 };
            let tl: [f64; 3] = std::array::from_fn(|q| light[q] - p[q]);
            let dl = (tl[0] * tl[0] + tl[1] * tl[1] + tl[2] * tl[2]).sqrt();
            let cos = (n[0] * tl[0] + n[1] * tl[1] + n[2] * tl[2]) / dl;
            let w = cone.as_ref().map_or(1.0, |c| c.weight(tl.map(|x| -x)));
            let alb = albedo(stage, id);
            let color: [f64; 3] = std::array::from_fn(|c| {
                let e = f64::from(stage.intensity) * f64::from(stage.colour[c]) * w * cos.max(0.0) / (dl * dl)
                    * (-f64::from(st[c]) * dl).exp()
                    * v;
                let surf = (alb[c] * e / std::f64::consts::PI + f64::from(stage.ambient) * alb[c])
                    * (-f64::from(st[c]) * end).exp();
                fog[c] + surf
            });
            (fog, color)
        },
        &|_, _| {},
    );
    out.into_iter().unzip()
}

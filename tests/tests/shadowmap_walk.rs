//! The generated f32 shadow-map walk (`airlight_kernels::shadowmap`) against the
//! f64 reference of the same map (`airlight_truth::shafts::ShadowMap::lit_runs`):
//! the same lit runs, up to f32 rounding of where the ray crosses a texel's edge,
//! for point lights (cube maps) and spot lights, open rays and surfaces.

use airlight_kernels::shadowmap::{Pyramid as WalkPyramid, Walk};
use airlight_truth::geometry::PhysicalRay;
use airlight_truth::shafts::{Occluder, Pyramid, ShadowMap};

struct Levels<'a>(&'a Pyramid);

impl WalkPyramid for Levels<'_> {
    fn node(&self, face: u32, level: u32, x: i32, y: i32) -> [f32; 2] {
        self.0.node(face as usize, level as usize, x as usize, y as usize)
    }
}

/// A small deterministic generator (xorshift), so the rays are the same on every machine.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

fn f32s(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| x as f32)
}

/// The walk's runs of `ray` through `map`.
pub fn walk_runs(map: &ShadowMap, p: &Pyramid, ray: &PhysicalRay) -> (Vec<(f64, f64)>, Walk) {
    let rows = map.faces[0].rows.map(f32s);
    let end = ray.surface_distance.map_or(-1.0, |s| s as f32);
    let mut w = Walk::new(
        f32s(ray.origin),
        f32s(ray.direction),
        end,
        f32s(map.light),
        rows,
        map.is_cube(),
        map.res as u32,
        map.bias as f32,
        0,
    );
    let mut out = Vec::new();
    while let Some([a, b]) = w.next(&Levels(p)) {
        out.push((f64::from(a), if b < 0.0 { f64::INFINITY } else { f64::from(b) }));
    }
    (out, w)
}

/// The length of the symmetric difference of two run lists over `[0, far]`.
fn mismatch(x: &[(f64, f64)], y: &[(f64, f64)], far: f64) -> f64 {
    let mut cuts: Vec<f64> = x.iter().chain(y).flat_map(|&(a, b)| [a.min(far), b.min(far)]).collect();
    cuts.push(0.0);
    cuts.push(far);
    cuts.sort_by(f64::total_cmp);
    let inside = |r: &[(f64, f64)], t: f64| r.iter().any(|&(a, b)| t > a && t < b);
    cuts.windows(2)
        .filter(|w| inside(x, 0.5 * (w[0] + w[1])) != inside(y, 0.5 * (w[0] + w[1])))
        .map(|w| w[1] - w[0])
        .sum()
}

fn scene(rng: &mut Rng, light: [f64; 3]) -> Vec<Occluder> {
    let n = 1 + (rng.next() * 3.0) as usize;
    let mut out: Vec<Occluder> = (0..n)
        .map(|_| {
            let c = [light[0] + rng.range(-3.0, 3.0), light[1] + rng.range(-3.0, 3.0), light[2] + rng.range(-3.0, 3.0)];
            Occluder::Sphere { center: c, radius: rng.range(0.1, 0.8) }
        })
        .filter(|o| !o.contains(light))
        .collect();
    // Thin bars: many changes along a ray.
    for k in 0..4 {
        let x = light[0] - 1.5 + 0.2 * k as f64;
        out.push(Occluder::Cuboid {
            min: [x, light[1] - 2.0, light[2] + 1.0],
            max: [x + 0.05, light[1] + 2.0, light[2] + 1.1],
        });
    }
    out
}

fn ray(rng: &mut Rng, light: [f64; 3], open: bool) -> PhysicalRay {
    let origin = [light[0] + rng.range(-6.0, 6.0), light[1] + rng.range(-3.0, 3.0), light[2] + rng.range(-6.0, 6.0)];
    let target = [light[0] + rng.range(-2.0, 2.0), light[1] + rng.range(-2.0, 2.0), light[2] + rng.range(-2.0, 2.0)];
    let d = [target[0] - origin[0], target[1] - origin[1], target[2] - origin[2]];
    PhysicalRay {
        origin,
        direction: d,
        surface_distance: if open { None } else { Some(rng.range(2.0, 20.0)) },
        light,
        intensity: 1.0,
        sigma_t: 0.1,
        sigma_s: 0.05,
    }
}

#[test]
fn the_walk_finds_the_reference_runs_of_cube_and_spot_maps() {
    let mut rng = Rng(0x5eed_0039);
    let mut worst: f64 = 0.0;
    let mut changes = 0;
    for case in 0..24 {
        let light = [rng.range(-2.0, 2.0), rng.range(1.0, 3.0), rng.range(-2.0, 2.0)];
        let occ = scene(&mut rng, light);
        let res = [64, 256, 1024][case % 3];
        let map = if case % 4 == 3 {
            ShadowMap::spot(light, [0.2, -0.3, 1.0], 1.2, res, &occ, 1e-3).unwrap()
        } else {
            ShadowMap::cube(light, res, &occ, 1e-3).unwrap()
        };
        let p = map.pyramid();
        for k in 0..20 {
            let r = ray(&mut rng, light, k % 3 == 0);
            let want = map.lit_runs(&r);
            let (got, w) = walk_runs(&map, &p, &r);
            assert!(!w.truncated, "case {case} ray {k}: truncated after {} steps", w.steps);
            let far = r.surface_distance.unwrap_or(60.0);
            let m = mismatch(&got, &want, far);
            // f32 rounding of a crossing: a few ulps of the distance, times the
            // changes (a grazing ray moves a crossing by more per ulp).
            let allow = 1e-4 * far * (1.0 + want.len() as f64);
            assert!(m <= allow, "case {case} ray {k} res {res}: mismatch {m:e}\n got {got:?}\nwant {want:?}");
            worst = worst.max(m / far);
            changes += want.len();
        }
    }
    assert!(changes > 200, "the rays must cross shadows: {changes} runs");
    eprintln!("worst mismatch / length: {worst:e}");
}

#[test]
fn a_map_without_occluders_is_lit_everywhere_and_the_walk_is_short() {
    let light = [0.0, 2.0, 0.0];
    let map = ShadowMap::cube(light, 2048, &[], 0.0).unwrap();
    let p = map.pyramid();
    let mut rng = Rng(7);
    for _ in 0..20 {
        let r = ray(&mut rng, light, false);
        let (got, w) = walk_runs(&map, &p, &r);
        assert_eq!(got.len(), 1, "{got:?}");
        assert!(got[0].0 == 0.0 && (got[0].1 - r.surface_distance.unwrap()).abs() < 1e-4, "{got:?}");
        // One step per face entered and one per face decided at the top.
        assert!(w.steps <= 14, "{} steps", w.steps);
    }
}

/// Rays aimed through the corners of the pyramid's nodes: where a ray leaves a
/// node through a corner, f32 rounding can put it a hair short of the other
/// axis's side. The walk once read that as "never gets there" and decided the
/// next node over the whole stretch to the following side — up to metres of a
/// ray dark (or lit) through shafts the map has (found in the `window-shafts`
/// render at 640×360: 3 of 6 lit runs lost on one pixel). Each ray here passes
/// through a node corner of level 2 to 7 of a map with a grid of thin bars (a
/// pergola, many changes per ray), so every such crossing is tried; the runs
/// must match the reference's as in the test above.
#[test]
fn rays_through_node_corners_keep_every_run() {
    let mut rng = Rng(0x00c0_4e85);
    let light = [0.3, 3.0, -0.2];
    let mut occ = Vec::new();
    for k in 0..16 {
        let x = -2.0 + 0.25 * k as f64;
        occ.push(Occluder::Cuboid { min: [x, 2.0, -2.0], max: [x + 0.06, 2.12, 2.0] });
        occ.push(Occluder::Cuboid { min: [-2.0, 2.14, x], max: [2.0, 2.2, x + 0.05] });
    }
    let (mut worst, mut runs, mut tried) = (0.0f64, 0usize, 0usize);
    for map in [
        ShadowMap::spot(light, [0.05, -1.0, 0.1], 0.9, 512, &occ, 1e-3).unwrap(),
        ShadowMap::cube(light, 256, &occ, 1e-3).unwrap(),
    ] {
        let p = map.pyramid();
        for k in 0..400 {
            let f = if map.is_cube() { 3 } else { 0 }; // the cube's −Y face looks down at the bars
            let rows = map.faces[f].rows;
            let level = 2 + k % 6;
            let nodes = (map.res >> level) as f64;
            let corner = |r: &mut Rng| 2.0 * ((r.next() * (nodes - 1.0)).floor() + 1.0) / nodes - 1.0;
            let (cx, cy) = (corner(&mut rng), corner(&mut rng));
            let n2 = |v: [f64; 3]| v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            let q: [f64; 3] =
                std::array::from_fn(|i| cx * rows[0][i] / n2(rows[0]) + cy * rows[1][i] / n2(rows[1]) + rows[2][i]);
            // A point on the corner's line below the bars, and a viewer elsewhere below them.
            let s = rng.range(1.2, 2.8) / -q[1];
            let on = [light[0] + s * q[0], light[1] + s * q[1], light[2] + s * q[2]];
            let origin = [rng.range(-3.0, 3.0), rng.range(0.2, 1.8), rng.range(-3.0, 3.0)];
            let d = [on[0] - origin[0], on[1] - origin[1], on[2] - origin[2]];
            let len = n2(d).sqrt();
            let r = PhysicalRay {
                origin,
                direction: d,
                surface_distance: Some(len * rng.range(1.5, 4.0)),
                light,
                intensity: 1.0,
                sigma_t: 0.1,
                sigma_s: 0.05,
            };
            let want = map.lit_runs(&r);
            let (got, w) = walk_runs(&map, &p, &r);
            assert!(!w.truncated, "ray {k}: truncated after {} steps", w.steps);
            let far = r.surface_distance.unwrap();
            let m = mismatch(&got, &want, far);
            let allow = 1e-4 * far * (1.0 + want.len() as f64);
            assert!(
                m <= allow,
                "ray {k} through a level-{level} corner ({cx}, {cy}) of a {} map: mismatch {m:e}\n got {got:?}\nwant {want:?}",
                if map.is_cube() { "cube" } else { "spot" }
            );
            worst = worst.max(m / far);
            runs += want.len();
            tried += 1;
        }
    }
    assert!(runs > 4 * tried, "the rays must cross the bars' shadows: {runs} runs on {tried} rays");
    eprintln!("{tried} rays through node corners, {runs} runs: worst mismatch / length {worst:e}");
}

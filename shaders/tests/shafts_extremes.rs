//! The physical extreme rays of the gate through the shafts accumulator (issue
//! 24): with a ball between the viewer and the light, fed the exact lit
//! intervals and 16 shadow-map samples, every value is finite and ≥ 0 — in the
//! Rust f32 kernels and, where an adapter is present, in their WGSL on the GPU.

use crate::common;

use airlight_shaders::gate;
use airlight_truth::shafts::{self, Feed, Occluder};

fn f32s(s: &[(f64, f64)]) -> Vec<[f32; 2]> {
    s.iter().map(|&(a, b)| [a as f32, b as f32]).collect()
}

/// The physical extreme rays of the gate through the shafts path, with a ball
/// between the viewer and the light: finite and ≥ 0, no hang.
#[test]
fn extreme_rays_through_the_shafts_path() {
    let compiled = common::compiled();
    let generated = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated");
    let index = gate::load_index(&generated).unwrap();
    let gpu = common::open_or_skip("extreme_rays_through_the_shafts_path (GPU part)");
    for name in ["phi-6", "equiangular-32", "sun2005-64", "phi-8", "raymarch-64"] {
        let entry = index.get(name).unwrap();
        let f = compiled.iter().find(|k| k.name == name).and_then(|k| k.shadowed).expect("compiled");
        let (mut rays, mut fed) = (Vec::new(), Vec::new());
        for (r, _, _) in gate::physical_extremes(entry).unwrap() {
            let phys = r.physical();
            let mid: [f64; 3] = std::array::from_fn(|q| 0.5 * (phys.origin[q] + phys.light[q]));
            let dl = ((phys.light[0] - phys.origin[0]).powi(2)
                + (phys.light[1] - phys.origin[1]).powi(2)
                + (phys.light[2] - phys.origin[2]).powi(2))
            .sqrt();
            let occ = vec![Occluder::Sphere { center: mid, radius: 0.1 * dl.max(1e-30) }];
            for feed in [Feed::Exact, Feed::Samples(16)] {
                let Ok(s) = shafts::feed(&phys, &occ, f64::from(r.g), feed) else { continue };
                let v = f(&f32s(&s), r.surface, r.origin, r.dir, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g);
                assert!(v.is_finite() && v >= 0.0, "{name} {r:?} {feed:?}: {v}");
                rays.push(r);
                fed.push(f32s(&s));
            }
        }
        if let Some(gpu) = &gpu {
            let text = std::fs::read_to_string(generated.join(entry.wgsl.as_deref().unwrap())).unwrap();
            let table = airlight_shaders::load_table(&generated, entry).unwrap();
            let src = airlight_shaders::KernelSource::of(entry, airlight_shapes::vocab::Target::Wgsl, &text)
                .with_table(table.as_ref());
            let got = gpu.shadowed(&src, &rays, &fed).unwrap();
            assert_eq!(got.len(), rays.len());
            for (v, r) in got.iter().zip(&rays) {
                assert!(v.is_finite() && *v >= 0.0, "{name} (WGSL) {r:?}: {v}");
            }
        }
    }
}

/// One case of the shadow-map extremes: a ray and the cube map at its light.
struct MapCase {
    what: String,
    ray: airlight_shaders::Ray,
    map: airlight_truth::shafts::ShadowMap,
    /// The light is sealed inside an occluder the viewer is outside of: no
    /// light may reach the ray.
    sealed: bool,
}

/// The shadow-map extremes: the gate's physical extreme rays (1e-12 … 1e12
/// in scale) with a ball between viewer and light cast into a 32² cube map at
/// the light; and the occluder extremes at a metre's scale — the light on a
/// ball's surface and inside it, the viewer inside it, the ray ending on its
/// surface, and a comb of 150 plates (100+ runs).
fn map_extremes(entry: &airlight_shapes::vocab::IndexEntry) -> Vec<MapCase> {
    use airlight_truth::shafts::ShadowMap;
    let mut out = Vec::new();
    for (r, _, _) in gate::physical_extremes(entry).unwrap() {
        let phys = r.physical();
        let mid: [f64; 3] = std::array::from_fn(|q| 0.5 * (phys.origin[q] + phys.light[q]));
        let dl = (0..3).map(|q| (phys.light[q] - phys.origin[q]).powi(2)).sum::<f64>().sqrt();
        let occ = vec![Occluder::Sphere { center: mid, radius: 0.1 * dl.max(1e-30) }];
        if occ[0].contains(phys.light) {
            continue;
        }
        if let Ok(map) = ShadowMap::cube(phys.light, 32, &occ, 0.0) {
            out.push(MapCase { what: format!("extreme {r:?}"), ray: r, map, sealed: false });
        }
    }
    let base = airlight_shaders::Ray {
        origin: [0.0, 0.0, -4.0],
        dir: [0.0, 0.0, 1.0],
        surface: -1.0,
        light: [0.0, 0.5, 2.0],
        intensity: 10.0,
        sigma_t: 0.3,
        sigma_s: 0.2,
        g: 0.0,
    };
    let f = |v: [f32; 3]| v.map(f64::from);
    let light = f(base.light);
    let ball = |c: [f64; 3], r: f64| vec![Occluder::Sphere { center: c, radius: r }];
    let mut add = |what: &str, ray: airlight_shaders::Ray, occ: Vec<Occluder>, sealed: bool| {
        let map = ShadowMap::cube(f(ray.light), 64, &occ, 0.0).unwrap();
        out.push(MapCase { what: what.into(), ray, map, sealed });
    };
    for dir in [[0.0, 0.0, 1.0], [0.3, 0.1, 1.0], [0.0, 0.125, 1.0], [-0.2, 0.0, -1.0]] {
        let r = airlight_shaders::Ray { dir, ..base };
        let (o, unit) = (f(r.origin), {
            let n = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
            f(dir).map(|x| x / f64::from(n))
        });
        add("light on the ball's surface", r, ball([light[0], light[1], light[2] + 0.5], 0.5), false);
        add("light on the ball's surface, below", r, ball([light[0], light[1] - 0.5, light[2]], 0.5), false);
        // A sealed light: the ray ends 1% before it would meet the ball, so all
        // of it is outside (on the ball's surface itself the nearest-texel test
        // lights a sliver a texel's curvature deep: the inside is lit).
        let sealed = ball([light[0] + 0.1, light[1], light[2]], 0.5);
        let end = sealed[0].enters(o, unit).map_or(-1.0, |t| (0.99 * t) as f32);
        add("light inside the ball", airlight_shaders::Ray { surface: end, ..r }, sealed, true);
        add("viewer inside the ball", r, ball([0.0, 0.1, -4.0], 1.0), false);
        let occ = ball([0.0, 0.2, 0.0], 0.6);
        if let Some(t) = occ[0].enters(o, unit) {
            add("ray ending on the ball's surface", airlight_shaders::Ray { surface: t as f32, ..r }, occ, false);
        }
    }
    // A comb of 150 plates 1.2 cm thick with 2.3 cm gaps, the ray 2 cm below
    // their tops and the light 2.5 m above: lit in nearly every gap, on a 512²
    // cube map (1 cm texels at the plates).
    let comb: Vec<Occluder> = (0..150)
        .map(|i| {
            let z = -3.5 + 0.035 * i as f64;
            Occluder::Cuboid { min: [-3.0, -3.0, z], max: [3.0, 0.02, z + 0.012] }
        })
        .collect();
    let ray = airlight_shaders::Ray { light: [0.0, 2.5, -0.9], ..base };
    let map = ShadowMap::cube(f(ray.light), 512, &comb, 0.0).unwrap();
    out.push(MapCase { what: "a comb of 150 plates".into(), ray, map, sealed: false });
    out
}

/// The exact mode at the extremes: the Rust f32 walk and accumulator and, where
/// an adapter is present, the WGSL walk fused with the accumulator, over
/// [`map_extremes`]: finite and ≥ 0, no hang (the walk is bounded; truncations
/// are counted), nothing at all where the light is sealed inside a ball.
#[test]
fn extreme_rays_through_the_shadow_map_walk() {
    use airlight_shaders::shafts::map_cases::{run_samples, rust_runs, upload};
    let compiled = common::compiled();
    let generated = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated");
    let index = gate::load_index(&generated).unwrap();
    let gpu = common::open_or_skip("extreme_rays_through_the_shadow_map_walk (GPU part)");
    let texts = airlight_shaders::shafts::WalkTexts::load(&generated).unwrap();
    for name in ["phi-6", "lite-4"] {
        let entry = index.get(name).unwrap();
        let ck = compiled.iter().find(|k| k.name == name).unwrap();
        let (f, walk) = (ck.shadowed.unwrap(), ck.walk.unwrap());
        let cases = map_extremes(entry);
        assert!(cases.len() >= 40, "{name}: {} cases", cases.len());
        let (mut truncated, mut most_runs) = (0, 0);
        for c in &cases {
            let r = &c.ray;
            let (runs, _, cut) = rust_runs(walk, &c.map, &c.map.pyramid(), r);
            truncated += usize::from(cut);
            most_runs = most_runs.max(runs.len());
            let v = f(&run_samples(&runs), r.surface, r.origin, r.dir, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g);
            assert!(v.is_finite() && v >= 0.0, "{name} {}: {v}", c.what);
            if c.sealed {
                assert!(runs.is_empty() && v == 0.0, "{name} {}: runs {runs:?}, {v}", c.what);
            }
        }
        eprintln!("{name}: {} cases, {truncated} truncated, at most {most_runs} runs", cases.len());
        assert!(most_runs >= 100, "the comb gives 100+ runs ({most_runs})");
        let Some(gpu) = &gpu else { continue };
        let text = std::fs::read_to_string(generated.join(entry.wgsl.as_deref().unwrap())).unwrap();
        let table = airlight_shaders::load_table(&generated, entry).unwrap();
        let src = airlight_shaders::KernelSource::of(entry, airlight_shapes::vocab::Target::Wgsl, &text)
            .with_table(table.as_ref());
        // Maps of one size share an array (at most 40 maps, 240 layers, a dispatch).
        for res in [32, 64, 512] {
            let same: Vec<&MapCase> = cases.iter().filter(|c| c.map.res == res).collect();
            for batch in same.chunks(40) {
                let maps: Vec<_> = batch.iter().map(|c| &c.map).collect();
                let (pyramid, specs) = upload(gpu, texts.sources().pyramid, &maps).unwrap();
                let rays: Vec<_> = batch.iter().map(|c| c.ray).collect();
                let got = gpu.mapped(&src, &texts.sources(), &rays, &specs, &pyramid).unwrap();
                for (g, c) in got.iter().zip(batch) {
                    assert!(g.value.is_finite() && g.value >= 0.0, "{name} (WGSL) {}: {g:?}", c.what);
                    if c.sealed {
                        assert_eq!(g.value, 0.0, "{name} (WGSL) {}", c.what);
                    }
                }
            }
        }
    }
}

/// The spot entry's extreme rays (the gate's: the light on the ray's line at
/// 0, 1e-30, 1e-12 … of its distance off it, ahead and behind, toward and away
/// from the viewer, sharp and smooth cones, open rays and surfaces, and sampled
/// rays over the physical extremes) through the shadow-map walk: a ball midway
/// between viewer and light casts into the spot's one-face map (64², over the
/// outer cone), the compiled Rust walk's runs go to the spot accumulator, and
/// the WGSL walk over the same maps feeds the WGSL one. Every value finite and
/// non-negative, and never more than the unshadowed spot entry gives beyond the
/// kernel's bound once per run (each run is a call of the kernel).
#[test]
fn extreme_spot_rays_through_the_shadow_map_walk() {
    use airlight_shaders::shafts::map_cases::{run_samples, rust_runs, upload};
    use airlight_truth::shafts::ShadowMap;
    let compiled = common::compiled();
    let generated = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated");
    let index = gate::load_index(&generated).unwrap();
    let gpu = common::open_or_skip("extreme_spot_rays_through_the_shadow_map_walk (GPU part)");
    let texts = airlight_shaders::shafts::WalkTexts::load(&generated).unwrap();
    for name in ["phi-6", "lite-4"] {
        let entry = index.get(name).unwrap();
        let ck = compiled.iter().find(|k| k.name == name).unwrap();
        let (Some(f), Some(walk), Some(plain)) = (ck.spot_shadowed, ck.walk, ck.spot) else {
            panic!("{name}: no spot accumulator")
        };
        let models = airlight_fit::catalog::load(&generated.join("coefficients")).unwrap();
        let bound = airlight_shapes::vocab::f32_limit(gate::declared_max(entry, &models).unwrap());
        let mut cases = Vec::new();
        for c in gate::spot_rays(entry, 24, 39).unwrap() {
            let r = c.ray;
            let Some(cone) = r.cone() else { continue };
            let ray = r.physical(0);
            let mid: [f64; 3] = std::array::from_fn(|q| 0.5 * (ray.origin[q] + ray.light[q]));
            let dl = (0..3).map(|q| (ray.light[q] - ray.origin[q]).powi(2)).sum::<f64>().sqrt();
            let occ = vec![Occluder::Sphere { center: mid, radius: 0.1 * dl.max(1e-30) }];
            if occ[0].contains(ray.light) {
                continue;
            }
            let tan_half = cone.cos_outer.clamp(89.5f64.to_radians().cos(), 1.0).acos().tan().max(1e-6);
            if let Ok(map) = ShadowMap::spot(ray.light, cone.axis, 1.05 * tan_half, 64, &occ, 0.0) {
                cases.push((r, map));
            }
        }
        assert!(cases.len() >= 30, "{name}: {} cases", cases.len());
        let mut most_runs = 0;
        for (r, map) in &cases {
            let as_ray = airlight_shaders::Ray {
                origin: r.origin,
                dir: r.dir,
                surface: r.surface,
                light: r.light,
                intensity: r.intensity,
                sigma_t: r.sigma_t[0],
                sigma_s: r.sigma_s[0],
                g: r.g,
            };
            let (runs, _, _) = rust_runs(walk, map, &map.pyramid(), &as_ray);
            most_runs = most_runs.max(runs.len());
            let args = (r.surface, r.origin, r.dir, r.light, r.axis, r.cos_outer, r.cos_inner, r.intensity);
            let v = f(
                &run_samples(&runs),
                args.0,
                args.1,
                args.2,
                args.3,
                args.4,
                args.5,
                args.6,
                args.7,
                r.sigma_t,
                r.sigma_s,
                r.g,
            );
            let open = plain(args.1, args.2, args.0, args.3, args.4, args.5, args.6, args.7, r.sigma_t, r.sigma_s, r.g);
            for c in 0..3 {
                assert!(v[c].is_finite() && v[c] >= 0.0, "{name} {r:?}: {v:?}");
                let most =
                    f64::from(open[c]) * (1.0 + 2.0 * bound * (1.0 + runs.len() as f64)) + f64::from(f32::MIN_POSITIVE);
                assert!(
                    f64::from(v[c]) <= most,
                    "{name} {r:?}: shadowed {v:?} above unshadowed {open:?} ({} runs)",
                    runs.len()
                );
            }
        }
        eprintln!("{name}: {} spot cases through the walk, at most {most_runs} runs", cases.len());
        let Some(gpu) = &gpu else { continue };
        let text = std::fs::read_to_string(generated.join(entry.wgsl.as_deref().unwrap())).unwrap();
        let table = airlight_shaders::load_table(&generated, entry).unwrap();
        let src = airlight_shaders::KernelSource::of(entry, airlight_shapes::vocab::Target::Wgsl, &text)
            .with_table(table.as_ref());
        for batch in cases.chunks(40) {
            let maps: Vec<_> = batch.iter().map(|c| &c.1).collect();
            let (pyramid, specs) = upload(gpu, texts.sources().pyramid, &maps).unwrap();
            let rays: Vec<_> = batch.iter().map(|c| c.0).collect();
            let got = gpu.spot_mapped(&src, &texts.sources(), &rays, &specs, &pyramid).unwrap();
            for (g, c) in got.iter().zip(batch) {
                assert!(g.value.iter().all(|x| x.is_finite() && *x >= 0.0), "{name} (WGSL) {:?}: {g:?}", c.0);
            }
        }
    }
}

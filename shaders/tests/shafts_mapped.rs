//! The exact mode on the GPU adapter: the shipped pyramid pass builds the same
//! min-max pyramid as the reference, bit for bit, and a kernel's accumulator fed
//! the walk's runs in WGSL and GLSL matches the in-scattering over the same
//! map's exact runs (f64) to the kernel's f32 bound times (1 + changes), as the
//! Rust walk does.

use crate::common;

use airlight_shaders::shafts::map_cases::{self, run_samples, rust_runs, upload};
use airlight_shaders::shafts::WalkTexts;
use airlight_shaders::{gate, KernelSource};
use airlight_shapes::vocab::{Domain, Target};
use airlight_truth::shafts::{Occluder, ShadowMap};

fn generated() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated")
}

#[test]
fn the_pyramid_pass_builds_the_reference_pyramid() {
    let Some(gpu) = common::open_or_skip("the_pyramid_pass_builds_the_reference_pyramid") else { return };
    let walk = WalkTexts::load(&generated()).unwrap();
    let occ = vec![
        Occluder::Sphere { center: [1.0, 0.5, 0.2], radius: 0.4 },
        Occluder::Cuboid { min: [-2.0, -0.5, -1.0], max: [-1.5, 2.0, 1.0] },
    ];
    // 1²: level 0 alone (airlight_pyramid_base); 2²: the fused first two levels
    // and nothing after; 64²: the fused pass, then a reduce per level.
    for res in [1, 2, 64] {
        let cube = ShadowMap::cube([0.0, 0.3, 0.0], res, &occ, 0.0).unwrap();
        let spot = ShadowMap::spot([0.0, 0.3, 0.0], [1.0, 0.0, 0.1], 0.7, res, &occ, 0.0).unwrap();
        let (p, specs) = upload(&gpu, walk.sources().pyramid, &[&cube, &spot]).unwrap();
        assert_eq!(specs[1].layer, 6);
        let got = gpu.read_pyramid(&p).unwrap();
        let (want_cube, want_spot) = (cube.pyramid(), spot.pyramid());
        assert_eq!(got.len(), 7);
        for (f, face) in got.iter().enumerate() {
            let want = if f < 6 { &want_cube.levels[f] } else { &want_spot.levels[0] };
            assert_eq!(face.len(), res.trailing_zeros() as usize + 1, "{res}²: layer {f}'s levels");
            assert_eq!(face, want, "{res}²: layer {f}");
        }
    }
}

#[test]
fn the_walk_feeds_the_accumulator_the_maps_runs_on_every_target() {
    let compiled = common::compiled();
    let index = gate::load_index(&generated()).unwrap();
    let k = index.get("phi-6").unwrap();
    // The recorded gate's f32 bounds of phi-6 (what its shadowed rows are held to).
    let text = std::fs::read_to_string(generated().join("gate.toml")).unwrap();
    let record = airlight_shapes::record::GateRecord::from_toml("gate.toml", &text).unwrap();
    let bound =
        [Domain::Thin, Domain::Dense].into_iter().filter_map(|d| record.f32_bound("phi-6", d)).fold(0.0, f64::max);
    assert!(bound > 0.0, "phi-6 has recorded f32 bounds");
    let cases = map_cases::map_cases(k, 24, 128, 0x39).unwrap();
    let ck = compiled.iter().find(|c| c.name == "phi-6").unwrap();
    let rel = |v: f64, c: &map_cases::MapCase| (v - c.reference).abs() / (c.case.unshadowed * (1.0 + c.changes as f64));
    let mut worst = 0.0f64;
    let mut changes = 0;
    for c in &cases {
        let r = &c.case.ray;
        let (runs, _, truncated) = rust_runs(ck.walk.unwrap(), &c.map, &c.map.pyramid(), r);
        assert!(!truncated);
        let s = run_samples(&runs);
        let v = (ck.shadowed.unwrap())(&s, r.surface, r.origin, r.dir, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g);
        let e = rel(f64::from(v), c);
        assert!(e <= bound, "Rust: {e:e} > {bound:e} on {r:?}");
        worst = worst.max(e);
        changes += c.changes;
    }
    assert!(changes >= 24, "the rays must cross shadows ({changes} changes)");
    eprintln!("Rust: worst {worst:e} (bound {bound:e})");
    let Some(gpu) = common::open_or_skip("the_walk_feeds_the_accumulator (GPU part)") else { return };
    let walk = WalkTexts::load(&generated()).unwrap();
    let maps: Vec<&ShadowMap> = cases.iter().map(|c| &c.map).collect();
    let rays: Vec<_> = cases.iter().map(|c| c.case.ray).collect();
    for t in [Target::Wgsl, Target::Glsl] {
        let text = std::fs::read_to_string(generated().join(k.file(t).unwrap())).unwrap();
        let src = KernelSource::of(k, t, &text);
        let (p, specs) = upload(&gpu, walk.sources().pyramid, &maps).unwrap();
        let got = gpu.mapped(&src, &walk.sources(), &rays, &specs, &p).unwrap();
        let mut worst = 0.0f64;
        for (m, c) in got.iter().zip(&cases) {
            assert!(m.steps > 0.0, "{t:?}: truncated or no walk: {}", m.steps);
            let e = rel(f64::from(m.value), c);
            assert!(e <= bound, "{t:?}: {e:e} > {bound:e} on {:?}", c.case.ray);
            worst = worst.max(e);
        }
        eprintln!("{t:?}: worst {worst:e}");
    }
}

/// The street lamp behind railings (the bench's scene) at 512² per face: the
/// walk leaks on no ray, never runs out of steps, and its error against the
/// analytic occluders is below the 256-step march's with exact look-ups.
#[test]
fn the_street_lamp_through_its_cube_map_leaks_nowhere() {
    use airlight_shaders::shafts::map_bench::{lamp_rays, lamp_scene, LAMP};
    use airlight_truth::shafts::{self, Feed};
    let compiled = common::compiled();
    let k = compiled.iter().find(|c| c.name == "phi-8").unwrap();
    let march = compiled.iter().find(|c| c.name == "raymarch-256").unwrap();
    let occ = lamp_scene();
    let map = ShadowMap::cube(LAMP, 512, &occ, 0.0).unwrap();
    let p = map.pyramid();
    let a = |q: airlight_truth::reference::Point| airlight_truth::reference::airlight(q).unwrap();
    let (mut walk_sum, mut march_sum, mut changes) = (0.0, 0.0, 0);
    for r in lamp_rays().iter().step_by(4) {
        let phys = r.physical();
        let lit = shafts::lit_intervals(&phys, &occ);
        changes += lit.len();
        let want = shafts::shadowed_radiance(&phys, None, f64::from(r.g), &lit, &a).unwrap();
        let u = phys.radiance(f64::from(r.g), &a).unwrap();
        let (runs, steps, truncated) = rust_runs(k.walk.unwrap(), &map, &p, r);
        assert!(!truncated && steps < 4096);
        let s = run_samples(&runs);
        let v = f64::from((k.shadowed.unwrap())(
            &s,
            r.surface,
            r.origin,
            r.dir,
            r.light,
            r.intensity,
            r.sigma_t,
            r.sigma_s,
            r.g,
        ));
        assert!(v <= 1.5 * want + 0.05 * u, "leak: {v} against {want} (U {u}) on {r:?}");
        let fed: Vec<[f32; 2]> = shafts::feed(&phys, &occ, f64::from(r.g), Feed::LookUps(256))
            .unwrap()
            .iter()
            .map(|&(x, y)| [x as f32, y as f32])
            .collect();
        let m = f64::from((march.shadowed.unwrap())(
            &fed,
            r.surface,
            r.origin,
            r.dir,
            r.light,
            r.intensity,
            r.sigma_t,
            r.sigma_s,
            r.g,
        ));
        walk_sum += (v - want).abs() / u;
        march_sum += (m - want).abs() / u;
    }
    assert!(changes > 200, "the railing must cut the rays ({changes} lit runs)");
    assert!(walk_sum < march_sum, "walk {walk_sum:e} against march {march_sum:e}");
    eprintln!("mean error of U over 64 rays: walk {:.3e}, raymarch-256 {:.3e}", walk_sum / 64.0, march_sum / 64.0);
}

/// The shadow-map rows' bound under an adversarial search: the gate's kind of
/// cases (rays among spheres, each cast into a 128² cube map), the six whose
/// Rust f32 error (walk and accumulator, against the f64 reference over the same
/// map's exact runs, relative to the unshadowed value times one plus the
/// changes) is largest, each moved by a compass search over its origin and
/// direction (steps from 1% down to 1e-6, the map held) toward a larger error;
/// the largest found stays within the kernel's recorded f32 bound (phi-6, lite-4).
#[test]
fn the_shadow_map_bound_survives_a_local_search_from_the_worst_rays() {
    use airlight_truth::reference;
    let compiled = common::compiled();
    let index = gate::load_index(&generated()).unwrap();
    let text = std::fs::read_to_string(generated().join("gate.toml")).unwrap();
    let record = airlight_shapes::record::GateRecord::from_toml("gate.toml", &text).unwrap();
    for name in ["phi-6", "lite-4"] {
        let k = index.get(name).unwrap();
        let bound =
            [Domain::Thin, Domain::Dense].into_iter().filter_map(|d| record.f32_bound(name, d)).fold(0.0, f64::max);
        assert!(bound > 0.0, "{name} has recorded f32 bounds");
        let ck = compiled.iter().find(|c| c.name == name).unwrap();
        let (f, walk) = (ck.shadowed.unwrap(), ck.walk.unwrap());
        let a = |q: reference::Point| reference::airlight(q).unwrap_or(f64::NAN);
        // The error of ray r through map (None where the reference is out of range).
        let error = |r: &airlight_shaders::Ray, map: &ShadowMap| -> Option<f64> {
            let phys = r.physical();
            let g = f64::from(r.g);
            let unshadowed = phys.radiance(g, &a).ok()?;
            let runs = map.lit_runs(&phys);
            let stop = phys.surface_distance.unwrap_or(f64::INFINITY);
            let changes: usize = runs.iter().map(|&(a, b)| usize::from(a > 0.0) + usize::from(b < stop)).sum();
            let want = airlight_truth::shafts::shadowed_radiance(&phys, None, g, &runs, &a).ok()?;
            if !(unshadowed > 1e-30 && unshadowed < 1e30 && want.is_finite()) {
                return None;
            }
            let (got, _, truncated) = rust_runs(walk, map, &map.pyramid(), r);
            assert!(!truncated, "{r:?}: the walk ran out of steps");
            let v = f64::from(f(
                &run_samples(&got),
                r.surface,
                r.origin,
                r.dir,
                r.light,
                r.intensity,
                r.sigma_t,
                r.sigma_s,
                r.g,
            ));
            assert!(v.is_finite() && v >= 0.0, "{r:?}: {v}");
            Some((v - want).abs() / (unshadowed * (1.0 + changes as f64)))
        };
        let cases = map_cases::map_cases(k, 64, 128, 0x39A).unwrap();
        let mut scored: Vec<(f64, usize)> =
            cases.iter().enumerate().filter_map(|(i, c)| error(&c.case.ray, &c.map).map(|e| (e, i))).collect();
        scored.sort_by(|x, y| y.0.total_cmp(&x.0));
        let mut worst = (0.0f64, None);
        for &(start, i) in scored.iter().take(6) {
            let map = &cases[i].map;
            let mut r = cases[i].case.ray;
            let mut e = start;
            let scale = {
                let d: Vec<f32> = (0..3).map(|q| r.light[q] - r.origin[q]).collect();
                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
            };
            for step in [1e-2f32, 1e-3, 1e-4, 1e-5, 1e-6] {
                let mut moved = true;
                while moved {
                    moved = false;
                    for p in 0..6 {
                        for sign in [1.0f32, -1.0] {
                            let mut t = r;
                            if p < 3 {
                                t.origin[p] += sign * step * scale;
                            } else {
                                t.dir[p - 3] += sign * step;
                            }
                            if let Some(et) = error(&t, map) {
                                if et > e {
                                    (r, e, moved) = (t, et, true);
                                }
                            }
                        }
                    }
                }
            }
            eprintln!("from {start:e} to {e:e}");
            if e > worst.0 {
                worst = (e, Some(r));
            }
        }
        eprintln!("{name} shadow-map rays, worst after the search: {:e} (bound {bound:e}) on {:?}", worst.0, worst.1);
        assert!(worst.0 <= bound, "{name}: {:e} > {bound:e} on {:?}", worst.0, worst.1);
    }
}

/// A ray past a fence of 48 posts has more lit runs than the accumulator holds
/// (32): the shipped loop leaves the walk to flush the full buffer and walks on.
/// On WGSL and GLSL the value matches the in-scattering over the map's exact
/// runs as closely as the Rust walk's does, and the ray really has more runs
/// than the buffer.
#[test]
fn a_walk_with_more_runs_than_the_buffer_flushes_and_goes_on() {
    use airlight_shaders::Ray;
    let compiled = common::compiled();
    let index = gate::load_index(&generated()).unwrap();
    let k = index.get("phi-6").unwrap();
    let ck = compiled.iter().find(|c| c.name == "phi-6").unwrap();
    let light = [0.0f64, 2.0, 0.0];
    let occ: Vec<Occluder> = (0..48)
        .map(|i| {
            let x = -6.0 + 0.25 * f64::from(i);
            Occluder::Cuboid { min: [x, 0.0, 1.0], max: [x + 0.05, 1.5, 1.01] }
        })
        .collect();
    let map = ShadowMap::cube(light, 1024, &occ, 0.0).unwrap();
    // Along the fence's shadows on the plane z = 1.5, at knee height.
    let ray = Ray {
        origin: [-9.0, 0.4, 1.5],
        dir: [1.0, 0.0, 0.0],
        surface: 18.0,
        light: light.map(|x| x as f32),
        intensity: 40.0,
        sigma_t: 0.1,
        sigma_s: 0.08,
        g: 0.5,
    };
    let (runs, _, truncated) = rust_runs(ck.walk.unwrap(), &map, &map.pyramid(), &ray);
    assert!(!truncated);
    assert!(runs.len() > 40, "the ray must cross the fence's shadows: {} runs", runs.len());
    let phys = ray.physical();
    let want_runs: Vec<(f64, f64)> = map.lit_runs(&phys);
    let a = |q: airlight_truth::reference::Point| airlight_truth::reference::airlight(q).unwrap();
    let want = airlight_truth::shafts::shadowed_radiance(&phys, None, f64::from(ray.g), &want_runs, &a).unwrap();
    let s = run_samples(&runs);
    let r = ray;
    let rust = f64::from((ck.shadowed.unwrap())(
        &s,
        r.surface,
        r.origin,
        r.dir,
        r.light,
        r.intensity,
        r.sigma_t,
        r.sigma_s,
        r.g,
    ));
    let e_rust = (rust - want).abs() / want;
    assert!(e_rust < 1e-3, "Rust: {e_rust:e}");
    let Some(gpu) = common::open_or_skip("a_walk_with_more_runs_than_the_buffer (GPU part)") else { return };
    let walk = WalkTexts::load(&generated()).unwrap();
    for t in [Target::Wgsl, Target::Glsl] {
        let text = std::fs::read_to_string(generated().join(k.file(t).unwrap())).unwrap();
        let src = KernelSource::of(k, t, &text);
        let (p, specs) = upload(&gpu, walk.sources().pyramid, &[&map]).unwrap();
        let got = gpu.mapped(&src, &walk.sources(), &[ray], &specs, &p).unwrap();
        let e = (f64::from(got[0].value) - want).abs() / want;
        assert!(got[0].steps > 0.0, "{t:?}: truncated");
        assert!(e <= 2.0 * e_rust + 1e-5, "{t:?}: {e:e} against Rust's {e_rust:e}");
        eprintln!("{t:?}: {e:e} (Rust {e_rust:e}, {} runs)", runs.len());
    }
}

//! The shafts accumulator of the generated Rust kernels against the shadowed
//! reference: exact lit intervals, soft visibility, refinement, the spot entry,
//! the march (the extreme rays through it: shaders/tests/shafts_extremes.rs).

use airlight_kernels::{Kernel, KERNELS};
use airlight_truth::geometry::{Cone, PhysicalRay};
use airlight_truth::reference::{self, Point};
use airlight_truth::shafts::{self, Feed, Occluder};

fn kernel(name: &str) -> &'static Kernel {
    KERNELS.iter().find(|k| k.name == name).unwrap_or_else(|| panic!("kernel {name} is generated"))
}

fn f32s(s: &[(f64, f64)]) -> Vec<[f32; 2]> {
    s.iter().map(|&(a, b)| [a as f32, b as f32]).collect()
}

/// Deterministic rays among 1–3 balls between the light and the ray.
fn scenes() -> Vec<(PhysicalRay, f64, Vec<Occluder>)> {
    let mut rng = airlight_truth::domains::SplitMix64(0x5AF7);
    let mut out = Vec::new();
    for i in 0..40 {
        let d = [1.0, 0.3 * (rng.next_f64() - 0.5), 0.3 * (rng.next_f64() - 0.5)];
        let light = [2.0 + 20.0 * rng.next_f64(), 1.0 + 5.0 * rng.next_f64(), 3.0 * (rng.next_f64() - 0.5)];
        let surface = if i % 3 == 0 { None } else { Some(5.0 + 40.0 * rng.next_f64()) };
        let ray = PhysicalRay {
            origin: [0.0; 3],
            direction: d,
            surface_distance: surface,
            light,
            intensity: 2.0,
            sigma_t: 0.01 + 0.2 * rng.next_f64(),
            sigma_s: 0.05,
        };
        let mut occ = Vec::new();
        for _ in 0..1 + i % 3 {
            let s = 30.0 * rng.next_f64();
            let u = 0.3 + 0.5 * rng.next_f64();
            let c: [f64; 3] = std::array::from_fn(|q| light[q] + u * (s * d[q] - light[q]));
            occ.push(Occluder::Sphere { center: c, radius: 0.2 + 0.8 * rng.next_f64() });
        }
        let g = 1.6 * rng.next_f64() - 0.8;
        out.push((ray, g, occ));
    }
    out
}

#[test]
fn exact_intervals_hold_the_kernels_bounds() {
    let a = |p: Point| reference::airlight(p).unwrap();
    for name in ["phi-6", "phi-8", "equiangular-32", "segments-8"] {
        let k = kernel(name);
        let f = k.shadowed.expect("shafts accumulator");
        let tol = k.thin_max_rel.max(k.dense_max_rel) * (1.0 + 1e-4) + 1e-4;
        for (ray, g, occ) in scenes() {
            let g = if name == "segments-8" { 0.0 } else { g };
            let lit = shafts::lit_intervals(&ray, &occ);
            let want = shafts::shadowed_radiance(&ray, None, g, &lit, &a).unwrap();
            let unshadowed = ray.radiance(g, &a).unwrap();
            let s = f32s(&shafts::exact_samples(&ray, &lit));
            let end = ray.surface_distance.map_or(-1.0, |x| x as f32);
            let d = ray.direction.map(|x| x as f32);
            let l = ray.light.map(|x| x as f32);
            let got = f64::from(f(&s, end, [0.0; 3], d, l, 2.0, ray.sigma_t as f32, 0.05, g as f32));
            let e = (got - want).abs() / unshadowed;
            assert!(e <= tol, "{name} {ray:?} g {g}: {got} vs {want} (unshadowed {unshadowed}): {e:.2e}");
        }
    }
}

/// Soft visibility (fractional, as PCF gives) and bisection: the f32 kernel
/// follows the f64 accumulator on the same samples, and refinement brings the
/// sampled answer towards the exact one.
#[test]
fn soft_visibility_and_refinement() {
    let a = |p: Point| reference::airlight(p).unwrap();
    let k = kernel("phi-8");
    let f = k.shadowed.unwrap();
    let (mut before, mut after) = (0.0f64, 0.0f64); // summed errors
    for (ray, g, occ) in scenes() {
        let len = shafts::march_length(&ray, g).unwrap();
        let hard = shafts::samples(&ray, &occ, 16, len);
        // PCF-like: a sample's visibility averaged with its neighbours'.
        let soft: Vec<(f64, f64)> = hard
            .iter()
            .enumerate()
            .map(|(i, &(s, v))| {
                let l = hard[i.saturating_sub(1)].1;
                let r = hard[(i + 1).min(hard.len() - 1)].1;
                (s, 0.25 * l + 0.5 * v + 0.25 * r)
            })
            .collect();
        let (want, _) = shafts::evaluate(&ray, None, g, &soft, &a, false).unwrap();
        let end = ray.surface_distance.map_or(-1.0, |x| x as f32);
        let d = ray.direction.map(|x| x as f32);
        let l = ray.light.map(|x| x as f32);
        let got = f64::from(f(&f32s(&soft), end, [0.0; 3], d, l, 2.0, ray.sigma_t as f32, 0.05, g as f32));
        let unshadowed = ray.radiance(g, &a).unwrap();
        assert!((got - want).abs() <= 2e-5 * unshadowed, "soft: {got} vs {want}");
        // Refinement with the f32 kernel's own accumulator.
        let exact = shafts::shadowed_radiance(&ray, None, g, &shafts::lit_intervals(&ray, &occ), &a).unwrap();
        let m = airlight_kernels::phi_8::Shafts::new();
        let run = |k: usize| {
            let mut acc = m;
            for &(s, v) in &hard {
                acc.push(s as f32, v as f32, [0.0; 3], d, l, 2.0, ray.sigma_t as f32, 0.05, g as f32);
                for _ in 0..k {
                    let p = acc.probe();
                    if p < 0.0 {
                        break;
                    }
                    acc.refine(if shafts::visible(&ray, &occ, f64::from(p)) { 1.0 } else { 0.0 });
                }
            }
            f64::from(acc.finish(end, [0.0; 3], d, l, 2.0, ray.sigma_t as f32, 0.05, g as f32))
        };
        let (e0, e16) = ((run(0) - exact).abs() / unshadowed, (run(16) - exact).abs() / unshadowed);
        // Per ray refinement need not help: a shadow no sample saw stays missed,
        // and placing one of two changes in a bracket exactly can undo the
        // cancellation of their midpoint errors. Over the rays it must.
        before += e0;
        after += e16;
    }
    assert!(after < before / 2.0, "mean error unrefined {before:.2e}, 16 bisections {after:.2e} (sums)");
}

/// The spot entry's accumulator, and the march's (the engines' way) against the
/// f64 march on the same samples.
#[test]
fn spot_and_march() {
    let a = |p: Point| reference::airlight(p).unwrap();
    let cone =
        Cone { axis: [0.3, -1.0, 0.1], cos_outer: 40f64.to_radians().cos(), cos_inner: 25f64.to_radians().cos() };
    let k = kernel("phi-8");
    let f = k.spot_shadowed.expect("spot accumulator");
    let march = kernel("raymarch-32").shadowed.unwrap();
    for (ray, g, occ) in scenes().into_iter().take(20) {
        let lit = shafts::lit_intervals(&ray, &occ);
        let want = shafts::shadowed_radiance(&ray, Some(&cone), g, &lit, &a).unwrap();
        let unshadowed = ray.spot_radiance(&cone, g, &a).unwrap();
        let s = f32s(&shafts::exact_samples(&ray, &lit));
        let end = ray.surface_distance.map_or(-1.0, |x| x as f32);
        let d = ray.direction.map(|x| x as f32);
        let l = ray.light.map(|x| x as f32);
        let st = ray.sigma_t as f32;
        let ax = cone.axis.map(|x| x as f32);
        let got = f(
            &s,
            end,
            [0.0; 3],
            d,
            l,
            ax,
            cone.cos_outer as f32,
            cone.cos_inner as f32,
            2.0,
            [st; 3],
            [0.05; 3],
            g as f32,
        );
        for c in got {
            assert!((f64::from(c) - want).abs() <= 2e-4 * unshadowed.max(1e-30), "spot: {c} vs {want}");
        }
        let samples = shafts::feed(&ray, &occ, g, Feed::LookUps(32)).unwrap();
        let m64 = shafts::march(&ray, None, g, &samples);
        let m32 = f64::from(march(&f32s(&samples), end, [0.0; 3], d, l, 2.0, st, 0.05, g as f32));
        assert!((m32 - m64).abs() <= 1e-4 * m64.abs().max(1e-30), "march: {m32} vs {m64}");
    }
}

/// Past the 32 held runs (issue 37): a walk that flushes when the buffer is full
/// sums any number of runs exactly; one that does not is told how many runs were
/// merged, so nothing is lost silently.
#[test]
fn past_the_held_runs_a_flush_is_exact_and_a_merge_is_counted() {
    use airlight_kernels::phi_8::Shafts;
    let occ: Vec<Occluder> = (0..100)
        .map(|k| Occluder::Sphere { center: [0.5 * (f64::from(k) + 0.5) + 25.0, 20.0, 0.0], radius: 0.08 })
        .collect();
    let ray = PhysicalRay {
        origin: [0.0; 3],
        direction: [1.0, 0.0, 0.0],
        surface_distance: Some(100.0),
        light: [50.0, 40.0, 0.0],
        intensity: 1.0,
        sigma_t: 0.02,
        sigma_s: 0.02,
    };
    let lit = shafts::lit_intervals(&ray, &occ);
    assert_eq!(lit.len(), 101);
    let a = |p: Point| reference::airlight(p).unwrap();
    let want = shafts::shadowed_radiance(&ray, None, 0.3, &lit, &a).unwrap();
    let args = ([0.0f32; 3], [1.0f32, 0.0, 0.0], [50.0f32, 40.0, 0.0], 1.0f32, 0.02f32, 0.02f32, 0.3f32);
    let (o, d, l, i, st, ss, g) = args;
    for flush in [true, false] {
        let mut acc = Shafts::new();
        for [s, v] in f32s(&shafts::exact_samples(&ray, &lit)) {
            acc.push(s, v, o, d, l, i, st, ss, g);
            if flush && acc.full() {
                acc.flush(o, d, l, i, st, ss, g);
            }
        }
        let merged = acc.merged();
        let got = f64::from(acc.finish(100.0, o, d, l, i, st, ss, g));
        let e = (got / want - 1.0).abs();
        if flush {
            assert_eq!(merged, 0);
            assert!(e < 2e-5, "flushed: {got} against {want}: {e:.2e}");
        } else {
            // The last run is the one `finish` closes at the surface, never held.
            assert_eq!(merged, 101 - 32 - 1, "every held run past the 32 is counted");
            assert!(e > 1e-3, "merged: {got} against {want}: {e:.2e} (the merge is not exact)");
        }
    }
}

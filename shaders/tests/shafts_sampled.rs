//! The shafts accumulator against the engines' march on the same shadow-map
//! look-ups (issue 24): on held-out shadowed rays (the gate's generator with
//! seeds neither the gate nor the bench uses), `phi-8`'s f32 accumulator fed N
//! look-ups and the two visibilities a renderer already has (the viewer's and the
//! surface's) against `raymarch-N` looking visibility up at its own N steps.

use crate::common;

use airlight_shaders::gate;
use airlight_shaders::shafts::cases;
use airlight_truth::shafts::{self, Feed};

fn f32s(s: &[(f64, f64)]) -> Vec<[f32; 2]> {
    s.iter().map(|&(a, b)| [a as f32, b as f32]).collect()
}

/// `[max rel, mean rel, max of U, mean of U]` of `f` fed by `feed` over `cases`.
fn errors(f: airlight_shapes::vocab::ShadowedFn, cases: &[cases::ShadowCase], feed: Feed) -> [f64; 4] {
    let (mut rel, mut of_u) = (Vec::new(), Vec::new());
    for c in cases {
        let s = shafts::feed(&c.ray.physical(), &c.occluders, f64::from(c.ray.g), feed).unwrap();
        let r = &c.ray;
        let v = f64::from(f(&f32s(&s), r.surface, r.origin, r.dir, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g));
        assert!(v.is_finite() && v >= 0.0, "{r:?}: {v}");
        if c.reference > 0.0 {
            rel.push((v - c.reference).abs() / c.reference);
        }
        of_u.push((v - c.reference).abs() / c.unshadowed);
    }
    let max = |e: &[f64]| e.iter().copied().fold(0.0, f64::max);
    let mean = |e: &[f64]| e.iter().sum::<f64>() / e.len() as f64;
    [max(&rel), mean(&rel), max(&of_u), mean(&of_u)]
}

/// At every N of the bench, the accumulator's largest and mean error relative
/// to the ray's unshadowed in-scattering (the gate's measure: how much of the
/// pixel's possible glow is wrong) are below the march's. Errors relative to the
/// shadowed value itself are printed, not held: where a ray is nearly all in
/// shadow, a shadow edge placed between two look-ups, or a shadow that falls
/// between them over the glow's peak, costs the accumulator that stretch's exact
/// in-scattering, while the march, whose midpoint rule misses the peak too,
/// errs by at most the (small) shadowed value (REPORT.md, "Light shafts").
#[test]
fn the_accumulator_beats_the_march_on_the_same_look_ups() {
    let compiled = common::compiled();
    let index = gate::load_index(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated")).unwrap();
    let entry = index.get("phi-8").unwrap();
    let mut cases = Vec::new();
    for seed in [0x0DD5_EED1u64, 0x0DD5_EED2, 0x0DD5_EED3] {
        cases.extend(cases::shadowed_rays(entry, 200, seed).unwrap());
    }
    let acc = compiled.iter().find(|k| k.name == "phi-8").and_then(|k| k.shadowed).expect("phi-8");
    for n in airlight_shaders::shafts::bench::SHAFTS_SAMPLES {
        let name = format!("raymarch-{n}");
        let march = compiled.iter().find(|k| k.name == name).and_then(|k| k.shadowed).expect("march");
        let a = errors(acc, &cases, Feed::Samples(n));
        let m = errors(march, &cases, Feed::LookUps(n));
        eprintln!("N = {n}: accumulator {a:.3?}, march {m:.3?}");
        assert!(a[2] < m[2], "N = {n}: max of unshadowed {} against the march's {}", a[2], m[2]);
        assert!(a[3] < m[3], "N = {n}: mean of unshadowed {} against the march's {}", a[3], m[3]);
    }
}

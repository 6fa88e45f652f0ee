//! The physical extreme rays of the gate through the shafts accumulator (issue
//! 24): with a ball between the viewer and the light, fed the exact lit
//! intervals and 16 shadow-map samples, every value is finite and ≥ 0 — in the
//! Rust f32 kernels and, where an adapter is present, in their WGSL on the GPU.

mod common;

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

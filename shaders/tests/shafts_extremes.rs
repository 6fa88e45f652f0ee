//! The physical extreme rays of the gate through the shafts accumulator (issue
//! 24): with a ball between the viewer and the light, fed the exact lit
//! intervals and 16 shadow-map samples, every value is finite and ≥ 0.

mod common;

use airlight_fit::shafts::{self, Feed, Occluder};
use airlight_shaders::gate;

fn f32s(s: &[(f64, f64)]) -> Vec<[f32; 2]> {
    s.iter().map(|&(a, b)| [a as f32, b as f32]).collect()
}

/// The physical extreme rays of the gate through the shafts path, with a ball
/// between the viewer and the light: finite and ≥ 0, no hang.
#[test]
fn extreme_rays_through_the_shafts_path() {
    let compiled = common::compiled();
    let index = gate::load_index(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated")).unwrap();
    for name in ["phi-6", "equiangular-32", "sun2005-64"] {
        let entry = index.get(name).unwrap();
        let f = compiled.iter().find(|k| k.name == name).and_then(|k| k.shadowed).expect("compiled");
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
            }
        }
    }
}

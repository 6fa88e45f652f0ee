//! What the GPU tests share.

use airlight_shaders::{gpu_required, Gpu};
use airlight_shapes::vocab::CompiledKernel;

/// The generated Rust kernels compiled into this test, as the gate takes them.
#[allow(dead_code)]
pub fn compiled() -> Vec<CompiledKernel> {
    airlight_kernels::KERNELS
        .iter()
        .map(|k| CompiledKernel {
            name: k.name,
            airlight: k.airlight,
            radiance: k.radiance,
            spot: k.spot,
            shadowed: k.shadowed,
            spot_shadowed: k.spot_shadowed,
            walk: Some(walk),
        })
        .collect()
}

/// The adapter, or `None` after printing SKIPPED when there is none — unless
/// `AIRLIGHT_REQUIRE_GPU=1`, which makes a missing adapter a failure.
#[allow(dead_code)]
pub fn open_or_skip(test: &str) -> Option<Gpu> {
    match Gpu::open() {
        Ok(gpu) => {
            eprintln!("{test}: adapter {}", gpu.adapter());
            Some(gpu)
        }
        Err(e) if gpu_required() => panic!("{test}: AIRLIGHT_REQUIRE_GPU=1 but {e}"),
        Err(e) => {
            eprintln!("SKIPPED {test}: {e} (set AIRLIGHT_REQUIRE_GPU=1 to make this a failure)");
            None
        }
    }
}

/// The crate's shadow-map walk behind [`airlight_shapes::vocab::WalkFn`].
fn walk(
    origin: [f32; 3],
    dir: [f32; 3],
    end: f32,
    map: airlight_shapes::vocab::WalkMap,
    node: airlight_shapes::vocab::NodeFn,
) -> (Vec<[f32; 2]>, u32, bool) {
    struct Nodes<'a>(airlight_shapes::vocab::NodeFn<'a>);
    impl airlight_kernels::shadowmap::Pyramid for Nodes<'_> {
        fn node(&self, face: u32, level: u32, x: i32, y: i32) -> [f32; 2] {
            (self.0)(face, level, x, y)
        }
    }
    let (light, rows, cube, res, bias) = map;
    let mut w = airlight_kernels::shadowmap::Walk::new(origin, dir, end, light, rows, cube, res, bias, 0);
    let mut runs = Vec::new();
    while let Some(r) = w.next(&Nodes(node)) {
        runs.push(r);
    }
    (runs, w.steps, w.truncated)
}

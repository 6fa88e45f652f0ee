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

//! airlight-shaders: the wgpu harness. It opens a GPU adapter headlessly (a real
//! GPU, or Mesa's lavapipe software Vulkan driver where there is none), wraps a
//! generated kernel — WGSL, or a GLSL include as a GLSL 4.50 compute shader
//! through wgpu's GLSL front end — in a compute shader, evaluates its canonical
//! entry on a batch of points `(τ, γ, ρ, g)` or its physical entry on a batch of
//! rays, and reads the f32 results back. Generated kernels are wrapped by the
//! arguments they take ([`KernelSource`]); a hand-written WGSL function can be run
//! with the ABI `fn NAME(tau: f32, gamma: f32, rho: f32, g: f32) -> f32` ([`Gpu::eval`]).
//! `rho = NO_SURFACE` (−1) stands for `ρ = ∞` in the canonical entry; the gate's
//! physical extreme set also passes `+∞` and `f32::MAX` surfaces, which every
//! kernel takes as none.
//!
//! One concept per module: its error (`error`), the adapter and dispatch (`gpu`), rays as the GPU takes
//! them (`rays`), the compute shader around a kernel (`wrap`), the error gate
//! (`gate/`), the bench (`bench`), the headless render (`render`), and light shafts
//! in a room of their own (`shafts/`: the accumulator on the GPU, the gate's
//! shadowed cases, the shafts render and bench).

#![warn(missing_docs)]

pub mod bench;
mod error;
pub mod gate;
mod gpu;
mod rays;
pub mod render;
pub mod shafts;
mod wrap;

pub use airlight_shapes::vocab::{rho_arg, Arg, Entry, Target, NO_SURFACE};
pub use error::GpuError;
pub use gpu::{AdapterSummary, Gpu};
pub use rays::{Ray, SpotRay};
pub use wrap::{f32_value, from_kernel, load_table, wrap_kernel, KernelSource, Table};

/// Environment variable that makes a missing adapter an error instead of a skip.
pub const REQUIRE_GPU_ENV: &str = "AIRLIGHT_REQUIRE_GPU";

/// Whether the environment demands an adapter (`AIRLIGHT_REQUIRE_GPU=1`).
pub fn gpu_required() -> bool {
    std::env::var(REQUIRE_GPU_ENV).is_ok_and(|v| v == "1" || v.eq_ignore_ascii_case("true"))
}

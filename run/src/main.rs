//! `airlight-run`: the `airlight` command line with the generated Rust kernels
//! (`generated/airlight-kernels`) compiled in. `airlight` builds and runs it for
//! the commands that evaluate those kernels (`eval --precision f32`, `check`,
//! `render`, `bench`, and the gate at the end of `regenerate`), so that a broken
//! generated kernel can never stop `airlight generate` from repairing it.

use airlight_shapes::vocab::CompiledKernel;

fn main() -> std::process::ExitCode {
    let kernels: Vec<CompiledKernel> = airlight_kernels::KERNELS
        .iter()
        .map(|k| CompiledKernel {
            name: k.name,
            airlight: k.airlight,
            radiance: k.radiance,
            spot: k.spot,
            shadowed: k.shadowed,
            spot_shadowed: k.spot_shadowed,
        })
        .collect();
    airlight_cli::main_with(airlight_cli::Kernels::Linked(&kernels))
}

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
            walk: Some(walk),
        })
        .collect();
    airlight_cli::main_with(airlight_cli::Kernels::Linked(&kernels))
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

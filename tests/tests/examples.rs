//! The examples the README and the guides quote (`examples/shaders/`, and the
//! Rust below, which `docs/shafts.md` quotes) compile as a user would build them
//! and compute what they say: the WGSL pass after its kernel and walk in naga (as
//! wgpu validates it), the GLSL passes with their includes and the HLSL pass in
//! glslangValidator, and the Rust crate's walk and accumulators on an empty
//! shadow map, where both must give the unshadowed fog.

use airlight_tests::calls::glslang;
use airlight_tests::{generated_dir, repo_root};
use std::path::Path;
use std::process::Command;

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn the_wgsl_example_validates_after_its_kernel_and_walk() {
    let g = generated_dir().join("wgsl");
    let example = repo_root().join("examples/shaders/fog.wgsl");
    let src = [read(&g.join("phi-6.wgsl")), read(&g.join("shadowmap.wgsl")), read(&example)].join("\n");
    let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("examples/shaders/fog.wgsl: {e:?}"));
    for entry in ["fog", "shafts", "lamp"] {
        assert!(module.entry_points.iter().any(|e| e.name == entry), "no entry point {entry}");
    }
}

fn compile(args: &[&str], file: &str) {
    let path = repo_root().join(file);
    let out = Command::new(glslang())
        .args(args)
        .arg(&path)
        .arg("-o")
        .arg(std::env::temp_dir().join(format!("airlight-example-{}.spv", std::process::id())))
        .output()
        .unwrap_or_else(|e| panic!("{}: {e}", glslang()));
    assert!(
        out.status.success(),
        "{file}:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn the_glsl_and_hlsl_examples_compile_with_their_includes() {
    let glsl = format!("-I{}", generated_dir().join("glsl").display());
    compile(&["-V", &glsl], "examples/shaders/fog.frag");
    compile(&["-V", &glsl], "examples/shaders/shafts.frag");
    let hlsl = format!("-I{}", generated_dir().join("hlsl").display());
    compile(&["-D", "-V", "-S", "frag", "-e", "main", &hlsl], "examples/shaders/fog.hlsl");
}

/// A shadow map with nothing in it: every node's depths are "no occluder".
struct Empty;

impl airlight_kernels::shadowmap::Pyramid for Empty {
    fn node(&self, _face: u32, _level: u32, _x: i32, _y: i32) -> [f32; 2] {
        [3.4e38, 3.4e38]
    }
}

/// docs/shafts.md's exact mode in Rust, as it quotes it.
#[allow(clippy::too_many_arguments, clippy::let_and_return)] // the let: as the guide quotes it
fn exact(
    my_pyramid: &Empty,
    origin: [f32; 3],
    dir: [f32; 3],
    surface: f32,
    light: [f32; 3],
    intensity: f32,
    sigma_t: f32,
    sigma_s: f32,
    g: f32,
) -> f32 {
    let (rows, bias) = ([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], 0.003);
    use airlight_kernels::{phi_6::Shafts, shadowmap::Walk};
    let mut w = Walk::new(origin, dir, surface, light, rows, true, 2048, bias, 0);
    let mut acc = Shafts::for_runs();
    while let Some([a, b]) = w.next(my_pyramid) {
        acc.add_run(a, b);
        if acc.full() {
            acc.flush(origin, dir, light, intensity, sigma_t, sigma_s, g);
        }
    }
    let shafts = acc.finish(surface, origin, dir, light, intensity, sigma_t, sigma_s, g);
    shafts
}

/// docs/shafts.md's sampled mode in Rust, as it quotes it: `shadow` is the
/// caller's shadow-map look-up at a distance along the ray.
#[allow(clippy::too_many_arguments, clippy::let_and_return)] // the let: as the guide quotes it
fn sampled(
    shadow: impl Fn(f32) -> f32,
    origin: [f32; 3],
    dir: [f32; 3],
    surface: f32,
    light: [f32; 3],
    intensity: f32,
    sigma_t: f32,
    sigma_s: f32,
    g: f32,
) -> f32 {
    use airlight_kernels::phi_6::Shafts;
    let mut acc = Shafts::new();
    for i in 0..32 {
        let s = (i as f32 + 0.5) * surface / 32.0;
        acc.push(s, shadow(s), origin, dir, light, intensity, sigma_t, sigma_s, g);
        for _ in 0..4 {
            let m = acc.probe();
            if m < 0.0 {
                break;
            }
            acc.refine(shadow(m));
        }
    }
    let shafts = acc.finish(surface, origin, dir, light, intensity, sigma_t, sigma_s, g);
    shafts
}

#[test]
fn the_rust_shafts_examples_give_the_unshadowed_fog_on_an_empty_map() {
    let (origin, dir, light) = ([0.0, 1.7, 0.0], [0.3, 0.1, -1.0], [2.0, 4.0, -8.0]);
    let (intensity, sigma_t, sigma_s, g) = (100.0, 0.09, 0.08, 0.6);
    for surface in [12.0, 40.0] {
        let plain = airlight_kernels::phi_6::radiance(origin, dir, surface, light, intensity, sigma_t, sigma_s, g);
        let walked = exact(&Empty, origin, dir, surface, light, intensity, sigma_t, sigma_s, g);
        let pushed = sampled(|_| 1.0, origin, dir, surface, light, intensity, sigma_t, sigma_s, g);
        assert!(plain > 0.0 && plain.is_finite());
        for (what, v) in [("exact", walked), ("sampled", pushed)] {
            assert!((v / plain - 1.0).abs() < 1e-4, "{what} on an empty map: {v} against {plain} (surface {surface})");
        }
        let dark = sampled(|_| 0.0, origin, dir, surface, light, intensity, sigma_t, sigma_s, g);
        assert_eq!(dark, 0.0, "everything in shadow");
    }
}

//! The error gate fails when a kernel breaks its bound: a wrong coefficient
//! planted in a copy of the generated WGSL and GLSL fails on the GPU targets; an
//! f32 bound the compiled Rust kernel cannot meet fails on the CPU; a kernel
//! without a recorded f32 bound is refused.

use crate::common;

use airlight_shaders::gate::{self, Target};
use std::path::{Path, PathBuf};

fn generated() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated")
}

/// A copy of the inputs the gate reads for `segments-8`, in a fresh directory.
fn copy(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("airlight-gate-{}-{name}", std::process::id()));
    for sub in ["coefficients", "wgsl", "glsl"] {
        std::fs::create_dir_all(dir.join(sub)).unwrap();
    }
    std::fs::copy(generated().join("kernels.toml"), dir.join("kernels.toml")).unwrap();
    for e in std::fs::read_dir(generated().join("coefficients")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.join("coefficients").join(p.file_name().unwrap())).unwrap();
    }
    for f in ["wgsl/segments-8.wgsl", "glsl/segments-8.glsl"].into_iter().chain(airlight_shaders::shafts::WALK_FILES) {
        std::fs::copy(generated().join(f), dir.join(f)).unwrap();
    }
    dir
}

fn replace_in(path: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(from), "{}: no '{from}'", path.display());
    std::fs::write(path, text.replacen(from, to, 1)).unwrap();
}

#[test]
fn the_committed_kernels_pass_on_the_cpu() {
    let rows =
        gate::run(&generated(), None, &common::compiled(), &["segments-8".into(), "scene-haze-sky".into()], &|_| {})
            .unwrap();
    assert_eq!(
        rows.len(),
        2 * (9 + 5),
        "f64 and rust-f32 rows of segments-8 (thin, dense, extreme, edge, physical, phys-extreme, spot, shadowed, \
         shadow-map) \
         and of the closed form (thin, extreme, edge, physical, phys-extreme; its scene has point lights, no spot \
         entry and no shadows)"
    );
    assert!(rows.iter().all(|r| r.passes()), "{}", gate::table(&rows, true));
}

/// The line `key = …` of segments-8's entry in `kernels.toml` under `dir`.
fn segments_8_line(dir: &Path, key: &str) -> String {
    let text = std::fs::read_to_string(dir.join("kernels.toml")).unwrap();
    let at = text.find("name = \"segments-8\"").unwrap();
    text[at..].lines().find(|l| l.starts_with(&format!("{key} = "))).unwrap().to_string()
}

#[test]
fn an_f32_bound_the_rust_kernel_cannot_meet_fails() {
    let dir = copy("bound");
    // Declare segments-8's f32 bound ten times better on thin than it is.
    let line = segments_8_line(&dir, "f32_thin_max_rel");
    let value: f64 = line["f32_thin_max_rel = ".len()..].trim().parse().unwrap();
    replace_in(&dir.join("kernels.toml"), &line, &format!("f32_thin_max_rel = {}", value / 10.0));
    let rows = gate::run(&dir, None, &common::compiled(), &["segments-8".into()], &|_| {}).unwrap();
    let failed: Vec<_> = rows.iter().filter(|r| !r.passes()).collect();
    assert!(!failed.is_empty(), "{}", gate::table(&rows, false));
    assert!(
        failed.iter().all(|r| r.target == Some(Target::Rust) && r.domain == "thin"),
        "{}",
        gate::table(&rows, true)
    );
    let table = gate::table(&rows, true);
    assert!(table.contains("segments-8") && table.contains("FAIL") && table.contains("rust-f32"), "{table}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_kernel_without_a_recorded_f32_bound_is_refused() {
    let dir = copy("no-f32");
    let line = segments_8_line(&dir, "f32_dense_max_rel");
    replace_in(&dir.join("kernels.toml"), &format!("{line}\n"), "");
    let Err(gate::GateError::Input(e)) = gate::run(&dir, None, &common::compiled(), &["segments-8".into()], &|_| {})
    else {
        panic!("the gate ran without an f32 bound")
    };
    assert!(e.contains("kernels.toml") && e.contains("segments-8") && e.contains("f32_dense_max_rel"), "{e}");
    assert!(e.contains("airlight check --record"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_wrong_coefficient_in_the_shaders_fails_on_the_gpu() {
    let Some(gpu) = common::open_or_skip("a_wrong_coefficient_in_the_shaders_fails_on_the_gpu") else { return };
    let dir = copy("coefficient");
    // The isotropic phase constant, 1/(4π), off by 0.5%.
    replace_in(&dir.join("wgsl/segments-8.wgsl"), "P_ISO: f32 = 7.95774683e-2", "P_ISO: f32 = 7.99753556e-2");
    replace_in(&dir.join("glsl/segments-8.glsl"), "P_ISO = 7.95774683e-2", "P_ISO = 7.99753556e-2");
    let rows = gate::run(&dir, Some(&gpu), &common::compiled(), &["segments-8".into()], &|_| {}).unwrap();
    let failed: Vec<_> = rows.iter().filter(|r| !r.passes()).collect();
    for target in [Target::Wgsl, Target::Glsl] {
        assert!(failed.iter().any(|r| r.target == Some(target) && r.domain == "thin"), "{}", gate::table(&rows, false));
    }
    assert!(failed.iter().all(|r| r.target != Some(Target::Rust)), "the compiled Rust kernel is untouched");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_wrong_cone_in_the_shaders_fails_the_spot_rows() {
    let Some(gpu) = common::open_or_skip("a_wrong_cone_in_the_shaders_fails_the_spot_rows") else { return };
    let dir = copy("cone");
    // The cone's axis turned by 0.01 rad about the ray's normal: only the spot entry reads it.
    let (from, to) =
        ("let psi = airlight_segments_8_arctan2(k, ca);", "let psi = airlight_segments_8_arctan2(k, ca) + 0.01;");
    replace_in(&dir.join("wgsl/segments-8.wgsl"), from, to);
    let (from, to) =
        ("float psi = airlight_segments_8_arctan2(k, ca);", "float psi = airlight_segments_8_arctan2(k, ca) + 0.01;");
    replace_in(&dir.join("glsl/segments-8.glsl"), from, to);
    let rows = gate::run(&dir, Some(&gpu), &common::compiled(), &["segments-8".into()], &|_| {}).unwrap();
    let failed: Vec<_> = rows.iter().filter(|r| !r.passes()).collect();
    for target in [Target::Wgsl, Target::Glsl] {
        assert!(
            failed.iter().any(|r| r.target == Some(target) && r.domain == gate::SPOT),
            "{}",
            gate::table(&rows, false)
        );
    }
    assert!(
        failed.iter().all(|r| r.domain == gate::SPOT && r.target != Some(Target::Rust)),
        "{}",
        gate::table(&rows, true)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

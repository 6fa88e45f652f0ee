//! Every generated shader validates: WGSL through naga's front end and
//! Validator (the Bevy variant composed through naga_oil), GLSL through
//! `glslangValidator` as GLSL ES 3.00 (fragment) and GLSL 4.50 (compute). Each
//! is wrapped with an entry point that calls both of its entry points, with the
//! arguments its header documents.

use airlight_tests::generated_dir;
use std::path::{Path, PathBuf};
use std::process::Command;

fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .collect();
    v.sort();
    v
}

/// `airlight_segments_8_` for `segments-8.wgsl`.
fn prefix(path: &Path) -> String {
    format!("airlight_{}_", path.file_stem().unwrap().to_string_lossy().replace('-', "_"))
}

/// The parameter names of `fn NAME(...)` / `float NAME(...)` in `text`.
fn params(text: &str, name: &str) -> Vec<String> {
    let at = text.find(&format!("{name}(")).unwrap_or_else(|| panic!("no function {name}"));
    let rest = &text[at + name.len() + 1..];
    let list = &rest[..rest.find(')').unwrap()];
    list.split(',')
        .map(|p| {
            let p = p.trim();
            // `tau: f32` (WGSL) or `float tau` (GLSL)
            if let Some((n, _)) = p.split_once(':') {
                n.trim().to_string()
            } else {
                p.rsplit(' ').next().unwrap().to_string()
            }
        })
        .collect()
}

/// Arguments for a call, by parameter name; `vec3` is the vector constructor.
fn args(names: &[String], vec3: &str) -> String {
    names
        .iter()
        .map(|n| match n.as_str() {
            "tau" => "1.5".to_string(),
            "gamma" => "0.7".to_string(),
            "rho" => "2.0".to_string(),
            "g" => "0.3".to_string(),
            "origin" => format!("{vec3}(0.0, 0.0, 0.0)"),
            "dir" => format!("{vec3}(0.0, 0.0, 1.0)"),
            "light" => format!("{vec3}(1.0, 0.5, 10.0)"),
            "surface" => "-1.0".to_string(),
            "intensity" => "100.0".to_string(),
            "sigma_t" => "0.05".to_string(),
            "sigma_s" => "0.04".to_string(),
            other => panic!("undocumented parameter {other}"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn validate(module: &naga::Module, what: &str) {
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(module)
        .unwrap_or_else(|e| panic!("{what}: {e:?}"));
}

fn wgsl_entry(text: &str, p: &str, call_prefix: &str) -> String {
    let a = args(&params(text, &format!("{p}airlight")), "vec3<f32>");
    let r = args(&params(text, &format!("{p}radiance")), "vec3<f32>");
    format!(
        "@group(0) @binding(0) var<storage, read_write> out: array<f32>;\n\
         @compute @workgroup_size(1)\n\
         fn main() {{\n    out[0] = {call_prefix}airlight({a});\n    out[1] = {call_prefix}radiance({r});\n}}\n"
    )
}

#[test]
fn every_wgsl_kernel_parses_and_validates_in_naga() {
    let wgsl = files(&generated_dir().join("wgsl"), "wgsl");
    assert!(wgsl.len() >= 15, "{} WGSL kernels", wgsl.len());
    for path in &wgsl {
        let text = std::fs::read_to_string(path).unwrap();
        let p = prefix(path);
        let source = format!("{text}\n{}", wgsl_entry(&text, &p, &p));
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&source)));
        validate(&module, &path.display().to_string());
    }
}

#[test]
fn every_bevy_variant_composes_through_naga_oil() {
    use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderLanguage};
    let bevy = files(&generated_dir().join("wgsl/bevy"), "wgsl");
    assert_eq!(bevy.len(), files(&generated_dir().join("wgsl"), "wgsl").len(), "one Bevy variant per WGSL kernel");
    for path in &bevy {
        let text = std::fs::read_to_string(path).unwrap();
        let ident = path.file_stem().unwrap().to_string_lossy().replace('-', "_");
        let import = format!("airlight::{ident}");
        assert!(text.starts_with(&format!("#define_import_path {import}\n")), "{}", path.display());
        let mut composer = Composer::default();
        composer
            .add_composable_module(ComposableModuleDescriptor {
                source: &text,
                file_path: &path.display().to_string(),
                language: ShaderLanguage::Wgsl,
                ..Default::default()
            })
            .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
        let user = format!("#import {import}\n{}", wgsl_entry(&text, "", &format!("{import}::")));
        let module = composer
            .make_naga_module(NagaModuleDescriptor { source: &user, file_path: "user.wgsl", ..Default::default() })
            .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
        validate(&module, &path.display().to_string());
    }
}

fn glslang() -> &'static str {
    let ok = Command::new("glslangValidator").arg("--version").output().is_ok_and(|o| o.status.success());
    assert!(ok, "glslangValidator not found: install glslang-tools (see README)");
    "glslangValidator"
}

#[test]
fn every_glsl_kernel_compiles_as_es_300_and_450() {
    let tool = glslang();
    let glsl = files(&generated_dir().join("glsl"), "glsl");
    assert!(glsl.len() >= 15, "{} GLSL kernels", glsl.len());
    let dir = std::env::temp_dir().join(format!("airlight-glsl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for path in &glsl {
        let text = std::fs::read_to_string(path).unwrap();
        assert!(
            !text.lines().any(|l| l.trim_start().starts_with("#version")),
            "{}: an include must not set #version",
            path.display()
        );
        let p = prefix(path);
        let a = args(&params(&text, &format!("{p}airlight")), "vec3");
        let r = args(&params(&text, &format!("{p}radiance")), "vec3");
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        let frag = format!(
            "#version 300 es\n{text}\nout highp vec4 color;\nvoid main() {{\n    color = vec4({p}airlight({a}), {p}radiance({r}), 0.0, 1.0);\n}}\n"
        );
        let comp = format!(
            "#version 450\n{text}\nlayout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer Out {{ float v[]; }} o;\n\
             void main() {{\n    o.v[0] = {p}airlight({a});\n    o.v[1] = {p}radiance({r});\n}}\n"
        );
        for (ext, src) in [("frag", frag), ("comp", comp)] {
            let file = dir.join(format!("{stem}.{ext}"));
            std::fs::write(&file, src).unwrap();
            let out = Command::new(tool).arg(&file).output().unwrap();
            assert!(
                out.status.success(),
                "{} as {ext}:\n{}{}",
                path.display(),
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

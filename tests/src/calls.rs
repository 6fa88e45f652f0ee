//! Calls of the generated entry points, written into test shaders: the files of
//! one language, each kernel's prefix, its entry points' parameters as its header
//! documents them, and plausible arguments for them in any shading language.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The files with extension `ext` in `dir`, sorted.
pub fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        // The shadow-map walk and its pyramid pass are shared by every kernel,
        // not kernels (tests/tests/shader_validation.rs checks them apart).
        .filter(|p| !p.file_stem().is_some_and(|s| s.to_string_lossy().starts_with("shadowmap")))
        .collect();
    v.sort();
    v
}

/// The prefix of a kernel file's items: `airlight_segments_8_` for `segments-8.wgsl`.
pub fn prefix(path: &Path) -> String {
    format!("airlight_{}_", path.file_stem().unwrap().to_string_lossy().replace('-', "_"))
}

/// The parameter names of `fn NAME(...)` / `float NAME(...)` in `text`.
pub fn params(text: &str, name: &str) -> Vec<String> {
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

/// The WGSL kernel a translation was made from.
pub fn wgsl_of(path: &Path) -> String {
    let name = path.with_extension("wgsl");
    std::fs::read_to_string(crate::generated_dir().join("wgsl").join(name.file_name().unwrap())).unwrap()
}

/// The parameters of `NAME(...)` in `text`, split at top-level commas (MSL types
/// such as `texture2d<float, access::sample>` hold commas).
pub fn top_level_params(text: &str, name: &str) -> Vec<String> {
    let at = text.find(&format!(" {name}(")).unwrap_or_else(|| panic!("no function {name}"));
    let rest = &text[at + name.len() + 2..];
    let (mut depth, mut cur, mut out) = (0i32, String::new(), Vec::new());
    for c in rest.chars() {
        match c {
            '<' | '(' => depth += 1,
            '>' => depth -= 1,
            ')' if depth == 0 => break,
            ')' => depth -= 1,
            ',' if depth == 0 => {
                out.push(cur.trim().to_string());
                cur.clear();
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    if !cur.trim().is_empty() {
        out.push(cur.trim().to_string());
    }
    out
}

/// Arguments for a call, by parameter name; `vec3` is the vector constructor.
pub fn args(names: &[String], vec3: &str) -> String {
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

/// A call of the kernel's spot entry `{p}spot` with plausible arguments (RGB
/// media, a smooth-edged cone), where `text` has one.
pub fn spot_call(text: &str, p: &str, call_prefix: &str, vec3: &str) -> Option<String> {
    let name = format!("{p}spot");
    if !text.contains(&format!("fn {name}(")) && !text.contains(&format!(" {name}(")) {
        return None;
    }
    let list: Vec<String> = params(text, &name)
        .iter()
        .map(|n| match n.as_str() {
            "axis" => format!("{vec3}(0.0, -1.0, 0.2)"),
            "cos_outer" => "0.8".to_string(),
            "cos_inner" => "0.9".to_string(),
            "sigma_t" => format!("{vec3}(0.05, 0.04, 0.03)"),
            "sigma_s" => format!("{vec3}(0.04, 0.03, 0.02)"),
            other => args(&[other.to_string()], vec3),
        })
        .collect();
    Some(format!("{call_prefix}spot({})", list.join(", ")))
}

/// `glslangValidator`, which must be installed (glslang-tools).
pub fn glslang() -> &'static str {
    let ok = Command::new("glslangValidator").arg("--version").output().is_ok_and(|o| o.status.success());
    assert!(ok, "glslangValidator not found: install glslang-tools (see README)");
    "glslangValidator"
}

/// Expressions calling each entry point of a kernel (`{p}airlight`,
/// `{p}radiance`, and `{p}spot`'s red channel where it has one) as `call_prefix` +
/// entry, with the parameters `text` documents; `vec3` is the language's vector
/// constructor. Each expression is a float.
pub fn entry_calls(text: &str, p: &str, call_prefix: &str, vec3: &str) -> Vec<String> {
    let mut calls: Vec<String> = ["airlight", "radiance"]
        .iter()
        .map(|e| format!("{call_prefix}{e}({})", args(&params(text, &format!("{p}{e}")), vec3)))
        .collect();
    calls.extend(spot_call(text, p, call_prefix, vec3).map(|c| format!("{c}.x")));
    calls
}

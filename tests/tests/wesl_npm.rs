//! The WESL modules linked by the npm `wesl` linker (0.7, pinned in
//! tests/node/package.json), as a JavaScript host links them: the plugin crate's
//! `src/*.wesl` as one library bundle (package `bevy_airlight`), a root module
//! importing one kernel, or two kernels at once, and calling every entry point.
//! naga 30 validates what the linker writes.

use airlight_tests::calls::{entry_calls, files};
use airlight_tests::{npm_tools, wesl_dir, WESL_PACKAGE};
use std::process::Command;

fn main_module(idents: &[&str]) -> String {
    let dir = wesl_dir();
    let mut imports = String::new();
    let mut calls = Vec::new();
    for ident in idents {
        let text = std::fs::read_to_string(dir.join(format!("{ident}.wesl"))).unwrap();
        imports.push_str(&format!("import {WESL_PACKAGE}::{ident};\n"));
        calls.extend(entry_calls(&text, "", &format!("{ident}::"), "vec3<f32>"));
    }
    format!(
        "{imports}@group(1) @binding(0) var<storage, read_write> airlight_test_out: array<f32>;\n\
         @compute @workgroup_size(1)\nfn main() {{\n    airlight_test_out[0] = {};\n}}\n",
        calls.join(" + ")
    )
}

#[test]
fn the_npm_wesl_linker_links_every_module_and_two_together() {
    let Some(tools) = npm_tools("wesl") else { return };
    let modules: Vec<String> =
        files(&wesl_dir(), "wesl").iter().map(|p| p.file_stem().unwrap().to_string_lossy().to_string()).collect();
    assert!(modules.len() >= 15, "{} modules", modules.len());
    let mut jobs: Vec<(String, String)> = modules.iter().map(|m| (m.clone(), main_module(&[m]))).collect();
    for pair in [["phi_iso_6", "phi_4"], ["scene_hg_fog", "phi_4"]] {
        jobs.push((pair.join("+"), main_module(&pair)));
    }
    let spec: Vec<serde_json::Value> =
        jobs.iter().map(|(name, main)| serde_json::json!({ "name": name, "main": main })).collect();
    let dir = std::env::temp_dir().join(format!("airlight-wesl-npm-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("jobs.json");
    std::fs::write(&file, serde_json::to_string(&spec).unwrap()).unwrap();
    // Run from outside the repository: only the script and its modules are found by path.
    let out = Command::new("node")
        .current_dir(&dir)
        .arg(tools.join("wesl-link.mjs"))
        .arg(wesl_dir())
        .arg(&file)
        .output()
        .expect("node runs (Debian's nodejs; see README)");
    assert!(out.status.success(), "node: {}", String::from_utf8_lossy(&out.stderr));
    let linked: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for (name, _) in &jobs {
        let r = &linked[name];
        let wgsl = r["wgsl"].as_str().unwrap_or_else(|| panic!("{name}: the npm linker failed: {}", r["error"]));
        let module = naga::front::wgsl::parse_str(wgsl)
            .unwrap_or_else(|e| panic!("{name} (as npm wesl linked it): {}", e.emit_to_string(wgsl)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name} (as npm wesl linked it): {e:?}"));
    }
    std::fs::remove_dir_all(&dir).ok();
}

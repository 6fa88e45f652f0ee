//! The engine packages under `generated/`: the Unity package (UPM layout, Shader
//! Graph wrappers, `.meta` files), the Unreal plugin (`.ush` includes under a
//! virtual path) and the Bevy 0.20 plugin crate's registration. Unity and Unreal
//! are not run here: every include is compiled by glslangValidator's HLSL front
//! end, with every wrapper (Unity: `_float` and `_half`) or every entry point
//! (Unreal, as a material Custom node's code would call it) called.

use airlight_tests::calls::{files, glslang, params, prefix, wgsl_of};
use airlight_tests::generated_dir;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

fn unity() -> PathBuf {
    generated_dir().join("unity/com.airlight.kernels")
}

fn unreal() -> PathBuf {
    generated_dir().join("unreal/Airlight")
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&read(p)).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Compiles `src` as an HLSL fragment shader with entry `airlight_test_main`.
fn compile_hlsl(src: &str, dir: &Path, stem: &str) {
    let file = dir.join(format!("{stem}.frag.hlsl"));
    std::fs::write(&file, src).unwrap();
    let spv = dir.join(format!("{stem}.spv"));
    let out = Command::new(glslang())
        .args(["-D", "-S", "frag", "-e", "airlight_test_main", "-V", "-o"])
        .arg(&spv)
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{stem}:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Arguments by parameter name, in HLSL with `scalar`/`vec3` types (`half`).
fn hlsl_args(names: &[String], scalar: &str, vec: &str) -> String {
    names
        .iter()
        .map(|n| {
            let v = |x: &str, y: &str, z: &str| format!("{vec}({x}, {y}, {z})");
            match n.as_str() {
                "origin" => v("0.0", "0.0", "0.0"),
                "dir" => v("0.0", "0.0", "1.0"),
                "light" => v("1.0", "0.5", "10.0"),
                "axis" => v("0.0", "-1.0", "0.2"),
                "sigma_t" if names.iter().any(|a| a == "axis") => v("0.05", "0.04", "0.03"),
                "sigma_s" if names.iter().any(|a| a == "axis") => v("0.04", "0.03", "0.02"),
                "tau" => format!("({scalar})1.5"),
                "gamma" => format!("({scalar})0.7"),
                "rho" => format!("({scalar})2.0"),
                "g" => format!("({scalar})0.3"),
                "surface" => format!("({scalar})-1.0"),
                "intensity" => format!("({scalar})100.0"),
                "sigma_t" => format!("({scalar})0.05"),
                "sigma_s" => format!("({scalar})0.04"),
                "cos_outer" => format!("({scalar})0.8"),
                "cos_inner" => format!("({scalar})0.9"),
                other => panic!("undocumented parameter {other}"),
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The entry points a kernel file's WGSL source has.
fn entries(wgsl: &str, p: &str) -> Vec<&'static str> {
    ["airlight", "radiance", "spot"].into_iter().filter(|e| wgsl.contains(&format!("fn {p}{e}("))).collect()
}

fn tmp(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("airlight-packages-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn unity_package_manifest_and_meta_files() {
    let manifest = json(&unity().join("package.json"));
    assert_eq!(manifest["name"], "com.airlight.kernels");
    assert!(manifest["version"].as_str().is_some_and(|v| v.split('.').count() == 3), "{manifest}");
    assert!(manifest["unity"].as_str().is_some(), "{manifest}");
    // Every asset and folder has a .meta with a GUID of its own.
    let mut guids = BTreeSet::new();
    let mut walk = vec![unity()];
    let mut assets = 0;
    while let Some(dir) = walk.pop() {
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let p = e.path();
            if p.extension().is_some_and(|x| x == "meta") {
                let text = read(&p);
                let guid =
                    text.lines().find_map(|l| l.strip_prefix("guid: ")).unwrap_or_else(|| panic!("{}", p.display()));
                assert!(guid.len() == 32 && guid.chars().all(|c| c.is_ascii_hexdigit()), "{}: {guid}", p.display());
                assert!(guids.insert(guid.to_string()), "{}: GUID {guid} repeated", p.display());
                let asset = PathBuf::from(p.to_string_lossy().trim_end_matches(".meta"));
                assert!(asset.exists(), "{}: no asset", p.display());
                assert_eq!(asset.is_dir(), text.contains("folderAsset: yes"), "{}", p.display());
                continue;
            }
            assets += 1;
            let meta = PathBuf::from(format!("{}.meta", p.display()));
            assert!(meta.exists(), "{}: no .meta (an immutable package ignores it)", p.display());
            if p.is_dir() {
                walk.push(p);
            }
        }
    }
    assert!(assets > 10, "{assets} assets");
}

#[test]
fn unity_shader_graph_wrappers_compile_in_float_and_half() {
    let shaders = files(&unity().join("Runtime/Shaders"), "hlsl");
    assert!(shaders.len() >= 10, "{} Unity includes", shaders.len());
    let dir = tmp("unity");
    for path in &shaders {
        let text = read(path);
        let p = prefix(path);
        let wgsl = wgsl_of(path);
        let mut body = String::new();
        for e in entries(&wgsl, &p) {
            let names = params(&wgsl, &format!("{p}{e}"));
            let (fty, hty) = if e == "spot" { ("float3", "half3") } else { ("float", "half") };
            body.push_str(&format!(
                "    {{ {fty} o; {p}{e}_float({}, o); acc += dot(float3(1.0, 1.0, 1.0), o); }}\n\
                 \x20   {{ {hty} o; {p}{e}_half({}, o); acc += dot(float3(1.0, 1.0, 1.0), (float3)o); }}\n",
                hlsl_args(&names, "float", "float3"),
                hlsl_args(&names, "half", "half3")
            ));
        }
        // A wrapper missing from the file would not compile: every entry has both.
        let src = format!(
            "{text}\nfloat4 airlight_test_main() : SV_Target {{\n    float acc = 0.0;\n{body}    return float4(acc, 0.0, 0.0, 1.0);\n}}\n"
        );
        compile_hlsl(&src, &dir, &path.file_stem().unwrap().to_string_lossy());
    }
    // Two packaged kernels and a plain include of one of them, in one shader.
    let two = ["phi-iso-6", "phi-4"].map(|k| read(&unity().join(format!("Runtime/Shaders/{k}.hlsl"))));
    let plain = read(&generated_dir().join("hlsl/phi-4.hlsl"));
    let src = format!(
        "{}\n{}\n{plain}\nfloat4 airlight_test_main() : SV_Target {{\n    float a; airlight_phi_iso_6_airlight_float(1.5, 0.7, 2.0, a);\n    float b; airlight_phi_4_airlight_float(1.5, 0.7, 2.0, 0.3, b);\n    return float4(a, b, 0.0, 1.0);\n}}\n",
        two[0], two[1]
    );
    compile_hlsl(&src, &dir, "two-unity-kernels");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unreal_plugin_maps_its_virtual_path_and_every_ush_compiles() {
    let plugin = json(&unreal().join("Airlight.uplugin"));
    let module = &plugin["Modules"][0];
    assert_eq!(module["Name"], "AirlightShaders");
    assert_eq!(module["LoadingPhase"], "PostConfigInit", "shader mappings must exist before shaders compile");
    let cpp = read(&unreal().join("Source/AirlightShaders/Private/AirlightShadersModule.cpp"));
    assert!(cpp.contains("AddShaderSourceDirectoryMapping(TEXT(\"/Plugin/Airlight\")"), "{cpp}");
    assert!(cpp.contains("IMPLEMENT_MODULE(FAirlightShadersModule, AirlightShaders)"), "{cpp}");
    assert!(unreal().join("Source/AirlightShaders/AirlightShaders.Build.cs").exists());
    let ush = files(&unreal().join("Shaders/Private"), "ush");
    assert!(ush.len() >= 10, "{} .ush", ush.len());
    let dir = tmp("unreal");
    for path in &ush {
        let text = read(path);
        let p = prefix(path);
        let wgsl = wgsl_of(path);
        // As a material Custom node: its code is one call, inputs by name.
        let calls: Vec<String> = entries(&wgsl, &p)
            .iter()
            .map(|e| {
                let c = format!("{p}{e}({})", hlsl_args(&params(&wgsl, &format!("{p}{e}")), "float", "float3"));
                if *e == "spot" {
                    format!("{c}.x")
                } else {
                    c
                }
            })
            .collect();
        let src = format!(
            "{text}\n{text}\nfloat4 airlight_test_main() : SV_Target {{\n    return float4({}, 0.0, 0.0, 1.0);\n}}\n",
            calls.join(" + ")
        );
        compile_hlsl(&src, &dir, &path.file_stem().unwrap().to_string_lossy());
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn packages_carry_every_general_model_without_a_table() {
    let unity_kernels: BTreeSet<String> = files(&unity().join("Runtime/Shaders"), "hlsl")
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().to_string())
        .collect();
    let unreal_kernels: BTreeSet<String> = files(&unreal().join("Shaders/Private"), "ush")
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().to_string())
        .collect();
    assert_eq!(unity_kernels, unreal_kernels);
    for m in airlight_tests::committed_models() {
        let table = read(&generated_dir().join(format!("wgsl/{}.wgsl", m.model.name))).contains("texture_2d");
        assert_eq!(unity_kernels.contains(&m.model.name), !table, "{}", m.model.name);
    }
}

//! Every generated shader validates: WGSL through naga's front end and
//! Validator; the Bevy 0.19 variant composed by naga_oil 0.22 and validated by
//! naga 29 (what Bevy 0.19 runs); the WESL module of the Bevy 0.20 plugin crate
//! compiled by the `wesl` crate the way `bevy_shader` does (package import, escape
//! mangler) and validated by naga 30; GLSL through `glslangValidator` as GLSL ES 3.00
//! (fragment) and GLSL 4.50 (compute); the HLSL through glslangValidator's HLSL
//! front end (`-D`, fragment); the MSL for its entry points (no Metal compiler
//! exists here). Each is wrapped with an entry point that calls both of its entry
//! points, with the arguments its header documents.

use airlight_tests::calls::{args, files, glslang, params, prefix, spot_call, top_level_params, wgsl_of};
use airlight_tests::generated_dir;
use std::process::Command;

fn validate(module: &naga::Module, what: &str) {
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(module)
        .unwrap_or_else(|e| panic!("{what}: {e:?}"));
}

fn validate29(module: &naga29::Module, what: &str) {
    naga29::valid::Validator::new(naga29::valid::ValidationFlags::all(), naga29::valid::Capabilities::empty())
        .validate(module)
        .unwrap_or_else(|e| panic!("{what}: {e:?}"));
}

fn wgsl_entry(text: &str, p: &str, call_prefix: &str) -> String {
    let a = args(&params(text, &format!("{p}airlight")), "vec3<f32>");
    let r = args(&params(text, &format!("{p}radiance")), "vec3<f32>");
    // The spot entry's name is unprefixed in the modules (p = ""), prefixed in the plain file.
    let spot = spot_call(text, p, call_prefix, "vec3<f32>").map_or(String::new(), |c| format!("    out[2] = {c}.x;\n"));
    format!(
        "@group(0) @binding(0) var<storage, read_write> out: array<f32>;\n\
         @compute @workgroup_size(1)\n\
         fn main() {{\n    out[0] = {call_prefix}airlight({a});\n    out[1] = {call_prefix}radiance({r});\n{spot}}}\n"
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
        validate29(&module, &path.display().to_string());
    }
}

#[test]
fn every_wesl_module_compiles_with_wesl_as_bevy_0_20_does() {
    use wesl::syntax::{ModulePath, PathOrigin};
    let dir = airlight_tests::wesl_dir();
    let modules = files(&dir, "wesl");
    assert_eq!(modules.len(), files(&generated_dir().join("wgsl"), "wgsl").len(), "one WESL module per WGSL kernel");
    let package = airlight_tests::WESL_PACKAGE;
    // The plugin registers each module where Bevy's loader imports it from.
    let lib = std::fs::read_to_string(dir.join("lib.rs")).unwrap();
    for path in &modules {
        let text = std::fs::read_to_string(path).unwrap();
        assert!(!text.contains("#define_import_path") && !text.contains("#import"), "{}", path.display());
        let ident = path.file_stem().unwrap().to_string_lossy().to_string();
        assert!(lib.contains(&format!("load_shader_library!(app, \"{ident}.wesl\");")), "{ident} not registered");
        assert!(lib.contains(&format!("(\"{package}::{ident}\", ")), "{ident} not listed");
        // Bevy 0.20: a library embedded as `embedded://bevy_airlight/<ident>.wesl` is
        // the package `bevy_airlight`, module `<ident>`; a user shader imports its functions.
        let module = ModulePath { origin: PathOrigin::Package(package.into()), components: vec![ident.clone()] };
        let root = ModulePath { origin: PathOrigin::Absolute, components: vec!["user".into()] };
        let spot = if text.contains("fn spot(") { ", spot" } else { "" };
        let user = format!("import {package}::{ident}::{{airlight, radiance{spot}}};\n{}", wgsl_entry(&text, "", ""));
        let mut resolver = wesl::VirtualResolver::new();
        resolver.add_module(module, text.clone().into());
        resolver.add_module(root.clone(), user.into());
        let options = wesl::CompileOptions { imports: true, condcomp: true, ..Default::default() };
        let compiled = wesl::compile_sourcemap(&root, &resolver, &wesl::EscapeMangler, &options)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let wgsl = compiled.to_string();
        let module = naga::front::wgsl::parse_str(&wgsl)
            .unwrap_or_else(|e| panic!("{} (as wesl compiled it): {}", path.display(), e.emit_to_string(&wgsl)));
        validate(&module, &path.display().to_string());
    }
}

#[test]
fn every_hlsl_kernel_compiles_in_glslang_hlsl_front_end() {
    let tool = glslang();
    let hlsl = files(&generated_dir().join("hlsl"), "hlsl");
    assert_eq!(hlsl.len(), files(&generated_dir().join("wgsl"), "wgsl").len(), "one HLSL include per WGSL kernel");
    let dir = std::env::temp_dir().join(format!("airlight-hlsl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for path in &hlsl {
        let text = std::fs::read_to_string(path).unwrap();
        let p = prefix(path);
        // naga's namer renames parameters (`origin_1`); the order is the WGSL's.
        let wgsl = wgsl_of(path);
        let a = args(&params(&wgsl, &format!("{p}airlight")), "float3");
        let r = args(&params(&wgsl, &format!("{p}radiance")), "float3");
        let spot = spot_call(&wgsl, &p, &p, "float3");
        let entries: &[&str] =
            if spot.is_some() { &["airlight", "radiance", "spot"] } else { &["airlight", "radiance"] };
        for f in entries {
            assert_eq!(
                top_level_params(&text, &format!("{p}{f}")).len(),
                params(&wgsl, &format!("{p}{f}")).len(),
                "{}: {p}{f}",
                path.display()
            );
        }
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        let src = format!(
            "{text}\nfloat4 airlight_test_main() : SV_Target {{\n    return float4({p}airlight({a}), {p}radiance({r}), {}, 1.0);\n}}\n",
            spot.map_or("0.0".to_string(), |c| format!("{c}.x"))
        );
        let file = dir.join(format!("{stem}.frag.hlsl"));
        std::fs::write(&file, src).unwrap();
        // -V compiles to SPIR-V; -o keeps it out of the working directory.
        let out = Command::new(tool)
            .args(["-D", "-S", "frag", "-e", "airlight_test_main", "-V", "-o"])
            .arg(dir.join(format!("{stem}.spv")))
            .arg(&file)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{} as HLSL:\n{}{}",
            path.display(),
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn every_msl_kernel_keeps_its_entry_points() {
    let msl = files(&generated_dir().join("msl"), "metal");
    assert_eq!(msl.len(), files(&generated_dir().join("wgsl"), "wgsl").len(), "one MSL include per WGSL kernel");
    for path in &msl {
        let text = std::fs::read_to_string(path).unwrap();
        assert!(text.contains("#include <metal_stdlib>"), "{}", path.display());
        let p = prefix(path);
        let wgsl = wgsl_of(path);
        let table = wgsl.contains("texture_2d");
        let entries: &[&str] = if wgsl.contains(&format!("fn {p}spot(")) {
            &["airlight", "radiance", "spot"]
        } else {
            &["airlight", "radiance"]
        };
        for f in entries {
            let got = top_level_params(&text, &format!("{p}{f}"));
            let want = params(&wgsl, &format!("{p}{f}")).len();
            // naga's MSL passes a module's resources as arguments: a table kernel
            // takes its texture last.
            assert_eq!(got.len(), want + usize::from(table), "{}: {p}{f}: {got:?}", path.display());
            if table {
                assert!(got.last().unwrap().contains("texture2d"), "{}: {got:?}", path.display());
            }
        }
    }
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
        let spot = spot_call(&text, &p, &p, "vec3").map_or("0.0".to_string(), |c| format!("{c}.x"));
        let frag = format!(
            "#version 300 es\n{text}\nout highp vec4 color;\nvoid main() {{\n    color = vec4({p}airlight({a}), {p}radiance({r}), {spot}, 1.0);\n}}\n"
        );
        let comp = format!(
            "#version 450\n{text}\nlayout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer Out {{ float v[]; }} o;\n\
             void main() {{\n    o.v[0] = {p}airlight({a});\n    o.v[1] = {p}radiance({r});\n    o.v[2] = {spot};\n}}\n"
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

/// The shadow-map walk every kernel shares, in each language: its WGSL (with a
/// caller that walks a ray into phi-8's accumulator) and its pyramid pass validate
/// in naga; its GLSL compiles as ES 3.00 (fragment) and 4.50 (compute) with the
/// caller's `airlight_smap_node`, and the WebGL 2 pyramid pass as ES 3.00; naga's
/// HLSL compiles in glslang's HLSL front end; naga's MSL keeps the walk's functions.
#[test]
fn the_shadow_map_walk_compiles_in_every_language() {
    let g = generated_dir();
    let read = |f: &str| std::fs::read_to_string(g.join(f)).unwrap();
    let (walk, kernel) = (read("wgsl/shadowmap.wgsl"), read("wgsl/phi-8.wgsl"));
    let caller = "@group(0) @binding(0) var pyr: texture_2d_array<f32>;\n\
        @group(0) @binding(1) var<storage, read_write> out: array<f32>;\n\
        @compute @workgroup_size(1)\n\
        fn main() {\n\
            let rows = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));\n\
            var w = airlight_smap_begin(vec3<f32>(0.0), vec3<f32>(1.0, 0.0, 0.0), 10.0, vec3<f32>(2.0, 1.0, 0.0), rows, true, 1024u, 0.01, 0u);\n\
            var acc = airlight_phi_8_shafts_begin_runs();\n\
            loop {\n\
                let r = airlight_smap_next(&w, pyr);\n\
                if r.x < 0.0 { break; }\n\
                airlight_phi_8_shafts_add_run(&acc, r.x, r.y);\n\
            }\n\
            out[0] = airlight_phi_8_shafts_finish(acc, 10.0, vec3<f32>(0.0), vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(2.0, 1.0, 0.0), 1.0, 0.1, 0.1, 0.5);\n\
        }\n";
    let source = format!("{kernel}\n{walk}\n{caller}");
    let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
    validate(&module, "wgsl/shadowmap.wgsl with phi-8");
    let pass = read("wgsl/shadowmap_pyramid.wgsl");
    validate(&naga::front::wgsl::parse_str(&pass).unwrap(), "wgsl/shadowmap_pyramid.wgsl");

    let tool = glslang();
    let dir = std::env::temp_dir().join(format!("airlight-smap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let compile = |name: &str, src: String, extra: &[&str]| {
        let file = dir.join(name);
        std::fs::write(&file, src).unwrap();
        let out = Command::new(tool).args(extra).arg(&file).output().unwrap();
        assert!(
            out.status.success(),
            "{name}:\n{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let glsl = read("glsl/shadowmap.glsl");
    let walk_main = "void walk_it(out float n) {\n\
        AirlightSmapWalk w = airlight_smap_begin(vec3(0.0), vec3(1.0, 0.0, 0.0), 10.0, vec3(2.0, 1.0, 0.0), mat3(1.0), true, 1024, 0.01, 0);\n\
        n = 0.0;\n\
        for (;;) {\n\
            vec2 r = airlight_smap_next(w);\n\
            if (r.x < 0.0) break;\n\
            n += r.y - r.x;\n\
        }\n\
    }\n";
    let frag = format!(
        "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2DArray;\n{glsl}\n\
         uniform sampler2DArray pyr;\nvec2 airlight_smap_node(int face, int level, ivec2 p) {{ return texelFetch(pyr, ivec3(p, face), level).rg; }}\n\
         {walk_main}out highp vec4 color;\nvoid main() {{ float n; walk_it(n); color = vec4(n); }}\n"
    );
    compile("walk.frag", frag, &[]);
    let comp = format!(
        "#version 450\n{glsl}\nlayout(binding = 1) uniform sampler2DArray pyr;\n\
         vec2 airlight_smap_node(int face, int level, ivec2 p) {{ return texelFetch(pyr, ivec3(p, face), level).rg; }}\n\
         {walk_main}layout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer Out {{ float v[]; }} o;\n\
         void main() {{ float n; walk_it(n); o.v[0] = n; }}\n"
    );
    compile("walk.comp", comp, &[]);
    compile("pyramid.frag", read("glsl/shadowmap_pyramid.frag.glsl"), &[]);
    let hlsl = read("hlsl/shadowmap.hlsl");
    assert!(hlsl.contains("airlight_smap_next(") && hlsl.contains("airlight_smap_begin("), "HLSL keeps the walk");
    let msl = read("msl/shadowmap.metal");
    assert!(msl.contains("airlight_smap_next(") && msl.contains("#include <metal_stdlib>"), "MSL keeps the walk");
    let hsrc = format!("{hlsl}\nfloat4 airlight_test_main() : SV_Target {{ return float4(1.0, 0.0, 0.0, 1.0); }}\n");
    compile(
        "walk.frag.hlsl",
        hsrc,
        &["-D", "-S", "frag", "-e", "airlight_test_main", "-V", "-o", dir.join("walk.spv").to_str().unwrap()],
    );
    std::fs::remove_dir_all(&dir).ok();
}

//! Two generated kernels in one shader, in every language: an isotropic kernel
//! beside a Henyey–Greenstein one, and a scene kernel beside the general model it
//! was planned from. Each shader includes the first kernel, the second, and (where
//! the language has a preprocessor) the first again, through its include guard,
//! and calls every entry point of both:
//!
//! - GLSL as ES 3.00 (fragment) and 4.50 (compute), HLSL through glslang's HLSL
//!   front end, by `glslangValidator`;
//! - WGSL (no preprocessor: each file once) parsed and validated by naga;
//! - MSL: no Metal compiler exists here, so the two `.metal` files are checked to
//!   define disjoint top-level names inside their guards, and the two kernels'
//!   WGSL, composed into one module, is written as MSL by naga's back end (the
//!   generator's own path) with both kernels' entry points kept;
//! - the Bevy 0.19 modules composed by naga_oil into one shader importing both,
//!   and the WESL modules linked by the `wesl` crate into one, both validated.

use airlight_tests::calls::{entry_calls, files, glslang, prefix, wgsl_of};
use airlight_tests::generated_dir;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The pairs: (first, second, what the pair is).
fn pairs() -> Vec<(String, String, &'static str)> {
    // The scene kernel's general model, as its header names it.
    let scene = "scene-hg-fog";
    let text = std::fs::read_to_string(generated_dir().join(format!("glsl/{scene}.glsl"))).unwrap();
    let model = text
        .lines()
        .find_map(|l| l.strip_prefix("// model: "))
        .and_then(|l| l.split(';').next())
        .unwrap_or_else(|| panic!("{scene}.glsl names no model"))
        .to_string();
    vec![
        ("phi-iso-6".into(), "phi-4".into(), "an isotropic kernel beside an HG one"),
        (scene.into(), model, "a scene kernel beside its general model"),
    ]
}

fn path(dir: &str, name: &str, ext: &str) -> PathBuf {
    generated_dir().join(dir).join(format!("{name}.{ext}"))
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn tmp(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("airlight-compose-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run_glslang(args: &[&str], file: &Path, what: &str) {
    let out = Command::new(glslang()).args(args).arg(file).output().unwrap();
    assert!(
        out.status.success(),
        "{what}:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn two_glsl_kernels_compile_together_as_es_300_and_450() {
    let dir = tmp("glsl");
    for (a, b, what) in pairs() {
        let (ta, tb) = (read(&path("glsl", &a, "glsl")), read(&path("glsl", &b, "glsl")));
        let mut calls = entry_calls(&ta, &prefix(Path::new(&a)), &prefix(Path::new(&a)), "vec3");
        calls.extend(entry_calls(&tb, &prefix(Path::new(&b)), &prefix(Path::new(&b)), "vec3"));
        let sum = calls.join(" + ");
        let frag = format!(
            "#version 300 es\n{ta}\n{tb}\n{ta}\nout highp vec4 color;\nvoid main() {{\n    color = vec4({sum});\n}}\n"
        );
        let comp = format!(
            "#version 450\n{ta}\n{tb}\n{ta}\nlayout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer Out {{ float v[]; }} o;\n\
             void main() {{\n    o.v[0] = {sum};\n}}\n"
        );
        for (ext, src) in [("frag", frag), ("comp", comp)] {
            let file = dir.join(format!("{a}+{b}.{ext}"));
            std::fs::write(&file, src).unwrap();
            run_glslang(&[], &file, &format!("{a} + {b} ({what}) as GLSL {ext}"));
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn two_hlsl_kernels_compile_together_in_glslang_hlsl_front_end() {
    let dir = tmp("hlsl");
    for (a, b, what) in pairs() {
        let (ha, hb) = (path("hlsl", &a, "hlsl"), path("hlsl", &b, "hlsl"));
        let (ta, tb) = (read(&ha), read(&hb));
        // naga renames parameters; the calls follow the WGSL's order.
        let mut calls = entry_calls(&wgsl_of(&ha), &prefix(&ha), &prefix(&ha), "float3");
        calls.extend(entry_calls(&wgsl_of(&hb), &prefix(&hb), &prefix(&hb), "float3"));
        let src = format!(
            "{ta}\n{tb}\n{ta}\nfloat4 airlight_test_main() : SV_Target {{\n    return float4({}, 0.0, 0.0, 1.0);\n}}\n",
            calls.join(" + ")
        );
        let file = dir.join(format!("{a}+{b}.frag.hlsl"));
        std::fs::write(&file, src).unwrap();
        let spv = dir.join(format!("{a}+{b}.spv"));
        let args = ["-D", "-S", "frag", "-e", "airlight_test_main", "-V", "-o", spv.to_str().unwrap()];
        run_glslang(&args, &file, &format!("{a} + {b} ({what}) as HLSL"));
    }
    std::fs::remove_dir_all(&dir).ok();
}

fn validate(module: &naga::Module, what: &str) {
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(module)
        .unwrap_or_else(|e| panic!("{what}: {e:?}"));
}

/// A compute entry point writing the sum of `calls`.
fn wgsl_main(calls: &[String]) -> String {
    format!(
        "@group(1) @binding(0) var<storage, read_write> airlight_test_out: array<f32>;\n\
         @compute @workgroup_size(1)\nfn main() {{\n    airlight_test_out[0] = {};\n}}\n",
        calls.join(" + ")
    )
}

#[test]
fn two_wgsl_kernels_validate_together_in_naga() {
    for (a, b, what) in pairs() {
        let (ta, tb) = (read(&path("wgsl", &a, "wgsl")), read(&path("wgsl", &b, "wgsl")));
        let mut calls = entry_calls(&ta, &prefix(Path::new(&a)), &prefix(Path::new(&a)), "vec3<f32>");
        calls.extend(entry_calls(&tb, &prefix(Path::new(&b)), &prefix(Path::new(&b)), "vec3<f32>"));
        let src = format!("{ta}\n{tb}\n{}", wgsl_main(&calls));
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{a} + {b} ({what}): {}", e.emit_to_string(&src)));
        validate(&module, &format!("{a} + {b}"));
    }
}

/// The top-level names a `.metal` or `.hlsl` file defines (a line at column 0
/// that starts a struct, typedef, constant or function), after `using`s and the
/// preprocessor.
fn defined(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') && !l.starts_with("using "))
        .filter_map(|l| {
            let head = l.split(['(', '[', '=', '{', ':', ';']).next()?;
            let words: Vec<&str> = head.split_whitespace().collect();
            (words.len() > 1).then(|| words.last().unwrap().to_string())
        })
        .collect()
}

#[test]
fn two_msl_kernels_define_disjoint_names_and_compose_through_naga() {
    for (a, b, what) in pairs() {
        let (ma, mb) = (path("msl", &a, "metal"), path("msl", &b, "metal"));
        let (ta, tb) = (read(&ma), read(&mb));
        for (p, t) in [(&ma, &ta), (&mb, &tb)] {
            let guard = format!("{}MSL_INCLUDED", prefix(p).to_ascii_uppercase());
            let lines: Vec<&str> = t.lines().filter(|l| !l.starts_with("//")).collect();
            assert_eq!(lines[..2], [format!("#ifndef {guard}"), format!("#define {guard}")], "{}", p.display());
            assert_eq!(*lines.last().unwrap(), format!("#endif // {guard}"), "{}", p.display());
            let names = defined(t);
            assert!(names.len() > 10, "{}: {names:?}", p.display());
            for n in &names {
                assert!(n.starts_with(&prefix(p)), "{}: {n} is not prefixed", p.display());
            }
        }
        let (na, nb) = (defined(&ta), defined(&tb));
        assert!(na.iter().all(|n| !nb.contains(n)), "{a} and {b} ({what}) share a name");
        // Both kernels' WGSL in one module, through naga's MSL back end.
        let (wa, wb) = (wgsl_of(&ma), wgsl_of(&mb));
        let functions: Vec<String> = [(&wa, &ma), (&wb, &mb)]
            .iter()
            .flat_map(|(w, p)| {
                let pre = prefix(p);
                ["airlight", "radiance", "spot"]
                    .iter()
                    .filter(|e| w.contains(&format!("fn {pre}{e}(")))
                    .map(|e| format!("{pre}{e}"))
                    .collect::<Vec<_>>()
            })
            .collect();
        let both = format!("{wa}\n{wb}");
        let msl = airlight_codegen::translate::translate(
            &both,
            airlight_codegen::translate::Backend::Msl,
            "airlight_",
            &functions,
        )
        .unwrap_or_else(|e| panic!("{a} + {b} ({what}) through naga msl-out: {e}"));
        assert!(functions.len() >= 4 && functions.iter().all(|f| msl.contains(&format!(" {f}("))), "{functions:?}");
    }
}

fn validate29(module: &naga29::Module, what: &str) {
    naga29::valid::Validator::new(naga29::valid::ValidationFlags::all(), naga29::valid::Capabilities::empty())
        .validate(module)
        .unwrap_or_else(|e| panic!("{what}: {e:?}"));
}

#[test]
fn two_bevy_modules_compose_through_naga_oil_in_one_shader() {
    use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderLanguage};
    for (a, b, what) in pairs() {
        let mut composer = Composer::default();
        let mut imports = String::new();
        let mut calls = Vec::new();
        for name in [&a, &b] {
            let file = path("wgsl/bevy", name, "wgsl");
            let text = read(&file);
            composer
                .add_composable_module(ComposableModuleDescriptor {
                    source: &text,
                    file_path: &file.display().to_string(),
                    language: ShaderLanguage::Wgsl,
                    ..Default::default()
                })
                .unwrap_or_else(|e| panic!("{}: {e:?}", file.display()));
            let module = format!("airlight::{}", name.replace('-', "_"));
            imports.push_str(&format!("#import {module}\n"));
            calls.extend(entry_calls(&text, "", &format!("{module}::"), "vec3<f32>"));
        }
        let user = format!("{imports}{}", wgsl_main(&calls));
        let module = composer
            .make_naga_module(NagaModuleDescriptor { source: &user, file_path: "user.wgsl", ..Default::default() })
            .unwrap_or_else(|e| panic!("{a} + {b} ({what}): {e:?}"));
        validate29(&module, &format!("{a} + {b}"));
    }
}

#[test]
fn two_wesl_modules_link_through_wesl_in_one_shader() {
    use wesl::syntax::{ModulePath, PathOrigin};
    let dir = airlight_tests::wesl_dir();
    assert!(!files(&dir, "wesl").is_empty(), "{}", dir.display());
    for (a, b, what) in pairs() {
        let mut resolver = wesl::VirtualResolver::new();
        let mut imports = String::new();
        let mut calls = Vec::new();
        for name in [&a, &b] {
            let ident = name.replace('-', "_");
            let text = read(&dir.join(format!("{ident}.wesl")));
            let lib = ModulePath {
                origin: PathOrigin::Package(airlight_tests::WESL_PACKAGE.into()),
                components: vec![ident.clone()],
            };
            resolver.add_module(lib, text.clone().into());
            // Two modules export the same names: import each module, call through its path.
            imports.push_str(&format!("import {}::{ident};\n", airlight_tests::WESL_PACKAGE));
            calls.extend(entry_calls(&text, "", &format!("{ident}::"), "vec3<f32>"));
        }
        let root = ModulePath { origin: PathOrigin::Absolute, components: vec!["user".into()] };
        resolver.add_module(root.clone(), format!("{imports}{}", wgsl_main(&calls)).into());
        let options = wesl::CompileOptions { imports: true, condcomp: true, ..Default::default() };
        let wgsl = wesl::compile_sourcemap(&root, &resolver, &wesl::EscapeMangler, &options)
            .unwrap_or_else(|e| panic!("{a} + {b} ({what}): {e}"))
            .to_string();
        let module = naga::front::wgsl::parse_str(&wgsl)
            .unwrap_or_else(|e| panic!("{a} + {b} (as wesl linked it): {}", e.emit_to_string(&wgsl)));
        validate(&module, &format!("{a} + {b}"));
    }
}

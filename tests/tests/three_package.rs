//! The three.js package's modules (`generated/three/airlight-three/kernels/` and
//! `sources/`): each exports its kernel's sources as they are in `generated/`
//! (the sources' module importing nothing), and every TSL
//! node's function — the entry points' wrappers and the shafts accumulator's walk
//! of a shadow map — compiles against them: the `wgslFn` code with the module's
//! WGSL and its shadow look-up, validated by naga; the `glslFn` code with its
//! GLSL, by glslangValidator as GLSL ES 3.00. Node checks each module's syntax.
//! (A browser runs them in `shaders/tests/browser.rs`.)

use airlight_tests::calls::{files, glslang};
use airlight_tests::generated_dir;
use std::process::Command;

/// Every JavaScript string literal passed as the first argument of `call(`.
fn string_args(js: &str, call: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = js;
    let open = format!("{call}(\"");
    while let Some(at) = rest.find(&open) {
        let start = at + open.len() - 1;
        let bytes = rest.as_bytes();
        let mut i = start + 1;
        while bytes[i] != b'"' {
            i += if bytes[i] == b'\\' { 2 } else { 1 };
        }
        out.push(serde_json::from_str::<String>(&rest[start..=i]).unwrap());
        rest = &rest[i..];
    }
    out
}

/// `export const NAME = "…";` of a module.
fn exported(js: &str, name: &str) -> String {
    let open = format!("export const {name} = ");
    let at = js.find(&open).unwrap_or_else(|| panic!("no export {name}")) + open.len();
    let end = js[at..].find(";\n").unwrap();
    serde_json::from_str(&js[at..at + end]).unwrap()
}

#[test]
fn every_module_carries_its_sources_and_every_tsl_function_compiles() {
    let dir = generated_dir().join("three/airlight-three/kernels");
    // The menu's modules and the research kernels' (`research/kernels/`), alike.
    let mut modules = files(&dir, "js");
    assert!(modules.len() >= 10, "{} modules", modules.len());
    modules.extend(files(&dir.join("../research/kernels"), "js"));
    let tmp = std::env::temp_dir().join(format!("airlight-three-fns-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let mut shafts = 0;
    let shadow = std::fs::read_to_string(dir.join("../shadow.js")).unwrap();
    // The exact mode's walk (one string per language, in the import-free walk.js,
    // which shadowmap.js wraps as code nodes) and its pyramid passes, compiled with it.
    let walk = std::fs::read_to_string(dir.join("../walk.js")).unwrap();
    assert!(!walk.lines().any(|l| l.starts_with("import ")), "walk.js imports");
    let (walk_wgsl, walk_glsl) = (exported(&walk, "walkWGSL"), exported(&walk, "walkGLSL"));
    let smap = std::fs::read_to_string(dir.join("../shadowmap.js")).unwrap();
    assert!(
        smap.contains("wgslCode(walkWGSL)") && smap.contains("glslCode(walkGLSL)"),
        "shadowmap.js wraps walk.js's strings"
    );
    assert!(walk_wgsl.contains("fn airlight_smap_next(") && walk_glsl.contains("vec2 airlight_smap_next("), "the walk");
    let passes = format!("{walk_wgsl}\n{}\n", string_args(&smap, "wgslFn").join("\n"));
    let module =
        naga::front::wgsl::parse_str(&passes).unwrap_or_else(|e| panic!("shadowmap.js: {}", e.emit_to_string(&passes)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("shadowmap.js: {e:?}"));
    let mut exact = 0;
    for path in &modules {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let js = std::fs::read_to_string(path).unwrap();
        // The sources' module: the strings alone, importing nothing (WebGLRenderer needs no TSL).
        let sources = std::fs::read_to_string(path.parent().unwrap().join(format!("../sources/{name}.js"))).unwrap();
        assert!(!sources.lines().any(|l| l.starts_with("import ")), "{name}: the sources module imports");
        assert!(
            js.contains(&format!("from '../sources/{name}.js'")),
            "{name}: the nodes' module re-exports the sources"
        );
        let (wgsl, glsl) = (exported(&sources, "wgsl"), exported(&sources, "glsl"));
        assert_eq!(wgsl, std::fs::read_to_string(generated_dir().join(format!("wgsl/{name}.wgsl"))).unwrap(), "{name}");
        assert_eq!(glsl, std::fs::read_to_string(generated_dir().join(format!("glsl/{name}.glsl"))).unwrap(), "{name}");
        assert!(std::path::Path::new(&path.with_extension("d.ts")).exists(), "{name}: no declarations");
        // wgslFn: the kernel, the shadow look-up (a wgsl code node), every wrapper.
        // The shadow look-up lives once, in shadow.js (two kernels' shafts nodes in
        // one material include the same code node): no module defines it again.
        assert!(
            !js.contains("fn airlight_shadow_visibility") && !js.contains("float airlight_shadow_visibility"),
            "{name}: the module defines the shadow look-up itself"
        );
        let codes = string_args(&shadow, "wgslCode");
        let fns = string_args(&js, "wgslFn");
        assert!(fns.len() >= 2, "{name}: {} wgslFn", fns.len());
        shafts += fns.iter().filter(|f| f.contains("shafts_begin")).count();
        exact += fns.iter().filter(|f| f.contains("airlight_smap_next(")).count();
        let src = format!(
            "{wgsl}\n{}\n{walk_wgsl}\n{}\n",
            codes.iter().filter(|c| c.starts_with("fn ")).cloned().collect::<Vec<_>>().join("\n"),
            fns.join("\n")
        );
        let module =
            naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
        // glslFn: the kernel, the GLSL shadow look-up and every wrapper (the shafts
        // walks' too, whose header defines the depth texture's parameter type), as
        // GLSL ES 3.00.
        let gcodes = string_args(&shadow, "glslCode");
        let gfns = string_args(&js, "glslFn");
        assert_eq!(gfns.len(), fns.len(), "{name}: a glslFn per wgslFn");
        let frag = format!(
            "#version 300 es\nprecision highp float;\nprecision highp sampler2DShadow;\n{glsl}\n{}\n{walk_glsl}\n{}\nout highp vec4 color;\nvoid main() {{ color = vec4(0.0); }}\n",
            gcodes.iter().filter(|c| c.starts_with("float ")).cloned().collect::<Vec<_>>().join("\n"),
            gfns.join("\n")
        );
        let file = tmp.join(format!("{name}.frag"));
        std::fs::write(&file, frag).unwrap();
        let out = Command::new(glslang()).arg(&file).output().unwrap();
        assert!(
            out.status.success(),
            "{name}: {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        // The sources' exact spot entry (WebGLRenderer's pass): after the kernel's
        // GLSL and the walk, called, as GLSL ES 3.00; null exactly where the
        // module has no exact nodes.
        let open = "export const shaftsSpotExactGLSL = ";
        let at = sources.find(open).unwrap_or_else(|| panic!("{name}: no shaftsSpotExactGLSL")) + open.len();
        let literal = &sources[at..at + sources[at..].find(";\n").unwrap()];
        let has_exact = fns.iter().any(|f| f.contains("shaftsSpotExact_tsl("));
        assert_eq!(literal != "null", has_exact, "{name}: shaftsSpotExactGLSL against the exact nodes");
        if has_exact {
            let exact: String = serde_json::from_str(literal).unwrap();
            let p = exported(&sources, "prefix");
            let call = format!("{p}shafts_spot_exact(");
            assert!(exact.contains(&format!("vec3 {call}")), "{name}: {exact}");
            let frag = format!(
                "#version 300 es\nprecision highp float;\n{glsl}\n{walk_glsl}\n{exact}\nuniform highp sampler2D e;\nuniform highp sampler2D o;\nout highp vec4 color;\nvoid main() {{ color = vec4({call}{}), 1.0); }}\n",
                exact[exact.find('(').unwrap() + 1..exact.find(')').unwrap()]
                    .split(',')
                    .map(|a| match a.split_whitespace().collect::<Vec<_>>().as_slice() {
                        [.., "sampler2D", "pyramid_even"] => "e".to_string(),
                        [.., "sampler2D", "pyramid_odd"] => "o".to_string(),
                        [ty, _] => format!("{ty}(0.5)"),
                        other => panic!("{name}: parameter {other:?}"),
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            let file = tmp.join(format!("{name}.exact.frag"));
            std::fs::write(&file, frag).unwrap();
            let out = Command::new(glslang()).arg(&file).output().unwrap();
            assert!(
                out.status.success(),
                "{name}: the exact spot entry: {}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
        }
        if Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success()) {
            let out = Command::new("node").arg("--check").arg(path).output().unwrap();
            assert!(out.status.success(), "{name}: node --check: {}", String::from_utf8_lossy(&out.stderr));
        }
    }
    assert!(shafts >= 10, "{shafts} shafts nodes");
    assert!(exact >= 10, "{exact} exact shafts nodes");
    if Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success()) {
        for f in ["shadow.js", "walk.js", "shadowmap.js", "lights.js", "lightset.js", "webgl.js"] {
            let out = Command::new("node").arg("--check").arg(dir.join("..").join(f)).output().unwrap();
            assert!(out.status.success(), "{f}: node --check: {}", String::from_utf8_lossy(&out.stderr));
        }
    }
    std::fs::remove_dir_all(&tmp).ok();
}

/// Two kernels' shafts nodes in one material, as TSL includes them: each
/// kernel's WGSL once, the shared shadow look-up once, the exact mode's walk
/// once, both kernels' sampled and exact nodes — one valid WGSL module (naga).
#[test]
fn two_kernels_shafts_nodes_compose_with_one_shadow_look_up() {
    let dir = generated_dir().join("three/airlight-three");
    let shadow = std::fs::read_to_string(dir.join("shadow.js")).unwrap();
    let lookup: Vec<String> = string_args(&shadow, "wgslCode");
    assert_eq!(lookup.len(), 1, "one WGSL look-up in shadow.js");
    let walk = exported(&std::fs::read_to_string(dir.join("walk.js")).unwrap(), "walkWGSL");
    let mut src = format!("{}\n{walk}", lookup[0]);
    for name in ["phi-4", "phi-iso-6"] {
        let js = std::fs::read_to_string(dir.join(format!("kernels/{name}.js"))).unwrap();
        assert!(js.contains("from '../shadow.js'"), "{name}: imports the shared look-up");
        assert!(js.contains("from '../shadowmap.js'"), "{name}: imports the shared walk");
        assert!(!js.contains("fn airlight_smap_next("), "{name}: defines the walk itself");
        let sources = std::fs::read_to_string(dir.join(format!("sources/{name}.js"))).unwrap();
        src.push('\n');
        src.push_str(&exported(&sources, "wgsl"));
        for f in string_args(&js, "wgslFn").iter().filter(|f| f.contains("shafts_begin")) {
            src.push('\n');
            src.push_str(f);
        }
    }
    let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{e:?}"));
}

/// The GLSL shafts nodes under three.js r187 in Node (no browser: the node graph
/// only): called by name and in order, as the WGSL nodes are, each builds a call
/// with `shadow_sampler` dropped and the shadow map marked for comparison
/// sampling — a bare `DepthTexture` in order is wrapped in a texture node first.
/// (The browser test draws through the named form.)
#[test]
fn the_glsl_shafts_nodes_map_both_argument_forms() {
    use airlight_tests::npm_tools;
    let Some(tools) = npm_tools("three") else { return };
    if !Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success()) {
        return;
    }
    let tmp = std::env::temp_dir().join(format!("airlight-three-args-{}", std::process::id()));
    let modules = tmp.join("node_modules");
    std::fs::create_dir_all(&modules).unwrap();
    std::os::unix::fs::symlink(tools.join("node_modules/three"), modules.join("three")).unwrap();
    std::os::unix::fs::symlink(generated_dir().join("three/airlight-three"), modules.join("airlight-three")).unwrap();
    let script = r#"import { float, vec3, uniform, texture } from 'three/tsl';
import * as THREE from 'three';
import * as K from 'airlight-three/kernels/phi-4.js';
const depth = new THREE.DepthTexture(16, 16);
const m = () => uniform(new THREE.Matrix4());
const named = K.shaftsSpotGLSL({ origin: vec3(0, 0, 0), dir: vec3(0, 0, 1), surface: float(1), light: vec3(0, 1, 0),
  axis: vec3(0, -1, 0), cos_outer: float(0.8), cos_inner: float(0.9), intensity: float(1), sigma_t: vec3(0.1),
  sigma_s: vec3(0.1), g: float(0.5), shadow_map: texture(depth), shadow_sampler: texture(depth), shadow_matrix: m(),
  shadow_bias: float(0), look_ups: float(8), reach: float(10) });
const inOrder = K.shaftsSpotGLSL(vec3(0, 0, 0), vec3(0, 0, 1), float(1), vec3(0, 1, 0), vec3(0, -1, 0), float(0.8),
  float(0.9), float(1), vec3(0.1), vec3(0.1), float(0.5), depth, texture(depth), m(), float(0), float(8), float(10));
const p = named.parameters;
console.log(JSON.stringify({
  named: Object.keys(p).length, namedSampler: 'shadow_sampler' in p, namedCompare: p.shadow_map.compareNode !== null,
  inOrder: inOrder.parameters.length, inOrderCompare: inOrder.parameters[11].compareNode !== null,
  inOrderMatrix: inOrder.parameters[12].isUniformNode === true,
}));
"#;
    std::fs::write(tmp.join("check.mjs"), script).unwrap();
    // The package is linked, not copied: node resolves its imports from the link.
    let out = Command::new("node").args(["--preserve-symlinks", "check.mjs"]).current_dir(&tmp).output().unwrap();
    std::fs::remove_dir_all(&tmp).ok();
    assert!(out.status.success(), "node: {}", String::from_utf8_lossy(&out.stderr));
    let got: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // 17 arguments of the WGSL node, less shadow_sampler.
    assert_eq!(
        got,
        serde_json::json!({ "named": 16, "namedSampler": false, "namedCompare": true,
            "inOrder": 16, "inOrderCompare": true, "inOrderMatrix": true }),
        "{got}"
    );
}

/// A menu, not a catalogue (issue 40, item 3): the package's index lists the
/// kernels a renderer should use — airlight's own tiers and the closed form —
/// each with its declared bounds and measured costs, and `pick` chooses from it
/// by budget; the paper's models and the baselines are importable under
/// `research/kernels/` and absent from the index. Run in Node with three r187.
#[test]
fn the_index_is_a_menu_and_pick_chooses_by_budget() {
    use airlight_tests::npm_tools;
    let pkg = generated_dir().join("three/airlight-three");
    let index = std::fs::read_to_string(pkg.join("index.js")).unwrap();
    let research = ["paper", "segments-8", "hg-exp2", "raymarch-64", "equiangular-16"];
    for name in research {
        assert!(!index.contains(&format!("name: \"{name}\"")), "{name} is on the menu");
        assert!(pkg.join(format!("research/kernels/{name}.js")).is_file(), "{name}: no research module");
        assert!(!pkg.join(format!("kernels/{name}.js")).exists(), "{name}: still among the kernels");
    }
    for name in ["lite-3", "lite-iso-2", "phi-6", "phi-iso-6", "no-extinction"] {
        assert!(index.contains(&format!("name: \"{name}\"")), "{name} is not on the menu");
    }
    let package: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(pkg.join("package.json")).unwrap()).unwrap();
    assert!(package["exports"]["./research/kernels/*.js"].is_object(), "research modules exported");
    assert!(package["files"].as_array().unwrap().iter().any(|f| f == "research"), "research files packed");
    let Some(tools) = npm_tools("three") else { return };
    if !Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success()) {
        return;
    }
    let script = r#"import { kernels, pick, load, research } from 'airlight-three';
const worst = (k) => Math.max(k.thin, k.dense);
const out = { menu: kernels.length, research: research.length, picks: {} };
for (const [maxError, g] of [[1e-1, 0], [1e-2, 0], [1e-3, 0], [1e-4, 0.5], [1e-2, [-0.99, 0.99]], [1e-4, [-0.99, 0.99]]]) {
  const k = pick({ maxError, g });
  const lo = Array.isArray(g) ? g[0] : g, hi = Array.isArray(g) ? g[1] : g;
  // Brute force: the cheapest serving kernel within the budget.
  const fits = kernels.filter((c) => c.gRange[0] <= lo && hi <= c.gRange[1] && worst(c) <= maxError);
  const cheapest = Math.min(...fits.map((c) => c.gpuNs ?? c.cpuNs));
  out.picks[`${maxError} ${g}`] = { name: k && k.name, worst: k && worst(k), cost: k && (k.gpuNs ?? k.cpuNs), cheapest,
    serves: !!k && k.gRange[0] <= lo && hi <= k.gRange[1] };
}
out.none = pick({ maxError: 1e-9 });
out.costs = kernels.every((k) => k.cpuNs > 0);
const m = await load('phi-6');
const r = await load('raymarch-64');
out.loaded = typeof m.radianceWGSL === 'function' && typeof r.radianceWGSL === 'function';
let bad = '';
try { pick({}); } catch (e) { bad = e.message; }
out.bad = bad;
console.log(JSON.stringify(out));
"#;
    let v = node_with_package(&tools, &pkg, "menu", script);
    assert!(v["menu"].as_u64().unwrap() >= 15 && v["research"].as_u64().unwrap() >= 20, "{v}");
    for (budget, p) in v["picks"].as_object().unwrap() {
        let max: f64 = budget.split(' ').next().unwrap().parse().unwrap();
        assert!(p["name"].is_string(), "{budget}: nothing picked: {v}");
        assert!(p["worst"].as_f64().unwrap() <= max && p["serves"].as_bool().unwrap(), "{budget}: {p}");
        assert!(
            p["cost"].as_f64().unwrap() <= 1.1 * p["cheapest"].as_f64().unwrap(),
            "{budget}: not the cheapest: {p}"
        );
    }
    assert!(v["none"].is_null(), "{v}");
    assert!(v["costs"].as_bool().unwrap(), "every menu kernel has a measured cost: {v}");
    assert!(v["loaded"].as_bool().unwrap(), "{v}");
    assert!(v["bad"].as_str().unwrap().contains("maxError"), "{v}");
}

/// Runs `script` (an ES module) in Node with three.js from `tools` and the
/// package `pkg` as `airlight-three`; the JSON it prints.
fn node_with_package(tools: &std::path::Path, pkg: &std::path::Path, name: &str, script: &str) -> serde_json::Value {
    let tmp = std::env::temp_dir().join(format!("airlight-three-{name}-{}", std::process::id()));
    let modules = tmp.join("node_modules");
    std::fs::create_dir_all(&modules).unwrap();
    std::os::unix::fs::symlink(tools.join("node_modules/three"), modules.join("three")).unwrap();
    std::os::unix::fs::symlink(pkg, modules.join("airlight-three")).unwrap();
    let file = format!("{name}.mjs");
    std::fs::write(tmp.join(&file), script).unwrap();
    let o = Command::new("node").args(["--preserve-symlinks", &file]).current_dir(&tmp).output().unwrap();
    std::fs::remove_dir_all(&tmp).ok();
    assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// Copies `from` into `to`, folders and all.
fn copy_tree(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        let (src, dst) = (e.path(), to.join(e.file_name()));
        if src.is_dir() {
            copy_tree(&src, &dst);
        } else {
            std::fs::copy(&src, &dst).unwrap();
        }
    }
}

/// `VolumetricLightsPass` (WebGLRenderer), built in Node with three.js r187 as a
/// page builds it, for every kernel on the menu — a point, a spot and (shafts on)
/// a shadowed slot — with shafts off and on: its fragment shader, each kernel call
/// built from the entry's own signature (a kernel without extinction takes no
/// σt), compiles as GLSL ES 3.00 (glslang, three's `#include`s aside); with shafts
/// on, a kernel without an exact entry is refused in one line that says so.
#[test]
fn every_menu_kernels_webgl_pass_shader_compiles() {
    let Some(node) = airlight_tests::npm_tools("three") else { return };
    let tmp = std::env::temp_dir().join(format!("airlight-three-pass-{}", std::process::id()));
    std::fs::remove_dir_all(&tmp).ok();
    copy_tree(&generated_dir().join("three/airlight-three"), &tmp.join("node_modules/airlight-three"));
    std::os::unix::fs::symlink(node.join("node_modules/three"), tmp.join("node_modules/three")).unwrap();
    std::fs::write(
        tmp.join("build.mjs"),
        "import * as THREE from 'three';
import { kernels } from 'airlight-three';
import { VolumetricLightsPass } from 'airlight-three/webgl.js';
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera();
const out = [];
for (const k of kernels) {
  const S = await import(`airlight-three/sources/${k.name}.js`);
  for (const shafts of [false, true]) {
    try {
      const p = new VolumetricLightsPass(scene, camera, S, { sigmaT: 0.1, sigmaS: 0.05, name: k.name,
        maxPointLights: 1, maxSpotLights: 1, shafts, maxShadowedLights: 1 });
      out.push({ name: k.name, shafts, fragment: p.material.fragmentShader });
      p.dispose();
    } catch (e) {
      out.push({ name: k.name, shafts, error: e.message });
    }
  }
}
console.log(JSON.stringify(out));
",
    )
    .unwrap();
    let out = Command::new("node").arg("build.mjs").current_dir(&tmp).output().unwrap();
    assert!(out.status.success(), "node: {}", String::from_utf8_lossy(&out.stderr));
    let built: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout).unwrap();
    let menu = built.len() / 2;
    assert!(menu >= 10, "{menu} kernels on the menu");
    let mut shafts = 0;
    for b in &built {
        let (name, on) = (b["name"].as_str().unwrap(), b["shafts"].as_bool().unwrap());
        if let Some(e) = b["error"].as_str() {
            assert!(on, "{name}: the pass without shafts refused: {e}");
            assert_eq!(e, format!("airlight-three: {name} has no exact shafts entry; pass shafts: false"), "{name}");
            continue;
        }
        let fragment = b["fragment"].as_str().unwrap();
        shafts += usize::from(on);
        assert_eq!(
            fragment.contains("shafts_spot_exact("),
            on,
            "{name}: the walk is in the shader exactly with shafts"
        );
        let body: String = fragment
            .lines()
            .filter(|l| !l.trim_start().starts_with("#include"))
            .map(|l| l.replace("varying ", "in "))
            .collect::<Vec<_>>()
            .join("\n");
        let file = tmp.join(format!("{name}-{on}.frag"));
        std::fs::write(
            &file,
            format!("#version 300 es\nprecision highp float;\nprecision highp int;\n#define NP 1\n#define NS 1\nout highp vec4 pc_fragColor;\n#define gl_FragColor pc_fragColor\n{body}\n"),
        )
        .unwrap();
        let out = Command::new(glslang()).arg(&file).output().unwrap();
        assert!(
            out.status.success(),
            "{name} (shafts {on}): {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    eprintln!("VolumetricLightsPass: {menu} menu kernels' shaders compile, {shafts} with shafts");
    assert!(shafts >= 10, "{shafts} kernels cast shafts through the pass");
    std::fs::remove_dir_all(&tmp).ok();
}

/// Issue 60 (13–17) in Node with three.js r187: the rules the passes hold a
/// three.js light and the medium to (the same as the Bevy plugin's). A light
/// whose intensity is NaN, ±∞ or negative, or whose cone is wider than a
/// hemisphere or too thin for f32's cosine, is refused by `add` and, turned so
/// later, left out of the frame (warned about once); a light under an invisible
/// group, on a layer the camera does not see, or removed from the scene is not
/// drawn, as three does not draw it; a spot aims at its target's `matrixWorld`
/// as three does, with no update as a side effect; σt = 0 with σs > 0 is the
/// medium without extinction; the messages name what is wrong.
#[test]
fn three_lights_are_drawn_as_three_draws_them_and_refused_by_name() {
    use airlight_tests::npm_tools;
    let pkg = generated_dir().join("three/airlight-three");
    let Some(tools) = npm_tools("three") else { return };
    if !Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success()) {
        return;
    }
    let script = r#"import * as THREE from 'three';
import { LightSet, lightProblem, medium, checkG, checkMaxError, LIGHT_CORE, MIN_SPOT_ANGLE } from 'airlight-three/lightset.js';
const out = {};
const warnings = [];
console.warn = (m) => warnings.push(m);
const thrown = (f) => { try { f(); return ''; } catch (e) { return e.message; } };
const set = new LightSet(4, 4);
const u = () => ({ pointPosition: [0, 1, 2, 3].map(() => new THREE.Vector3()), pointIntensity: [0, 1, 2, 3].map(() => new THREE.Vector3()),
  spotPosition: [0, 1, 2, 3].map(() => new THREE.Vector3()), spotIntensity: [0, 1, 2, 3].map(() => new THREE.Vector3()),
  spotAxis: [0, 1, 2, 3].map(() => new THREE.Vector3()), spotCone: [0, 1, 2, 3].map(() => new THREE.Vector3()) });
// add refuses what the kernels cannot take, naming the light.
out.refused = {};
for (const [what, make] of [
  ['nan', () => new THREE.SpotLight(0xffffff, NaN)], ['inf', () => new THREE.PointLight(0xffffff, Infinity)],
  ['negative', () => new THREE.PointLight(0xffffff, -20)], ['wide', () => new THREE.SpotLight(0xffffff, 10, 0, 2.0)],
  ['thin', () => new THREE.SpotLight(0xffffff, 10, 0, 1e-4)], ['decay', () => new THREE.PointLight(0xffffff, 10, 0, 1)],
  ['undefined', () => undefined],
]) out.refused[what] = thrown(() => set.add(make()));
// Every kind of light three may not draw, and one it draws.
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(50, 1, 0.1, 100);
const good = new THREE.PointLight(0xffffff, 10, 0, 2); good.name = 'good';
const grouped = new THREE.PointLight(0xffffff, 10, 0, 2);
const group = new THREE.Group(); group.add(grouped); group.visible = false;
const layered = new THREE.PointLight(0xffffff, 10, 0, 2); layered.layers.set(3);
const removed = new THREE.PointLight(0xffffff, 10, 0, 2);
scene.add(good, group, layered, removed);
for (const l of [good, grouped, layered, removed]) set.add(l);
scene.remove(removed);
scene.updateMatrixWorld();
out.drawn = set.write(u(), camera).points;
// Turned bad after add: left out, warned once; good again: drawn again.
good.intensity = NaN;
out.nan = set.write(u(), camera).points;
set.write(u(), camera);
out.warnings = warnings.length;
out.warning = warnings[0] ?? '';
good.intensity = 10;
out.again = set.write(u(), camera).points;
good.decay = 1;
out.decayChanged = set.write(u(), camera).points;
good.decay = 2;
// A spot whose target is outside the scene aims at its target's matrixWorld as
// three does; getWorldPosition would have moved it.
const spot = new THREE.SpotLight(0xffffff, 10, 0, 0.5); spot.position.set(0, 5, 0);
scene.add(spot); scene.updateMatrixWorld();
spot.target.position.set(3, 0, 0);
set.add(spot);
const v = u();
set.write(v, camera);
out.axis = v.spotAxis[0].toArray();
out.targetMatrixUntouched = spot.target.matrixWorld.elements[12];
// The medium.
out.noExtinction = thrown(() => medium({ sigmaT: 0, sigmaS: 0.05 }, true, 'k'));
out.nanSigma = thrown(() => medium({ sigmaT: NaN, sigmaS: 0.05 }, true, 'k'));
out.stringG = thrown(() => checkG('0.5'));
out.wideG = thrown(() => checkG(0.995));
out.infError = thrown(() => checkMaxError(Infinity));
out.core = LIGHT_CORE;
out.minAngle = MIN_SPOT_ANGLE;
set.clear();
out.cleared = set.points.length + set.spots.length;
console.log(JSON.stringify(out));
"#;
    let v = node_with_package(&tools, &pkg, "rules", script);
    for (what, says) in [
        ("nan", "intensity NaN"),
        ("inf", "intensity Infinity"),
        ("negative", "intensity -20"),
        ("wide", "angle 2"),
        ("thin", "angle 0.0001"),
        ("decay", "decay = 1"),
        ("undefined", "got undefined"),
    ] {
        let m = v["refused"][what].as_str().unwrap();
        assert!(m.contains(says), "{what}: '{m}'");
    }
    assert_eq!(v["drawn"], 1, "{v}");
    assert_eq!(v["nan"], 0, "{v}");
    assert_eq!(v["warnings"], 1, "{v}");
    assert!(v["warning"].as_str().unwrap().contains("'good'"), "{v}");
    assert_eq!(v["again"], 1, "{v}");
    assert_eq!(v["decayChanged"], 0, "{v}");
    // Straight down, as the target's matrixWorld (at the origin) says.
    let axis: Vec<f64> = v["axis"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    assert!(axis[0].abs() < 1e-6 && (axis[1] + 1.0).abs() < 1e-6, "{v}");
    assert_eq!(v["targetMatrixUntouched"], 0, "{v}");
    assert_eq!(v["noExtinction"], "", "{v}");
    assert!(v["nanSigma"].as_str().unwrap().contains("got NaN"), "{v}");
    assert!(v["stringG"].as_str().unwrap().contains("the string '0.5'"), "{v}");
    assert!(v["wideG"].as_str().unwrap().contains("[-0.99, 0.99]"), "{v}");
    assert!(v["infError"].as_str().unwrap().contains("maxError"), "{v}");
    assert_eq!(v["core"], 0.01);
    assert_eq!(v["cleared"], 0);
}

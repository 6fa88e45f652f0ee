//! The browser driver of `main.rs` (beside it, with the page sources in `pages/`,
//! filled by [`fill`]): the airlight-three package where three.js users are: a page (three.js r187
//! from npm, pinned in `tests/node/package.json`) imports a kernel's ES module
//! from the package and draws the render's view of a scene in one full-screen
//! pass, through `WebGLRenderer` with the module's GLSL include in a
//! `RawShaderMaterial`, or through `WebGPURenderer` with its TSL node (`wgslFn`
//! on WebGPU, `glslFn` on the WebGL 2 backend), tone-mapped to 8 bits and read
//! back. Headless Chromium (WebGL 2 and WebGPU on SwiftShader), driven by
//! playwright-core (npm, pinned in `tests/node`) from `tests/node/browser.mjs` —
//! one browser for every page of the test binary — loads the page as
//! `http://127.0.0.1:8123/…`, every request answered from the page's files (no
//! network); the page POSTs the pixels back, and they are compared with the f64
//! reference render.

use airlight_shaders::render::{View, FOV_Y, GROUND_Y};
use airlight_shaders::shafts::render::{ShaftsView, Stage, WALK_BIAS};
use airlight_shapes::vocab::{Arg, IndexEntry};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

/// The three.js the pages load (npm, pinned in tests/node/package.json).
pub const THREE_VERSION: &str = "0.187.0";

/// The page's fragment shader: the GLSL include `kernel` of `k`, the view's rays
/// (the arithmetic of [`View::ray`], rows from the top), every light summed.
pub fn fragment_shader(k: &IndexEntry, kernel: &str, view: &View, exposure: f64) -> String {
    let args = airlight_shaders::render::radiance_args(k, view, "vec3(0.0)", "LIGHTS[i].xyz", "LIGHTS[i].w");
    let lights: Vec<String> =
        view.lights().iter().map(|(p, i)| format!("vec4({:?}, {:?}, {:?}, {:?})", p[0], p[1], p[2], i)).collect();
    let sigmas: Vec<String> = view.sigma_t.iter().map(|s| format!("{s:?}")).collect();
    fill(
        include_str!("pages/fragment.glsl"),
        &[
            ("kernel", kernel.to_string()),
            ("nl", format!("{}", lights.len())),
            ("lights", lights.join(", ").to_string()),
            ("np", format!("{}", sigmas.len())),
            ("sigmas", sigmas.join(", ").to_string()),
            ("pw_dbg", format!("{:?}", view.panel_width as f32)),
            ("h_dbg", format!("{:?}", view.height as f32)),
            ("half_dbg", format!("{:?}", 0.5 * FOV_Y)),
            ("ground", format!("{}", view.ground)),
            ("gy_dbg", format!("{:?}", GROUND_Y * view.scale)),
            ("prefix", k.prefix.to_string()),
            ("args", args.join(", ").to_string()),
            ("exposure_dbg", format!("{:?}", exposure as f32)),
        ],
    )
}

/// `s` as a JavaScript string literal.
fn js_string(s: &str) -> String {
    let mut o = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => o.push_str("\\\""),
            '\\' => o.push_str("\\\\"),
            '\n' => o.push_str("\\n"),
            c if (c as u32) < 0x20 || !c.is_ascii() => o.push_str(&format!("\\u{:04x}", c as u32)),
            c => o.push(c),
        }
    }
    o.push('"');
    o
}

/// Which three.js renderer a page draws with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
// The names are three.js's (WebGL, WebGPU): the shared prefix is theirs.
#[allow(clippy::enum_variant_names)]
pub enum Renderer {
    /// `WebGLRenderer` and a `RawShaderMaterial` that prepends the package's GLSL include.
    WebGl,
    /// `WebGPURenderer` on WebGPU, a node material calling the package's WGSL TSL node.
    WebGpu,
    /// `WebGPURenderer` forced onto its WebGL 2 backend, calling the GLSL TSL node.
    WebGpuOnWebGl,
}

impl Renderer {
    /// All three.
    pub const ALL: [Renderer; 3] = [Renderer::WebGl, Renderer::WebGpu, Renderer::WebGpuOnWebGl];

    /// Its name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Renderer::WebGl => "WebGLRenderer + GLSL include",
            Renderer::WebGpu => "WebGPURenderer (WebGPU) + TSL wgslFn",
            Renderer::WebGpuOnWebGl => "WebGPURenderer (WebGL 2 backend) + TSL glslFn",
        }
    }
}

/// The import map of a page: three.js r187's builds and the package, served
/// side by side (`three/`, `airlight-three/`).
const IMPORT_MAP: &str = r#"<script type="importmap">{"imports": {"three": "./three/three.module.js", "three/webgpu": "./three/three.webgpu.js", "three/tsl": "./three/three.tsl.js"}}</script>"#;

/// The page's TSL colour node: the ray of [`View::ray`] from the pixel, the
/// package's `radiance` node per light, tone-mapped as [`airlight_shaders::render::tone`].
fn tsl_colour(k: &IndexEntry, view: &View, exposure: f64, node: &str) -> String {
    let lights: Vec<String> =
        view.lights().iter().map(|(p, i)| format!("[{:?}, {:?}, {:?}, {:?}]", p[0], p[1], p[2], i)).collect();
    let sigma = view.sigma_t.iter().enumerate().skip(1).fold(format!("float({:?})", view.sigma_t[0]), |acc, (i, s)| {
        format!("select(panel.greaterThanEqual({i:?}.0), float({s:?}), {acc})")
    });
    let args: Vec<String> = k
        .radiance_params
        .iter()
        .map(|p| {
            let v = match p {
                Arg::Origin => "vec3(0.0, 0.0, 0.0)".to_string(),
                Arg::Dir => "dir".into(),
                Arg::Surface => "surface".into(),
                Arg::Light => "vec3(l[0], l[1], l[2])".into(),
                Arg::Intensity => "float(l[3])".into(),
                Arg::SigmaT => "sigmaT".into(),
                Arg::SigmaS => format!("sigmaT.mul({:?})", airlight_shaders::render::ALBEDO),
                Arg::G => format!("float({:?})", view.g),
                other => unreachable!("{other} is not an argument of radiance"),
            };
            format!("{}: {v}", p.name())
        })
        .collect();
    let ground = if view.ground {
        format!("select(dir.y.lessThan(0.0), float({:?}).div(dir.y), float(-1.0))", GROUND_Y * view.scale)
    } else {
        "float(-1.0)".into()
    };
    fill(
        include_str!("pages/tsl_colour.js"),
        &[
            ("pw_dbg", format!("{:?}", view.panel_width as f32)),
            ("h_dbg", format!("{:?}", view.height as f32)),
            ("t_dbg", format!("{:?}", (0.5 * FOV_Y).tan())),
            ("ground", ground.to_string()),
            ("sigma", sigma.to_string()),
            ("lights", lights.join(", ").to_string()),
            ("node", node.to_string()),
            ("args", args.join(", ").to_string()),
            ("exposure_dbg", format!("{:?}", exposure as f32)),
        ],
    )
}

/// The page for `renderer`: it imports the kernel's module from the package
/// (`airlight-three/kernels/<name>.js`), draws the view once into a `width ×
/// height` target, reads it back as 8-bit RGBA, rows from the top, and POSTs
/// to `/result` either `ok`, the adapter and the pixels (base64) on three lines,
/// or `error` and the message.
pub fn page(k: &IndexEntry, view: &View, exposure: f64, renderer: Renderer) -> String {
    let (width, height) = (view.width(), view.height);
    let module = format!("./airlight-three/kernels/{}.js", k.name);
    let sources = format!("./airlight-three/sources/{}.js", k.name);
    let (imports, body) = match renderer {
        Renderer::WebGl => (
            format!("import * as THREE from 'three';\nimport {{ glsl }} from '{sources}';"),
            fill(
                include_str!("pages/webgl.js"),
                &[("main", js_string(&fragment_shader(k, "", view, exposure)).to_string())],
            ),
        ),
        Renderer::WebGpu | Renderer::WebGpuOnWebGl => {
            let force = renderer == Renderer::WebGpuOnWebGl;
            let node = if force { "K.radianceGLSL" } else { "K.radianceWGSL" };
            let imports = format!(
                "import * as THREE from 'three/webgpu';\n\
                 import {{ Fn, float, vec3, vec4, screenCoordinate, floor, sqrt, dot, max, pow, select }} from 'three/tsl';\n\
                 import * as K from '{module}';"
            );
            let body = fill(
                include_str!("pages/webgpu.js"),
                &[
                    ("force", format!("{}", force)),
                    ("want", (if force { "WebGL 2" } else { "WebGPU" }).to_string()),
                    ("colour", tsl_colour(k, view, exposure, node).to_string()),
                ],
            );
            (imports, body)
        }
    };
    wrap_page(&imports, &body, width, height)
}

/// The page around a renderer's `imports` and the body of its `async draw()`,
/// which returns `{adapter, rgba, bottomUp, texel}` (`texel`: bytes per pixel, 4
/// unless given): the pixels go back rows from the top.
fn wrap_page(imports: &str, body: &str, width: u32, height: u32) -> String {
    fill(
        include_str!("pages/page.html"),
        &[
            ("IMPORT_MAP", IMPORT_MAP.to_string()),
            ("imports", imports.to_string()),
            ("width", format!("{}", width)),
            ("height", format!("{}", height)),
            ("body", body.to_string()),
        ],
    )
}

/// `vec3(x, y, z)` in GLSL.
fn glsl_v3(v: [f32; 3]) -> String {
    format!("vec3({:?}, {:?}, {:?})", v[0], v[1], v[2])
}

/// The light-shafts page (`WebGLRenderer`): the window-shafts room's occluders
/// (`airlight_shaders::shafts::render`) as three.js meshes that cast shadows, its spot as a
/// `SpotLight` with a shadow map (`PCFShadowMap`: a depth texture with a
/// comparison sampler, 2×2 filtered); one render builds three.js's shadow map,
/// then a full-screen `RawShaderMaterial` with the kernel's GLSL include walks
/// each view ray to its first surface in `look_ups` steps, looks visibility up
/// in that shadow map (through `light.shadow.matrix`) and feeds the kernel's
/// shafts accumulator (`shafts_push_spot`, `refine` bisection steps per change,
/// `shafts_finish_spot`). It reads back the fog (RGB) and the surface distance
/// as f32 and POSTs them (base64 of the floats, rows from the top).
pub fn shafts_page(k: &IndexEntry, view: &ShaftsView, look_ups: u32, refine: u32) -> String {
    use airlight_shaders::shafts::render as sr;
    let (width, height) = (view.width, view.height);
    let sources = format!("./airlight-three/sources/{}.js", k.name);
    let p = &k.prefix;
    let (st, ss) = sr::medium();
    let axis = sr::axis();
    let cos = sr::CONE_DEG.map(|d| d.to_radians().cos());
    let args: Vec<String> = k
        .spot_params
        .iter()
        .filter(|a| **a != Arg::Surface)
        .map(|a| match a {
            Arg::Origin => "CAMERA".to_string(),
            Arg::Dir => "dir".into(),
            Arg::Light => "LIGHT".into(),
            Arg::Axis => glsl_v3(axis),
            Arg::CosOuter => format!("{:?}", cos[0]),
            Arg::CosInner => format!("{:?}", cos[1]),
            Arg::Intensity => format!("{:?}", sr::INTENSITY),
            Arg::SigmaTRgb => glsl_v3(st),
            Arg::SigmaSRgb => glsl_v3(ss),
            Arg::G => format!("{:?}", sr::G),
            other => unreachable!("{other} is not an argument of spot"),
        })
        .collect();
    let args = args.join(", ");
    let [f, r, u] = sr::camera_basis();
    let boxes = sr::boxes();
    let slabs: String = boxes
        .iter()
        .map(|b| format!("    end = min(end, box_entry({}, {}, dir, end));\n", glsl_v3(b.0), glsl_v3(b.1)))
        .collect();
    let room = sr::ROOM;
    let main = fill(
        include_str!("pages/shafts.glsl"),
        &[
            ("camera", glsl_v3(sr::CAMERA).to_string()),
            ("light", glsl_v3(sr::LIGHT).to_string()),
            ("h_dbg", format!("{:?}", height as f32)),
            ("w_dbg", format!("{:?}", width as f32)),
            ("t_dbg", format!("{:?}", (0.5 * FOV_Y).tan())),
            ("f", glsl_v3(f).to_string()),
            ("aspect_dbg", format!("{:?}", width as f32 / height as f32)),
            ("r", glsl_v3(r).to_string()),
            ("up", glsl_v3(u).to_string()),
            ("room_lo", glsl_v3([room[0][0], room[1][0], room[2][0]]).to_string()),
            ("room_hi", glsl_v3([room[0][1], room[1][1], room[2][1]]).to_string()),
            ("slabs", slabs.to_string()),
            ("ball_c", glsl_v3(sr::BALL.0).to_string()),
            ("ball_r2_dbg", format!("{:?}", sr::BALL.1 * sr::BALL.1)),
            ("p", p.to_string()),
            ("args", args.to_string()),
            ("n", format!("{}", look_ups)),
            ("nf_dbg", format!("{:?}", look_ups as f32)),
            ("refine", format!("{}", refine)),
        ],
    );
    let body = fill(
        include_str!("pages/shafts_webgl.js"),
        &[
            (
                "scene",
                shafts_scene_js(
                    &Stage::window_shafts(),
                    "new THREE.MeshBasicMaterial()",
                    "new THREE.MeshBasicMaterial()",
                    "WebGLRenderTarget",
                    sr::SHADOW_MAP,
                    ShadowSide::Default,
                ),
            ),
            ("main", js_string(&main).to_string()),
        ],
    );
    let imports = format!("import * as THREE from 'three';\nimport {{ glsl }} from '{sources}';");
    wrap_page(&imports, &body, width, height)
}

/// The TSL page's scene code in the node's language (GLSL for the WebGL 2
/// backend, WGSL for WebGPU): where a ray from the stage's camera first meets its
/// room or an occluder (`airlight_page_end`), and the slab test it calls (`box_entry`).
fn tsl_scene_code(stage: &Stage, webgl: bool) -> (String, String) {
    let v3 = |v: [f32; 3]| {
        if webgl {
            glsl_v3(v)
        } else {
            format!("vec3<f32>({:?}, {:?}, {:?})", v[0], v[1], v[2])
        }
    };
    let slabs: String = stage
        .boxes
        .iter()
        .map(|b| format!("    end = min(end, box_entry(o, {}, {}, dir, end));\n", v3(b.0), v3(b.1)))
        .collect();
    // Declarations by what they hold: a vector, a scalar, a scalar that changes.
    let (vector, scalar, mutable, fn_end, fn_box) = if webgl {
        (
            "vec3",
            "float",
            "float",
            "float airlight_page_end(vec3 dir)",
            "float box_entry(vec3 o, vec3 lo, vec3 hi, vec3 d, float end)",
        )
    } else {
        (
            "let",
            "let",
            "var",
            "fn airlight_page_end(dir: vec3<f32>) -> f32",
            "fn box_entry(o: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>, d: vec3<f32>, end: f32) -> f32",
        )
    };
    let scene_end = fill(
        include_str!("pages/shafts_scene_end.txt"),
        &[
            ("fn_end", fn_end.to_string()),
            ("vector", vector.to_string()),
            ("cam", v3(stage.camera)),
            ("lo", v3(stage.room[0])),
            ("hi", v3(stage.room[1])),
            ("mutable", mutable.to_string()),
            ("slabs", slabs),
            ("ball", v3(stage.ball.0)),
            ("scalar", scalar.to_string()),
            ("r2_dbg", format!("{:?}", stage.ball.1 * stage.ball.1)),
        ],
    );
    let box_entry = fill(
        include_str!("pages/shafts_box_entry.txt"),
        &[
            ("fn_box", fn_box.to_string()),
            ("vector", vector.to_string()),
            ("scalar", scalar.to_string()),
            (
                "pick",
                (if webgl { "(t0 < t1 && t0 > 0.0) ? t0 : end" } else { "select(end, t0, t0 < t1 && t0 > 0.0)" })
                    .to_string(),
            ),
        ],
    );
    (scene_end, box_entry)
}

/// The light node's arguments, by name, as the TSL page passes them: the spot
/// entry's for a spot stage, the radiance entry's (one channel of the stage's
/// grey medium) for a point light.
fn tsl_light_args(k: &IndexEntry, stage: &Stage) -> Vec<String> {
    let t3 = |v: [f32; 3]| format!("vec3({:?}, {:?}, {:?})", v[0], v[1], v[2]);
    let spot = stage.spot.zip(stage.axis());
    let params = if spot.is_some() { &k.spot_params } else { &k.radiance_params };
    params
        .iter()
        .map(|a| {
            let v = match (a, spot) {
                (Arg::Origin, _) => t3(stage.camera),
                (Arg::Dir, _) => "dir".to_string(),
                (Arg::Surface, _) => "end".into(),
                (Arg::Light, _) => t3(stage.light),
                (Arg::Axis, Some((_, axis))) => t3(axis),
                (Arg::CosOuter, Some((s, _))) => format!("float({:?})", s.cone_deg[0].to_radians().cos()),
                (Arg::CosInner, Some((s, _))) => format!("float({:?})", s.cone_deg[1].to_radians().cos()),
                (Arg::Intensity, _) => format!("float({:?})", stage.intensity),
                (Arg::SigmaTRgb, _) => t3(stage.sigma_t),
                (Arg::SigmaSRgb, _) => t3(stage.sigma_s),
                (Arg::SigmaT, _) => format!("float({:?})", stage.sigma_t[0]),
                (Arg::SigmaS, _) => format!("float({:?})", stage.sigma_s[0]),
                (Arg::G, _) => format!("float({:?})", stage.g),
                (other, _) => unreachable!("{other} is not an argument of a light entry"),
            };
            format!("{}: {v}", a.name())
        })
        .collect()
}

/// The three.js scene of a light-shafts stage (JavaScript, `THREE` in scope):
/// its occluders as meshes casting shadows (`material`), a floor receiving them
/// (`floor`), its light as a `SpotLight` or a `PointLight` with a `map`² shadow
/// map (a cube map for the point light), and a camera; then one render that
/// draws three.js's shadow map into `light.shadow`.
fn shafts_scene_js(stage: &Stage, material: &str, floor: &str, target: &str, map: u32, side: ShadowSide) -> String {
    let js_boxes: Vec<String> = stage
        .boxes
        .iter()
        .map(|b| format!("[{:?}, {:?}, {:?}, {:?}, {:?}, {:?}]", b.0[0], b.0[1], b.0[2], b.1[0], b.1[1], b.1[2]))
        .collect();
    let light = match stage.spot {
        Some(s) => format!(
            "const light = new THREE.SpotLight(0xffffff, 1.0, 0, {:?}, 0.0, 2);\nlight.target.position.set({:?}, {:?}, {:?});\nscene.add(light.target);",
            s.cone_deg[0].to_radians(),
            s.aim[0],
            s.aim[1],
            s.aim[2]
        ),
        None => "const light = new THREE.PointLight(0xffffff, 1.0, 0, 2);".to_string(),
    };
    let [lo, hi] = stage.room;
    fill(
        include_str!("pages/shafts_scene.js"),
        &[
            ("material", material.to_string()),
            ("shadow_side", side.js().to_string()),
            ("boxes", js_boxes.join(", ")),
            ("ball_r_dbg", format!("{:?}", stage.ball.1)),
            ("bx_dbg", format!("{:?}", stage.ball.0[0])),
            ("by_dbg", format!("{:?}", stage.ball.0[1])),
            ("bz_dbg", format!("{:?}", stage.ball.0[2])),
            ("floor", floor.to_string()),
            ("floor_w_dbg", format!("{:?}", hi[0] - lo[0])),
            ("floor_d_dbg", format!("{:?}", hi[2] - lo[2])),
            ("floor_x_dbg", format!("{:?}", 0.5 * (lo[0] + hi[0]))),
            ("floor_y_dbg", format!("{:?}", lo[1])),
            ("floor_z_dbg", format!("{:?}", 0.5 * (lo[2] + hi[2]))),
            ("light", light),
            ("lx_dbg", format!("{:?}", stage.light[0])),
            ("ly_dbg", format!("{:?}", stage.light[1])),
            ("lz_dbg", format!("{:?}", stage.light[2])),
            ("map", format!("{map}")),
            ("near_dbg", format!("{:?}", stage.near_far[0])),
            ("far_dbg", format!("{:?}", stage.near_far[1])),
            ("cx_dbg", format!("{:?}", stage.camera[0])),
            ("cy_dbg", format!("{:?}", stage.camera[1])),
            ("cz_dbg", format!("{:?}", stage.camera[2])),
            ("target", target.to_string()),
        ],
    )
}

/// Which faces of the occluders three.js draws into the shadow map: its
/// default (the back faces, against shadow acne on lit surfaces) or the front
/// faces (the depth of the surface the light sees).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowSide {
    Default,
    Front,
}

impl ShadowSide {
    fn js(self) -> &'static str {
        match self {
            ShadowSide::Default => "",
            ShadowSide::Front => "stone.shadowSide = THREE.FrontSide;\n",
        }
    }
}

/// How a TSL light-shafts page finds the lit runs: the shafts node's `look_ups`
/// equal steps through three.js's shadow map, or the exact mode's walk over a
/// `ShadowPyramid` of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fog {
    Sampled(u32),
    Exact,
}

/// The light-shafts page on `WebGPURenderer`: `stage`'s room, three.js's shadow
/// map of its light (`map`² texels a face), and a shafts TSL node of the package
/// (the page's own code node finds the first surface) — on WebGPU through the
/// `…WGSL` node, or (`webgl`) on the WebGL 2 backend through the `…GLSL` one: by
/// `fog`, the sampled node (`shaftsSpot`, spot stages only) or the exact mode
/// (`shaftsSpotExact` / `shaftsExact` over a `ShadowPyramid`).
pub fn shafts_page_tsl(
    k: &IndexEntry,
    stage: &Stage,
    view: &ShaftsView,
    fog: Fog,
    map: u32,
    side: ShadowSide,
    webgl: bool,
) -> String {
    let (width, height) = (view.width, view.height);
    let module = format!("./airlight-three/kernels/{}.js", k.name);
    let t3 = |v: [f32; 3]| format!("vec3({:?}, {:?}, {:?})", v[0], v[1], v[2]);
    let (scene_end, box_entry) = tsl_scene_code(stage, webgl);
    let args = tsl_light_args(k, stage).join(", ");
    let lang = if webgl { "GLSL" } else { "WGSL" };
    let spot = stage.spot.is_some();
    let (setup, call) = match fog {
        Fog::Sampled(n) => {
            assert!(spot, "the sampled node takes a spot light's 2D map");
            (
                "const depth = texture(light.shadow.map.depthTexture);".to_string(),
                format!("K.shaftsSpot{lang}({{ {args}, shadow_map: depth, shadow_sampler: depth, shadow_matrix: uniform(light.shadow.matrix), shadow_bias: float(-0.0005), look_ups: float({n:?}), reach: float(100.0) }})"),
            )
        }
        Fog::Exact => (
            format!(
                "const pyramid = new ShadowPyramid(light, {{ bias: {:?} }});\npyramid.update(renderer);",
                WALK_BIAS
            ),
            format!("K.shafts{}Exact{lang}({{ {args}, ...pyramid.nodes() }})", if spot { "Spot" } else { "" }),
        ),
    };
    // A point light's node is one channel of the grey medium: its colour outside.
    let colour = stage.colour;
    let fog_node = if spot { call } else { format!("vec3({call}).mul({})", t3(colour)) };
    let [f, r, u] = stage.camera_basis();
    let body = fill(
        include_str!("pages/shafts_tsl.js"),
        &[
            ("webgl", format!("{}", webgl)),
            ("want", (if webgl { "WebGL 2" } else { "WebGPU" }).to_string()),
            (
                "scene",
                shafts_scene_js(
                    stage,
                    "new THREE.MeshStandardNodeMaterial()",
                    "new THREE.MeshStandardNodeMaterial()",
                    "RenderTarget",
                    map,
                    side,
                ),
            ),
            ("code_fn", (if webgl { "glslFn" } else { "wgslFn" }).to_string()),
            ("scene_end", js_string(&scene_end)),
            ("code", (if webgl { "glslCode" } else { "wgslCode" }).to_string()),
            ("box_entry", js_string(&box_entry)),
            ("fog_setup", setup),
            ("t_dbg", format!("{:?}", (0.5 * FOV_Y).tan())),
            ("f", t3(f)),
            ("r", t3(r)),
            ("aspect_dbg", format!("{:?}", width as f32 / height as f32)),
            ("up", t3(u)),
            ("fog", fog_node),
            ("per_frame", (if fog == Fog::Exact { "() => pyramid.update(renderer)" } else { "null" }).to_string()),
        ],
    );
    let imports = format!(
        "import * as THREE from 'three/webgpu';\nimport {{ Fn, float, vec3, vec4, screenCoordinate, sqrt, dot, texture, uniform, wgslFn, wgsl as wgslCode, glslFn, glsl as glslCode }} from 'three/tsl';\nimport * as K from '{module}';\nimport {{ ShadowPyramid }} from './airlight-three/shadowmap.js';"
    );
    wrap_page(&imports, &body, width, height)
}

/// The three.js camera basis for a camera at the stage's position looking along
/// `forward` with world +Y up (`lookAt`): forward, right (`forward × Y`), up.
pub fn three_basis(forward: [f32; 3]) -> [[f32; 3]; 3] {
    use airlight_shaders::shafts::render::{cross, unit};
    let r = unit(cross(forward, [0.0, 1.0, 0.0]));
    [forward, r, cross(r, forward)]
}

/// The scene-level API's page (`airlight-three/lights.js`): `stage`'s room drawn
/// by three.js with its light as a `THREE.PointLight` or `THREE.SpotLight` of
/// the stage's intensity and colour, added to a `VolumetricLights` of kernel
/// `k` in the stage's medium; the fog alone (`fog()`: RGB, and the distance to
/// the first surface from the scene pass's depth), the scene's colour, the
/// composite, the next frame's fog and the composite as `PostProcessing`'s
/// output, read back as floats. The
/// camera is three's, aimed as the stage's (its pixels' rays: [`three_basis`]).
/// `shafts`: the light casts shafts from its own `map`² shadow map (the
/// API's default for a light with `castShadow`); otherwise `shafts: false`
/// and a 512² map that only the surfaces use.
pub fn lights_page_tsl(k: &IndexEntry, stage: &Stage, view: &ShaftsView, webgl: bool, shafts: Option<u32>) -> String {
    let module = format!("./airlight-three/kernels/{}.js", k.name);
    let imports = format!(
        "import * as THREE from 'three/webgpu';\nimport {{ pass, screenUV }} from 'three/tsl';\nimport * as K from '{module}';\nimport {{ VolumetricLights }} from './airlight-three/lights.js';"
    );
    lights_page(k, stage, view, Some(webgl), shafts, &imports)
}

/// The same check on `WebGLRenderer` through `VolumetricLightsPass`
/// (`airlight-three/webgl.js`), the kernel's GLSL from its sources module:
/// the fog alone, the scene's colour as the pass drew it, the composite, and
/// the next frame's fog with the light's intensity doubled (16 bytes each).
/// `shafts` as on the WebGPURenderer page: the light's own `map`² shadow map
/// walked (a `ShadowPyramidGL` the pass rebuilds each frame), or none.
pub fn lights_page_webgl(k: &IndexEntry, stage: &Stage, view: &ShaftsView, shafts: Option<u32>) -> String {
    let imports = format!(
        "import * as THREE from 'three';\nimport * as S from './airlight-three/sources/{}.js';\nimport {{ VolumetricLightsPass }} from './airlight-three/webgl.js';",
        k.name
    );
    lights_page(k, stage, view, None, shafts, &imports)
}

/// A lights page: `lights_tsl.js` on WebGPURenderer (`webgl`: its backend), or
/// `lights_webgl.js` on WebGLRenderer (None).
fn lights_page(
    k: &IndexEntry,
    stage: &Stage,
    view: &ShaftsView,
    webgl: Option<bool>,
    shafts: Option<u32>,
    imports: &str,
) -> String {
    let (width, height) = (view.width, view.height);
    let l3 = |v: [f32; 3]| format!("{:?}, {:?}, {:?}", v[0], v[1], v[2]);
    let f = stage.camera_basis()[0];
    let c = stage.camera;
    let penumbra = match stage.spot {
        Some(s) => format!("light.penumbra = {:?};", 1.0 - s.cone_deg[1] / s.cone_deg[0]),
        None => String::new(),
    };
    let (page, material, target) = match webgl {
        Some(_) => (include_str!("pages/lights_tsl.js"), "new THREE.MeshStandardNodeMaterial()", "RenderTarget"),
        None => (include_str!("pages/lights_webgl.js"), "new THREE.MeshStandardMaterial()", "WebGLRenderTarget"),
    };
    // The shafts: on, over the stage's map, or off.
    let extra = match shafts {
        Some(_) => format!(", shafts: true, maxShadowedLights: 1, shadowBias: {WALK_BIAS:?}"),
        None => ", shafts: false".to_string(),
    };
    let webgl = webgl.unwrap_or(true);
    let body = fill(
        page,
        &[
            ("webgl", format!("{webgl}")),
            ("want", (if webgl { "WebGL 2" } else { "WebGPU" }).to_string()),
            ("scene", shafts_scene_js(stage, material, material, target, shafts.unwrap_or(512), ShadowSide::Front)),
            ("intensity", format!("{:?}", stage.intensity)),
            ("colour", l3(stage.colour)),
            ("spot_penumbra", penumbra),
            ("fov_deg", format!("{:?}", FOV_Y.to_degrees())),
            ("camera", l3(c)),
            ("target_pos", l3([c[0] + f[0], c[1] + f[1], c[2] + f[2]])),
            ("sigma_t", l3(stage.sigma_t)),
            ("sigma_s", l3(stage.sigma_s)),
            ("g", format!("{:?}", stage.g)),
            ("name", k.name.clone()),
            (
                "limits",
                format!(
                    "{}{}",
                    if stage.spot.is_some() {
                        "maxPointLights: 0, maxSpotLights: 1"
                    } else {
                        "maxPointLights: 1, maxSpotLights: 0"
                    },
                    extra
                ),
            ),
        ],
    );
    wrap_page(imports, &body, width, height)
}

/// What the page drew.
#[derive(Debug, Clone, PartialEq)]
pub struct Drawn {
    /// three.js revision, WebGL version and renderer string.
    pub adapter: String,
    /// Gray levels, rows from the top, `width × height`.
    pub pixels: Vec<u8>,
}

/// Why the page did not draw.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BrowserError(pub String);

impl std::fmt::Display for BrowserError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BrowserError {}

/// Debian's Chromium, where it is installed (`AIRLIGHT_CHROMIUM` overrides).
pub fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("AIRLIGHT_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    ["/usr/bin/chromium", "/usr/bin/chromium-browser"].iter().map(PathBuf::from).find(|p| p.exists())
}

fn decode_base64(s: &str) -> Result<Vec<u8>, BrowserError> {
    let val = |c: u8| -> Result<u32, BrowserError> {
        Ok(match c {
            b'A'..=b'Z' => u32::from(c - b'A'),
            b'a'..=b'z' => u32::from(c - b'a') + 26,
            b'0'..=b'9' => u32::from(c - b'0') + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return Err(BrowserError(format!("bad base64 byte {c}"))),
        })
    };
    let bytes: Vec<u8> = s.bytes().filter(|c| !c.is_ascii_whitespace()).collect();
    let mut out = Vec::with_capacity(bytes.len() / 4 * 3);
    for chunk in bytes.chunks(4) {
        let pad = chunk.iter().filter(|&&c| c == b'=').count();
        let mut n = 0u32;
        for &c in chunk {
            n = (n << 6) | if c == b'=' { 0 } else { val(c)? };
        }
        let b = n.to_be_bytes();
        out.extend_from_slice(&b[1..4 - pad]);
    }
    Ok(out)
}

/// How long a page may take to report (`AIRLIGHT_BROWSER_TIMEOUT_S` overrides).
pub const TIMEOUT_S: u64 = 240;

/// The one browser of this test binary: `tests/node/browser.mjs`, which drives
/// `chrome` through playwright-core (npm, pinned in `tests/node`), launched on
/// the first page and kept for every page after it (each page in a fresh browser
/// context). It ends when this process does (its stdin closes).
struct Browser {
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
}

impl Browser {
    fn start(chrome: &Path) -> Result<Browser, BrowserError> {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/node/browser.mjs");
        let mut child = Command::new("node")
            .arg(&script)
            .arg(chrome)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| BrowserError(format!("node {}: {e}", script.display())))?;
        let (Some(stdin), Some(stdout)) = (child.stdin.take(), child.stdout.take()) else {
            return Err(BrowserError("node's pipes".into()));
        };
        Ok(Browser { child, stdin, stdout: BufReader::new(stdout) })
    }

    /// Loads `page` from the files under `dir` and waits for its POST.
    fn draw(&mut self, dir: &Path, page: &str, timeout_s: u64) -> Result<String, BrowserError> {
        let quote = |s: &str| {
            let mut q = String::from('"');
            for c in s.chars() {
                match c {
                    '"' => q.push_str("\\\""),
                    '\\' => q.push_str("\\\\"),
                    c if (c as u32) < 0x20 => q.push_str(&format!("\\u{:04x}", c as u32)),
                    c => q.push(c),
                }
            }
            q.push('"');
            q
        };
        // The test drawing it (libtest names its threads after the tests), for
        // the driver's line of timing.
        let what = std::thread::current().name().unwrap_or("a page").to_string();
        let request = format!(
            "{{\"dir\":{},\"page\":{},\"timeout_s\":{timeout_s},\"what\":{}}}\n",
            quote(&dir.to_string_lossy()),
            quote(page),
            quote(&what)
        );
        let gone =
            |e: std::io::Error| BrowserError(format!("the browser driver (tests/node/browser.mjs) stopped: {e}"));
        self.stdin.write_all(request.as_bytes()).map_err(gone)?;
        self.stdin.flush().map_err(gone)?;
        let mut head = String::new();
        if self.stdout.read_line(&mut head).map_err(gone)? == 0 {
            let status = self.child.try_wait().ok().flatten();
            return Err(BrowserError(format!("the browser driver (tests/node/browser.mjs) exited ({status:?})")));
        }
        let (kind, len) = head.trim_end().split_once(' ').unwrap_or(("", ""));
        let len: usize = len.parse().map_err(|_| BrowserError(format!("the browser driver said {head:?}")))?;
        let mut body = vec![0u8; len];
        self.stdout.read_exact(&mut body).map_err(gone)?;
        let body = String::from_utf8_lossy(&body).into_owned();
        match kind {
            "ok" => Ok(body),
            _ => Err(BrowserError(body)),
        }
    }
}

/// Serves `files` (name → contents) to the page, loads `index.html` in
/// headless `chrome` and returns what the page read back: the adapter it names
/// and its bytes, rows from the top.
pub fn draw_raw(chrome: &Path, files: Vec<(String, Vec<u8>)>) -> Result<(String, Vec<u8>), BrowserError> {
    draw_raw_within(chrome, files, "index.html", TIMEOUT_S)
}

/// [`draw_raw`] with the page at `page` (a path, and a query, among `files`),
/// given `timeout_s` seconds (`AIRLIGHT_BROWSER_TIMEOUT_S` overrides it).
pub fn draw_raw_within(
    chrome: &Path,
    files: Vec<(String, Vec<u8>)>,
    page: &str,
    timeout_s: u64,
) -> Result<(String, Vec<u8>), BrowserError> {
    // One page at a time: on two cores, pages drawn side by side by the
    // parallel tests (SwiftShader, both CPU-bound) ran past their timeouts.
    static BROWSER: std::sync::Mutex<Option<Browser>> = std::sync::Mutex::new(None);
    static PAGES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let mut browser = BROWSER.lock().unwrap_or_else(|e| e.into_inner());
    let n = PAGES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("airlight-page-{}-{n}", std::process::id()));
    let io = |e: std::io::Error| BrowserError(format!("{}: {e}", dir.display()));
    for (name, body) in &files {
        let p = dir.join(name);
        std::fs::create_dir_all(p.parent().unwrap_or(&dir)).map_err(io)?;
        std::fs::write(&p, body).map_err(io)?;
    }
    let timeout = std::env::var("AIRLIGHT_BROWSER_TIMEOUT_S").ok().and_then(|v| v.parse().ok()).unwrap_or(timeout_s);
    if browser.is_none() {
        *browser = Some(Browser::start(chrome)?);
    }
    let ran = browser.as_mut().map_or_else(|| Err(BrowserError("no browser".into())), |b| b.draw(&dir, page, timeout));
    std::fs::remove_dir_all(&dir).ok();
    if ran.as_ref().is_err_and(|e| e.0.starts_with("the browser driver")) {
        *browser = None; // the next page starts a new one
    }
    let posted = ran?;
    let mut lines = posted.splitn(3, '\n');
    match (lines.next(), lines.next(), lines.next()) {
        (Some("ok"), Some(adapter), Some(pixels)) => Ok((adapter.to_string(), decode_base64(pixels)?)),
        _ => Err(BrowserError(format!("the page failed: {}", posted.trim_start_matches("error\n")))),
    }
}

/// [`draw_raw`] for a [`page`]: its gray levels (8-bit RGBA read back), `width ×
/// height`, rows from the top.
pub fn draw(chrome: &Path, files: Vec<(String, Vec<u8>)>, width: u32, height: u32) -> Result<Drawn, BrowserError> {
    let (adapter, rgba) = draw_raw(chrome, files)?;
    let (w, h) = (width as usize, height as usize);
    if rgba.len() != 4 * w * h {
        return Err(BrowserError(format!("{} bytes read back, expected {}", rgba.len(), 4 * w * h)));
    }
    Ok(Drawn { adapter, pixels: rgba.chunks(4).map(|p| p[0]).collect() })
}

/// [`draw_raw`] for a [`shafts_page`]: per pixel the fog (RGB) and the surface
/// distance, as f32, rows from the top.
pub fn draw_shafts(
    chrome: &Path,
    files: Vec<(String, Vec<u8>)>,
    width: u32,
    height: u32,
) -> Result<(String, Vec<[f32; 4]>), BrowserError> {
    let (adapter, bytes) = draw_raw(chrome, files)?;
    if bytes.len() != 16 * (width * height) as usize {
        return Err(BrowserError(format!("{} bytes read back, expected {}", bytes.len(), 16 * width * height)));
    }
    let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
    Ok((adapter, bytes.chunks(16).map(|p| [f(&p[0..4]), f(&p[4..8]), f(&p[8..12]), f(&p[12..16])]).collect()))
}

/// The files a page needs: itself, three.js's builds from `three` (the npm
/// package's `build/`) as `three/…`, and every file of the airlight-three
/// package at `package` as `airlight-three/…`.
pub fn page_files(three: &Path, package: &Path, page: String) -> Result<Vec<(String, Vec<u8>)>, BrowserError> {
    let read = |p: &Path| std::fs::read(p).map_err(|e| BrowserError(format!("{}: {e}", p.display())));
    let mut files = vec![("index.html".to_string(), page.into_bytes())];
    for f in ["three.module.js", "three.core.js", "three.webgpu.js", "three.tsl.js"] {
        files.push((format!("three/{f}"), read(&three.join(f))?));
    }
    let mut dirs = vec![package.to_path_buf()];
    while let Some(dir) = dirs.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|e| BrowserError(format!("{}: {e}", dir.display())))?;
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else if let Ok(rel) = p.strip_prefix(package) {
                files.push((format!("airlight-three/{}", rel.to_string_lossy().replace('\\', "/")), read(&p)?));
            }
        }
    }
    Ok(files)
}

/// `template` (a page source in `pages/`) with each `{{key}}` replaced by its value,
/// in one pass (a value is never scanned again); a key the template names and
/// `vars` lacks is a bug in the caller, and panics.
fn fill(template: &str, vars: &[(&str, String)]) -> String {
    let mut out = String::with_capacity(template.len());
    let mut rest = template;
    while let Some(k) = rest.find("{{") {
        out.push_str(&rest[..k]);
        let tail = &rest[k + 2..];
        match tail.find("}}") {
            Some(e) if tail[..e].chars().all(|c| c.is_ascii_alphanumeric() || c == '_') => {
                let key = &tail[..e];
                let v = vars.iter().find(|(n, _)| *n == key).unwrap_or_else(|| panic!("no value for {{{{{key}}}}}"));
                out.push_str(&v.1);
                rest = &tail[e + 2..];
            }
            _ => {
                out.push_str("{{");
                rest = tail;
            }
        }
    }
    out.push_str(rest);
    out
}

/// The three.js example (`examples/three/`) as the repository lays it out for
/// `node examples/three/serve.mjs`: its page with a script appended that waits
/// for the example to start, lets it run two seconds (its frame time), reads
/// its fog back (`window.airlightExample.readFog()`) and POSTs the fog's floats
/// (RGB and the surface distance, rows from the top) and, as the "adapter"
/// line, JSON with the kernel, the frame time, the camera, the medium and the
/// lights as the page held them, and the adapter.
pub fn example_files(root: &Path, three: &Path, package: &Path) -> Result<Vec<(String, Vec<u8>)>, BrowserError> {
    let read = |p: &Path| std::fs::read(p).map_err(|e| BrowserError(format!("{}: {e}", p.display())));
    let dir = root.join("examples/three");
    let page = String::from_utf8_lossy(&read(&dir.join("index.html"))?).into_owned();
    let probe = include_str!("pages/example_probe.html");
    let page = page.replacen("</body>", &format!("{probe}</body>"), 1);
    let mut files = vec![
        ("examples/three/index.html".to_string(), page.into_bytes()),
        ("examples/three/main.js".to_string(), read(&dir.join("main.js"))?),
        ("examples/three/quickstart.js".to_string(), read(&dir.join("quickstart.js"))?),
    ];
    for f in ["three.core.js", "three.module.js", "three.webgpu.js", "three.tsl.js"] {
        files.push((format!("tests/node/node_modules/three/build/{f}"), read(&three.join(f))?));
    }
    // The addons the page imports: the orbit control, and the composer its WebGL
    // form draws through (with what the composer imports).
    for addon in [
        "controls/OrbitControls.js",
        "postprocessing/EffectComposer.js",
        "postprocessing/ShaderPass.js",
        "postprocessing/MaskPass.js",
        "postprocessing/Pass.js",
        "shaders/CopyShader.js",
    ] {
        let rel = format!("examples/jsm/{addon}");
        files.push((format!("tests/node/node_modules/three/{rel}"), read(&three.join("..").join(&rel))?));
    }
    for (name, bytes) in page_files(three, package, String::new())? {
        if let Some(rel) = name.strip_prefix("airlight-three/") {
            files.push((format!("generated/three/airlight-three/{rel}"), bytes));
        }
    }
    Ok(files)
}

/// The arguments `spot_entries_page` passes every kernel's spot entry: the
/// viewer, the light, its axis, (cos_outer, cos_inner, intensity), σt, σs, g,
/// and the fan of rays (x0, dx, y, surface): pixel x's direction is
/// (x0 + dx (x + 0.5), y, 1), its surface at `surface` for even x, none for odd.
pub struct SpotArgs {
    pub origin: [f32; 3],
    pub light: [f32; 3],
    pub axis: [f32; 3],
    pub cone: [f32; 3],
    pub sigma_t: [f32; 3],
    pub sigma_s: [f32; 3],
    pub g: f32,
    pub fan: [f32; 4],
}

/// A WebGL 2 page (no three.js) that compiles each named kernel's spot entry
/// from its `airlight-three/sources/<name>.js` with every argument a uniform
/// and draws `width` rays per kernel (`pages/spot_entries.js`): RGBA32F per
/// pixel, RGB the fog, A the seconds the kernel's program took to compile and
/// draw; one row per kernel.
pub fn spot_entries_page(names: &[&str], args: &SpotArgs, width: u32) -> String {
    let list = |v: &[f32]| v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(", ");
    let names_js = format!("[{}]", names.iter().map(|n| format!("{n:?}")).collect::<Vec<_>>().join(", "));
    let body = fill(
        include_str!("pages/spot_entries.js"),
        &[
            ("names", names_js),
            ("origin", list(&args.origin)),
            ("light", list(&args.light)),
            ("axis", list(&args.axis)),
            ("cone", list(&args.cone)),
            ("sigma_t", list(&args.sigma_t)),
            ("sigma_s", list(&args.sigma_s)),
            ("g", format!("{:?}", args.g)),
            ("fan", list(&args.fan)),
        ],
    );
    wrap_page("", &body, width, names.len() as u32)
}

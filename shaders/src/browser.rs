//! The airlight-three package where three.js users are: a page (three.js r187
//! from npm, pinned in `tests/node/package.json`) imports a kernel's ES module
//! from the package and draws the render's view of a scene in one full-screen
//! pass, through `WebGLRenderer` with the module's GLSL include in a
//! `RawShaderMaterial`, or through `WebGPURenderer` with its TSL node (`wgslFn`
//! on WebGPU, `glslFn` on the WebGL 2 backend), tone-mapped to 8 bits and read
//! back. Headless Chromium (WebGL 2 and WebGPU on SwiftShader) loads the page from
//! a loopback HTTP server started here (no network beyond 127.0.0.1); the page
//! POSTs the pixels back, and they are compared with the f64 reference render.

use crate::render::{View, FOV_Y, GROUND_Y};
use airlight_shapes::vocab::{Arg, IndexEntry};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The three.js the pages load (npm, pinned in tests/node/package.json).
pub const THREE_VERSION: &str = "0.187.0";

/// The page's fragment shader: the GLSL include `kernel` of `k`, the view's rays
/// (the arithmetic of [`View::ray`], rows from the top), every light summed.
pub fn fragment_shader(k: &IndexEntry, kernel: &str, view: &View, exposure: f64) -> String {
    let args = crate::render::radiance_args(k, view, "vec3(0.0)", "LIGHTS[i].xyz", "LIGHTS[i].w");
    let lights: Vec<String> =
        view.lights().iter().map(|(p, i)| format!("vec4({:?}, {:?}, {:?}, {:?})", p[0], p[1], p[2], i)).collect();
    let sigmas: Vec<String> = view.sigma_t.iter().map(|s| format!("{s:?}")).collect();
    format!(
        "{kernel}
// ---- the three.js page (shaders/src/browser.rs) ----
out highp vec4 airlight_color;
const vec4 LIGHTS[{nl}] = vec4[{nl}]({lights});
const float SIGMA_T[{np}] = float[{np}]({sigmas});
void main() {{
    float pw = {pw:?};
    vec2 pos = vec2(gl_FragCoord.x, {h:?} - gl_FragCoord.y);
    float panel = floor(pos.x / pw);
    float u = 2.0 * (pos.x - panel * pw) / pw - 1.0;
    float v = 1.0 - 2.0 * pos.y / {h:?};
    float t = tan({half:?});
    vec3 d = vec3(u * t * (pw / {h:?}), v * t, 1.0);
    vec3 dir = d / sqrt(dot(d, d));
    float surface = -1.0;
    if ({ground} && dir.y < 0.0) {{
        surface = {gy:?} / dir.y;
    }}
    float sigma_t = SIGMA_T[int(panel)];
    float sum = 0.0;
    for (int i = 0; i < {nl}; i++) {{
        sum += {prefix}radiance({args});
    }}
    // render::tone, in f32.
    float x = max(sum * {exposure:?}, 0.0);
    float c = pow(x / (1.0 + x), 1.0 / 2.2);
    airlight_color = vec4(c, c, c, 1.0);
}}
",
        nl = lights.len(),
        lights = lights.join(", "),
        np = sigmas.len(),
        sigmas = sigmas.join(", "),
        pw = view.panel_width as f32,
        h = view.height as f32,
        half = 0.5 * FOV_Y,
        ground = view.ground,
        gy = GROUND_Y * view.scale,
        prefix = k.prefix,
        args = args.join(", "),
        exposure = exposure as f32,
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
/// package's `radiance` node per light, tone-mapped as [`crate::render::tone`].
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
                Arg::SigmaS => format!("sigmaT.mul({:?})", crate::render::ALBEDO),
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
    format!(
        "Fn(() => {{
    const pw = float({pw:?}), h = float({h:?});
    // screenCoordinate: pixels from the top left, on both backends.
    const pos = screenCoordinate.xy;
    const panel = floor(pos.x.div(pw));
    const u = pos.x.sub(panel.mul(pw)).div(pw).mul(2.0).sub(1.0);
    const v = float(1.0).sub(pos.y.mul(2.0).div(h));
    const t = float({t:?});
    const d = vec3(u.mul(t.mul(pw.div(h))), v.mul(t), 1.0);
    const dir = d.div(sqrt(dot(d, d)));
    const surface = {ground};
    const sigmaT = {sigma};
    let sum = float(0.0);
    for (const l of [{lights}]) {{
        sum = sum.add({node}({{ {args} }}));
    }}
    const x = max(sum.mul({exposure:?}), 0.0);
    const c = pow(x.div(x.add(1.0)), 1.0 / 2.2);
    return vec4(c, c, c, 1.0);
}})()",
        pw = view.panel_width as f32,
        h = view.height as f32,
        t = (0.5 * FOV_Y).tan(),
        lights = lights.join(", "),
        args = args.join(", "),
        exposure = exposure as f32,
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
            format!(
                r#"const canvas = document.createElement('canvas');
canvas.width = W; canvas.height = H;
document.body.appendChild(canvas);
const renderer = new THREE.WebGLRenderer({{ canvas, antialias: false, alpha: false, preserveDrawingBuffer: true }});
renderer.setPixelRatio(1);
renderer.setSize(W, H, false);
let shaderError = null;
renderer.debug.checkShaderErrors = true;
renderer.debug.onShaderError = (gl, program, vs, fs) => {{
  shaderError = 'shader: ' + gl.getShaderInfoLog(fs) + gl.getShaderInfoLog(vs) + gl.getProgramInfoLog(program);
}};
const material = new THREE.RawShaderMaterial({{
  glslVersion: THREE.GLSL3,
  vertexShader: 'in vec3 position;\nvoid main() {{ gl_Position = vec4(position.xy, 0.0, 1.0); }}\n',
  fragmentShader: glsl + {main},
}});
const mesh = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
mesh.frustumCulled = false;
const scene = new THREE.Scene();
scene.add(mesh);
renderer.render(scene, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
if (shaderError) throw new Error(shaderError);
const gl = renderer.getContext();
const px = new Uint8Array(W * H * 4);
gl.readPixels(0, 0, W, H, gl.RGBA, gl.UNSIGNED_BYTE, px);
const info = gl.getExtension('WEBGL_debug_renderer_info');
const adapter = 'three.js r' + THREE.REVISION + ', WebGLRenderer, ' + gl.getParameter(gl.VERSION) + ', ' +
  (info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
// readPixels starts at the bottom row.
return {{ adapter, rgba: px, bottomUp: true }};"#,
                main = js_string(&fragment_shader(k, "", view, exposure)),
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
            let body = format!(
                r#"const renderer = new THREE.WebGPURenderer({{ antialias: false, forceWebGL: {force} }});
await renderer.init();
const backend = renderer.backend.isWebGPUBackend ? 'WebGPU' : 'WebGL 2';
if (backend !== '{want}') throw new Error('asked for {want}, got ' + backend);
const material = new THREE.MeshBasicNodeMaterial();
material.colorNode = {colour};
const mesh = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
mesh.frustumCulled = false;
const scene = new THREE.Scene();
scene.add(mesh);
const target = new THREE.RenderTarget(W, H, {{ type: THREE.UnsignedByteType, depthBuffer: false }});
renderer.setRenderTarget(target);
renderer.render(scene, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
const px = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
let adapter = 'three.js r' + THREE.REVISION + ', WebGPURenderer (' + backend + ')';
if (renderer.backend.isWebGPUBackend) {{
  const i = (await navigator.gpu.requestAdapter()).info;
  adapter += ', ' + [i.vendor, i.architecture, i.device, i.description].filter((x) => x).join(' ');
}} else {{
  const gl = renderer.getContext();
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  adapter += ', ' + (info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
}}
return {{ adapter, rgba: new Uint8Array(px.buffer, px.byteOffset, px.byteLength), bottomUp: !renderer.backend.isWebGPUBackend }};"#,
                want = if force { "WebGL 2" } else { "WebGPU" },
                colour = tsl_colour(k, view, exposure, node),
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
    format!(
        r#"<!doctype html>
<html><head><meta charset="utf-8"><title>airlight in three.js</title>
{IMPORT_MAP}
</head>
<body>
<script type="module">
{imports}
const W = {width}, H = {height};
async function draw() {{
{body}
}}
let reply;
try {{
  const {{ adapter, rgba, bottomUp, texel = 4 }} = await draw();
  if (rgba.length !== W * H * texel) throw new Error(rgba.length + ' bytes read back, expected ' + W * H * texel);
  const rows = new Uint8Array(W * H * texel);
  for (let y = 0; y < H; y++) {{
    const from = bottomUp ? H - 1 - y : y;
    rows.set(rgba.subarray(from * W * texel, (from + 1) * W * texel), y * W * texel);
  }}
  let bin = '';
  for (let i = 0; i < rows.length; i++) bin += String.fromCharCode(rows[i]);
  reply = 'ok\n' + adapter + '\n' + btoa(bin);
}} catch (e) {{
  reply = 'error\n' + String(e && e.stack || e);
}}
await fetch('/result', {{ method: 'POST', body: reply }});
</script>
</body></html>
"#
    )
}

/// `vec3(x, y, z)` in GLSL.
fn glsl_v3(v: [f32; 3]) -> String {
    format!("vec3({:?}, {:?}, {:?})", v[0], v[1], v[2])
}

/// The light-shafts page (`WebGLRenderer`): the window-shafts room's occluders
/// (`crate::shafts::render`) as three.js meshes that cast shadows, its spot as a
/// `SpotLight` with a shadow map (`PCFShadowMap`: a depth texture with a
/// comparison sampler, 2×2 filtered); one render builds three.js's shadow map,
/// then a full-screen `RawShaderMaterial` with the kernel's GLSL include walks
/// each view ray to its first surface in `look_ups` steps, looks visibility up
/// in that shadow map (through `light.shadow.matrix`) and feeds the kernel's
/// shafts accumulator (`shafts_push_spot`, `refine` bisection steps per change,
/// `shafts_finish_spot`). It reads back the fog (RGB) and the surface distance
/// as f32 and POSTs them (base64 of the floats, rows from the top).
pub fn shafts_page(
    k: &IndexEntry,
    view: &crate::shafts::render::ShaftsView,
    look_ups: u32,
    refine: u32,
    renderer: Renderer,
) -> String {
    use crate::shafts::render as sr;
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
    let main = format!(
        r#"
// ---- the light-shafts pass (shaders/src/browser.rs) ----
uniform highp sampler2DShadow shadowMap;
uniform highp mat4 shadowMatrix;
out highp vec4 airlight_fog;
const vec3 CAMERA = {camera};
const vec3 LIGHT = {light};
// three.js's shadow: light.shadow.matrix maps the world to [0, 1]^3; outside it, lit.
float visibility(vec3 q) {{
    vec4 c = shadowMatrix * vec4(q, 1.0);
    if (c.w <= 0.0) return 1.0;
    vec3 t = c.xyz / c.w;
    if (any(lessThan(t, vec3(0.0))) || any(greaterThan(t, vec3(1.0)))) return 1.0;
    return texture(shadowMap, vec3(t.xy, t.z - 0.0005));
}}
float box_entry(vec3 lo, vec3 hi, vec3 d, float end) {{
    vec3 a = (lo - CAMERA) / d, b = (hi - CAMERA) / d;
    vec3 n = min(a, b), x = max(a, b);
    float t0 = max(max(n.x, n.y), n.z), t1 = min(min(x.x, x.y), x.z);
    return (t0 < t1 && t0 > 0.0) ? t0 : end;
}}
void main() {{
    vec2 pos = vec2(gl_FragCoord.x, {h:?} - gl_FragCoord.y);
    float u = 2.0 * pos.x / {w:?} - 1.0;
    float v = 1.0 - 2.0 * pos.y / {h:?};
    float t = {t:?};
    vec3 d = {f} + (u * t * {aspect:?}) * {r} + (v * t) * {up};
    vec3 dir = d / sqrt(dot(d, d));
    // The first surface: the room's walls from inside, the beams, pillars and ball.
    vec3 a = ({room_lo} - CAMERA) / dir, b = ({room_hi} - CAMERA) / dir;
    vec3 x = max(a, b);
    float end = min(min(x.x, x.y), x.z);
{slabs}    vec3 w = CAMERA - {ball_c};
    float bb = dot(w, dir), disc = bb * bb - (dot(w, w) - {ball_r2:?});
    float sb = -bb - sqrt(max(disc, 0.0));
    if (disc >= 0.0 && sb > 0.0) end = min(end, sb);
    {p}Shafts acc = {p}shafts_begin();
    {p}shafts_push_spot(acc, 0.0, visibility(CAMERA), {args});
    for (int i = 0; i < {n}; i++) {{
        float s = (float(i) + 0.5) * end / {nf:?};
        {p}shafts_push_spot(acc, s, visibility(CAMERA + s * dir), {args});
        for (int k = 0; k < {refine} && {p}shafts_probe(acc) >= 0.0; k++) {{
            {p}shafts_refine(acc, visibility(CAMERA + {p}shafts_probe(acc) * dir));
        }}
    }}
    {p}shafts_push_spot(acc, end, visibility(CAMERA + end * (1.0 - 1e-4) * dir), {args});
    vec3 fog = {p}shafts_finish_spot(acc, end, {args});
    airlight_fog = vec4(fog, end);
}}
"#,
        camera = glsl_v3(sr::CAMERA),
        light = glsl_v3(sr::LIGHT),
        h = height as f32,
        w = width as f32,
        t = (0.5 * FOV_Y).tan(),
        aspect = width as f32 / height as f32,
        f = glsl_v3(f),
        r = glsl_v3(r),
        up = glsl_v3(u),
        room_lo = glsl_v3([room[0][0], room[1][0], room[2][0]]),
        room_hi = glsl_v3([room[0][1], room[1][1], room[2][1]]),
        ball_c = glsl_v3(sr::BALL.0),
        ball_r2 = sr::BALL.1 * sr::BALL.1,
        n = look_ups,
        nf = look_ups as f32,
    );
    if renderer != Renderer::WebGl {
        return shafts_page_tsl(k, view, look_ups, renderer == Renderer::WebGpuOnWebGl);
    }
    let body = format!(
        r#"const renderer = new THREE.WebGLRenderer({{ antialias: false }});
renderer.setPixelRatio(1);
renderer.setSize(W, H, false);
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;
let shaderError = null;
renderer.debug.checkShaderErrors = true;
renderer.debug.onShaderError = (gl, program, vs, fs) => {{
  shaderError = 'shader: ' + gl.getShaderInfoLog(fs) + gl.getShaderInfoLog(vs) + gl.getProgramInfoLog(program);
}};
// The room's occluders, casting shadows, its spot light, and three.js's shadow map.
{scene}
const material = new THREE.RawShaderMaterial({{
  glslVersion: THREE.GLSL3,
  vertexShader: 'in vec3 position;\nvoid main() {{ gl_Position = vec4(position.xy, 0.0, 1.0); }}\n',
  fragmentShader: glsl + {main},
  uniforms: {{ shadowMap: {{ value: light.shadow.map.depthTexture }}, shadowMatrix: {{ value: light.shadow.matrix }} }},
}});
const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
quad.frustumCulled = false;
const pass = new THREE.Scene();
pass.add(quad);
const target = new THREE.WebGLRenderTarget(W, H, {{ type: THREE.FloatType, depthBuffer: false }});
renderer.setRenderTarget(target);
renderer.render(pass, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
if (shaderError) throw new Error(shaderError);
const px = new Float32Array(W * H * 4);
renderer.readRenderTargetPixels(target, 0, 0, W, H, px);
const gl = renderer.getContext();
const info = gl.getExtension('WEBGL_debug_renderer_info');
const adapter = 'three.js r' + THREE.REVISION + ', WebGLRenderer, shadow map ' + light.shadow.map.width + '², ' +
  (info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
return {{ adapter, rgba: new Uint8Array(px.buffer), bottomUp: true, texel: 16 }};"#,
        scene = shafts_scene_js("new THREE.MeshBasicMaterial()", "new THREE.MeshBasicMaterial()", "WebGLRenderTarget"),
        main = js_string(&main),
    );
    let imports = format!("import * as THREE from 'three';\nimport {{ glsl }} from '{sources}';");
    wrap_page(&imports, &body, width, height)
}

/// The three.js scene of the light-shafts room (JavaScript, `THREE` in scope):
/// its occluders as meshes casting shadows (`material`), a floor receiving them
/// (`floor`), the spot as a `SpotLight` with a shadow map, and a camera; then one
/// render that draws three.js's shadow map into `light.shadow`.
fn shafts_scene_js(material: &str, floor: &str, target: &str) -> String {
    use crate::shafts::render as sr;
    let js_boxes: Vec<String> = sr::boxes()
        .iter()
        .map(|b| format!("[{:?}, {:?}, {:?}, {:?}, {:?}, {:?}]", b.0[0], b.0[1], b.0[2], b.1[0], b.1[1], b.1[2]))
        .collect();
    format!(
        r#"const scene = new THREE.Scene();
const stone = {material};
for (const [x0, y0, z0, x1, y1, z1] of [{boxes}]) {{
  const m = new THREE.Mesh(new THREE.BoxGeometry(x1 - x0, y1 - y0, z1 - z0), stone);
  m.position.set((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2);
  m.castShadow = true;
  scene.add(m);
}}
const ball = new THREE.Mesh(new THREE.SphereGeometry({ball_r:?}, 96, 48), stone);
ball.position.set({bx:?}, {by:?}, {bz:?});
ball.castShadow = true;
scene.add(ball);
const floor = new THREE.Mesh(new THREE.PlaneGeometry(10, 18), {floor});
floor.rotation.x = -Math.PI / 2;
floor.position.set(0, 0, 7);
floor.receiveShadow = true;
scene.add(floor);
const light = new THREE.SpotLight(0xffffff, 1.0, 0, {angle:?}, 0.0, 2);
light.position.set({lx:?}, {ly:?}, {lz:?});
light.target.position.set({ax:?}, {ay:?}, {az:?});
light.castShadow = true;
light.shadow.mapSize.set({map}, {map});
light.shadow.camera.near = 0.3;
light.shadow.camera.far = 30.0;
scene.add(light, light.target);
const camera = new THREE.PerspectiveCamera(60, W / H, 0.1, 100);
camera.position.set({cx:?}, {cy:?}, {cz:?});
camera.lookAt({cx:?}, {cy:?}, {cz:?} + 1.0);
// This render draws three.js's shadow map (light.shadow.map, light.shadow.matrix).
const scratch = new THREE.{target}(W, H);
renderer.setRenderTarget(scratch);
renderer.render(scene, camera);
if (!light.shadow.map || !light.shadow.map.depthTexture) throw new Error('three.js drew no shadow map');"#,
        boxes = js_boxes.join(", "),
        ball_r = sr::BALL.1,
        bx = sr::BALL.0[0],
        by = sr::BALL.0[1],
        bz = sr::BALL.0[2],
        angle = sr::CONE_DEG[0].to_radians(),
        lx = sr::LIGHT[0],
        ly = sr::LIGHT[1],
        lz = sr::LIGHT[2],
        ax = sr::AIM[0],
        ay = sr::AIM[1],
        az = sr::AIM[2],
        map = sr::SHADOW_MAP,
        cx = sr::CAMERA[0],
        cy = sr::CAMERA[1],
        cz = sr::CAMERA[2],
    )
}

/// The light-shafts page on `WebGPURenderer`: the same room, three.js's shadow
/// map, and the package's shafts TSL node walking each ray in `look_ups` steps
/// (the page's own code node finds the first surface) — on WebGPU through
/// `shaftsSpotWGSL`, or (`webgl`) on the WebGL 2 backend through `shaftsSpotGLSL`.
fn shafts_page_tsl(k: &IndexEntry, view: &crate::shafts::render::ShaftsView, look_ups: u32, webgl: bool) -> String {
    use crate::shafts::render as sr;
    let (width, height) = (view.width, view.height);
    let module = format!("./airlight-three/kernels/{}.js", k.name);
    let v3 = |v: [f32; 3]| {
        if webgl {
            glsl_v3(v)
        } else {
            format!("vec3<f32>({:?}, {:?}, {:?})", v[0], v[1], v[2])
        }
    };
    let t3 = |v: [f32; 3]| format!("vec3({:?}, {:?}, {:?})", v[0], v[1], v[2]);
    let slabs: String = sr::boxes()
        .iter()
        .map(|b| format!("    end = min(end, box_entry(o, {}, {}, dir, end));\n", v3(b.0), v3(b.1)))
        .collect();
    let room = sr::ROOM;
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
    let scene_end = format!(
        "{fn_end} {{
    {vector} o = {cam};
    {vector} a = ({lo} - o) / dir;
    {vector} b = ({hi} - o) / dir;
    {vector} x = max(a, b);
    {mutable} end = min(min(x.x, x.y), x.z);
{slabs}    {vector} w = o - {ball};
    {scalar} bb = dot(w, dir);
    {scalar} disc = bb * bb - (dot(w, w) - {r2:?});
    {scalar} sb = -bb - sqrt(max(disc, 0.0));
    if (disc >= 0.0 && sb > 0.0) {{ end = min(end, sb); }}
    return end;
}}",
        cam = v3(sr::CAMERA),
        lo = v3([room[0][0], room[1][0], room[2][0]]),
        hi = v3([room[0][1], room[1][1], room[2][1]]),
        ball = v3(sr::BALL.0),
        r2 = sr::BALL.1 * sr::BALL.1,
    );
    let box_entry = format!(
        "{fn_box} {{
    {vector} a = (lo - o) / d;
    {vector} b = (hi - o) / d;
    {vector} n = min(a, b);
    {vector} x = max(a, b);
    {scalar} t0 = max(max(n.x, n.y), n.z);
    {scalar} t1 = min(min(x.x, x.y), x.z);
    return {pick};
}}",
        pick = if webgl { "(t0 < t1 && t0 > 0.0) ? t0 : end" } else { "select(end, t0, t0 < t1 && t0 > 0.0)" },
    );
    let (st, ss) = sr::medium();
    let cos = sr::CONE_DEG.map(|d| d.to_radians().cos());
    let args: Vec<String> = k
        .spot_params
        .iter()
        .map(|a| {
            let v = match a {
                Arg::Origin => t3(sr::CAMERA),
                Arg::Dir => "dir".to_string(),
                Arg::Surface => "end".into(),
                Arg::Light => t3(sr::LIGHT),
                Arg::Axis => t3(sr::axis()),
                Arg::CosOuter => format!("float({:?})", cos[0]),
                Arg::CosInner => format!("float({:?})", cos[1]),
                Arg::Intensity => format!("float({:?})", sr::INTENSITY),
                Arg::SigmaTRgb => t3(st),
                Arg::SigmaSRgb => t3(ss),
                Arg::G => format!("float({:?})", sr::G),
                other => unreachable!("{other} is not an argument of spot"),
            };
            format!("{}: {v}", a.name())
        })
        .collect();
    let [f, r, u] = sr::camera_basis();
    let body = format!(
        r#"const renderer = new THREE.WebGPURenderer({{ antialias: false, forceWebGL: {webgl} }});
await renderer.init();
const backend = renderer.backend.isWebGPUBackend ? 'WebGPU' : 'WebGL 2';
if (backend !== '{want}') throw new Error('asked for {want}, got ' + backend);
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;
{scene}
const sceneEnd = {code_fn}({scene_end}, [{code}({box_entry})]);
const depth = texture(light.shadow.map.depthTexture);
const material = new THREE.MeshBasicNodeMaterial();
material.fragmentNode = Fn(() => {{
  const pos = screenCoordinate.xy;
  const u = pos.x.mul(2.0 / W).sub(1.0);
  const v = float(1.0).sub(pos.y.mul(2.0 / H));
  const t = float({t:?});
  const d = {f}.add({r}.mul(u.mul(t).mul({aspect:?}))).add({up}.mul(v.mul(t)));
  const dir = d.div(sqrt(dot(d, d)));
  const end = sceneEnd({{ dir }});
  const fog = K.{node}({{ {args}, shadow_map: depth, shadow_sampler: depth,
    shadow_matrix: uniform(light.shadow.matrix), shadow_bias: float(-0.0005), look_ups: float({n:?}), reach: float(100.0) }});
  return vec4(fog, end);
}})();
const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
quad.frustumCulled = false;
const pass = new THREE.Scene();
pass.add(quad);
const target = new THREE.RenderTarget(W, H, {{ type: THREE.FloatType, depthBuffer: false }});
renderer.setRenderTarget(target);
renderer.render(pass, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
const px = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
let adapter = 'three.js r' + THREE.REVISION + ', WebGPURenderer (' + backend + '), shadow map ' + light.shadow.mapSize.x + '², ';
if (renderer.backend.isWebGPUBackend) {{
  const i = (await navigator.gpu.requestAdapter()).info;
  adapter += [i.vendor, i.architecture, i.device, i.description].filter((x) => x).join(' ');
}} else {{
  const gl = renderer.getContext();
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  adapter += info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
}}
return {{ adapter, rgba: new Uint8Array(px.buffer, px.byteOffset, px.byteLength), bottomUp: {webgl}, texel: 16 }};"#,
        scene = shafts_scene_js(
            "new THREE.MeshStandardNodeMaterial()",
            "new THREE.MeshStandardNodeMaterial()",
            "RenderTarget"
        ),
        scene_end = js_string(&scene_end),
        box_entry = js_string(&box_entry),
        code_fn = if webgl { "glslFn" } else { "wgslFn" },
        code = if webgl { "glslCode" } else { "wgslCode" },
        node = if webgl { "shaftsSpotGLSL" } else { "shaftsSpotWGSL" },
        want = if webgl { "WebGL 2" } else { "WebGPU" },
        t = (0.5 * FOV_Y).tan(),
        aspect = width as f32 / height as f32,
        f = t3(f),
        r = t3(r),
        up = t3(u),
        args = args.join(", "),
        n = look_ups as f32,
    );
    let imports = format!(
        "import * as THREE from 'three/webgpu';\nimport {{ Fn, float, vec3, vec4, screenCoordinate, sqrt, dot, texture, uniform, wgslFn, wgsl as wgslCode, glslFn, glsl as glslCode }} from 'three/tsl';\nimport * as K from '{module}';"
    );
    wrap_page(&imports, &body, width, height)
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
const TIMEOUT_S: u64 = 240;

/// What the page POSTed to `/result`.
type Posted = std::sync::Arc<std::sync::Mutex<Option<String>>>;

/// Answers one HTTP request on `s`: a GET from `files` (`/`: `index.html`), or
/// the page's POST of its result to `/result`, kept in `posted`.
fn serve_one(mut s: std::net::TcpStream, files: &[(String, Vec<u8>)], posted: &Posted) {
    let _ = s.set_nonblocking(false);
    let _ = s.set_read_timeout(Some(Duration::from_secs(30)));
    let mut line = String::new();
    let mut reader = BufReader::new(match s.try_clone() {
        Ok(c) => c,
        Err(_) => return,
    });
    if reader.read_line(&mut line).is_err() {
        return;
    }
    let mut length = 0usize;
    let mut h = String::new();
    while reader.read_line(&mut h).is_ok_and(|n| n > 2) {
        if let Some(v) = h.to_ascii_lowercase().strip_prefix("content-length:") {
            length = v.trim().parse().unwrap_or(0);
        }
        h.clear();
    }
    let mut words = line.split_whitespace();
    let method = words.next().unwrap_or("GET");
    let path = words.next().unwrap_or("/").trim_start_matches('/');
    let reply = if method == "POST" && path == "result" {
        let mut body = vec![0u8; length];
        if reader.read_exact(&mut body).is_ok() {
            *posted.lock().unwrap_or_else(|e| e.into_inner()) = Some(String::from_utf8_lossy(&body).into_owned());
        }
        b"HTTP/1.1 204 No Content\r\nConnection: close\r\n\r\n".to_vec()
    } else {
        let path = if path.is_empty() { "index.html" } else { path };
        match files.iter().find(|(n, _)| n == path) {
            Some((n, body)) => {
                let ty = if n.ends_with(".js") { "text/javascript" } else { "text/html; charset=utf-8" };
                let mut r = format!(
                    "HTTP/1.1 200 OK\r\nContent-Type: {ty}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
                    body.len()
                )
                .into_bytes();
                r.extend_from_slice(body);
                r
            }
            None => b"HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\nConnection: close\r\n\r\n".to_vec(),
        }
    };
    let _ = s.write_all(&reply);
    let _ = s.flush();
}

/// A loopback HTTP server of `files` until [`Server::stop`].
struct Server {
    port: u16,
    posted: Posted,
    done: std::sync::Arc<std::sync::atomic::AtomicBool>,
    thread: std::thread::JoinHandle<()>,
}

impl Server {
    fn start(files: Vec<(String, Vec<u8>)>) -> Result<Server, BrowserError> {
        let err = |e: std::io::Error| BrowserError(e.to_string());
        let listener = TcpListener::bind("127.0.0.1:0").map_err(err)?;
        let port = listener.local_addr().map_err(err)?.port();
        listener.set_nonblocking(true).map_err(err)?;
        let done = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let posted: Posted = std::sync::Arc::new(std::sync::Mutex::new(None));
        let (stop, post) = (done.clone(), posted.clone());
        let files = std::sync::Arc::new(files);
        let thread = std::thread::spawn(move || {
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                match listener.accept() {
                    Ok((s, _)) => {
                        let (files, post) = (files.clone(), post.clone());
                        std::thread::spawn(move || serve_one(s, &files, &post));
                    }
                    Err(_) => std::thread::sleep(Duration::from_millis(5)),
                }
            }
        });
        Ok(Server { port, posted, done, thread })
    }

    fn posted(&self) -> Option<String> {
        self.posted.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    fn stop(self) {
        self.done.store(true, std::sync::atomic::Ordering::Relaxed);
        let _ = self.thread.join();
    }
}

/// Runs headless `chrome` on `url` with a fresh profile (WebGL 2 and WebGPU on
/// SwiftShader) until the page has POSTed its result to `server`, then stops
/// it; its log is kept for errors. A page that never reports is stopped after
/// 240 s.
fn run_chromium(chrome: &Path, url: &str, profile: &Path, server: &Server) -> Result<String, BrowserError> {
    let mut child = Command::new(chrome)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--enable-unsafe-webgpu",
            "--use-webgpu-adapter=swiftshader",
            "--ignore-gpu-blocklist",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            // The page's console in the log: its errors explain a page that never reports.
            "--enable-logging=stderr",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(url)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| BrowserError(format!("{}: {e}", chrome.display())))?;
    let errs = child.stderr.take().map(|mut p| {
        std::thread::spawn(move || {
            let mut text = String::new();
            let _ = p.read_to_string(&mut text);
            text
        })
    });
    let timeout = std::env::var("AIRLIGHT_BROWSER_TIMEOUT_S").ok().and_then(|v| v.parse().ok()).unwrap_or(TIMEOUT_S);
    let start = Instant::now();
    let outcome = loop {
        if let Some(p) = server.posted() {
            break Ok(p);
        }
        match child.try_wait() {
            Ok(Some(s)) => break Err(format!("chromium exited ({s}) before the page reported")),
            Err(e) => break Err(e.to_string()),
            Ok(None) if start.elapsed() > Duration::from_secs(timeout) => {
                break Err(format!("the page did not report within {timeout} s"));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(50)),
        }
    };
    let _ = child.kill();
    let _ = child.wait();
    let log = errs.and_then(|t| t.join().ok()).unwrap_or_default();
    if std::env::var_os("AIRLIGHT_BROWSER_CONSOLE").is_some() {
        for l in log.lines().filter(|l| l.contains("CONSOLE")) {
            eprintln!("{l}");
        }
    }
    outcome.map_err(|e| {
        let console: Vec<&str> = log.lines().filter(|l| l.contains("CONSOLE") || l.contains("Uncaught")).collect();
        let lines: Vec<&str> = if console.is_empty() { log.lines().collect() } else { console };
        let tail = lines[lines.len().saturating_sub(12)..].join("\n");
        BrowserError(format!("{e}; chromium's log ends:\n{tail}"))
    })
}

/// Serves `files` (name → contents) on 127.0.0.1, loads `index.html` in
/// headless `chrome` and returns what the page read back: the adapter it names
/// and its bytes, rows from the top.
pub fn draw_raw(chrome: &Path, files: Vec<(String, Vec<u8>)>) -> Result<(String, Vec<u8>), BrowserError> {
    let server = Server::start(files)?;
    let url = format!("http://127.0.0.1:{}/index.html", server.port);
    let profile = std::env::temp_dir().join(format!("airlight-chromium-{}-{}", std::process::id(), server.port));
    let ran = run_chromium(chrome, &url, &profile, &server);
    server.stop();
    std::fs::remove_dir_all(&profile).ok();
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

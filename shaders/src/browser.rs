//! The generated GLSL ES 3.00 include where three.js users are: a WebGL2 page
//! (three.js r181, vendored under `tests/browser/vendor/`, MIT) draws the
//! render's view of a scene in a full-screen `RawShaderMaterial` pass that
//! includes the kernel, tone-maps it to the 8-bit canvas and reads the pixels
//! back with `readPixels`. Headless Chromium loads the page from a loopback HTTP
//! server started here (no network beyond 127.0.0.1) and prints the DOM, which
//! carries the pixels; they are compared with the f64 reference render.

use crate::render::{View, FOV_Y, GROUND_Y};
use airlight_fit::vocab::IndexEntry;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The vendored three.js.
pub const THREE_VERSION: &str = "0.181.0";

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

/// The page: three.js renders the fragment shader once and writes what it read
/// back into `<pre id="result">` (or the shader log into `<pre id="error">`).
pub fn page(fragment: &str, width: u32, height: u32) -> String {
    let js_string = |s: &str| {
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
    };
    format!(
        r#"<!doctype html>
<html><head><meta charset="utf-8"><title>airlight in three.js</title></head>
<body>
<pre id="status">loading</pre>
<script type="module">
import * as THREE from './three.module.min.js';
const W = {width}, H = {height};
const status = document.getElementById('status');
function say(id, text) {{ const e = document.createElement('pre'); e.id = id; e.textContent = text; document.body.appendChild(e); }}
try {{
  const canvas = document.createElement('canvas');
  canvas.width = W; canvas.height = H;
  document.body.appendChild(canvas);
  const renderer = new THREE.WebGLRenderer({{ canvas, antialias: false, alpha: false, preserveDrawingBuffer: true }});
  renderer.setPixelRatio(1);
  renderer.setSize(W, H, false);
  renderer.debug.checkShaderErrors = true;
  renderer.debug.onShaderError = (gl, program, vs, fs) => {{
    say('error', 'shader: ' + gl.getShaderInfoLog(fs) + gl.getShaderInfoLog(vs) + gl.getProgramInfoLog(program));
  }};
  const material = new THREE.RawShaderMaterial({{
    glslVersion: THREE.GLSL3,
    vertexShader: 'in vec3 position;\nvoid main() {{ gl_Position = vec4(position.xy, 0.0, 1.0); }}\n',
    fragmentShader: {fragment},
  }});
  const mesh = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
  mesh.frustumCulled = false;
  const scene = new THREE.Scene();
  scene.add(mesh);
  renderer.render(scene, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
  const gl = renderer.getContext();
  const px = new Uint8Array(W * H * 4);
  gl.readPixels(0, 0, W, H, gl.RGBA, gl.UNSIGNED_BYTE, px);
  let bin = '';
  for (let i = 0; i < px.length; i++) bin += String.fromCharCode(px[i]);
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const adapter = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
  say('adapter', 'three.js r' + THREE.REVISION + ', ' + gl.getParameter(gl.VERSION) + ', ' + adapter);
  say('result', btoa(bin));
}} catch (e) {{
  say('error', String(e && e.stack || e));
}}
status.textContent = 'done';
</script>
</body></html>
"#,
        fragment = js_string(fragment),
    )
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

fn between<'a>(dom: &'a str, id: &str) -> Option<&'a str> {
    let open = format!("<pre id=\"{id}\">");
    let at = dom.find(&open)? + open.len();
    let end = dom[at..].find("</pre>")?;
    Some(&dom[at..at + end])
}

/// Answers one HTTP request on `s` from `files` (`/`: `index.html`).
fn serve_one(mut s: std::net::TcpStream, files: &[(String, Vec<u8>)]) {
    let _ = s.set_nonblocking(false);
    let mut line = String::new();
    let mut reader = BufReader::new(match s.try_clone() {
        Ok(c) => c,
        Err(_) => return,
    });
    if reader.read_line(&mut line).is_err() {
        return;
    }
    // Drain the headers.
    let mut h = String::new();
    while reader.read_line(&mut h).is_ok_and(|n| n > 2) {
        h.clear();
    }
    let path = line.split_whitespace().nth(1).unwrap_or("/").trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    let reply = match files.iter().find(|(n, _)| n == path) {
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
    };
    let _ = s.write_all(&reply);
    let _ = s.flush();
    let mut sink = [0u8; 1];
    let _ = s.set_read_timeout(Some(Duration::from_millis(1)));
    let _ = s.read(&mut sink);
}

/// A loopback HTTP server of `files` until [`Server::stop`].
struct Server {
    port: u16,
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
        let stop = done.clone();
        let thread = std::thread::spawn(move || {
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                match listener.accept() {
                    Ok((s, _)) => serve_one(s, &files),
                    Err(_) => std::thread::sleep(Duration::from_millis(5)),
                }
            }
        });
        Ok(Server { port, done, thread })
    }

    fn stop(self) {
        self.done.store(true, std::sync::atomic::Ordering::Relaxed);
        let _ = self.thread.join();
    }
}

/// Runs headless `chrome` on `url` with a fresh profile, reading both pipes
/// while it runs (the dumped DOM can pass a pipe's buffer): its exit status, the
/// DOM and its log. A page that never settles is killed after 240 s.
fn run_chromium(
    chrome: &Path,
    url: &str,
    profile: &Path,
    (width, height): (u32, u32),
) -> Result<(std::process::ExitStatus, String, String), BrowserError> {
    let mut child = Command::new(chrome)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--ignore-gpu-blocklist",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--virtual-time-budget=60000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size={width},{height}"))
        .arg(url)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| BrowserError(format!("{}: {e}", chrome.display())))?;
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_string(&mut text);
            }
            text
        })
    };
    let out = drain(child.stdout.take().map(|p| Box::new(p) as Box<dyn Read + Send>));
    let errs = drain(child.stderr.take().map(|p| Box::new(p) as Box<dyn Read + Send>));
    let start = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break Ok(s),
            Err(e) => break Err(BrowserError(e.to_string())),
            Ok(None) if start.elapsed() > Duration::from_secs(240) => {
                let _ = child.kill();
                let _ = child.wait();
                break Err(BrowserError("chromium did not finish within 240 s".into()));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(50)),
        }
    };
    let (dom, log) = (out.join().unwrap_or_default(), errs.join().unwrap_or_default());
    Ok((status?, dom, log))
}

/// Serves `files` (name → contents) on 127.0.0.1 and loads `index.html` in
/// headless `chrome`; the page's pixels, rows from the top.
pub fn draw(chrome: &Path, files: Vec<(String, Vec<u8>)>, width: u32, height: u32) -> Result<Drawn, BrowserError> {
    let server = Server::start(files)?;
    let url = format!("http://127.0.0.1:{}/index.html", server.port);
    let profile = std::env::temp_dir().join(format!("airlight-chromium-{}-{}", std::process::id(), server.port));
    let ran = run_chromium(chrome, &url, &profile, (width, height));
    server.stop();
    std::fs::remove_dir_all(&profile).ok();
    let (status, dom, log) = ran?;
    if let Some(e) = between(&dom, "error") {
        return Err(BrowserError(format!("the page failed: {e}")));
    }
    let Some(result) = between(&dom, "result") else {
        let tail: String =
            log.lines().rev().take(12).collect::<Vec<_>>().into_iter().rev().collect::<Vec<_>>().join("\n");
        return Err(BrowserError(format!("chromium ({status}) printed no pixels; its log ends:\n{tail}")));
    };
    let rgba = decode_base64(result)?;
    let (w, h) = (width as usize, height as usize);
    if rgba.len() != 4 * w * h {
        return Err(BrowserError(format!("{} bytes read back, expected {}", rgba.len(), 4 * w * h)));
    }
    // readPixels starts at the bottom row.
    let pixels =
        (0..h).flat_map(|y| (0..w).map(move |x| (y, x))).map(|(y, x)| rgba[4 * ((h - 1 - y) * w + x)]).collect();
    Ok(Drawn { adapter: between(&dom, "adapter").unwrap_or("unknown").to_string(), pixels })
}

/// The files the page needs: itself and the vendored three.js under `vendor`.
pub fn page_files(vendor: &Path, page: String) -> Result<Vec<(String, Vec<u8>)>, BrowserError> {
    let mut files = vec![("index.html".to_string(), page.into_bytes())];
    for f in ["three.module.min.js", "three.core.min.js"] {
        let p = vendor.join(f);
        let body = std::fs::read(&p).map_err(|e| BrowserError(format!("{}: {e}", p.display())))?;
        files.push((f.to_string(), body));
    }
    Ok(files)
}

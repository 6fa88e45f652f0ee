//! The renders `airlight render --report` recorded under `generated/render/`, as
//! the report quotes them (the scene renders and the light-shafts frames).

use crate::output::Output;
use airlight_truth::stats::fmt_err;
use serde::Serialize;

/// A light-shafts render (`kind = "shafts"`): its frames (the exact walk, the
/// sampled accumulator, the marches), which are shown, and how the exact frame
/// stands against the marches.
#[derive(Serialize)]
pub(super) struct ShaftsRender {
    scene: String,
    description: String,
    light: String,
    kernel: String,
    march_kernel: String,
    adapter: String,
    size: String,
    shadow_map: i64,
    faces: i64,
    walk_bias: String,
    /// Texels short of a surface facing away from the light that the fog ends.
    end_texels: String,
    /// Degrees past a spot's outer cone that its frames still walk (or march).
    clip_margin_deg: String,
    /// GPU ms of the exact frame's walk alone (no kernel).
    walk_ms: String,
    /// The walk's steps and lit runs per walked view ray (`—`: a file from
    /// before they were written).
    walk_counts: String,
    refine_steps: i64,
    lit_pixels: i64,
    edge_pixels: i64,
    march_shown: i64,
    sampled_shown: i64,
    rows: Vec<ShaftsRenderRow>,
    /// The exact frame against the 64-step march's time and the 512-step
    /// march's errors, and its leaks.
    verdict: Vec<String>,
    /// Where the exact frame loses to the march shown.
    losses: Vec<String>,
    /// The report's opening row: the exact frame against the marches (lit max,
    /// GPU time, leak pixels).
    glance: Vec<String>,
}

/// One frame of a light-shafts render: its method, GPU time, fog errors, leaks.
#[derive(Serialize)]
pub(super) struct ShaftsRenderRow {
    method: String,
    steps: String,
    gpu_ms: String,
    pyramid_ms: String,
    lit_max: String,
    lit_mean: String,
    edge_max: String,
    edge_mean: String,
    leaks: i64,
    shown: bool,
}

/// The light-shafts renders under `render/`.
pub(super) fn shafts_renders(renders: &[Output]) -> Vec<ShaftsRender> {
    renders
        .iter()
        .filter(|o| o.path.ends_with(".toml"))
        .filter_map(|o| {
            let t: toml::Table = String::from_utf8_lossy(&o.contents).parse().ok()?;
            if t.get("kind").and_then(|v| v.as_str()) != Some("shafts") {
                return None;
            }
            let s = |k: &str| t.get(k).and_then(|v| v.as_str()).unwrap_or("—").to_string();
            let i = |k: &str| t.get(k).and_then(|v| v.as_integer()).unwrap_or(0);
            let frames: Vec<&toml::Table> =
                t.get("frame").and_then(|v| v.as_array())?.iter().filter_map(|f| f.as_table()).collect();
            let x = |t: &toml::Table, k: &str| t.get(k).and_then(|v| v.as_float()).unwrap_or(f64::NAN);
            let method = |t: &toml::Table| t.get("method").and_then(|v| v.as_str()).unwrap_or("—").to_string();
            let steps = |t: &toml::Table| t.get("steps").and_then(|v| v.as_integer()).unwrap_or(0);
            let find =
                |m: &str, n: i64| frames.iter().copied().find(|f| method(f) == m && (m == "exact" || steps(f) == n));
            let rows = frames
                .iter()
                .map(|f| {
                    let m = method(f);
                    let e = |k: &str| f.get(k).and_then(|v| v.as_float()).map_or("—".to_string(), fmt_err);
                    ShaftsRenderRow {
                        method: match m.as_str() {
                            "exact" => "exact walk".to_string(),
                            "sampled" => "sampled accumulator".to_string(),
                            other => other.to_string(),
                        },
                        steps: if m == "exact" { "—".into() } else { steps(f).to_string() },
                        gpu_ms: format!("{:.1}", x(f, "gpu_ms")),
                        pyramid_ms: if m == "exact" { format!("{:.2}", x(f, "pyramid_ms")) } else { "—".into() },
                        lit_max: e("lit_max"),
                        lit_mean: e("lit_mean"),
                        edge_max: e("edge_max"),
                        edge_mean: e("edge_mean"),
                        leaks: f.get("leak_pixels").and_then(|v| v.as_integer()).unwrap_or(-1),
                        shown: m == "exact"
                            || (m == "march" && steps(f) == i("march_shown"))
                            || (m == "sampled" && steps(f) == i("sampled_shown")),
                    }
                })
                .collect();
            let exact = find("exact", 0)?;
            let mut verdict = Vec::new();
            let time = x(exact, "gpu_ms") + x(exact, "pyramid_ms");
            if let Some(m64) = find("march", 64) {
                let ratio = time / x(m64, "gpu_ms");
                verdict.push(format!(
                    "GPU time (pass and pyramid) {time:.1} ms, {ratio:.2}× the 64-step march's ({:.1} ms): {}",
                    x(m64, "gpu_ms"),
                    if ratio <= 1.0 { "no more" } else { "**more**" }
                ));
            }
            if let Some(m512) = find("march", 512) {
                for (k, what) in [("lit_max", "lit max"), ("lit_mean", "lit mean")] {
                    let (a, b) = (x(exact, k), x(m512, k));
                    verdict.push(format!(
                        "{what} {} against the 512-step march's {}: {}",
                        fmt_err(a),
                        fmt_err(b),
                        if a < b { "below" } else { "**not below**" }
                    ));
                }
            }
            verdict
                .push(format!("leak pixels: {}", exact.get("leak_pixels").and_then(|v| v.as_integer()).unwrap_or(-1)));
            let mut losses = Vec::new();
            if let Some(m) = find("march", i("march_shown")) {
                for (k, what) in [
                    ("lit_max", "lit max"),
                    ("lit_mean", "lit mean"),
                    ("edge_max", "edge max"),
                    ("edge_mean", "edge mean"),
                ] {
                    if x(exact, k) > x(m, k) {
                        losses.push(format!("{what} ({} against {})", fmt_err(x(exact, k)), fmt_err(x(m, k))));
                    }
                }
                if time > x(m, "gpu_ms") {
                    losses.push(format!("GPU time ({time:.1} ms against {:.1} ms)", x(m, "gpu_ms")));
                }
            }
            let glance = {
                let err = |f: Option<&&toml::Table>, k: &str| f.map_or("—".to_string(), |f| fmt_err(x(f, k)));
                let leaks = |f: Option<&&toml::Table>| {
                    f.and_then(|f| f.get("leak_pixels")).and_then(|v| v.as_integer()).map_or("—".into(), |n| n.to_string())
                };
                let (m64, m512) = (find("march", 64), find("march", 512));
                vec![
                    format!("{} / {} / {}", err(Some(&exact), "lit_max"), err(m64.as_ref(), "lit_max"), err(m512.as_ref(), "lit_max")),
                    match m64 {
                        Some(m) => format!("{time:.1} / {:.1} ({:.2}×)", x(m, "gpu_ms"), time / x(m, "gpu_ms")),
                        None => format!("{time:.1} / —"),
                    },
                    format!("{} / {}", leaks(Some(&exact)), leaks(m64.as_ref())),
                ]
            };
            Some(ShaftsRender {
                glance,
                scene: o.path.trim_start_matches("render/").trim_end_matches(".toml").to_string(),
                description: s("description"),
                light: s("light"),
                kernel: s("kernel"),
                march_kernel: s("march_kernel"),
                adapter: s("adapter"),
                size: format!("{}×{}", i("width"), i("height")),
                shadow_map: i("shadow_map"),
                faces: i("faces"),
                walk_bias: t.get("walk_bias").and_then(|v| v.as_float()).map_or("—".into(), |b| format!("{b}")),
                end_texels: t.get("end_texels").and_then(|v| v.as_float()).map_or("—".into(), |b| format!("{b}")),
                clip_margin_deg: t
                    .get("clip_margin_deg")
                    .and_then(|v| v.as_float())
                    .map_or("—".into(), |b| format!("{b}")),
                walk_ms: t.get("walk_ms").and_then(|v| v.as_float()).map_or("—".into(), |b| format!("{b:.1}")),
                walk_counts: match (
                    t.get("walked_pixels").and_then(|v| v.as_integer()),
                    ["walk_steps_mean", "walk_steps_p90", "walk_steps_max", "walk_runs_mean"]
                        .map(|k| t.get(k).and_then(|v| v.as_float())),
                ) {
                    (Some(n), [Some(m), Some(p90), Some(max), Some(runs)]) => format!(
                        "its {n} walked view rays take {m:.1} steps on average (90th percentile {p90}, max {max}) and hand the kernel {runs:.2} lit runs each"
                    ),
                    _ => "—".into(),
                },
                refine_steps: i("refine_steps"),
                lit_pixels: i("lit_pixels"),
                edge_pixels: i("edge_pixels"),
                march_shown: i("march_shown"),
                sampled_shown: i("sampled_shown"),
                rows,
                verdict,
                losses,
            })
        })
        .collect()
}

#[derive(Serialize)]
pub(super) struct RenderRow {
    scene: String,
    kernel: String,
    adapter: String,
    size: String,
    sigma_t: String,
    gpu_max: String,
    gpu_mean: String,
    rust_max: String,
    rust_mean: String,
}

/// One row per `render/<scene>.toml` written by `airlight render --report`
/// (light-shafts renders apart: [`shafts_renders`]).
pub(super) fn render_rows(renders: &[Output]) -> Vec<RenderRow> {
    renders
        .iter()
        .filter(|o| o.path.ends_with(".toml"))
        .filter_map(|o| {
            let t: toml::Table = String::from_utf8_lossy(&o.contents).parse().ok()?;
            // Light shafts and the three.js example are recorded apart.
            if t.get("kind").is_some() {
                return None;
            }
            let s = |k: &str| t.get(k).and_then(|v| v.as_str()).unwrap_or("—").to_string();
            let f = |k: &str| t.get(k).and_then(|v| v.as_float()).map_or("—".to_string(), fmt_err);
            let i = |k: &str| t.get(k).and_then(|v| v.as_integer()).unwrap_or(0);
            let scene = o.path.trim_start_matches("render/").trim_end_matches(".toml").to_string();
            Some(RenderRow {
                kernel: s("kernel"),
                adapter: s("adapter"),
                size: format!("{}×{}", i("width"), i("height")),
                sigma_t: t.get("sigma_t").map_or("—".into(), |v| v.to_string()),
                gpu_max: f("gpu_max_rel"),
                gpu_mean: f("gpu_mean_rel"),
                rust_max: f("rust_max_rel"),
                rust_mean: f("rust_mean_rel"),
                scene,
            })
        })
        .collect()
}

/// The three.js example page as its browser test recorded it, per renderer
/// (`render/three-example.toml` on WebGPU, `render/three-example-webgl.toml`
/// on WebGL 2; `AIRLIGHT_RECORD_EXAMPLE=1`).
#[derive(Serialize)]
pub(super) struct ThreeExample {
    /// The records' base name under `render/` (its pictures: `-page`, `-fog`, `-reference`).
    base: String,
    renderer: String,
    adapter: String,
    kernel: String,
    bound: String,
    size: String,
    lit_pixels: i64,
    lit_max: String,
    lit_mean: String,
    edge_max: String,
    edge_mean: String,
    bad_pixels: i64,
    frame_ms: String,
}

/// The example's records, WebGPU's first; empty if there are none.
pub(super) fn three_example(renders: &[Output]) -> Vec<ThreeExample> {
    ["three-example", "three-example-webgl"]
        .into_iter()
        .filter_map(|base| {
            let o = renders.iter().find(|o| o.path == format!("render/{base}.toml"))?;
            let t: toml::Table = String::from_utf8_lossy(&o.contents).parse().ok()?;
            let s = |k: &str| t.get(k).and_then(|v| v.as_str()).unwrap_or("—").to_string();
            let f = |k: &str| t.get(k).and_then(|v| v.as_float()).map_or("—".to_string(), fmt_err);
            let i = |k: &str| t.get(k).and_then(|v| v.as_integer()).unwrap_or(0);
            Some(ThreeExample {
                base: base.to_string(),
                renderer: t.get("renderer").and_then(|v| v.as_str()).unwrap_or("WebGPURenderer").to_string(),
                adapter: s("adapter"),
                kernel: s("kernel"),
                bound: f("bound"),
                size: format!("{}×{}", i("width"), i("height")),
                lit_pixels: i("lit_pixels"),
                lit_max: f("lit_max"),
                lit_mean: f("lit_mean"),
                edge_max: f("edge_max"),
                edge_mean: f("edge_mean"),
                bad_pixels: i("bad_pixels"),
                frame_ms: t.get("frame_ms").and_then(|v| v.as_float()).map_or("—".into(), |x| format!("{x:.1}")),
            })
        })
        .collect()
}

/// The Bevy example's street as its headless test recorded it
/// (`render/bevy-street.toml`; `AIRLIGHT_RECORD_EXAMPLE=1`).
#[derive(Serialize)]
pub(super) struct BevyExample {
    bevy: String,
    adapter: String,
    profile: String,
    kernel: String,
    bound: String,
    size: String,
    msaa: i64,
    compared_pixels: i64,
    lit_pixels: i64,
    lit_max: String,
    lit_mean: String,
    /// The signed error's range in f16 ulps of the frame.
    ulps: String,
    over: i64,
    bad_pixels: i64,
    update_ms: String,
}

/// The Bevy example's record, if there is one.
pub(super) fn bevy_example(renders: &[Output]) -> Option<BevyExample> {
    let o = renders.iter().find(|o| o.path == "render/bevy-street.toml")?;
    let t: toml::Table = String::from_utf8_lossy(&o.contents).parse().ok()?;
    let s = |k: &str| t.get(k).and_then(|v| v.as_str()).unwrap_or("—").to_string();
    let f = |k: &str| t.get(k).and_then(|v| v.as_float()).map_or("—".to_string(), fmt_err);
    let i = |k: &str| t.get(k).and_then(|v| v.as_integer()).unwrap_or(0);
    Some(BevyExample {
        bevy: s("bevy"),
        adapter: s("adapter"),
        profile: s("profile"),
        kernel: s("kernel"),
        bound: f("bound"),
        size: format!("{}×{}", i("width"), i("height")),
        msaa: i("msaa"),
        compared_pixels: i("compared_pixels"),
        lit_pixels: i("lit_pixels"),
        lit_max: f("lit_max"),
        lit_mean: f("lit_mean"),
        ulps: match (t.get("ulps_min").and_then(|v| v.as_float()), t.get("ulps_max").and_then(|v| v.as_float())) {
            (Some(lo), Some(hi)) => format!("{lo:.2} … {hi:.2}"),
            _ => "—".into(),
        },
        over: i("over"),
        bad_pixels: i("bad_pixels"),
        update_ms: t.get("update_ms").and_then(|v| v.as_float()).map_or("—".into(), |x| format!("{x:.1}")),
    })
}

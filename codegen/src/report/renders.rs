//! The renders `airlight render --report` recorded under `generated/render/`, as
//! the report quotes them (the scene renders and the light-shafts frames).

use crate::output::Output;
use airlight_truth::stats::fmt_err;
use serde::Serialize;

/// A light-shafts render (`kind = "shafts"`): the accumulator's frame, the
/// marches tried, which march is shown.
#[derive(Serialize)]
pub(super) struct ShaftsRender {
    scene: String,
    kernel: String,
    march_kernel: String,
    adapter: String,
    size: String,
    shadow_map: i64,
    look_ups: i64,
    refine_steps: i64,
    lit_pixels: i64,
    edge_pixels: i64,
    march_shown: i64,
    rows: Vec<ShaftsRenderRow>,
    /// Where the accumulator's frame loses to the march shown.
    losses: Vec<String>,
}

/// One frame of a light-shafts render: its method, GPU time and fog errors.
#[derive(Serialize)]
pub(super) struct ShaftsRenderRow {
    method: String,
    steps: i64,
    gpu_ms: String,
    lit_max: String,
    lit_mean: String,
    edge_max: String,
    edge_mean: String,
}

/// The light-shafts renders under `render/`.
pub(super) fn shafts_renders(renders: &[Output]) -> Vec<ShaftsRender> {
    let row = |method: &str, t: &toml::Table| {
        let f = |k: &str| t.get(k).and_then(|v| v.as_float()).map_or("—".to_string(), fmt_err);
        ShaftsRenderRow {
            method: method.to_string(),
            steps: t.get("steps").and_then(|v| v.as_integer()).unwrap_or(0),
            gpu_ms: t.get("gpu_ms").and_then(|v| v.as_float()).map_or("—".into(), |x| format!("{x:.1}")),
            lit_max: f("lit_max"),
            lit_mean: f("lit_mean"),
            edge_max: f("edge_max"),
            edge_mean: f("edge_mean"),
        }
    };
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
            let acc = t.get("accumulator").and_then(|v| v.as_table())?;
            let mut rows = vec![row("shafts accumulator", acc)];
            let mut losses = Vec::new();
            for m in t.get("march").and_then(|v| v.as_array()).into_iter().flatten() {
                let m = m.as_table()?;
                rows.push(row("march", m));
                if m.get("steps").and_then(|v| v.as_integer()) == Some(i("march_shown")) {
                    let x = |t: &toml::Table, k: &str| t.get(k).and_then(|v| v.as_float()).unwrap_or(f64::NAN);
                    for (k, what) in [
                        ("lit_max", "lit max"),
                        ("lit_mean", "lit mean"),
                        ("edge_max", "edge max"),
                        ("edge_mean", "edge mean"),
                        ("gpu_ms", "GPU time"),
                    ] {
                        if x(acc, k) > x(m, k) {
                            losses.push(format!("{what} ({:.3e} against {:.3e})", x(acc, k), x(m, k)));
                        }
                    }
                }
            }
            Some(ShaftsRender {
                scene: o.path.trim_start_matches("render/").trim_end_matches(".toml").to_string(),
                kernel: s("kernel"),
                march_kernel: s("march_kernel"),
                adapter: s("adapter"),
                size: format!("{}×{}", i("width"), i("height")),
                shadow_map: i("shadow_map"),
                look_ups: acc.get("steps").and_then(|v| v.as_integer()).unwrap_or(0),
                refine_steps: i("refine_steps"),
                lit_pixels: i("lit_pixels"),
                edge_pixels: i("edge_pixels"),
                march_shown: i("march_shown"),
                rows,
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
            if t.get("kind").and_then(|v| v.as_str()) == Some("shafts") {
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

//! `generated/bench.json`, the speed/accuracy trade as `airlight bench` measured it
//! on one machine: its shape, read back by the planner and the report. The CPU side
//! (`airlight-fit`'s `bench`) and the GPU side (`airlight-shaders`' `bench`) fill
//! it; `airlight bench` writes it; `airlight generate` reads it. Never written by
//! `regenerate` (timings differ between machines; regenerating stays byte-identical).

use serde::{Deserialize, Serialize};

/// The file's name under `generated/`.
pub const FILE: &str = "bench.json";

/// A figure on each of the two sampled domains.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PerDomain {
    /// On `thin`.
    pub thin: f64,
    /// On `dense`.
    pub dense: f64,
}

impl PerDomain {
    /// The larger of the two.
    pub fn max(&self) -> f64 {
        self.thin.max(self.dense)
    }
}

/// Errors of one kernel at one `g`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GErrors {
    /// The asymmetry.
    pub g: f64,
    /// Largest relative error over the sampled points.
    pub max_rel: PerDomain,
    /// 99th percentile.
    pub p99_rel: PerDomain,
    /// Median.
    pub p50_rel: PerDomain,
}

/// One model's row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchModel {
    /// Model name.
    pub name: String,
    /// `airlight` or `baseline`.
    pub kind: crate::vocab::Role,
    /// Supported `g`.
    pub g_range: [f64; 2],
    /// Errors of the f32 Rust kernel at each bench `g` in its range.
    pub errors: Vec<GErrors>,
    /// Median thread CPU time per evaluation of the f32 Rust kernel, ns.
    pub cpu_ns_per_eval: f64,
    /// Fastest and slowest of the repeats, ns.
    pub cpu_ns_range: [f64; 2],
    /// Median ns per evaluation one call at a time ([`time_kernels`]): each call's
    /// arguments and result opaque to the compiler (through memory), each call's
    /// first argument depending on the last result; 0 where not measured.
    #[serde(default)]
    pub cpu_ns_one_at_a_time: f64,
    /// Operations in the naga IR of its WGSL `airlight` (worst path, loops counted by trip count).
    pub ops: usize,
    /// Of those, calls of transcendental built-ins (exp, log, sqrt, pow, trigonometry).
    pub transcendentals: usize,
    /// GPU evaluations per second (timestamp queries) over the random batch
    /// (every lane on its own branch: the worst case for divergence), 0 where
    /// not measured.
    pub gpu_evals_per_s: f64,
    /// GPU evaluations per second over frame-coherent points: every pixel of two
    /// rendered frames, light by light, in pixel order (neighbouring lanes on
    /// neighbouring rays); 0 where not measured.
    #[serde(default)]
    pub gpu_frame_evals_per_s: f64,
    /// Bytes of tables it needs (0: none).
    pub bytes: usize,
}

/// Everything `airlight bench` measures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bench {
    /// The GPU adapter the throughputs come from (lavapipe is labelled CPU emulation).
    pub adapter: String,
    /// The CPU the kernels were timed on.
    pub cpu: String,
    /// Points per `(g, domain)` for the errors.
    pub error_points: usize,
    /// Points in the timing batch.
    pub cost_batch: usize,
    /// Timing repeats.
    pub repeats: usize,
    /// One row per model, in catalog order.
    pub models: Vec<BenchModel>,
    /// The RGB (spot) entry against three scalar calls, per model with a spot entry.
    #[serde(default)]
    pub rgb: Vec<RgbCost>,
    /// Light shafts: the accumulator against the march, on the same shadow-map
    /// samples, per sample count.
    #[serde(default)]
    pub shafts: Vec<ShaftsCost>,
    /// Light shafts from a shadow map: the exact walk per map resolution, against
    /// the march and the sampled accumulator, on one street-lamp scene.
    #[serde(default)]
    pub shadow_map: Vec<MapCost>,
    /// Where `shadow_map` was measured in a run of its own (`airlight bench
    /// --only shadow-map`), after the rest: that run's adapter. Its rows compare
    /// with each other, not with the other sections'. `None`: the same run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shadow_map_alone: Option<String>,
}

/// One method on the shadow-map bench's rays: errors against the analytic
/// reference, the walk's effort, and costs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapCost {
    /// What ran: `walk` (the exact mode), a march, or an accumulator at `N` look-ups.
    pub method: String,
    /// The map's texels per side (0: visibility from the analytic occluders).
    pub res: usize,
    /// Look-ups (or steps) per ray (0: the walk).
    pub samples: usize,
    /// Mean lit runs per ray.
    pub runs_per_ray: f64,
    /// The walk's mean and largest steps per ray (0 for the others).
    pub steps_mean: f64,
    /// Largest.
    pub steps_max: f64,
    /// Rays whose walk ran out of steps.
    pub truncated: usize,
    /// Largest and mean error relative to each ray's unshadowed in-scattering.
    pub max_of_unshadowed: f64,
    /// Mean.
    pub mean_of_unshadowed: f64,
    /// Rays brighter than 1.5× the reference plus 5% of their unshadowed value.
    pub leaks: usize,
    /// CPU ns per ray (f32; the map and its pyramid built beforehand).
    pub cpu_ns_per_ray: f64,
    /// GPU rays per second (timestamps; 0 without them).
    pub gpu_rays_per_s: f64,
}

/// One method of shadowed in-scattering at one sample count: errors against the
/// shadowed reference and costs, over the gate's shadowed rays.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShaftsCost {
    /// The kernel: a model's accumulator, or `raymarch-N` (the engines' march).
    pub name: String,
    /// Visibility samples per ray (0: the exact lit intervals).
    pub samples: usize,
    /// Mean kernel (or integrand) evaluations per ray.
    pub calls_per_ray: f64,
    /// Largest relative error against the shadowed reference (rays with some light).
    pub max_rel: f64,
    /// Mean relative error.
    pub mean_rel: f64,
    /// Largest error relative to the ray's unshadowed in-scattering (as the gate
    /// holds it: how much of the pixel's possible glow is wrong).
    #[serde(default)]
    pub max_of_unshadowed: f64,
    /// Mean error relative to the unshadowed in-scattering.
    #[serde(default)]
    pub mean_of_unshadowed: f64,
    /// CPU ns per ray, f32 kernel, samples given (the shadow look-ups are the caller's).
    pub cpu_ns_per_ray: f64,
    /// GPU rays per second (timestamp queries); 0 without timestamps or not run there.
    pub gpu_rays_per_s: f64,
    /// A per-frame table's build per light (the seed's `F'`): CPU ms (0: none).
    #[serde(default)]
    pub build_cpu_ms: f64,
    /// The same build as one GPU compute pass over the kernel, ms (0: not measured).
    #[serde(default)]
    pub build_gpu_ms: f64,
}

/// What RGB costs: a model's spot entry (one call, three channels) against its
/// physical entry called once per channel, on the same rays; CPU ns per ray
/// (median of interleaved repeats).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RgbCost {
    /// Model name.
    pub name: String,
    /// `radiance` three times (R, G, B) per ray.
    pub three_scalar_ns: f64,
    /// `spot` with a point light (`cos_outer = −1`): the RGB price alone.
    pub rgb_point_ns: f64,
    /// `spot` with a hard-edged cone.
    pub rgb_hard_cone_ns: f64,
    /// `spot` with a smooth-edged cone.
    pub rgb_soft_cone_ns: f64,
    /// GPU rays per second (RGB each) by three `radiance` dispatches: a third of
    /// the physical entry's rate; 0 without timestamps.
    #[serde(default)]
    pub gpu_three_scalar_rays_per_s: f64,
    /// GPU rays per second of `spot` with a point light; 0 without timestamps.
    #[serde(default)]
    pub gpu_rgb_point_rays_per_s: f64,
}

impl Bench {
    /// The file's text (pretty JSON, trailing newline): deterministic for a value.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serialises") + "\n"
    }
    /// Reads the file's text.
    pub fn from_json(text: &str) -> Result<Bench, String> {
        serde_json::from_str(text).map_err(|e| format!("line {}: {e}", e.line()))
    }
    /// The row of `name`.
    pub fn model(&self, name: &str) -> Option<&BenchModel> {
        self.models.iter().find(|m| m.name == name)
    }
}

impl BenchModel {
    /// Its errors at `g`, if measured.
    pub fn at(&self, g: f64) -> Option<&GErrors> {
        self.errors.iter().find(|e| e.g == g)
    }
}

impl Bench {
    /// The table `airlight bench` prints: the adapter and CPU, every model's
    /// errors, time, IR cost and GPU rate, the RGB costs, and both light-shafts
    /// sections.
    pub fn table(&self) -> String {
        let mut lines = Vec::new();
        lines.push(format!("adapter: {}\ncpu: {}", self.adapter, self.cpu));
        lines.push(format!(
            "{:<16} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10} {:>6} {:>5} {:>12} {:>12}",
            "model",
            "thin max",
            "dense max",
            "thin p50",
            "dense p50",
            "ns/eval",
            "ns one",
            "ops",
            "tr",
            "GPU evals/s",
            "GPU frame/s"
        ));
        for m in &self.models {
            let e = m.errors.first();
            let f = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.2e}"));
            lines.push(format!(
                "{:<16} {:>9} {:>9} {:>9} {:>9} {:>10.1} {:>10.1} {:>6} {:>5} {:>12.3e} {:>12.3e}   (g = {})",
                m.name,
                f(e.map(|e| e.max_rel.thin)),
                f(e.map(|e| e.max_rel.dense)),
                f(e.map(|e| e.p50_rel.thin)),
                f(e.map(|e| e.p50_rel.dense)),
                m.cpu_ns_per_eval,
                m.cpu_ns_one_at_a_time,
                m.ops,
                m.transcendentals,
                m.gpu_evals_per_s,
                m.gpu_frame_evals_per_s,
                e.map_or(0.0, |e| e.g)
            ));
        }
        lines.push("\nRGB, CPU ns per ray: three scalar `radiance` calls against one `spot` call".to_string());
        lines.push(format!(
            "{:<16} {:>10} {:>10} {:>7} {:>10} {:>10} {:>12} {:>12}",
            "model", "3 scalar", "RGB point", "ratio", "hard cone", "soft cone", "GPU 3 scalar", "GPU RGB"
        ));
        for r in &self.rgb {
            lines.push(format!(
                "{:<16} {:>10.1} {:>10.1} {:>7.2} {:>10.1} {:>10.1} {:>12.3e} {:>12.3e}",
                r.name,
                r.three_scalar_ns,
                r.rgb_point_ns,
                r.rgb_point_ns / r.three_scalar_ns,
                r.rgb_hard_cone_ns,
                r.rgb_soft_cone_ns,
                r.gpu_three_scalar_rays_per_s,
                r.gpu_rgb_point_rays_per_s
            ));
        }
        lines.push("\nLight shafts: accumulator against the march on the same shadow-map samples".to_string());
        lines.push(format!(
            "{:<22} {:>7} {:>8} {:>9} {:>9} {:>9} {:>9} {:>10} {:>12} {:>10} {:>10}",
            "kernel",
            "samples",
            "calls",
            "max rel",
            "mean rel",
            "max/U",
            "mean/U",
            "ns/ray",
            "GPU rays/s",
            "build ms",
            "GPU build"
        ));
        for r in &self.shafts {
            lines.push(format!(
                "{:<22} {:>7} {:>8.2} {:>9.2e} {:>9.2e} {:>9.2e} {:>9.2e} {:>10.1} {:>12.3e} {:>10.2} {:>10.3}",
                r.name,
                if r.samples == 0 { "exact".to_string() } else { r.samples.to_string() },
                r.calls_per_ray,
                r.max_rel,
                r.mean_rel,
                r.max_of_unshadowed,
                r.mean_of_unshadowed,
                r.cpu_ns_per_ray,
                r.gpu_rays_per_s,
                r.build_cpu_ms,
                r.build_gpu_ms
            ));
        }
        lines.push(format!(
            "\nLight shafts from a shadow map: the exact walk per resolution, the march and the sampled accumulator{}",
            self.shadow_map_alone.as_ref().map_or(String::new(), |a| format!(" (measured alone, on {a})"))
        ));
        lines.push(format!(
            "{:<30} {:>5} {:>7} {:>7} {:>8} {:>6} {:>5} {:>9} {:>9} {:>5} {:>10} {:>12}",
            "method",
            "res",
            "samples",
            "runs",
            "steps",
            "max",
            "trunc",
            "max/U",
            "mean/U",
            "leaks",
            "ns/ray",
            "GPU rays/s"
        ));
        for r in &self.shadow_map {
            lines.push(format!(
                "{:<30} {:>5} {:>7} {:>7.2} {:>8.1} {:>6} {:>5} {:>9.2e} {:>9.2e} {:>5} {:>10.1} {:>12.3e}",
                r.method,
                r.res,
                if r.samples == 0 { "walk".to_string() } else { r.samples.to_string() },
                r.runs_per_ray,
                r.steps_mean,
                r.steps_max,
                r.truncated,
                r.max_of_unshadowed,
                r.mean_of_unshadowed,
                r.leaks,
                r.cpu_ns_per_ray,
                r.gpu_rays_per_s
            ));
        }
        lines.join("\n")
    }
}

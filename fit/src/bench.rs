//! The speed/accuracy trade (`airlight bench`, `generated/bench.json`): every
//! shipped model — airlight's and the baselines — measured in one run on the same
//! seeded points: the generated f32 Rust kernel's relative error against the
//! reference per `g` and domain, its CPU cost in thread CPU time, and (from the
//! callers that have them) the operations of its WGSL in naga's IR and its GPU
//! throughput. Timings never enter the tests; the report quotes this file, so
//! regenerating stays byte-identical.

use crate::domains::{Domain, VALIDATION_SEED};
use crate::reference::Point;
use crate::vocab::CanonicalFn;
use serde::{Deserialize, Serialize};
use std::hint::black_box;

/// The `g` values errors are measured at: isotropic, then the HG media of the issue.
pub const BENCH_GS: [f64; 6] = [0.0, -0.95, -0.5, 0.5, 0.9, 0.95];
/// Points per `(g, domain)` for the errors.
pub const ERROR_POINTS: usize = 20_000;
/// Points of the fixed timing batch.
pub const COST_BATCH: usize = 100_000;
/// Interleaved timing repeats (the median is quoted).
pub const REPEATS: usize = 7;
/// Seed of the bench's points (not the validation's nor any fit's).
pub const BENCH_SEED: u64 = VALIDATION_SEED ^ 0xBE7C_0000_0000_0000;

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

/// Rays for the RGB timing: `n` view rays from the origin, lights 1…100 units
/// away in random directions, a cone aimed near the ray (its axis from the light
/// to a point of the ray, 30° outer, 20° inner half-angle), σt = (0.03, 0.05,
/// 0.08), σs = 0.8 σt, g = 0.5; deterministic. Items: (dir, light, axis).
pub fn rgb_rays(n: usize) -> Vec<RgbRay> {
    let mut rng = crate::domains::SplitMix64(0xB0B5);
    let mut unit = move || loop {
        let v = [2.0 * rng.next_f64() - 1.0, 2.0 * rng.next_f64() - 1.0, 2.0 * rng.next_f64() - 1.0];
        let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if r > 0.1 && r <= 1.0 {
            return ([v[0] / r, v[1] / r, v[2] / r], rng.next_f64());
        }
    };
    (0..n)
        .map(|_| {
            let (d, a) = unit();
            let (l, b) = unit();
            let dist = 100f64.powf(a);
            let light = l.map(|x| x * dist);
            let s = 2.0 * dist * b;
            let axis: [f64; 3] = std::array::from_fn(|j| s * d[j] - light[j]);
            [d.map(|x| x as f32), light.map(|x| x as f32), axis.map(|x| x as f32)]
        })
        .collect()
}

/// A timing ray of [`rgb_rays`]: direction, light, axis.
pub type RgbRay = [[f32; 3]; 3];

/// Times `three` (one ray, three scalar calls) and `rgb` at `cos_outer` −1, and a
/// hard and a soft 30° cone, interleaved, `repeats` times over `rays`: medians
/// of ns per ray, in that order.
pub fn time_rgb(
    three: &dyn Fn(&RgbRay) -> f32,
    rgb: &dyn Fn(&RgbRay, f32, f32) -> f32,
    rays: &[RgbRay],
    repeats: usize,
) -> [f64; 4] {
    let (c30, c20) = (30f32.to_radians().cos(), 20f32.to_radians().cos());
    let mut times: Vec<Vec<f64>> = (0..4).map(|_| Vec::with_capacity(repeats)).collect();
    for _ in 0..repeats {
        for (k, t) in times.iter_mut().enumerate() {
            let start = thread_cpu_s();
            let mut acc = 0.0f32;
            for r in black_box(rays) {
                acc += match k {
                    0 => three(r),
                    1 => rgb(r, -1.0, -1.0),
                    2 => rgb(r, c30, c30),
                    _ => rgb(r, c30, c20),
                };
            }
            black_box(acc);
            t.push((thread_cpu_s() - start) * 1e9 / rays.len() as f64);
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    [median(&mut times[0]), median(&mut times[1]), median(&mut times[2]), median(&mut times[3])]
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

/// One domain's bench points with their reference `A`.
pub type DomainSet = (Domain, Vec<(Point, f64)>);

/// The points errors are measured on, with their reference values: per bench `g`,
/// per domain (thin, dense).
pub struct ErrorSets {
    /// `(g, [thin, dense])`.
    pub sets: Vec<(f64, Vec<DomainSet>)>,
}

/// Draws `n` points per `(g, domain)` and evaluates the reference at each (in
/// parallel); `progress(done, total)` counts reference evaluations.
pub fn error_sets(n: usize, progress: &(dyn Fn(usize, usize) + Sync)) -> ErrorSets {
    let domains = [Domain::Thin, Domain::Dense];
    let mut pts = Vec::new();
    for (i, &g) in BENCH_GS.iter().enumerate() {
        for (j, d) in domains.iter().enumerate() {
            pts.push(d.validation_set((g, g), n, BENCH_SEED ^ ((i * 2 + j) as u64)));
        }
    }
    let all: Vec<Point> = pts.iter().flatten().copied().collect();
    let values =
        crate::parallel::map(&all, |p| crate::reference::airlight(*p).expect("bench points are valid"), progress);
    let mut it = values.into_iter();
    let mut sets = Vec::new();
    let mut pts = pts.into_iter();
    for &g in &BENCH_GS {
        let mut per = Vec::new();
        for d in domains {
            let p = pts.next().expect("one set per (g, domain)");
            per.push((d, p.into_iter().map(|p| (p, it.next().expect("one value per point"))).collect()));
        }
        sets.push((g, per));
    }
    ErrorSets { sets }
}

/// Errors of `eval` (`A` at a point, ∞ for a kernel's saturated value) at every
/// bench `g` inside `g_range`.
pub fn errors(eval: &dyn Fn(Point) -> f64, g_range: (f64, f64), sets: &ErrorSets) -> Vec<GErrors> {
    let mut out = Vec::new();
    for (g, per) in &sets.sets {
        if *g < g_range.0 || *g > g_range.1 {
            continue;
        }
        let mut stats = [[0.0; 3]; 2];
        for (k, (_, pts)) in per.iter().enumerate() {
            let mut e: Vec<f64> = pts.iter().map(|&(p, exact)| crate::stats::rel_error(eval(p), exact)).collect();
            e.sort_by(f64::total_cmp);
            let rank = |q| crate::stats::nearest_rank(&e, q);
            stats[k] = [rank(1.0), rank(0.99), rank(0.5)];
        }
        let pd = |i: usize| PerDomain { thin: stats[0][i], dense: stats[1][i] };
        out.push(GErrors { g: *g, max_rel: pd(0), p99_rel: pd(1), p50_rel: pd(2) });
    }
    out
}

/// The fixed timing batch: `n` points, half from thin and half from dense, `g`
/// cycling through [`BENCH_GS`] (kernels without `g` ignore it), each coordinate
/// already an f32 value so that the CPU and GPU kernels see the same inputs: the
/// same points for every kernel, **in a seeded random order**. The points are a
/// low-discrepancy sequence, whose order is so regular that a CPU's branch
/// predictor learns a short kernel's branches from it: in that order the closed
/// form without extinction measured 16 ns per call, on independent uniform
/// random points 30 ns (the same loop, one run, this machine), while `phi-iso-4`
/// stayed at 85 ns. Shuffled, the batch costs what random rays cost.
pub fn cost_batch(n: usize) -> Vec<Point> {
    let thin = Domain::Thin.validation_set((-0.95, 0.95), n.div_ceil(2), BENCH_SEED ^ 0xC057);
    let dense = Domain::Dense.validation_set((-0.95, 0.95), n / 2, BENCH_SEED ^ 0xC058);
    let f = |x: f64| f64::from(x as f32);
    let mut out: Vec<Point> = (0..n)
        .map(|i| {
            let p = if i % 2 == 0 { thin[i / 2] } else { dense[i / 2] };
            Point { tau: f(p.tau), gamma: f(p.gamma), rho: f(p.rho), g: f(BENCH_GS[i % BENCH_GS.len()]) }
        })
        .collect();
    // Fisher–Yates with a seeded stream: the same order on every machine.
    let mut rng = crate::domains::SplitMix64(BENCH_SEED ^ 0x5EF1_E000);
    for i in (1..out.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        out.swap(i, j);
    }
    out
}

/// Points as every kernel's canonical entry takes them: `(τ, γ, ρ, g)` in f32,
/// `ρ = ∞` as [`crate::vocab::NO_SURFACE`].
pub fn canonical_args(points: &[Point]) -> Vec<[f32; 4]> {
    points.iter().map(|p| [p.tau as f32, p.gamma as f32, crate::vocab::rho_arg(p.rho), p.g as f32]).collect()
}

/// CPU time of the calling thread, in seconds (wall time where the platform has no thread clock).
pub fn thread_cpu_s() -> f64 {
    #[cfg(unix)]
    {
        let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
        // SAFETY: clock_gettime writes one timespec through a valid pointer.
        if unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0 {
            return t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9;
        }
    }
    use std::sync::OnceLock;
    static START: OnceLock<std::time::Instant> = OnceLock::new();
    START.get_or_init(std::time::Instant::now).elapsed().as_secs_f64()
}

/// What [`time_kernels`] measures of one kernel, ns per evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CpuTimes {
    /// The throughput loop: median of the repeats.
    pub median: f64,
    /// Its fastest and slowest repeat.
    pub range: [f64; 2],
    /// One call at a time: median of the repeats.
    pub one_at_a_time: f64,
}

/// Thread CPU time per evaluation of each kernel over `batch`, in ns, two ways:
/// a **throughput loop** (the batch in and the results out through `black_box`,
/// each call free to overlap the next), and **one call at a time** (every
/// argument and the result through `black_box`, and each call's first argument
/// depending on the last result, `τ + 0·r`, so that no call starts before the
/// last ends and none is specialised to its caller's values, as an independent
/// harness would call it). `repeats` rounds, each timing every kernel both ways
/// in turn (interleaved, so drifts of the machine spread over all);
/// `progress(round)` after each round.
pub fn time_kernels(
    kernels: &[CanonicalFn],
    batch: &[[f32; 4]],
    repeats: usize,
    progress: &dyn Fn(usize),
) -> Vec<CpuTimes> {
    let mut times = vec![Vec::with_capacity(repeats); kernels.len()];
    let mut single = vec![Vec::with_capacity(repeats); kernels.len()];
    let mut out = vec![0.0f32; batch.len()];
    let per = |t: f64| (thread_cpu_s() - t) * 1e9 / batch.len().max(1) as f64;
    for round in 0..repeats {
        for (k, f) in kernels.iter().enumerate() {
            let t = thread_cpu_s();
            for (o, a) in out.iter_mut().zip(black_box(batch)) {
                *o = f(a[0], a[1], a[2], a[3]);
            }
            black_box(&out);
            times[k].push(per(t));
            let t = thread_cpu_s();
            let mut last = 0.0f32;
            for a in black_box(batch) {
                // The kernels' results are finite, so 0·r is 0: the same inputs.
                let tau = black_box(a[0] + 0.0 * last);
                last = black_box(f(tau, black_box(a[1]), black_box(a[2]), black_box(a[3])));
            }
            black_box(last);
            single[k].push(per(t));
        }
        progress(round + 1);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    times
        .into_iter()
        .zip(single)
        .map(|(mut v, mut s)| {
            let m = median(&mut v);
            CpuTimes { median: m, range: [v[0], v[v.len() - 1]], one_at_a_time: median(&mut s) }
        })
        .collect()
}

/// The CPU's model name (`/proc/cpuinfo`), or the architecture.
pub fn cpu_name() -> String {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let name = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    format!("{name} ({cores} cores visible; one thread timed)")
}

impl Bench {
    /// The table `airlight bench` prints: the adapter and CPU, every model's
    /// errors, time, IR cost and GPU rate, and the RGB costs.
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
        lines.join("\n")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bench_runs_on_a_small_batch() {
        let sets = error_sets(50, &|_, _| {});
        let e = errors(&|p| crate::family::CLOSED_FORM.eval(p), (0.0, 0.0), &sets);
        assert_eq!(e.len(), 1);
        assert!(e[0].max_rel.thin.is_finite() && e[0].max_rel.thin > 0.0 && e[0].p50_rel.dense > 0.0);
        fn k(tau: f32, gamma: f32, _rho: f32, _g: f32) -> f32 {
            (-tau).exp() * gamma
        }
        let t = time_kernels(&[k as CanonicalFn], &canonical_args(&cost_batch(1000)), 3, &|_| {});
        assert!(t[0].median.is_finite() && t[0].median > 0.0 && t[0].range[0] <= t[0].median);
        assert!(t[0].median <= t[0].range[1] && t[0].one_at_a_time.is_finite() && t[0].one_at_a_time > 0.0);
    }

    #[test]
    fn the_table_has_a_row_per_model_and_per_rgb_cost() {
        let sets = error_sets(20, &|_, _| {});
        let b = Bench {
            adapter: "none".into(),
            cpu: cpu_name(),
            error_points: 20,
            cost_batch: 1,
            repeats: 1,
            models: vec![BenchModel {
                name: "closed".into(),
                kind: crate::vocab::Role::Baseline,
                g_range: [0.0, 0.0],
                errors: errors(&|p| crate::family::CLOSED_FORM.eval(p), (0.0, 0.0), &sets),
                cpu_ns_per_eval: 12.5,
                cpu_ns_range: [12.0, 13.0],
                cpu_ns_one_at_a_time: 20.0,
                gpu_frame_evals_per_s: 0.0,
                ops: 7,
                transcendentals: 2,
                gpu_evals_per_s: 0.0,
                bytes: 0,
            }],
            rgb: vec![RgbCost {
                name: "closed".into(),
                three_scalar_ns: 30.0,
                rgb_point_ns: 15.0,
                rgb_hard_cone_ns: 20.0,
                rgb_soft_cone_ns: 40.0,
                gpu_three_scalar_rays_per_s: 0.0,
                gpu_rgb_point_rays_per_s: 0.0,
            }],
            shafts: vec![ShaftsCost {
                name: "phi-8".into(),
                samples: 0,
                calls_per_ray: 1.5,
                max_rel: 1e-7,
                mean_rel: 1e-8,
                max_of_unshadowed: 1e-8,
                mean_of_unshadowed: 1e-9,
                cpu_ns_per_ray: 900.0,
                gpu_rays_per_s: 0.0,
                build_cpu_ms: 0.0,
                build_gpu_ms: 0.0,
            }],
        };
        let t = b.table();
        assert!(t.starts_with("adapter: none\ncpu: "), "{t}");
        let closed: Vec<&str> = t.lines().filter(|l| l.starts_with("closed ")).collect();
        assert_eq!(closed.len(), 2, "{t}");
        assert!(closed[0].contains("12.5") && closed[0].ends_with("(g = 0)"), "{t}");
        assert!(closed[1].contains(" 0.50 "), "{t}");
        assert!(t.lines().any(|l| l.starts_with("phi-8") && l.contains("exact")), "{t}");
        assert_eq!(Bench::from_json(&b.to_json()).unwrap(), b);
    }
}

//! The speed/accuracy trade (`airlight bench`, `generated/bench.json`, whose shape
//! is `airlight_shapes::bench`): every
//! shipped model — airlight's and the baselines — measured in one run on the same
//! seeded points: the generated f32 Rust kernel's relative error against the
//! reference per `g` and domain, its CPU cost in thread CPU time, and (from the
//! callers that have them) the operations of its WGSL in naga's IR and its GPU
//! throughput. Timings never enter the tests; the report quotes this file, so
//! regenerating stays byte-identical.

use airlight_shapes::bench::{GErrors, PerDomain};
use airlight_shapes::vocab::CanonicalFn;
use airlight_truth::domains::{Domain, VALIDATION_SEED};
use airlight_truth::reference::Point;
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

/// Rays for the RGB timing: `n` view rays from the origin, lights 1…100 units
/// away in random directions, a cone aimed near the ray (its axis from the light
/// to a point of the ray, 30° outer, 20° inner half-angle), σt = (0.03, 0.05,
/// 0.08), σs = 0.8 σt, g = 0.5; deterministic. Items: (dir, light, axis).
pub fn rgb_rays(n: usize) -> Vec<RgbRay> {
    let mut rng = airlight_truth::domains::SplitMix64(0xB0B5);
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
    let values = airlight_truth::parallel::map(
        &all,
        |p| airlight_truth::reference::airlight(*p).expect("bench points are valid"),
        progress,
    );
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
            let mut e: Vec<f64> =
                pts.iter().map(|&(p, exact)| airlight_truth::stats::rel_error(eval(p), exact)).collect();
            e.sort_by(f64::total_cmp);
            let rank = |q| airlight_truth::stats::nearest_rank(&e, q);
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
    let mut rng = airlight_truth::domains::SplitMix64(BENCH_SEED ^ 0x5EF1_E000);
    for i in (1..out.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        out.swap(i, j);
    }
    out
}

/// Points as every kernel's canonical entry takes them: `(τ, γ, ρ, g)` in f32,
/// `ρ = ∞` as [`airlight_shapes::vocab::NO_SURFACE`].
pub fn canonical_args(points: &[Point]) -> Vec<[f32; 4]> {
    points.iter().map(|p| [p.tau as f32, p.gamma as f32, airlight_shapes::vocab::rho_arg(p.rho), p.g as f32]).collect()
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

#[cfg(test)]
mod tests {
    use super::*;
    use airlight_shapes::bench::{Bench, BenchModel, MapCost, RgbCost, ShaftsCost};

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
                kind: airlight_shapes::vocab::Role::Baseline,
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
            shadow_map: vec![MapCost {
                method: "phi-8, exact walk".into(),
                res: 512,
                samples: 0,
                runs_per_ray: 5.0,
                steps_mean: 107.0,
                steps_max: 239.0,
                truncated: 0,
                max_of_unshadowed: 5.5e-3,
                mean_of_unshadowed: 7.9e-4,
                leaks: 0,
                cpu_ns_per_ray: 6000.0,
                gpu_rays_per_s: 2.2e5,
            }],
            shadow_map_alone: Some("lavapipe".into()),
        };
        let t = b.table();
        let walk: Vec<&str> = t.lines().filter(|l| l.starts_with("phi-8, exact walk")).collect();
        assert_eq!(walk.len(), 1, "{t}");
        assert!(walk[0].contains(" 512 ") && walk[0].contains(" walk ") && walk[0].contains("5.50e-3"), "{t}");
        assert!(t.contains("(measured alone, on lavapipe)"), "{t}");
        assert!(t.starts_with("adapter: none\ncpu: "), "{t}");
        let closed: Vec<&str> = t.lines().filter(|l| l.starts_with("closed ")).collect();
        assert_eq!(closed.len(), 2, "{t}");
        assert!(closed[0].contains("12.5") && closed[0].ends_with("(g = 0)"), "{t}");
        assert!(closed[1].contains(" 0.50 "), "{t}");
        assert!(t.lines().any(|l| l.starts_with("phi-8") && l.contains("exact")), "{t}");
        assert_eq!(Bench::from_json(&b.to_json()).unwrap(), b);
    }
}

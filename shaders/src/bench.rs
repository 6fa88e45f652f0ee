//! What `airlight bench` measures, in one run: for every shipped model, the
//! errors of its compiled f32 Rust kernel at each bench `g`, its CPU time per
//! evaluation (interleaved repeats, median), the operations in the naga IR of its
//! WGSL, its GPU throughput (timestamp queries) where an adapter is present, and
//! for the kernels with a spot entry the cost of one RGB `spot` call against
//! three scalar `radiance` calls, on the CPU and the GPU.

use crate::{Gpu, GpuError, KernelSource, Ray, SpotRay};
use airlight_fit::bench::{self, RgbRay};
use airlight_fit::coeffs::ModelFile;
use airlight_shapes::bench::{Bench, BenchModel, RgbCost, ShaftsCost};
use airlight_shapes::vocab::{CompiledKernel, Index, IndexEntry, Target};
use std::path::Path;

/// How much is measured.
#[derive(Debug, Clone, Copy)]
pub struct BenchSize {
    /// Points per `(g, domain)` for the errors.
    pub points: usize,
    /// Points (and rays) in the timing batch.
    pub batch: usize,
    /// Timing repeats.
    pub repeats: usize,
}

/// Why the bench could not run: bad input (exit 2), or a failure (exit 1).
#[derive(Debug)]
pub enum BenchError {
    /// A size of zero, a missing kernel or file entry.
    Input(String),
    /// A file that cannot be read, a GPU failure.
    Failed(String),
}

/// Where the bench is, for a progress display: what, done, of how many.
pub type Progress<'a> = dyn Fn(&str, usize, usize) + Sync + 'a;

/// σt of the RGB timing's three channels (σs is 0.8 σt).
const ST: [f32; 3] = [0.03, 0.05, 0.08];

/// The adapter the GPU figures come from, lavapipe labelled as CPU emulation.
fn adapter_label(gpu: &Result<Gpu, GpuError>) -> String {
    match gpu {
        Ok(g) => {
            let a = g.adapter();
            let emulated = a.device_type == "Cpu" || a.name.contains("llvmpipe");
            format!("{a}{}", if emulated { " — CPU emulation (lavapipe), not a GPU" } else { "" })
        }
        Err(e) => format!("none ({e})"),
    }
}

/// The RGB timing's rays: the physical entry's (red channel's σt) and the spot
/// entry's with a point light.
fn rgb_inputs(rays: &[RgbRay]) -> (Vec<Ray>, Vec<SpotRay>) {
    let scalar = rays
        .iter()
        .map(|r| Ray {
            origin: [0.0; 3],
            dir: r[0],
            surface: -1.0,
            light: r[1],
            intensity: 100.0,
            sigma_t: ST[0],
            sigma_s: 0.8 * ST[0],
            g: 0.5,
        })
        .collect();
    let spots = rays
        .iter()
        .map(|r| SpotRay {
            origin: [0.0; 3],
            dir: r[0],
            surface: -1.0,
            light: r[1],
            axis: r[2],
            cos_outer: -1.0,
            cos_inner: -1.0,
            intensity: 100.0,
            sigma_t: ST,
            sigma_s: ST.map(|x| 0.8 * x),
            g: 0.5,
        })
        .collect();
    (scalar, spots)
}

/// Everything one model's row needs that the loop shares.
struct Inputs<'a> {
    generated: &'a Path,
    index: &'a Index,
    gpu: Option<&'a Gpu>,
    batch64: Vec<[f64; 4]>,
    /// The frame-coherent points at each `g` a model takes them at ([`frame_g`]),
    /// built once (empty without a GPU).
    frames: Vec<(f64, Vec<[f64; 4]>)>,
    rgb_scalar: Vec<Ray>,
    rgb_spots: Vec<SpotRay>,
    repeats: usize,
}

/// A model's WGSL kernel: its index entry and source.
fn wgsl_of<'i>(inputs: &Inputs<'i>, name: &str) -> Result<(&'i IndexEntry, std::path::PathBuf, String), BenchError> {
    let entry = inputs.index.get(name).map_err(BenchError::Input)?;
    let wgsl =
        entry.file(Target::Wgsl).ok_or_else(|| BenchError::Input(format!("kernel '{name}' has no WGSL file")))?;
    let path = inputs.generated.join(wgsl);
    let source = std::fs::read_to_string(&path)
        .map_err(|e| BenchError::Failed(format!("{}: cannot read: {e}", path.display())))?;
    Ok((entry, path, source))
}

/// The g of the frame-coherent points for a model of g range `range`: 0.5 (the
/// render's) where it takes it, else the range's own.
fn frame_g(range: (f64, f64)) -> f64 {
    if range.0 <= 0.5 && 0.5 <= range.1 {
        0.5
    } else {
        range.0
    }
}

/// The frames of the GPU-path bench's frame-coherent measure: the render's
/// street of five lights (shaders/src/render.rs), three panels of 160 × 120
/// pixels each, once in fog with the ground plane (σt = 0.025, 0.05, 0.1 per
/// metre) and once in haze without it (σt = 0.002, 0.004, 0.008).
pub const FRAMES: [(bool, [f32; 3]); 2] = [(true, [0.025, 0.05, 0.1]), (false, [0.002, 0.004, 0.008])];

/// Frame-coherent canonical points `(τ, γ, ρ, g)`: for each frame of [`FRAMES`]
/// and each light, every pixel's ray in pixel order, as a fragment shader that
/// loops over its lights evaluates them (a wave's lanes on neighbouring pixels).
pub fn frame_points(g: f64) -> Vec<[f64; 4]> {
    let mut out = Vec::new();
    for (ground, sigma_t) in FRAMES {
        let view = crate::render::View {
            panel_width: 160,
            height: 120,
            sigma_t: sigma_t.to_vec(),
            ground,
            g: g as f32,
            scale: 1.0,
        };
        for (light, intensity) in view.lights() {
            for y in 0..view.height {
                for x in 0..view.width() {
                    let (st, dir, surface) = view.ray(x, y);
                    let ray = Ray {
                        origin: [0.0; 3],
                        dir,
                        surface,
                        light,
                        intensity,
                        sigma_t: st,
                        sigma_s: crate::render::ALBEDO * st,
                        g: g as f32,
                    };
                    if let Ok(c) = ray.physical().to_canonical(g) {
                        out.push([c.point.tau, c.point.gamma, c.point.rho, g]);
                    }
                }
            }
        }
    }
    out
}

/// A model's row (CPU time still 0) and its GPU RGB rates (three scalar calls'
/// rays/s over three, the spot entry's), from its kernels.
fn model_row(
    inputs: &Inputs,
    f: &ModelFile,
    k: &CompiledKernel,
    errors: Vec<airlight_shapes::bench::GErrors>,
) -> Result<(BenchModel, (f64, f64)), BenchError> {
    let name = &f.model.name;
    let (entry, path, source) = wgsl_of(inputs, name)?;
    let fail = |e: String| BenchError::Failed(format!("{}: {e}", path.display()));
    let cost = airlight_shapes::ircost::ir_cost(&source, &format!("{}airlight", entry.prefix))
        .map_err(|e| fail(e.to_string()))?;
    let (mut gpu_evals_per_s, mut gpu_frame_evals_per_s, mut gpu_rgb) = (0.0, 0.0, (0.0, 0.0));
    if let Some(g) = inputs.gpu {
        let table = crate::load_table(inputs.generated, entry).map_err(|e| BenchError::Failed(e.to_string()))?;
        let src = KernelSource::of(entry, Target::Wgsl, &source).with_table(table.as_ref());
        let err = |e: GpuError| fail(e.to_string());
        gpu_evals_per_s = g.throughput(&src, &inputs.batch64, inputs.repeats).map_err(err)?.unwrap_or(0.0);
        let fg = frame_g(f.model.g_range);
        let frames = inputs.frames.iter().find(|(g, _)| *g == fg).map_or(&[][..], |(_, p)| p.as_slice());
        gpu_frame_evals_per_s = g.throughput(&src, frames, inputs.repeats).map_err(err)?.unwrap_or(0.0);
        // RGB: the physical entry's rate over three, against the spot entry with a point light.
        if k.spot.is_some() {
            gpu_rgb = (
                g.radiance_throughput(&src, &inputs.rgb_scalar, inputs.repeats).map_err(err)?.unwrap_or(0.0) / 3.0,
                g.spot_throughput(&src, &inputs.rgb_spots, inputs.repeats).map_err(err)?.unwrap_or(0.0),
            );
        }
    }
    let row = BenchModel {
        name: name.clone(),
        kind: f.model.body.role(),
        g_range: [f.model.g_range.0, f.model.g_range.1],
        errors,
        cpu_ns_per_eval: 0.0,
        cpu_ns_range: [0.0, 0.0],
        cpu_ns_one_at_a_time: 0.0,
        gpu_frame_evals_per_s,
        ops: cost.ops,
        transcendentals: cost.transcendentals,
        gpu_evals_per_s,
        bytes: f.model.body.texture().map_or(0, |t| t.bytes()),
    };
    Ok((row, gpu_rgb))
}

/// The CPU cost of one RGB `spot` call (point light, hard and soft cones)
/// against three scalar `radiance` calls on the same rays, with the GPU rates.
fn rgb_cost(k: &CompiledKernel, rays: &[RgbRay], repeats: usize, gpu: (f64, f64)) -> Option<RgbCost> {
    let spot = k.spot?;
    let radiance = k.radiance;
    let three = |r: &RgbRay| -> f32 {
        ST.iter().map(|&st| radiance([0.0; 3], r[0], -1.0, r[1], 100.0, st, 0.8 * st, 0.5)).sum()
    };
    let one = |r: &RgbRay, co: f32, ci: f32| -> f32 {
        spot([0.0; 3], r[0], -1.0, r[1], r[2], co, ci, 100.0, ST, ST.map(|x| 0.8 * x), 0.5).iter().sum()
    };
    let [t3, tp, th, ts] = bench::time_rgb(&three, &one, rays, repeats);
    Some(RgbCost {
        name: k.name.to_string(),
        three_scalar_ns: t3,
        rgb_point_ns: tp,
        rgb_hard_cone_ns: th,
        rgb_soft_cone_ns: ts,
        gpu_three_scalar_rays_per_s: gpu.0,
        gpu_rgb_point_rays_per_s: gpu.1,
    })
}

/// Errors of `values` (one per case) against the shadowed reference: max and mean
/// relative to it (rays with some light), then max and mean relative to the ray's
/// unshadowed value.
fn shafts_errors(cases: &[crate::shafts::cases::ShadowCase], values: &[f64]) -> [f64; 4] {
    let (mut rel, mut of_u) = (Vec::new(), Vec::new());
    for (c, &v) in cases.iter().zip(values) {
        if c.reference > 0.0 && c.reference.is_finite() {
            rel.push((v - c.reference).abs() / c.reference);
        }
        if c.unshadowed > 0.0 && c.unshadowed.is_finite() {
            of_u.push((v - c.reference).abs() / c.unshadowed);
        }
    }
    let max = |e: &[f64]| e.iter().copied().fold(0.0, f64::max);
    let mean = |e: &[f64]| e.iter().sum::<f64>() / e.len().max(1) as f64;
    [max(&rel), mean(&rel), max(&of_u), mean(&of_u)]
}

/// Thread-CPU ns per item of `f(0) … f(n − 1)`: the median of `repeats` passes.
fn median_ns(repeats: usize, n: usize, f: &dyn Fn(usize) -> f64) -> f64 {
    let mut times: Vec<f64> = (0..repeats.max(1))
        .map(|_| {
            let start = bench::thread_cpu_s();
            let mut acc = 0.0;
            for i in 0..n {
                acc += f(std::hint::black_box(i));
            }
            std::hint::black_box(acc);
            (bench::thread_cpu_s() - start) * 1e9 / n.max(1) as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// The seed's table for the frame of `r` (its viewer and light), filled by the f32
/// kernel's `radiance` over `x ∈ [0, x_max]`.
fn fprime_table(
    radiance: airlight_shapes::vocab::RadianceFn,
    r: &Ray,
    x_max: f64,
) -> airlight_truth::shafts::FPrimeTable {
    let fill = |d: [f64; 3], x: f64| {
        f64::from(radiance(r.origin, d.map(|v| v as f32), x as f32, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g))
    };
    let phys = r.physical();
    airlight_truth::shafts::FPrimeTable::build(
        airlight_truth::shafts::FPRIME_RES,
        phys.origin,
        phys.light,
        x_max,
        &fill,
    )
}

/// Sample counts of the shafts bench.
pub const SHAFTS_SAMPLES: [usize; 4] = [8, 16, 32, 64];

/// The suffix of the shafts bench's row that feeds an accumulator the look-ups
/// alone, without the viewer's and the surface's visibility.
pub const LOOK_UPS_ONLY: &str = ", look-ups only";

/// The accumulator kernels the shafts bench follows.
pub const SHAFTS_KERNELS: [&str; 2] = ["phi-6", "phi-8"];

/// Light shafts on the gate's shadowed rays of `phi-8` (point lights among balls
/// and boxes): each followed model's accumulator on the exact lit intervals and on
/// `N` shadow-map samples, and `raymarch-N` on the same samples, with errors
/// against the shadowed reference, CPU ns per ray (median of interleaved repeats)
/// and GPU rays per second.
fn shafts_costs(
    inputs: &Inputs,
    kernels: &[CompiledKernel],
    progress: &Progress,
) -> Result<Vec<ShaftsCost>, BenchError> {
    use airlight_truth::shafts::{self, Feed};
    let entry = inputs.index.get("phi-8").map_err(BenchError::Input)?;
    let cases = crate::shafts::cases::shadowed_rays(entry, crate::shafts::cases::SHADOWED_RAYS, 0x5AF7_BE7C)
        .map_err(|e| BenchError::Failed(e.to_string()))?;
    let rays: Vec<crate::Ray> = cases.iter().map(|c| c.ray).collect();
    let mut jobs: Vec<(String, usize)> = Vec::new();
    for n in std::iter::once(0).chain(SHAFTS_SAMPLES) {
        for name in SHAFTS_KERNELS {
            jobs.push((name.to_string(), n));
        }
        if n > 0 {
            jobs.push((format!("{}{LOOK_UPS_ONLY}", SHAFTS_KERNELS[1]), n));
            jobs.push((format!("raymarch-{n}"), n));
        }
    }
    let mut out = Vec::new();
    for (j, (name, n)) in jobs.iter().enumerate() {
        progress(&format!("bench: shafts, {name} at {n} samples"), j, jobs.len());
        let (kernel, look_ups_only) = match name.strip_suffix(LOOK_UPS_ONLY) {
            Some(k) => (k, true),
            None => (name.as_str(), name.starts_with("raymarch")),
        };
        let k = kernels.iter().find(|k| k.name == kernel).ok_or_else(|| {
            BenchError::Failed(format!("bench: no compiled kernel '{kernel}': run `airlight generate` and rebuild"))
        })?;
        let f = k.shadowed.ok_or_else(|| BenchError::Failed(format!("bench: {kernel} has no shafts accumulator")))?;
        let feed = match (*n, look_ups_only) {
            (0, _) => Feed::Exact,
            (n, true) => Feed::LookUps(n),
            (n, false) => Feed::Samples(n),
        };
        let samples: Vec<Vec<[f32; 2]>> = cases
            .iter()
            .map(|c| {
                let s = shafts::feed(&c.ray.physical(), &c.occluders, f64::from(c.ray.g), feed).unwrap_or_default();
                s.iter().map(|&(a, b)| [a as f32, b as f32]).collect()
            })
            .collect();
        let call = |i: usize| {
            let r = &rays[i];
            f(&samples[i], r.surface, r.origin, r.dir, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g)
        };
        let values: Vec<f64> = (0..cases.len()).map(|i| crate::from_kernel(call(i))).collect();
        let errors = shafts_errors(&cases, &values);
        // Lit runs for the accumulator, lit samples for the march.
        let calls: f64 = samples
            .iter()
            .map(|s| {
                if name.starts_with("raymarch") {
                    s.iter().filter(|x| x[1] > 0.0).count() as f64
                } else {
                    1.0 + s.windows(2).filter(|w| w[0][1] != w[1][1] && w[1][1] > 0.0).count() as f64
                }
            })
            .sum();
        let cpu_ns_per_ray = median_ns(inputs.repeats, rays.len(), &|i| f64::from(call(i)));
        let gpu_rays_per_s = match (inputs.gpu, wgsl_of(inputs, kernel)) {
            (Some(gpu), Ok((e, _, text))) => {
                let table = crate::load_table(inputs.generated, e).map_err(|e| BenchError::Failed(e.to_string()))?;
                let src = KernelSource::of(e, Target::Wgsl, &text).with_table(table.as_ref());
                gpu.shadowed_throughput(&src, &rays, &samples, inputs.repeats)
                    .map_err(|e| BenchError::Failed(format!("{name}: {e}")))?
                    .unwrap_or(0.0)
            }
            _ => 0.0,
        };
        out.push(ShaftsCost {
            name: name.clone(),
            samples: *n,
            calls_per_ray: calls / cases.len() as f64,
            max_rel: errors[0],
            mean_rel: errors[1],
            max_of_unshadowed: errors[2],
            mean_of_unshadowed: errors[3],
            cpu_ns_per_ray,
            gpu_rays_per_s,
            build_cpu_ms: 0.0,
            build_gpu_ms: 0.0,
        });
    }
    out.extend(fprime_costs(inputs, kernels, &cases, progress)?);
    Ok(out)
}

/// The seed's method on the same rays and samples: per ray (each has its own
/// viewer and light, so its own frame) a [`FPRIME_RES`]² table `F'(cos γ, x)` filled
/// by [`FPRIME_KERNEL`]'s f32 `radiance`, read at each step. Errors against the
/// shadowed reference; CPU ns per ray of the reads and differences alone; the
/// build per frame on the CPU (median of the repeats over a few rays) and as one
/// GPU pass of `radiance` over the texels (timestamp queries).
fn fprime_costs(
    inputs: &Inputs,
    kernels: &[CompiledKernel],
    cases: &[crate::shafts::cases::ShadowCase],
    progress: &Progress,
) -> Result<Vec<ShaftsCost>, BenchError> {
    use airlight_truth::shafts::{self, FPrimeTable, Feed, FPRIME_KERNEL, FPRIME_RES};
    let k = kernels.iter().find(|k| k.name == FPRIME_KERNEL).ok_or_else(|| {
        BenchError::Failed(format!("bench: no compiled kernel '{FPRIME_KERNEL}': run `airlight generate` and rebuild"))
    })?;
    let radiance = k.radiance;
    let tables: Vec<FPrimeTable> = cases
        .iter()
        .enumerate()
        .map(|(i, c)| {
            progress("bench: shafts, the seed's F' tables", i, cases.len());
            let x_max = shafts::march_length(&c.ray.physical(), f64::from(c.ray.g)).unwrap_or(1.0);
            fprime_table(radiance, &c.ray, x_max)
        })
        .collect();
    // The build per frame, CPU: the median over a few rays' tables.
    let mut builds: Vec<f64> = cases
        .iter()
        .take(inputs.repeats.max(3))
        .map(|c| {
            let start = bench::thread_cpu_s();
            std::hint::black_box(fprime_table(radiance, &c.ray, 10.0));
            (bench::thread_cpu_s() - start) * 1e3
        })
        .collect();
    builds.sort_by(f64::total_cmp);
    let build_cpu_ms = builds[builds.len() / 2];
    // The build per frame, GPU: one pass of `radiance` over the texels.
    let build_gpu_ms = match (inputs.gpu, wgsl_of(inputs, FPRIME_KERNEL)) {
        (Some(gpu), Ok((e, _, text))) => {
            let r = cases[0].ray;
            let texels: Vec<crate::Ray> = (0..FPRIME_RES * FPRIME_RES)
                .map(|t| {
                    let c = -1.0 + 2.0 * (t % FPRIME_RES) as f32 / (FPRIME_RES - 1) as f32;
                    let x = 10.0 * (t / FPRIME_RES) as f32 / (FPRIME_RES - 1) as f32;
                    crate::Ray { dir: [c, (1.0 - c * c).max(0.0).sqrt(), 0.0], surface: x, ..r }
                })
                .collect();
            let src = KernelSource::of(e, Target::Wgsl, &text);
            gpu.radiance_throughput(&src, &texels, inputs.repeats)
                .map_err(|e| BenchError::Failed(format!("{FPRIME_KERNEL}: {e}")))?
                .map_or(0.0, |rate| texels.len() as f64 / rate * 1e3)
        }
        _ => 0.0,
    };
    let mut out = Vec::new();
    for n in SHAFTS_SAMPLES {
        progress(&format!("bench: shafts, the seed's table at {n} samples"), n, 64);
        let samples: Vec<Vec<(f64, f64)>> = cases
            .iter()
            .map(|c| {
                shafts::feed(&c.ray.physical(), &c.occluders, f64::from(c.ray.g), Feed::LookUps(n)).unwrap_or_default()
            })
            .collect();
        let physical: Vec<_> = cases.iter().map(|c| c.ray.physical()).collect();
        let read = |i: usize| tables[i].shadowed(&physical[i], &samples[i]);
        let values: Vec<f64> = (0..cases.len()).map(read).collect();
        let errors = shafts_errors(cases, &values);
        let lookups: f64 = samples.iter().map(|s| 2.0 * s.iter().filter(|x| x.1 > 0.0).count() as f64).sum();
        let cpu_ns_per_ray = median_ns(inputs.repeats, cases.len(), &read);
        out.push(ShaftsCost {
            name: format!("F' {FPRIME_RES}² ({FPRIME_KERNEL})"),
            samples: n,
            calls_per_ray: lookups / cases.len() as f64,
            max_rel: errors[0],
            mean_rel: errors[1],
            max_of_unshadowed: errors[2],
            mean_of_unshadowed: errors[3],
            cpu_ns_per_ray,
            gpu_rays_per_s: 0.0,
            build_cpu_ms,
            build_gpu_ms,
        });
    }
    Ok(out)
}

/// Measures every model in `files` with its compiled kernel from `kernels` and
/// the generated files under `generated` (the GPU figures where an adapter opens).
pub fn measure(
    generated: &Path,
    files: &[ModelFile],
    kernels: &[CompiledKernel],
    size: BenchSize,
    progress: &Progress,
) -> Result<Bench, BenchError> {
    if size.points == 0 || size.batch == 0 || size.repeats == 0 {
        return Err(BenchError::Input("bench: --points, --batch and --repeats must be at least 1".into()));
    }
    let index = crate::gate::load_index(generated).map_err(|e| BenchError::Input(e.to_string()))?;
    let sets = bench::error_sets(size.points, &|done, total| progress("bench: reference values", done, total));
    let points = bench::cost_batch(size.batch);
    let gpu = Gpu::open();
    let rgb_rays = bench::rgb_rays(size.batch);
    let (rgb_scalar, rgb_spots) = rgb_inputs(&rgb_rays);
    let mut frame_gs: Vec<f64> = Vec::new();
    for f in files {
        let g = frame_g(f.model.g_range);
        if gpu.is_ok() && !frame_gs.contains(&g) {
            frame_gs.push(g);
        }
    }
    let inputs = Inputs {
        generated,
        index: &index,
        gpu: gpu.as_ref().ok(),
        batch64: points.iter().map(|p| [p.tau, p.gamma, p.rho, p.g]).collect(),
        frames: frame_gs.into_iter().map(|g| (g, frame_points(g))).collect(),
        rgb_scalar,
        rgb_spots,
        repeats: size.repeats,
    };
    let (mut rows, mut compiled, mut gpu_rgb) = (Vec::new(), Vec::new(), Vec::new());
    for (i, f) in files.iter().enumerate() {
        let name = &f.model.name;
        let k = kernels.iter().find(|k| k.name == name.as_str()).ok_or_else(|| {
            BenchError::Failed(format!("bench: no compiled kernel '{name}': run `airlight generate` and rebuild"))
        })?;
        progress(&format!("bench: {name}"), i, files.len());
        let errors = bench::errors(&|p| crate::f32_value(k, p), f.model.g_range, &sets);
        let (row, rates) = model_row(&inputs, f, k, errors)?;
        rows.push(row);
        gpu_rgb.push(rates);
        compiled.push(k);
    }
    let batch = bench::canonical_args(&points);
    let fns: Vec<_> = compiled.iter().map(|k| k.airlight).collect();
    let times = bench::time_kernels(&fns, &batch, size.repeats, &|r| {
        progress("bench: CPU time (interleaved repeats)", r, size.repeats)
    });
    for (row, t) in rows.iter_mut().zip(times) {
        row.cpu_ns_per_eval = t.median;
        row.cpu_ns_range = t.range;
        row.cpu_ns_one_at_a_time = t.one_at_a_time;
    }
    progress("bench: RGB against three scalar calls", 0, 1);
    let rgb = compiled.iter().zip(&gpu_rgb).filter_map(|(k, &g)| rgb_cost(k, &rgb_rays, size.repeats, g)).collect();
    let shafts = shafts_costs(&inputs, kernels, progress)?;
    Ok(Bench {
        adapter: adapter_label(&gpu),
        cpu: bench::cpu_name(),
        error_points: size.points,
        cost_batch: size.batch,
        repeats: size.repeats,
        models: rows,
        rgb,
        shafts,
    })
}

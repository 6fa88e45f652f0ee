//! The shafts bench (`bench.json`'s `shafts`): each accumulator against the
//! engines' march on the same shadow-map samples, per sample count, with the
//! per-frame table `F'` built on the CPU and the GPU.

use crate::bench::inputs::{wgsl_of, BenchError, Inputs, Progress};
use crate::{KernelSource, Ray};
use airlight_fit::bench::{self};
use airlight_shapes::bench::ShaftsCost;
use airlight_shapes::vocab::{CompiledKernel, Target};

/// Errors of `values` (one per case) against the shadowed reference: max and mean
/// relative to it (rays with some light), then max and mean relative to the ray's
/// unshadowed value.
pub(crate) fn shafts_errors(cases: &[crate::shafts::cases::ShadowCase], values: &[f64]) -> [f64; 4] {
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
pub(crate) fn median_ns(repeats: usize, n: usize, f: &dyn Fn(usize) -> f64) -> f64 {
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
pub(crate) fn fprime_table(
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

/// Light shafts on the gate's shadowed rays of the headline accumulator (point
/// lights among balls and boxes): each accumulator `fit/src/roles.toml` names
/// (`[shafts] kernels`) on the exact lit intervals and on `N` shadow-map samples,
/// and the march at `N` steps on the same samples, with errors
/// against the shadowed reference, CPU ns per ray (median of interleaved repeats)
/// and GPU rays per second.
pub(crate) fn shafts_costs(
    inputs: &Inputs,
    kernels: &[CompiledKernel],
    progress: &Progress,
) -> Result<Vec<ShaftsCost>, BenchError> {
    use airlight_truth::shafts::{self, Feed};
    let roles = airlight_fit::roles::roles();
    let entry = inputs.index.get(&roles.shafts.headline).map_err(BenchError::Input)?;
    let cases = crate::shafts::cases::shadowed_rays(entry, crate::shafts::cases::SHADOWED_RAYS, 0x5AF7_BE7C)
        .map_err(|e| BenchError::Failed(e.to_string()))?;
    let rays: Vec<crate::Ray> = cases.iter().map(|c| c.ray).collect();
    let mut jobs: Vec<(String, usize)> = Vec::new();
    for n in std::iter::once(0).chain(SHAFTS_SAMPLES) {
        for name in &roles.shafts.kernels {
            jobs.push((name.clone(), n));
        }
        if n > 0 {
            jobs.push((format!("{}{LOOK_UPS_ONLY}", roles.shafts.headline), n));
            jobs.push((roles.march(n), n));
        }
    }
    let mut out = Vec::new();
    for (j, (name, n)) in jobs.iter().enumerate() {
        progress(&format!("bench: shafts, {name} at {n} samples"), j, jobs.len());
        let (kernel, look_ups_only) = match name.strip_suffix(LOOK_UPS_ONLY) {
            Some(k) => (k, true),
            None => (name.as_str(), roles.is_march(name)),
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
                if roles.is_march(name) {
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
pub(crate) fn fprime_costs(
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

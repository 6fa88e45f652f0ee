//! The shadow-map bench (`bench.json`'s `shadow_map`): a street lamp behind an
//! iron railing (thin bars, a rail, a bench, a ball), 256 view rays from a camera
//! at eye height, the headline kernel's accumulator fed the exact walk through the
//! lamp's cube map at 512 … 4096 texels per side, against the march and the
//! sampled accumulator (look-ups of the analytic occluders: a map of infinite
//! resolution, the most they could be given), all against the analytic reference.

use crate::bench::inputs::{wgsl_of, BenchError, Inputs, Progress};
use crate::shafts::bench::median_ns;
use crate::shafts::map_cases::{run_samples, rust_runs, upload};
use crate::{KernelSource, Ray};
use airlight_shapes::bench::MapCost;
use airlight_shapes::vocab::{CompiledKernel, Target};
use airlight_truth::reference::{self, Point};
use airlight_truth::shafts::{self, Feed, Occluder, ShadowMap};

/// Map resolutions of the bench.
pub const MAP_RES: [usize; 4] = [512, 1024, 2048, 4096];

/// Look-ups (steps) of the sampled methods beside it.
pub const MAP_SAMPLES: [usize; 2] = [64, 256];

/// The lamp.
pub const LAMP: [f64; 3] = [0.0, 3.0, 0.0];

/// The street lamp's occluders: 27 bars 3 cm wide every 15 cm, a rail, a bench
/// and a ball.
pub fn lamp_scene() -> Vec<Occluder> {
    let mut occ: Vec<Occluder> = (0..27)
        .map(|i| {
            let x = -2.0 + 0.15 * f64::from(i);
            Occluder::Cuboid { min: [x, 0.0, 1.0], max: [x + 0.03, 2.2, 1.03] }
        })
        .collect();
    occ.push(Occluder::Cuboid { min: [-2.05, 2.2, 0.98], max: [2.05, 2.26, 1.05] });
    occ.push(Occluder::Cuboid { min: [-1.8, 0.42, 2.2], max: [-0.4, 0.5, 2.7] });
    occ.push(Occluder::Sphere { center: [1.1, 0.45, 2.4], radius: 0.45 });
    occ
}

/// 256 rays from a camera at (0, 1.6, 9) over a 16 × 16 grid of directions
/// towards the railing, ending on the floor (y = 0) where they meet it, open
/// otherwise; fog σt = 0.08, σs = 0.06, g = 0.6, the lamp 60 units.
pub fn lamp_rays() -> Vec<Ray> {
    let eye = [0.0f32, 1.6, 9.0];
    let mut out = Vec::with_capacity(256);
    for j in 0..16 {
        for i in 0..16 {
            let dx = -0.45 + 0.9 * (i as f32 + 0.5) / 16.0;
            let dy = -0.3 + 0.45 * (j as f32 + 0.5) / 16.0;
            let dir = [dx, dy, -1.0];
            let surface = if dy < 0.0 { eye[1] / -dy * (dx * dx + dy * dy + 1.0).sqrt() } else { -1.0 };
            out.push(Ray {
                origin: eye,
                dir,
                surface,
                light: LAMP.map(|x| x as f32),
                intensity: 60.0,
                sigma_t: 0.08,
                sigma_s: 0.06,
                g: 0.6,
            });
        }
    }
    out
}

/// Errors of `values` against the reference `want`, relative to `unshadowed`:
/// max, mean, leaks.
fn errors(values: &[f64], want: &[f64], unshadowed: &[f64]) -> (f64, f64, usize) {
    let e: Vec<f64> = values.iter().zip(want).zip(unshadowed).map(|((v, w), u)| (v - w).abs() / u).collect();
    let leaks = values.iter().zip(want).zip(unshadowed).filter(|((v, w), u)| **v > 1.5 * **w + 0.05 * **u).count();
    (e.iter().copied().fold(0.0, f64::max), e.iter().sum::<f64>() / e.len().max(1) as f64, leaks)
}

/// The bench's rows (see the module's header).
pub(crate) fn map_costs(
    inputs: &Inputs,
    kernels: &[CompiledKernel],
    progress: &Progress,
) -> Result<Vec<MapCost>, BenchError> {
    let roles = airlight_fit::roles::roles();
    let name = &roles.shafts.headline;
    let k = kernels.iter().find(|k| k.name == *name).ok_or_else(|| {
        BenchError::Failed(format!("bench: no compiled kernel '{name}': run `airlight generate` and rebuild"))
    })?;
    let (f, walk) = match (k.shadowed, k.walk) {
        (Some(f), Some(w)) => (f, w),
        _ => return Err(BenchError::Failed(format!("bench: {name} has no shafts accumulator or walk"))),
    };
    let occ = lamp_scene();
    let rays = lamp_rays();
    progress("bench: shadow map, the analytic reference", 0, 1);
    let a = |q: Point| reference::airlight(q).unwrap_or(f64::NAN);
    let refs: Vec<(f64, f64)> = airlight_truth::parallel::map(
        &rays,
        |r| {
            let phys = r.physical();
            let lit = shafts::lit_intervals(&phys, &occ);
            let g = f64::from(r.g);
            let want = shafts::shadowed_radiance(&phys, None, g, &lit, &a).unwrap_or(f64::NAN);
            (want, phys.radiance(g, &a).unwrap_or(f64::NAN))
        },
        &|_, _| {},
    );
    let (want, unshadowed): (Vec<f64>, Vec<f64>) = refs.into_iter().unzip();
    let gpu_src = match (inputs.gpu, wgsl_of(inputs, name)) {
        (Some(_), Ok((e, _, text))) => Some((e, text)),
        _ => None,
    };
    let walk_texts = crate::shafts::WalkTexts::load(inputs.generated).map_err(|e| BenchError::Failed(e.to_string()))?;
    let mut out = Vec::new();
    for (j, &res) in MAP_RES.iter().enumerate() {
        progress(&format!("bench: shadow map {res}², the walk"), j, MAP_RES.len());
        let map = ShadowMap::cube(LAMP, res, &occ, 0.0).map_err(|e| BenchError::Failed(e.to_string()))?;
        let pyramid = map.pyramid();
        let walked: Vec<(Vec<[f32; 2]>, u32, bool)> = rays.iter().map(|r| rust_runs(walk, &map, &pyramid, r)).collect();
        let call = |i: usize| {
            let r = &rays[i];
            let (runs, _, _) = rust_runs(walk, &map, &pyramid, r);
            let s = run_samples(&runs);
            f(&s, r.surface, r.origin, r.dir, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g)
        };
        // The values from the walks already taken; `call` (walk and accumulator) is what is timed.
        let values: Vec<f64> = rays
            .iter()
            .zip(&walked)
            .map(|(r, (runs, _, _))| {
                let s = run_samples(runs);
                crate::from_kernel(f(&s, r.surface, r.origin, r.dir, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g))
            })
            .collect();
        let (max, mean, leaks) = errors(&values, &want, &unshadowed);
        let cpu_ns_per_ray = median_ns(inputs.repeats, rays.len(), &|i| f64::from(call(i)));
        let gpu_rays_per_s = match (inputs.gpu, &gpu_src) {
            (Some(gpu), Some((e, text))) => {
                let src = KernelSource::of(e, Target::Wgsl, text);
                let fail = |e: crate::GpuError| BenchError::Failed(format!("{name} walk {res}: {e}"));
                let (p, specs) = upload(gpu, walk_texts.sources().pyramid, &[&map]).map_err(fail)?;
                let specs = vec![specs[0]; rays.len()];
                gpu.mapped_throughput(&src, &walk_texts.sources(), &rays, &specs, &p, inputs.repeats)
                    .map_err(fail)?
                    .unwrap_or(0.0)
            }
            _ => 0.0,
        };
        let n = rays.len() as f64;
        out.push(MapCost {
            method: format!("{name}, exact walk"),
            res,
            samples: 0,
            runs_per_ray: walked.iter().map(|w| w.0.len() as f64).sum::<f64>() / n,
            steps_mean: walked.iter().map(|w| f64::from(w.1)).sum::<f64>() / n,
            steps_max: walked.iter().map(|w| f64::from(w.1)).fold(0.0, f64::max),
            truncated: walked.iter().filter(|w| w.2).count(),
            max_of_unshadowed: max,
            mean_of_unshadowed: mean,
            leaks,
            cpu_ns_per_ray,
            gpu_rays_per_s,
        });
    }
    out.extend(sampled_costs(inputs, kernels, &occ, &rays, &want, &unshadowed, progress)?);
    Ok(out)
}

/// The march and the sampled accumulator on the same rays, their look-ups of
/// the analytic occluders.
#[allow(clippy::too_many_arguments)]
fn sampled_costs(
    inputs: &Inputs,
    kernels: &[CompiledKernel],
    occ: &[Occluder],
    rays: &[Ray],
    want: &[f64],
    unshadowed: &[f64],
    progress: &Progress,
) -> Result<Vec<MapCost>, BenchError> {
    let roles = airlight_fit::roles::roles();
    let mut out = Vec::new();
    for (j, &n) in MAP_SAMPLES.iter().enumerate() {
        for (name, feed) in [(roles.shafts.headline.clone(), Feed::Samples(n)), (roles.march(n), Feed::LookUps(n))] {
            progress(&format!("bench: shadow map, {name} at {n}"), j, MAP_SAMPLES.len());
            let k = kernels.iter().find(|k| k.name == name).ok_or_else(|| {
                BenchError::Failed(format!("bench: no compiled kernel '{name}': run `airlight generate` and rebuild"))
            })?;
            let f = k.shadowed.ok_or_else(|| BenchError::Failed(format!("bench: {name} has no shafts functions")))?;
            let samples: Vec<Vec<[f32; 2]>> = rays
                .iter()
                .map(|r| {
                    let s = shafts::feed(&r.physical(), occ, f64::from(r.g), feed).unwrap_or_default();
                    s.iter().map(|&(a, b)| [a as f32, b as f32]).collect()
                })
                .collect();
            let call = |i: usize| {
                let r = &rays[i];
                f(&samples[i], r.surface, r.origin, r.dir, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g)
            };
            let values: Vec<f64> = (0..rays.len()).map(|i| crate::from_kernel(call(i))).collect();
            let (max, mean, leaks) = errors(&values, want, unshadowed);
            let gpu_rays_per_s = match (inputs.gpu, wgsl_of(inputs, &name)) {
                (Some(gpu), Ok((e, _, text))) => {
                    let table =
                        crate::load_table(inputs.generated, e).map_err(|e| BenchError::Failed(e.to_string()))?;
                    let src = KernelSource::of(e, Target::Wgsl, &text).with_table(table.as_ref());
                    gpu.shadowed_throughput(&src, rays, &samples, inputs.repeats)
                        .map_err(|e| BenchError::Failed(format!("{name}: {e}")))?
                        .unwrap_or(0.0)
                }
                _ => 0.0,
            };
            let lit_runs = samples
                .iter()
                .map(|s| 1.0 + s.windows(2).filter(|w| w[0][1] != w[1][1] && w[1][1] > 0.0).count() as f64)
                .sum::<f64>();
            out.push(MapCost {
                method: if roles.is_march(&name) { name.clone() } else { format!("{name}, {n} look-ups") },
                res: 0,
                samples: n,
                runs_per_ray: lit_runs / rays.len() as f64,
                steps_mean: 0.0,
                steps_max: 0.0,
                truncated: 0,
                max_of_unshadowed: max,
                mean_of_unshadowed: mean,
                leaks,
                cpu_ns_per_ray: median_ns(inputs.repeats, rays.len(), &|i| f64::from(call(i))),
                gpu_rays_per_s,
            });
        }
    }
    Ok(out)
}

//! What `airlight bench` measures, in one run: for every shipped model, the
//! errors of its compiled f32 Rust kernel at each bench `g`, its CPU time per
//! evaluation (interleaved repeats, median), the operations in the naga IR of its
//! WGSL, its GPU throughput (timestamp queries) where an adapter is present, and
//! for the kernels with a spot entry the cost of one RGB `spot` call against
//! three scalar `radiance` calls, on the CPU and the GPU.

pub(crate) mod inputs;

use inputs::{wgsl_of, Inputs};
pub use inputs::{BenchError, BenchSize, Progress};

use crate::shafts::bench::shafts_costs;
use crate::{Gpu, GpuError, KernelSource, Ray, SpotRay};
use airlight_fit::bench::{self, RgbRay};
use airlight_fit::coeffs::ModelFile;
use airlight_shapes::bench::{Bench, BenchModel, RgbCost};
use airlight_shapes::vocab::{CompiledKernel, Target};
use std::path::Path;

/// σt of the RGB timing's three channels (σs is 0.8 σt).
pub(crate) const ST: [f32; 3] = [0.03, 0.05, 0.08];

/// The adapter the GPU figures come from, lavapipe labelled as CPU emulation.
pub(crate) fn adapter_label(gpu: &Result<Gpu, GpuError>) -> String {
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
pub(crate) fn rgb_inputs(rays: &[RgbRay]) -> (Vec<Ray>, Vec<SpotRay>) {
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

/// The g of the frame-coherent points for a model of g range `range`: 0.5 (the
/// render's) where it takes it, else the range's own.
pub(crate) fn frame_g(range: (f64, f64)) -> f64 {
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
pub(crate) fn model_row(
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
pub(crate) fn rgb_cost(k: &CompiledKernel, rays: &[RgbRay], repeats: usize, gpu: (f64, f64)) -> Option<RgbCost> {
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

/// Measures the shadow-map section alone (`bench.json`'s `shadow_map`, from
/// [`crate::shafts::map_bench`]), for `airlight bench --only shadow-map`: its
/// rows compare with each other (one run), and the models' rows, which the
/// planner ranks by, are left as they were measured. Returns the adapter's label
/// and the rows.
pub fn measure_shadow_map(
    generated: &Path,
    kernels: &[CompiledKernel],
    repeats: usize,
    progress: &Progress,
) -> Result<(String, Vec<airlight_shapes::bench::MapCost>), BenchError> {
    if repeats == 0 {
        return Err(BenchError::Input("bench: --repeats must be at least 1".into()));
    }
    let index = crate::gate::load_index(generated).map_err(|e| BenchError::Input(e.to_string()))?;
    let gpu = Gpu::open();
    let inputs = Inputs {
        generated,
        index: &index,
        gpu: gpu.as_ref().ok(),
        batch64: Vec::new(),
        frames: Vec::new(),
        rgb_scalar: Vec::new(),
        rgb_spots: Vec::new(),
        repeats,
    };
    let rows = crate::shafts::map_bench::map_costs(&inputs, kernels, progress)?;
    Ok((adapter_label(&gpu), rows))
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
    let shadow_map = crate::shafts::map_bench::map_costs(&inputs, kernels, progress)?;
    Ok(Bench {
        adapter: adapter_label(&gpu),
        cpu: bench::cpu_name(),
        error_points: size.points,
        cost_batch: size.batch,
        repeats: size.repeats,
        models: rows,
        rgb,
        shafts,
        shadow_map,
        shadow_map_alone: None,
    })
}

//! The consumer: a headless full-screen fragment pass that includes a generated
//! WGSL kernel the way a renderer would, drawing point lights in fog (the
//! paper's Figs. 12–14: the glow grows with σt and shrinks with distance), and
//! the same image from the Rust kernel on the CPU and from the reference, with a
//! relative-difference image.
//!
//! The image is three panels side by side, one per extinction coefficient
//! (a quarter, half and all of the scene's largest σt); each shows the same
//! street of lights at increasing distances. Scenes with surfaces get a ground
//! plane, which ends the rays that hit it.

use crate::{Gpu, GpuError};
use airlight_shapes::vocab::{Arg, CompiledKernel, IndexEntry};
use airlight_truth::reference;

/// Lights: position and radiant intensity.
pub const LIGHTS: [([f32; 3], f32); 5] = [
    ([-3.0, 1.0, 6.0], 40.0),
    ([3.0, 1.0, 12.0], 40.0),
    ([-3.0, 1.0, 24.0], 40.0),
    ([3.0, 1.0, 48.0], 40.0),
    ([0.0, 4.0, 90.0], 200.0),
];
/// Height of the ground plane (scenes with surfaces).
pub const GROUND_Y: f32 = -1.6;
/// Vertical field of view, radians.
pub const FOV_Y: f32 = 0.9;
/// σs / σt of the medium.
pub const ALBEDO: f32 = 0.8;

/// The size of a light-shafts frame, pixels (width, height).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShaftsSize(pub u32, pub u32);

/// What is drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// Width of one panel in pixels.
    pub panel_width: u32,
    /// Height in pixels.
    pub height: u32,
    /// σt of each panel.
    pub sigma_t: Vec<f32>,
    /// Whether the ground plane ends rays.
    pub ground: bool,
    /// The phase function's g.
    pub g: f32,
    /// Scale from world units to the scene's: lights at up to `max_distance`.
    pub scale: f32,
}

impl View {
    /// The view for a kernel of a scene with largest σt `sigma_max` and lights
    /// up to `max_distance` away.
    pub fn for_scene(k: &IndexEntry, sigma_max: f64, max_distance: f64, panel_width: u32, height: u32) -> View {
        let far = LIGHTS.iter().map(|l| (l.0[0].powi(2) + l.0[1].powi(2) + l.0[2].powi(2)).sqrt()).fold(0.0, f32::max);
        let scale = (max_distance as f32 / far).min(1.0);
        View {
            panel_width,
            height,
            sigma_t: [0.25f32, 0.5, 1.0].iter().map(|f| f * sigma_max as f32).collect(),
            ground: k.surfaces,
            g: 0.5 * (k.g[0] + k.g[1]) as f32,
            scale,
        }
    }

    /// Total width.
    pub fn width(&self) -> u32 {
        self.panel_width * self.sigma_t.len() as u32
    }

    /// The ray through pixel `(x, y)` (pixel centres): panel σt, direction (unit),
    /// distance to the ground or −1. The same arithmetic as the fragment shader.
    pub fn ray(&self, x: u32, y: u32) -> (f32, [f32; 3], f32) {
        let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
        let pw = self.panel_width as f32;
        let panel = (px / pw).floor();
        let u = 2.0 * (px - panel * pw) / pw - 1.0;
        let v = 1.0 - 2.0 * py / self.height as f32;
        let t = (0.5 * FOV_Y).tan();
        let aspect = pw / self.height as f32;
        let d = [u * t * aspect, v * t, 1.0];
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let dir = [d[0] / n, d[1] / n, d[2] / n];
        let surface = if self.ground && dir[1] < 0.0 { GROUND_Y * self.scale / dir[1] } else { -1.0 };
        (self.sigma_t[panel as usize], dir, surface)
    }

    /// The lights in world units.
    pub fn lights(&self) -> Vec<([f32; 3], f32)> {
        LIGHTS.iter().map(|(p, i)| (p.map(|c| c * self.scale), *i)).collect()
    }
}

/// The arguments of the kernel's physical entry in a fragment shader of the
/// view: a viewer at `origin`, the light's position and intensity as written
/// (the shader's locals `dir`, `surface` and `sigma_t`).
pub fn radiance_args(k: &IndexEntry, view: &View, origin: &str, light: &str, intensity: &str) -> Vec<String> {
    k.radiance_params
        .iter()
        .map(|p| match p {
            Arg::Origin => origin.to_string(),
            Arg::Dir => "dir".into(),
            Arg::Surface => "surface".into(),
            Arg::Light => light.into(),
            Arg::Intensity => intensity.into(),
            Arg::SigmaT => "sigma_t".into(),
            Arg::SigmaS => format!("{ALBEDO:?} * sigma_t"),
            Arg::G => format!("{:?}", view.g),
            other => unreachable!("{other} is not an argument of radiance"),
        })
        .collect()
}

/// The fragment shader around the kernel, as a user's renderer would write it.
pub fn shader(k: &IndexEntry, kernel: &str, view: &View) -> String {
    let args = radiance_args(k, view, "vec3<f32>(0.0)", "light.xyz", "light.w");
    let lights: Vec<String> =
        view.lights().iter().map(|(p, i)| format!("vec4<f32>({:?}, {:?}, {:?}, {:?})", p[0], p[1], p[2], i)).collect();
    let sigmas: Vec<String> = view.sigma_t.iter().map(|s| format!("{s:?}")).collect();
    format!(
        "{kernel}
// ---- the renderer (shaders/src/render.rs) ----
const LIGHTS = array<vec4<f32>, {nl}>({lights});
const SIGMA_T = array<f32, {np}>({sigmas});

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {{
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0);
}}

@fragment
fn fs(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {{
    let pw = {pw:?};
    let panel = floor(pos.x / pw);
    let u = 2.0 * (pos.x - panel * pw) / pw - 1.0;
    let v = 1.0 - 2.0 * pos.y / {h:?};
    let t = tan({half:?});
    let d = vec3<f32>(u * t * (pw / {h:?}), v * t, 1.0);
    let dir = d / sqrt(dot(d, d));
    var surface = -1.0;
    if {ground} && dir.y < 0.0 {{
        surface = {gy:?} / dir.y;
    }}
    var sigmas = SIGMA_T;
    var lights = LIGHTS;
    let sigma_t = sigmas[u32(panel)];
    var sum = 0.0;
    for (var i = 0u; i < {nl}u; i++) {{
        let light = lights[i];
        sum += {prefix}radiance({args});
    }}
    return vec4<f32>(sum, 0.0, 0.0, 1.0);
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
    )
}

impl Gpu {
    /// Renders `view` with the WGSL kernel `kernel` (of index entry `k`) in a
    /// full-screen fragment pass into an R32Float target; the radiance per pixel,
    /// row by row.
    pub fn render(&self, k: &IndexEntry, kernel: &str, view: &View) -> Result<Vec<f32>, GpuError> {
        let d = self.device();
        let (w, h) = (view.width(), view.height);
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("airlight render"),
            source: wgpu::ShaderSource::Wgsl(shader(k, kernel, view).into()),
        });
        let format = wgpu::TextureFormat::R32Float;
        let pipeline = d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("airlight render"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })],
            }),
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            // An earlier device failure (out of memory) is the cause to report.
            self.failed()?;
            return Err(GpuError::Shader(e.to_string()));
        }
        let texture = d.create_texture(&wgpu::TextureDescriptor {
            label: Some("radiance"),
            size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let tview = texture.create_view(&Default::default());
        let row = (w * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let staging = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging"),
            size: (row * h) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &tview,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            pass.draw(0..3, 0..1);
        }
        enc.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(h) },
            },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
        self.queue().submit([enc.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        d.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| GpuError::Readback(e.to_string()))?;
        rx.recv().map_err(|e| GpuError::Readback(e.to_string()))?.map_err(|e| GpuError::Readback(e.to_string()))?;
        let bytes = staging.get_mapped_range(..).map_err(|e| GpuError::Readback(e.to_string()))?;
        let mut out = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            let start = (y * row) as usize;
            out.extend_from_slice(bytemuck::cast_slice(&bytes[start..start + (w * 4) as usize]));
        }
        drop(bytes);
        staging.unmap();
        Ok(out)
    }
}

/// The same image from the Rust kernel (`airlight-kernels`) on the CPU.
pub fn render_rust(k: &CompiledKernel, view: &View) -> Vec<f32> {
    let lights = view.lights();
    let mut out = Vec::with_capacity((view.width() * view.height) as usize);
    for y in 0..view.height {
        for x in 0..view.width() {
            let (sigma_t, dir, surface) = view.ray(x, y);
            out.push(
                lights
                    .iter()
                    .map(|(p, i)| (k.radiance)([0.0; 3], dir, surface, *p, *i, sigma_t, ALBEDO * sigma_t, view.g))
                    .sum(),
            );
        }
    }
    out
}

/// The same image from the reference (f64; `extinction = false` scenes at τ = 0).
pub fn render_reference(k: &IndexEntry, view: &View) -> Vec<f64> {
    let lights = view.lights();
    let pixels: Vec<(u32, u32)> = (0..view.height).flat_map(|y| (0..view.width()).map(move |x| (x, y))).collect();
    airlight_truth::parallel::map(
        &pixels,
        |&(x, y)| {
            let (sigma_t, dir, surface) = view.ray(x, y);
            lights
                .iter()
                .map(|&(light, intensity)| {
                    let ray = crate::Ray {
                        origin: [0.0; 3],
                        dir,
                        surface,
                        light,
                        intensity,
                        sigma_t,
                        sigma_s: ALBEDO * sigma_t,
                        g: view.g,
                    };
                    let c = ray.physical().to_canonical(f64::from(view.g)).expect("the view's rays are physical");
                    c.scale * reference::airlight(crate::gate::project(k, c.point)).unwrap_or(f64::INFINITY)
                })
                .sum()
        },
        &|_, _| {},
    )
}

/// Relative error statistics of an image against the reference: (max, mean)
/// over pixels with a positive, finite reference.
pub fn compare(image: &[f32], reference: &[f64]) -> (f64, f64) {
    let errs: Vec<f64> = image
        .iter()
        .zip(reference)
        .filter(|(_, r)| r.is_finite() && **r > 0.0)
        .map(|(&v, &r)| (f64::from(v) - r).abs() / r)
        .collect();
    let max = errs.iter().copied().fold(0.0, f64::max);
    (max, errs.iter().sum::<f64>() / errs.len().max(1) as f64)
}

/// 8-bit RGB of a radiance image, tone-mapped with `exposure` (the same for
/// all three images): `x/(1 + x)`, gamma 2.2, a warm sodium-lamp tint.
pub fn tone_map(image: &[f64], exposure: f64) -> Vec<[u8; 3]> {
    image
        .iter()
        .map(|&l| {
            let v = tone(l, exposure);
            [(255.0 * v).round() as u8, (255.0 * v * 0.82).round() as u8, (255.0 * v * 0.6).round() as u8]
        })
        .collect()
}

/// The tone curve of [`tone_map`] (and of the three.js page), in [0, 1]:
/// `x/(1 + x)` of the exposed radiance, gamma 2.2; 1 where it is infinite.
pub fn tone(radiance: f64, exposure: f64) -> f64 {
    let x = (radiance * exposure).max(0.0);
    if x.is_finite() {
        (x / (1.0 + x)).powf(1.0 / 2.2)
    } else {
        1.0
    }
}

/// The exposure that maps the reference's 99th-percentile radiance to 0.6 (before `x/(1 + x)`).
pub fn exposure(reference: &[f64]) -> f64 {
    let mut v: Vec<f64> = reference.iter().copied().filter(|x| x.is_finite() && *x > 0.0).collect();
    v.sort_by(f64::total_cmp);
    let p99 = v.get((v.len() as f64 * 0.99) as usize).copied().unwrap_or(1.0);
    0.6 / p99
}

/// A relative-difference image: log10 of the relative error from 1e-7 (black)
/// through 1e-4 (orange) to 1e-1 (white).
pub fn difference(image: &[f32], reference: &[f64]) -> Vec<[u8; 3]> {
    image
        .iter()
        .zip(reference)
        .map(|(&v, &r)| {
            let e = if r > 0.0 && r.is_finite() { (f64::from(v) - r).abs() / r } else { 0.0 };
            let s = ((e.max(1e-7).log10() + 7.0) / 6.0).clamp(0.0, 1.0);
            let c = |a: f64| (255.0 * a.clamp(0.0, 1.0)).round() as u8;
            [c(2.0 * s), c(2.0 * s - 0.6), c(2.0 * s - 1.2)]
        })
        .collect()
}

/// Writes an RGB image as PNG, atomically (a temporary file, then a rename).
pub fn write_png(path: &std::path::Path, width: u32, height: u32, pixels: &[[u8; 3]]) -> Result<(), String> {
    use plotters::prelude::*;
    let tmp = path.with_extension("tmp.png");
    {
        let root = BitMapBackend::new(&tmp, (width, height));
        let mut root = root;
        for (i, p) in pixels.iter().enumerate() {
            let (x, y) = ((i as u32 % width) as i32, (i as u32 / width) as i32);
            root.draw_pixel((x, y), RGBColor(p[0], p[1], p[2]).to_backend_color())
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
        root.present().map_err(|e| format!("{}: {e}", path.display()))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

/// Spot lights of a `kind = "spot"` scene: the street lamps of [`LIGHTS`] as
/// lamps that shine down and a little towards the viewer, outer half-angle
/// [`SPOT_OUTER_DEG`], fully lit within [`SPOT_INNER_DEG`].
pub const SPOT_AXIS: [f32; 3] = [0.0, -1.0, -0.25];
/// Outer half-angle of the render's spot lights, degrees.
pub const SPOT_OUTER_DEG: f32 = 32.0;
/// Inner half-angle of the render's spot lights, degrees (the smooth edge between).
pub const SPOT_INNER_DEG: f32 = 22.0;
/// σt per colour channel relative to the panel's σt: a coloured fog (water-laden
/// air over a harbour: red extinguished most).
pub const RGB_EXTINCTION: [f32; 3] = [1.0, 0.7, 0.45];
/// σs / σt per channel.
pub const RGB_ALBEDO: [f32; 3] = [0.6, 0.75, 0.9];

impl View {
    /// The spot rays of pixel `(x, y)`, one per light (the view's lights with the
    /// spot cone and the RGB medium above).
    pub fn spot_rays(&self, x: u32, y: u32) -> Vec<crate::SpotRay> {
        let (sigma_t, dir, surface) = self.ray(x, y);
        let (co, ci) = (SPOT_OUTER_DEG.to_radians().cos(), SPOT_INNER_DEG.to_radians().cos());
        self.lights()
            .into_iter()
            .map(|(light, intensity)| crate::SpotRay {
                origin: [0.0; 3],
                dir,
                surface,
                light,
                axis: SPOT_AXIS,
                cos_outer: co,
                cos_inner: ci,
                intensity,
                sigma_t: RGB_EXTINCTION.map(|f| f * sigma_t),
                sigma_s: [0, 1, 2].map(|c| RGB_ALBEDO[c] * RGB_EXTINCTION[c] * sigma_t),
                g: self.g,
            })
            .collect()
    }

    fn all_spot_rays(&self) -> Vec<crate::SpotRay> {
        (0..self.height).flat_map(|y| (0..self.width()).flat_map(move |x| self.spot_rays(x, y))).collect()
    }
}

/// Sums the lights of each pixel (the values are pixel by pixel, light by light).
fn per_pixel<T: Copy + Default + std::ops::Add<Output = T>>(view: &View, values: &[[T; 3]]) -> Vec<[T; 3]> {
    values
        .chunks(view.lights().len())
        .map(|c| c.iter().fold([T::default(); 3], |a, v| [a[0] + v[0], a[1] + v[1], a[2] + v[2]]))
        .collect()
}

impl Gpu {
    /// The spot render of `view` on the GPU: the kernel's spot entry (WGSL, from
    /// `kernel`, its index entry `k`) for every pixel and light, RGB per pixel.
    pub fn render_spot(&self, k: &IndexEntry, kernel: &str, view: &View) -> Result<Vec<[f32; 3]>, GpuError> {
        let src = crate::KernelSource::of(k, airlight_shapes::vocab::Target::Wgsl, kernel);
        let got = self.spot(&src, &view.all_spot_rays())?;
        Ok(per_pixel(view, &got))
    }
}

/// The spot render from the Rust kernel on the CPU (`None`: it has no spot entry).
pub fn render_spot_rust(k: &CompiledKernel, view: &View) -> Option<Vec<[f32; 3]>> {
    let got: Option<Vec<[f32; 3]>> = view.all_spot_rays().iter().map(|r| r.spot_of(k)).collect();
    Some(per_pixel(view, &got?))
}

/// The spot render from the reference (f64).
pub fn render_spot_reference(k: &IndexEntry, view: &View) -> Vec<[f64; 3]> {
    let rays = view.all_spot_rays();
    let got = airlight_truth::parallel::map(
        &rays,
        |r| {
            let a = |p| reference::airlight(crate::gate::project(k, p)).unwrap_or(f64::INFINITY);
            [0, 1, 2].map(|c| r.reference(c, &a).unwrap_or(f64::NAN))
        },
        &|_, _| {},
    );
    per_pixel(view, &got)
}

/// 8-bit RGB of an RGB radiance image: [`tone`] per channel.
pub fn tone_map_rgb(image: &[[f64; 3]], exposure: f64) -> Vec<[u8; 3]> {
    image.iter().map(|p| p.map(|l| (255.0 * tone(l, exposure)).round() as u8)).collect()
}

/// An RGB image as its channels in a row (for [`compare`], [`exposure`] and
/// [`difference`], which take one value per sample).
pub fn channels<T: Copy>(image: &[[T; 3]]) -> Vec<T> {
    image.iter().flat_map(|p| *p).collect()
}

/// [`difference`] of RGB images: the largest channel's relative error per pixel.
pub fn difference_rgb(image: &[[f32; 3]], reference: &[[f64; 3]]) -> Vec<[u8; 3]> {
    let worst: Vec<(f32, f64)> = image
        .iter()
        .zip(reference)
        .map(|(v, r)| {
            (0..3)
                .map(|c| (v[c], r[c]))
                .max_by(|a, b| {
                    let e =
                        |(v, r): (f32, f64)| if r > 0.0 && r.is_finite() { (f64::from(v) - r).abs() / r } else { 0.0 };
                    e(*a).total_cmp(&e(*b))
                })
                .expect("three channels")
        })
        .collect();
    let (v, r): (Vec<f32>, Vec<f64>) = worst.into_iter().unzip();
    difference(&v, &r)
}
/// Tone-mapped 8-bit pixels.
pub type Pixels = Vec<[u8; 3]>;

/// A scene's images, tone-mapped with the reference's exposure, and their
/// errors against the reference (max, mean relative): one channel (point
/// lights), or RGB (spot lights in a coloured medium).
pub struct Images {
    /// The GPU kernel's image.
    pub gpu: Pixels,
    /// The reference's.
    pub reference: Pixels,
    /// The GPU's relative difference from the reference.
    pub diff: Pixels,
    /// The GPU's error.
    pub gpu_err: (f64, f64),
    /// The compiled Rust kernel's image and error, where it is given.
    pub rust: Option<(Pixels, (f64, f64))>,
}

impl Images {
    /// Draws the scene kernel `k` (WGSL source `kernel`) on `gpu`, the reference
    /// and, when given, the compiled Rust kernel `rk`; `spot`: the spot entry in RGB.
    pub fn draw(
        gpu: &Gpu,
        k: &IndexEntry,
        kernel: &str,
        view: &View,
        spot: bool,
        rk: Option<&CompiledKernel>,
    ) -> Result<Images, GpuError> {
        let as64 = |v: &[f32]| v.iter().map(|&x| f64::from(x)).collect::<Vec<_>>();
        if spot {
            let image = gpu.render_spot(k, kernel, view)?;
            let reference = render_spot_reference(k, view);
            let flat = channels(&reference);
            let exposure = exposure(&flat);
            let rgb64 = |v: &[[f32; 3]]| v.iter().map(|p| p.map(f64::from)).collect::<Vec<_>>();
            return Ok(Images {
                gpu: tone_map_rgb(&rgb64(&image), exposure),
                reference: tone_map_rgb(&reference, exposure),
                diff: difference_rgb(&image, &reference),
                gpu_err: compare(&channels(&image), &flat),
                rust: rk
                    .and_then(|rk| render_spot_rust(rk, view))
                    .map(|r| (tone_map_rgb(&rgb64(&r), exposure), compare(&channels(&r), &flat))),
            });
        }
        let image = gpu.render(k, kernel, view)?;
        let reference = render_reference(k, view);
        let exposure = exposure(&reference);
        Ok(Images {
            gpu: tone_map(&as64(&image), exposure),
            reference: tone_map(&reference, exposure),
            diff: difference(&image, &reference),
            gpu_err: compare(&image, &reference),
            rust: rk.map(|rk| {
                let r = render_rust(rk, view);
                (tone_map(&as64(&r), exposure), compare(&r, &reference))
            }),
        })
    }
}

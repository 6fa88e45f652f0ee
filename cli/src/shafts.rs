//! `airlight eval --entry shadowed`: the shafts accumulator (or, for a
//! `raymarch-N` model, the engines' march) over each ray's lit runs among its
//! spheres, fed by a visibility source (exact boundaries, `--samples` shadow-map
//! look-ups, or a march's own steps), through the f64 model, a compiled f32
//! kernel or a shader on the GPU adapter. The CLI's part of the shafts room.

use crate::eval::{compiled, read_text, shader_source, unknown_model, write_csv};
use crate::workspace::{generated_dir, registry};
use crate::{bad_input, Failure};
use airlight_fit::model::Model;
use airlight_shaders::shafts::map_cases;
use airlight_shaders::{gate, Gpu, KernelSource, Ray, SpotRay};
use airlight_shapes::vocab::{CompiledKernel, IndexEntry, Target};
use airlight_truth::geometry::{GeometryError, PhysicalRay};
use airlight_truth::points_csv;
use airlight_truth::shafts::{self, Feed};
use std::path::{Path, PathBuf};

/// Where `eval --entry shadowed` runs: the f64 model, a compiled f32 Rust kernel,
/// or a shader kernel on the GPU adapter.
pub(crate) enum Runner<'a> {
    F64,
    F32(&'a [CompiledKernel]),
    Gpu(Target),
}

/// `--shadow-map RES --bias B`: each row's occluders cast into a map at its light.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MapFeed {
    pub(crate) res: usize,
    pub(crate) bias: f64,
}

impl MapFeed {
    /// `--shadow-map RES --bias B`, checked before any row is read.
    pub(crate) fn new(res: i64, bias: f64) -> Result<MapFeed, Failure> {
        let max = shafts::MAX_RES as i64;
        if !(res > 0 && res <= max && (res & (res - 1)) == 0) {
            return Err(bad_input(format!("--shadow-map {res}: give a power of two from 1 to {max} texels per side")));
        }
        if !(bias >= 0.0 && bias.is_finite()) {
            return Err(bad_input(format!("--bias {bias}: give a finite depth bias >= 0, in world units")));
        }
        Ok(MapFeed { res: res as usize, bias })
    }
}

/// The rows of a shadowed file: rays of the physical entry, or of the spot entry
/// (its header names `cos_outer`).
enum ShadowRows {
    Point(Vec<points_csv::RayRow>),
    Spot(Vec<points_csv::SpotRow>),
}

/// One `eval --entry shadowed` run: the model, where it runs, what feeds it.
struct Job<'a> {
    model: &'a str,
    name: String,
    on: Runner<'a>,
    root: Option<PathBuf>,
    /// The f64 model (absent when only a kernel of that name exists).
    f64_model: Option<&'a dyn Model>,
    /// The kernel's index entry, when it runs as a kernel.
    entry: Option<&'a IndexEntry>,
    /// Whether the model is a march (it looks visibility up at its own steps).
    marches: bool,
    feed: Feed,
    /// The shadow map the walk feeds from, instead of `feed`.
    map: Option<MapFeed>,
    /// Per input line: its spheres and the `spheres` field as written.
    spheres: Vec<(usize, Vec<shafts::Occluder>, String)>,
}

/// The visibility source: a march's own steps, `--samples` look-ups, or the exact boundaries.
fn choose_feed(model: &str, march_steps: Option<usize>, samples: Option<usize>) -> Result<Feed, Failure> {
    match (march_steps, samples) {
        (Some(n), Some(m)) if m != n => Err(bad_input(format!(
            "{model} looks visibility up at its own {n} steps; --samples {m} differs (give {n} or none)"
        ))),
        (Some(n), _) => Ok(Feed::LookUps(n)),
        (None, Some(0)) => Err(bad_input("--samples needs at least 1".to_string())),
        (None, Some(n)) => Ok(Feed::Samples(n)),
        (None, None) => Ok(Feed::Exact),
    }
}

/// `eval --entry shadowed`.
pub(crate) fn eval_shadowed(
    model: &str,
    input: &Path,
    output: Option<&Path>,
    on: Runner,
    samples: Option<usize>,
    map: Option<MapFeed>,
    root: Option<PathBuf>,
) -> Result<(), Failure> {
    let name = input.display().to_string();
    let text = read_text(input)?;
    let spheres = points_csv::parse_spheres_column(&name, &text).map_err(bad_input)?;
    // The f64 models say which are marches, and check g on the f64 path.
    let (reg, _) = registry(root.clone())?;
    let f64_model = reg.get(model).ok();
    let march_steps = f64_model.and_then(|m| m.march_steps());
    let feed = choose_feed(model, march_steps, samples)?;
    if let (Some(n), Some(_)) = (march_steps, map) {
        return Err(bad_input(format!(
            "{model} looks visibility up at its own {n} steps; --shadow-map feeds an accumulator"
        )));
    }
    let index = match on {
        Runner::F64 => None,
        _ => Some(gate::load_index(&generated_dir(root.clone())?).map_err(|e| bad_input(e.to_string()))?),
    };
    let entry = match &index {
        Some(ix) => Some(ix.get(model).map_err(bad_input)?),
        None => None,
    };
    if let (Runner::F64, None) = (&on, f64_model) {
        let e = reg.get(model).err().map(|e| e.to_string()).unwrap_or_default();
        return Err(unknown_model(model, e, &root));
    }
    let job = Job {
        model,
        name,
        on,
        root,
        f64_model: f64_model.map(|m| m as &dyn Model),
        entry,
        marches: march_steps.is_some(),
        feed,
        map,
        spheres,
    };
    let out = match job.rows(&text)? {
        ShadowRows::Point(rows) => job.point_csv(&rows)?,
        ShadowRows::Spot(rows) => job.spot_csv(&rows)?,
    };
    write_csv(output, &out)
}

impl Job<'_> {
    /// The file's rows, each checked by what runs it: the kernel's arguments, or the model's `g` range.
    fn rows(&self, text: &str) -> Result<ShadowRows, Failure> {
        let check = |r: &PhysicalRay, g: f64| -> Result<(), (&'static str, String)> {
            match (self.entry, self.f64_model) {
                (Some(e), _) => e.check_ray(r, g),
                (None, Some(m)) => m
                    .check(&airlight_truth::reference::Point { tau: 0.0, gamma: 1.0, rho: f64::INFINITY, g })
                    .map_err(|e| ("g", e.to_string())),
                (None, None) => Ok(()),
            }
        };
        if points_csv::names_spot_columns(text) {
            let rows = points_csv::parse_spots(&self.name, text, check).map_err(bad_input)?;
            if self.entry.is_some() {
                points_csv::check_axes_f32(&self.name, &rows).map_err(bad_input)?;
            }
            Ok(ShadowRows::Spot(rows))
        } else {
            Ok(ShadowRows::Point(points_csv::parse_rays(&self.name, text, check).map_err(bad_input)?))
        }
    }

    fn bad_ray(&self, line: usize, e: GeometryError) -> Failure {
        bad_input(format!("{}:{line}: {e}", self.name))
    }

    /// The `spheres` field of `line`, as written.
    fn field(&self, line: usize) -> String {
        self.spheres.iter().find(|s| s.0 == line).map(|s| s.2.clone()).unwrap_or_default()
    }

    /// A row's `[s, v]` samples, from its (red channel's) ray among its spheres.
    fn fed(&self, line: usize, ray: &PhysicalRay, g: f64) -> Result<Vec<(f64, f64)>, Failure> {
        let occluders = self.spheres.iter().find(|s| s.0 == line).map(|s| s.1.clone()).unwrap_or_default();
        shafts::feed(ray, &occluders, g, self.feed).map_err(|e| self.bad_ray(line, e))
    }

    /// The f64 model's shadowed value of `ray` fed `samples`.
    fn f64_value(
        &self,
        line: usize,
        ray: &PhysicalRay,
        cone: Option<&airlight_truth::geometry::Cone>,
        g: f64,
        samples: &[(f64, f64)],
    ) -> Result<f64, Failure> {
        let m = self.f64_model.expect("checked when the job was made");
        let v = shafts::evaluate(ray, cone, g, samples, &|p| m.eval_unchecked(p), self.marches);
        Ok(v.map_err(|e| self.bad_ray(line, e))?.0)
    }

    /// The kernel's shader on the GPU adapter: its source and the adapter.
    fn on_gpu(&self, t: Target) -> Result<(String, Option<airlight_shaders::Table>, PathBuf, Gpu), Failure> {
        let k = self.entry.expect("loaded for a kernel");
        let (src_text, table, path) = shader_source(self.root.clone(), k, t)?;
        let gpu = Gpu::open().map_err(|e| Failure(1, format!("{e}")))?;
        eprintln!("adapter: {}", gpu.adapter());
        Ok((src_text, table, path, gpu))
    }

    /// The rays of the physical entry: one radiance per row.
    fn point_csv(&self, rows: &[points_csv::RayRow]) -> Result<String, Failure> {
        if let Some(m) = self.map {
            let values = self.point_mapped(rows, m)?;
            return Ok(self.point_text(rows, &values));
        }
        let fed = rows.iter().map(|r| self.fed(r.line, &r.ray, r.g)).collect::<Result<Vec<_>, _>>()?;
        let values: Vec<f64> = match &self.on {
            Runner::F64 => rows
                .iter()
                .zip(&fed)
                .map(|(r, s)| self.f64_value(r.line, &r.ray, None, r.g, s))
                .collect::<Result<_, _>>()?,
            Runner::F32(ks) => {
                let k = compiled(ks, self.model)?;
                let f = k
                    .shadowed
                    .ok_or_else(|| bad_input(format!("kernel '{}' has no shafts accumulator", self.model)))?;
                rows.iter()
                    .zip(&fed)
                    .map(|(r, s)| {
                        let x = Ray::from_row(r);
                        f64::from(f(
                            &as_f32(s),
                            x.surface,
                            x.origin,
                            x.dir,
                            x.light,
                            x.intensity,
                            x.sigma_t,
                            x.sigma_s,
                            x.g,
                        ))
                    })
                    .collect()
            }
            Runner::Gpu(t) => {
                let (src_text, table, path, gpu) = self.on_gpu(*t)?;
                let src = KernelSource::of(self.entry.expect("loaded"), *t, &src_text).with_table(table.as_ref());
                let plain: Vec<Ray> = rows.iter().map(Ray::from_row).collect();
                let s: Vec<Vec<[f32; 2]>> = fed.iter().map(|s| as_f32(s)).collect();
                let got = gpu.shadowed(&src, &plain, &s).map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
                got.into_iter().map(f64::from).collect()
            }
        };
        Ok(self.point_text(rows, &values))
    }

    fn point_text(&self, rows: &[points_csv::RayRow], values: &[f64]) -> String {
        let mut out = format!("{},spheres,radiance\n", points_csv::RAY_COLUMNS.join(","));
        for (r, v) in rows.iter().zip(values) {
            out.push_str(&format!("{},{},{v:?}\n", r.text.join(","), self.field(r.line)));
        }
        out
    }

    /// The rays of the spot entry: RGB per row.
    fn spot_csv(&self, rows: &[points_csv::SpotRow]) -> Result<String, Failure> {
        if let Some(m) = self.map {
            let values = self.spot_mapped(rows, m)?;
            return Ok(self.spot_text(rows, &values));
        }
        let fed = rows.iter().map(|r| self.fed(r.line, &r.rays[0], r.g)).collect::<Result<Vec<_>, _>>()?;
        let values: Vec<[f64; 3]> = match &self.on {
            Runner::F64 => {
                let mut out = Vec::with_capacity(rows.len());
                for (r, s) in rows.iter().zip(&fed) {
                    let mut v = [0.0; 3];
                    for (c, ray) in r.rays.iter().enumerate() {
                        v[c] = self.f64_value(r.line, ray, r.cone.as_ref(), r.g, s)?;
                    }
                    out.push(v);
                }
                out
            }
            Runner::F32(ks) => self.spot_f32(ks, rows, &fed)?,
            Runner::Gpu(t) => {
                let k = self.entry.expect("loaded");
                if !k.has(airlight_shapes::vocab::Entry::Spot) {
                    return Err(bad_input(format!("kernel '{}' has no spot entry", self.model)));
                }
                let (src_text, table, path, gpu) = self.on_gpu(*t)?;
                let src = KernelSource::of(k, *t, &src_text).with_table(table.as_ref());
                let plain: Vec<SpotRay> = rows.iter().map(SpotRay::from_row).collect();
                let s: Vec<Vec<[f32; 2]>> = fed.iter().map(|s| as_f32(s)).collect();
                let got =
                    gpu.spot_shadowed(&src, &plain, &s).map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
                got.into_iter().map(|v| v.map(f64::from)).collect()
            }
        };
        Ok(self.spot_text(rows, &values))
    }

    fn spot_text(&self, rows: &[points_csv::SpotRow], values: &[[f64; 3]]) -> String {
        let mut out = format!("{},spheres,r,g_out,b\n", points_csv::SPOT_COLUMNS.join(","));
        for (r, v) in rows.iter().zip(values) {
            out.push_str(&format!("{},{},{:?},{:?},{:?}\n", r.text.join(","), self.field(r.line), v[0], v[1], v[2]));
        }
        out
    }

    /// The compiled f32 kernel's accumulator over its spot entry.
    fn spot_f32(
        &self,
        ks: &[CompiledKernel],
        rows: &[points_csv::SpotRow],
        fed: &[Vec<(f64, f64)>],
    ) -> Result<Vec<[f64; 3]>, Failure> {
        let k = compiled(ks, self.model)?;
        let f = k
            .spot_shadowed
            .ok_or_else(|| bad_input(format!("kernel '{}' has no shafts accumulator over a spot entry", self.model)))?;
        Ok(rows
            .iter()
            .zip(fed)
            .map(|(r, s)| {
                let x = SpotRay::from_row(r);
                f(
                    &as_f32(s),
                    x.surface,
                    x.origin,
                    x.dir,
                    x.light,
                    x.axis,
                    x.cos_outer,
                    x.cos_inner,
                    x.intensity,
                    x.sigma_t,
                    x.sigma_s,
                    x.g,
                )
                .map(f64::from)
            })
            .collect())
    }
}

fn as_f32(s: &[(f64, f64)]) -> Vec<[f32; 2]> {
    s.iter().map(|&(a, b)| [a as f32, b as f32]).collect()
}

/// Texels a GPU batch of maps may hold (their depths and pyramids on the adapter).
const GPU_BATCH_TEXELS: usize = 1 << 25;

/// The widest spot cone (half-angle) that gets a one-face map; a wider one gets
/// a cube map. One face cannot cover a cone of 90° or more (it lit everything
/// outside its face: a 90° cone leaked completely), and past 60° its edge
/// texels are over 4× the centre's.
const SPOT_FACE_MAX_DEG: f64 = 60.0;

/// The tangent of a spot map's half-angle for a cone of outer cosine `c`, at
/// most [`SPOT_FACE_MAX_DEG`]: `None` where a cube map covers the cone.
fn spot_tan_half(cos_outer: f64) -> Option<f64> {
    (cos_outer >= SPOT_FACE_MAX_DEG.to_radians().cos()).then(|| cos_outer.min(1.0).acos().tan().max(1e-6))
}

impl Job<'_> {
    /// The shadow map of `line`'s occluders at `ray`'s light: a cube map, or a spot map over `cone`.
    fn map_for(
        &self,
        m: MapFeed,
        line: usize,
        ray: &PhysicalRay,
        cone: Option<&airlight_truth::geometry::Cone>,
    ) -> Result<shafts::ShadowMap, Failure> {
        let occ = self.spheres.iter().find(|s| s.0 == line).map(|s| s.1.clone()).unwrap_or_default();
        let map = match cone.and_then(|c| Some((c, spot_tan_half(c.cos_outer)?))) {
            None => shafts::ShadowMap::cube(ray.light, m.res, &occ, m.bias),
            Some((c, tan_half)) => shafts::ShadowMap::spot(ray.light, c.axis, tan_half, m.res, &occ, m.bias),
        };
        map.map_err(|e| bad_input(format!("{}:{line}: --shadow-map: {e}", self.name)))
    }

    /// The walk's steps per ray, summarised on standard error; a ray whose walk
    /// ran out of steps (its rest counted as shadowed) fails the run, naming the
    /// first such line.
    fn report_steps(&self, m: MapFeed, lines: &[usize], steps: &[f32]) -> Result<(), Failure> {
        if steps.is_empty() {
            return Ok(());
        }
        let mut s: Vec<f32> = steps.iter().map(|x| x.abs()).collect();
        s.sort_by(f32::total_cmp);
        let truncated = steps.iter().filter(|&&x| x < 0.0).count();
        eprintln!(
            "shadow map {0}x{0}: walk steps median {1}, max {2}; {truncated} of {3} rays ran out of steps",
            m.res,
            s[s.len() / 2],
            s[s.len() - 1],
            s.len()
        );
        match steps.iter().position(|&x| x < 0.0) {
            None => Ok(()),
            Some(i) => Err(Failure(
                1,
                format!(
                    "{}:{}: the shadow-map walk ran out of its {} steps ({truncated} of {} rays did; the rest of \
                     each counted as shadowed): give a smaller --shadow-map or fewer occluders",
                    self.name,
                    lines.get(i).copied().unwrap_or(0),
                    s[s.len() - 1],
                    s.len()
                ),
            )),
        }
    }

    /// The physical entry through the walk's runs.
    fn point_mapped(&self, rows: &[points_csv::RayRow], m: MapFeed) -> Result<Vec<f64>, Failure> {
        let mut steps = Vec::new();
        let values = match &self.on {
            Runner::F64 => rows
                .iter()
                .map(|r| {
                    let map = self.map_for(m, r.line, &r.ray, None)?;
                    let samples = shafts::exact_samples(&r.ray, &map.lit_runs(&r.ray));
                    self.f64_value(r.line, &r.ray, None, r.g, &samples)
                })
                .collect::<Result<_, _>>()?,
            Runner::F32(ks) => {
                let k = compiled(ks, self.model)?;
                let (f, walk) = match (k.shadowed, k.walk) {
                    (Some(f), Some(w)) => (f, w),
                    _ => return Err(bad_input(format!("kernel '{}' has no shafts accumulator", self.model))),
                };
                let mut out = Vec::with_capacity(rows.len());
                for r in rows {
                    let map = self.map_for(m, r.line, &r.ray, None)?;
                    let x = Ray::from_row(r);
                    let (runs, n, cut) = map_cases::rust_runs(walk, &map, &map.pyramid(), &x);
                    steps.push(if cut { -(n as f32) } else { n as f32 });
                    let s = map_cases::run_samples(&runs);
                    out.push(f64::from(f(
                        &s,
                        x.surface,
                        x.origin,
                        x.dir,
                        x.light,
                        x.intensity,
                        x.sigma_t,
                        x.sigma_s,
                        x.g,
                    )));
                }
                out
            }
            Runner::Gpu(t) => {
                let (src_text, table, path, gpu) = self.on_gpu(*t)?;
                let k = self.entry.expect("loaded");
                let src = KernelSource::of(k, *t, &src_text).with_table(table.as_ref());
                let walk = self.walk_texts()?;
                let mut out = Vec::with_capacity(rows.len());
                for chunk in rows.chunks(batch_rows(m.res, 6)) {
                    let maps =
                        chunk.iter().map(|r| self.map_for(m, r.line, &r.ray, None)).collect::<Result<Vec<_>, _>>()?;
                    let refs: Vec<&shafts::ShadowMap> = maps.iter().collect();
                    let fail = |e: airlight_shaders::GpuError| Failure(1, format!("{}: {e}", path.display()));
                    let (pyramid, specs) = map_cases::upload(&gpu, walk.sources().pyramid, &refs).map_err(fail)?;
                    let plain: Vec<Ray> = chunk.iter().map(Ray::from_row).collect();
                    let got = gpu.mapped(&src, &walk.sources(), &plain, &specs, &pyramid).map_err(fail)?;
                    steps.extend(got.iter().map(|g| g.steps));
                    out.extend(got.iter().map(|g| f64::from(g.value)));
                }
                out
            }
        };
        let lines: Vec<usize> = rows.iter().map(|r| r.line).collect();
        self.report_steps(m, &lines, &steps)?;
        Ok(values)
    }

    /// The spot entry through the walk's runs (one map per row, from its red channel's ray).
    fn spot_mapped(&self, rows: &[points_csv::SpotRow], m: MapFeed) -> Result<Vec<[f64; 3]>, Failure> {
        let mut steps = Vec::new();
        let values = match &self.on {
            Runner::F64 => {
                let mut out = Vec::with_capacity(rows.len());
                for r in rows {
                    let map = self.map_for(m, r.line, &r.rays[0], r.cone.as_ref())?;
                    let samples = shafts::exact_samples(&r.rays[0], &map.lit_runs(&r.rays[0]));
                    let mut v = [0.0; 3];
                    for (c, ray) in r.rays.iter().enumerate() {
                        v[c] = self.f64_value(r.line, ray, r.cone.as_ref(), r.g, &samples)?;
                    }
                    out.push(v);
                }
                out
            }
            Runner::F32(ks) => {
                let k = compiled(ks, self.model)?;
                let (f, walk) = match (k.spot_shadowed, k.walk) {
                    (Some(f), Some(w)) => (f, w),
                    _ => {
                        return Err(bad_input(format!(
                            "kernel '{}' has no shafts accumulator over a spot entry",
                            self.model
                        )))
                    }
                };
                let mut out = Vec::with_capacity(rows.len());
                for r in rows {
                    let map = self.map_for(m, r.line, &r.rays[0], r.cone.as_ref())?;
                    let x = SpotRay::from_row(r);
                    let plain = Ray {
                        origin: x.origin,
                        dir: x.dir,
                        surface: x.surface,
                        light: x.light,
                        intensity: x.intensity,
                        sigma_t: x.sigma_t[0],
                        sigma_s: x.sigma_s[0],
                        g: x.g,
                    };
                    let (runs, n, cut) = map_cases::rust_runs(walk, &map, &map.pyramid(), &plain);
                    steps.push(if cut { -(n as f32) } else { n as f32 });
                    let s = map_cases::run_samples(&runs);
                    let v = f(
                        &s,
                        x.surface,
                        x.origin,
                        x.dir,
                        x.light,
                        x.axis,
                        x.cos_outer,
                        x.cos_inner,
                        x.intensity,
                        x.sigma_t,
                        x.sigma_s,
                        x.g,
                    );
                    out.push(v.map(f64::from));
                }
                out
            }
            Runner::Gpu(t) => {
                let k = self.entry.expect("loaded");
                if !k.has(airlight_shapes::vocab::Entry::Spot) {
                    return Err(bad_input(format!("kernel '{}' has no spot entry", self.model)));
                }
                let (src_text, table, path, gpu) = self.on_gpu(*t)?;
                let src = KernelSource::of(k, *t, &src_text).with_table(table.as_ref());
                let walk = self.walk_texts()?;
                let mut out = Vec::with_capacity(rows.len());
                for chunk in rows.chunks(batch_rows(m.res, 1)) {
                    let maps = chunk
                        .iter()
                        .map(|r| self.map_for(m, r.line, &r.rays[0], r.cone.as_ref()))
                        .collect::<Result<Vec<_>, _>>()?;
                    let refs: Vec<&shafts::ShadowMap> = maps.iter().collect();
                    let fail = |e: airlight_shaders::GpuError| Failure(1, format!("{}: {e}", path.display()));
                    let (pyramid, specs) = map_cases::upload(&gpu, walk.sources().pyramid, &refs).map_err(fail)?;
                    let plain: Vec<SpotRay> = chunk.iter().map(SpotRay::from_row).collect();
                    let got = gpu.spot_mapped(&src, &walk.sources(), &plain, &specs, &pyramid).map_err(fail)?;
                    steps.extend(got.iter().map(|g| g.steps));
                    out.extend(got.iter().map(|g| g.value.map(f64::from)));
                }
                out
            }
        };
        let lines: Vec<usize> = rows.iter().map(|r| r.line).collect();
        self.report_steps(m, &lines, &steps)?;
        Ok(values)
    }

    /// The walk's generated sources.
    fn walk_texts(&self) -> Result<airlight_shaders::shafts::WalkTexts, Failure> {
        let dir = generated_dir(self.root.clone())?;
        airlight_shaders::shafts::WalkTexts::load(&dir).map_err(|e| Failure(1, e.to_string()))
    }
}

/// Rows per GPU batch: as many maps of `faces × res²` texels as [`GPU_BATCH_TEXELS`] holds, at least one.
fn batch_rows(res: usize, faces: usize) -> usize {
    (GPU_BATCH_TEXELS / (faces * res * res)).max(1)
}

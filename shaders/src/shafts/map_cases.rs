//! The gate's shadow-map rows: shadowed rays whose occluders are cast into a
//! cube map at the light, the accumulator fed the lit runs of the generated walk
//! on every target, against the reference in-scattering over the same map's
//! exact runs ([`airlight_truth::shafts::ShadowMap::lit_runs`], f64).

use super::cases::{shadow_row_in, shadowed_rays, Held, ShadowCase};
use super::{MapSpec, PyramidTexture};
use crate::gate::subject::Subject;
use crate::gate::*;
use crate::{Gpu, GpuError};
use airlight_shapes::vocab::IndexEntry;
use airlight_truth::domains::VALIDATION_SEED;
use airlight_truth::reference::{self, Point};
use airlight_truth::shafts::{self, ShadowMap};

/// Shadowed rays in the gate's shadow-map rows.
pub const MAPPED_RAYS: usize = 32;

/// Texels per side of their cube maps.
pub const GATE_MAP_RES: usize = 256;

/// One ray through a shadow map: the shadowed case, its light's cube map, the
/// map's exact runs and the reference in-scattering over them.
#[derive(Debug, Clone)]
pub struct MapCase {
    /// The ray, its occluders and the analytic reference.
    pub case: ShadowCase,
    /// The cube map of the occluders at the ray's light.
    pub map: ShadowMap,
    /// The map's exact lit runs along the ray.
    pub runs: Vec<(f64, f64)>,
    /// Visibility changes on the ray under the map.
    pub changes: usize,
    /// The reference in-scattering over `runs`.
    pub reference: f64,
}

/// [`MAPPED_RAYS`]-style cases for `k`: [`shadowed_rays`], each cast into a
/// `res²` cube map (bias 0) at its light.
pub fn map_cases(k: &IndexEntry, n: usize, res: usize, seed: u64) -> Result<Vec<MapCase>, GateError> {
    let cases = shadowed_rays(k, n, seed)?;
    let a = |q: Point| reference::airlight(q).unwrap_or(f64::NAN);
    cases
        .into_iter()
        .map(|case| {
            let phys = case.ray.physical();
            let map = ShadowMap::cube(phys.light, res, &case.occluders, 0.0)
                .map_err(|e| GateError::Input(format!("{}: shadow map: {e}", k.name)))?;
            let runs = map.lit_runs(&phys);
            let stop = phys.surface_distance.unwrap_or(f64::INFINITY);
            let changes = runs.iter().map(|&(a, b)| usize::from(a > 0.0) + usize::from(b < stop)).sum();
            let reference = shafts::shadowed_radiance(&phys, None, f64::from(case.ray.g), &runs, &a)
                .map_err(|e| GateError::Input(format!("{}: shadow-map ray: {e}", k.name)))?;
            Ok(MapCase { case, map, runs, changes, reference })
        })
        .collect()
}

impl MapCase {
    fn held(&self) -> Held {
        Held {
            point: self.case.point,
            reference: self.reference,
            unshadowed: self.case.unshadowed,
            transitions: self.changes,
        }
    }
}

/// The maps of `maps` stacked as layers of one array (each map's faces in
/// order), and each one's [`MapSpec`] (all must share one resolution).
pub fn stack(maps: &[&ShadowMap]) -> (Vec<f32>, Vec<MapSpec>, u32) {
    let mut depth = Vec::new();
    let mut specs = Vec::with_capacity(maps.len());
    for m in maps {
        let layer = (depth.len() / (m.res * m.res)) as u32;
        depth.extend_from_slice(&m.depth);
        specs.push(spec_of(m, layer));
    }
    let faces = maps.first().map_or(0, |m| (depth.len() / (m.res * m.res)) as u32);
    (depth, specs, faces)
}

/// How the walk reads `map` from `layer` on.
pub fn spec_of(map: &ShadowMap, layer: u32) -> MapSpec {
    MapSpec {
        cube: map.is_cube(),
        rows: map.faces[0].rows.map(|r| r.map(|x| x as f32)),
        res: map.res as u32,
        bias: map.bias as f32,
        layer,
    }
}

/// The maps of `maps` on the adapter: their stacked depths, the pyramid built by
/// the shipped pass.
pub fn upload(gpu: &Gpu, pass: &str, maps: &[&ShadowMap]) -> Result<(PyramidTexture, Vec<MapSpec>), GpuError> {
    let (depth, specs, faces) = stack(maps);
    let res = maps.first().map_or(1, |m| m.res as u32);
    Ok((gpu.build_pyramid(pass, &depth, res, faces)?, specs))
}

/// The lit runs of the compiled Rust walk through `map` (a pyramid of its own).
pub fn rust_runs(
    walk: airlight_shapes::vocab::WalkFn,
    map: &ShadowMap,
    pyramid: &shafts::Pyramid,
    ray: &crate::Ray,
) -> (Vec<[f32; 2]>, u32, bool) {
    let s = spec_of(map, 0);
    let node = |f: u32, l: u32, x: i32, y: i32| pyramid.node(f as usize, l as usize, x as usize, y as usize);
    walk(ray.origin, ray.dir, ray.surface, (ray.light, s.rows, s.cube, s.res, s.bias), &node)
}

/// Runs `[a, b]` (`b < 0`: open) as the accumulator's `[s, v]` samples.
pub fn run_samples(runs: &[[f32; 2]]) -> Vec<[f32; 2]> {
    let mut out = vec![[0.0, 0.0]];
    for &[a, b] in runs {
        out.push([a, 0.0]);
        out.push([a, 1.0]);
        if b >= 0.0 {
            out.push([b, 1.0]);
            out.push([b, 0.0]);
        }
    }
    out
}

impl Subject<'_> {
    /// The accumulator fed the shadow-map walk's runs, on every target, held to
    /// `bound` relative to each ray's unshadowed value times one plus its changes
    /// under the map.
    pub(crate) fn mapped_rows(&self, bound: Bound) -> Result<Vec<Row>, GateError> {
        let k = self.k;
        let cases = map_cases(k, MAPPED_RAYS, GATE_MAP_RES, VALIDATION_SEED ^ 0x3A9)?;
        let held: Vec<Held> = cases.iter().map(MapCase::held).collect();
        let f64s: Vec<f64> = airlight_truth::parallel::map(
            &cases,
            |c| {
                let phys = c.case.ray.physical();
                let samples = shafts::exact_samples(&phys, &c.runs);
                shafts::evaluate(&phys, None, f64::from(c.case.ray.g), &samples, &|p| (self.model)(p), false)
                    .map_or(f64::NAN, |v| v.0)
            },
            &|_, _| {},
        );
        let mut rows = vec![shadow_row_in(SHADOW_MAP, k, None, &held, &f64s, bound)];
        if let (Some(f), Some(walk)) = (self.compiled.and_then(|c| c.shadowed), self.compiled.and_then(|c| c.walk)) {
            let got: Vec<f64> = cases
                .iter()
                .map(|c| {
                    let r = &c.case.ray;
                    let (runs, _, _) = rust_runs(walk, &c.map, &c.map.pyramid(), r);
                    let s = run_samples(&runs);
                    crate::from_kernel(f(
                        &s,
                        r.surface,
                        r.origin,
                        r.dir,
                        r.light,
                        r.intensity,
                        r.sigma_t,
                        r.sigma_s,
                        r.g,
                    ))
                })
                .collect();
            rows.push(shadow_row_in(SHADOW_MAP, k, Some(airlight_shapes::vocab::Target::Rust), &held, &got, bound));
        }
        if let Some(gpu) = self.gpu {
            let maps: Vec<&ShadowMap> = cases.iter().map(|c| &c.map).collect();
            let rays: Vec<crate::Ray> = cases.iter().map(|c| c.case.ray).collect();
            for (target, src) in &self.shaders {
                let (pyramid, specs) = upload(gpu, self.walk.pyramid, &maps).map_err(self.gpu_error(*target))?;
                let got = gpu.mapped(src, &self.walk, &rays, &specs, &pyramid).map_err(self.gpu_error(*target))?;
                let values: Vec<f64> = got.iter().map(|m| crate::from_kernel(m.value)).collect();
                rows.push(shadow_row_in(SHADOW_MAP, k, Some(*target), &held, &values, bound));
            }
        }
        Ok(rows)
    }
}

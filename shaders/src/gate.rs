//! The error-bound gate (`airlight check`): every generated kernel, on every
//! target — the Rust f32 kernel on the CPU, the WGSL and the GLSL kernel on the
//! GPU adapter — against the reference on the validation sets of its domains
//! (the points its model's declared bounds were measured on) and on the extreme
//! set of docs/MATH.md §5. A kernel fails when its error exceeds the declared bound
//! plus the f32 allowance ([`Row::limit`]), or when it returns NaN, ∞ or a
//! negative value where `A` is finite.
//!
//! Scene kernels take fewer arguments than their model: their points are the
//! same sets projected onto the scene (`ρ = ∞` without surfaces, `τ = 0` without
//! extinction, a fixed `g`), with the reference recomputed there.

use crate::{Gpu, GpuError, KernelSource};
use airlight_fit::catalog::{self, Validation};
use airlight_fit::coeffs::ModelFile;
use airlight_fit::family::Body;
pub use airlight_shapes::vocab::{
    f32_domain_limit, f32_limit, Target, F32_ADAPTER_ALLOWANCE, F32_ALLOWANCE, F32_RANGE, F32_REL_ALLOWANCE,
};
use airlight_shapes::vocab::{CompiledKernel, Entry, Index, IndexEntry};
use airlight_truth::domains::{Domain, VALIDATION_POINTS, VALIDATION_SEED};
use airlight_truth::reference::{self, Point};
use std::fmt;
use std::path::Path;

pub use airlight_shapes::record::{target_label, F32Bound, EDGE, PHYSICAL, PHYS_EXTREME, SHADOWED, SPOT};

/// One kernel × target × domain.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Kernel name.
    pub kernel: String,
    /// Where it ran; `None`: the f64 model (reported, never failing the gate).
    pub target: Option<Target>,
    /// `thin`, `dense`, `extreme` (canonical entry), `physical` or
    /// `phys-extreme` (physical entry).
    pub domain: &'static str,
    /// Points with `A` in f32's range (the error statistics' population).
    pub points: usize,
    /// Largest relative error.
    pub max: f64,
    /// 99th-percentile relative error.
    pub p99: f64,
    /// The declared bound it is held to: the f64 model's for the f64 row, the
    /// kernel's f32 bound for an f32 target ([`Bound`]).
    pub declared: f64,
    /// Where the largest error occurs.
    pub worst: Option<Point>,
    /// NaN, ∞ or negative results where the value is finite (the kernels' `HUGE`
    /// counts as ∞ unless the exact value is beyond f32's checked range).
    pub bad: usize,
    /// The first such point and value.
    pub first_bad: Option<(Point, f64)>,
}

impl Row {
    /// The limit the error must stay within: on `thin` and `dense` an f32 target's
    /// own bound widened only by another adapter's rounding
    /// ([`f32_domain_limit`]); elsewhere (the edge, extreme and physical sets, the
    /// spot and shafts entries, none of which the f32 bound was measured on) the
    /// bound plus the f32 allowance ([`f32_limit`]).
    pub fn limit(&self) -> f64 {
        if self.target.is_some() && (self.domain == Domain::Thin.name() || self.domain == Domain::Dense.name()) {
            f32_domain_limit(self.declared)
        } else {
            f32_limit(self.declared)
        }
    }
    /// Whether this row passes: no bad value and, for an f32 target, the error
    /// within [`Row::limit`]. The f64 rows hold the model's own error and only
    /// need to be free of bad values (their bounds are the fit's business).
    pub fn passes(&self) -> bool {
        self.bad == 0 && (self.target.is_none() || self.max <= self.limit())
    }
}

/// What a set of rows is held to: the f64 model's declared bound (its f64 row)
/// and the kernel's f32 bound (its f32 targets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// The model's declared bound.
    pub model: f64,
    /// The kernel's f32 bound.
    pub f32: f64,
}

impl Bound {
    /// The bound of a row on `target`.
    pub fn on(self, target: Option<Target>) -> f64 {
        if target.is_some() {
            self.f32
        } else {
            self.model
        }
    }

    /// The larger of two, each part.
    fn max(self, o: Bound) -> Bound {
        Bound { model: self.model.max(o.model), f32: self.f32.max(o.f32) }
    }
}

/// Why the gate could not run at all.
#[derive(Debug)]
pub enum GateError {
    /// An input file is missing or malformed (message names it).
    Input(String),
    /// The GPU failed on a kernel (not: produced wrong numbers).
    Gpu(String, GpuError),
}

impl fmt::Display for GateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GateError::Input(m) => write!(f, "{m}"),
            GateError::Gpu(k, e) => write!(f, "{k}: {e}"),
        }
    }
}

impl std::error::Error for GateError {}

/// The kernels to check: every entry of `generated/kernels.toml` (or those named).
pub fn load_index(generated: &Path) -> Result<Index, GateError> {
    Index::load(generated).map_err(|e| GateError::Input(e.to_string()))
}

/// Projects a point onto what a kernel takes (its scene's subspace).
pub fn project(k: &IndexEntry, p: Point) -> Point {
    Point {
        tau: if k.extinction { p.tau } else { 0.0 },
        gamma: p.gamma,
        rho: if k.surfaces { p.rho } else { f64::INFINITY },
        g: if k.g[0] == k.g[1] { k.g[0] } else { p.g.clamp(k.g[0], k.g[1]) },
    }
}

/// Points with their reference `A`.
type Checked = Vec<(Point, f64)>;

/// The points and reference values a kernel is checked on, per domain.
fn point_sets(k: &IndexEntry, validations: &[Validation]) -> Result<Vec<(Domain, Checked)>, GateError> {
    let scene = k.scene.is_some();
    let mut out = Vec::new();
    for d in Domain::ALL {
        if d != Domain::Extreme && !k.domains.contains(&d) {
            continue;
        }
        let set = validations.iter().find(|v| v.domain == d && v.g_range == (k.g[0], k.g[1])).map(|v| v.points.clone());
        let pts = match (set, scene) {
            (Some(p), false) => p,
            _ => {
                let base = d.validation_set((k.g[0], k.g[1]), VALIDATION_POINTS, VALIDATION_SEED);
                with_reference(k, base.into_iter().map(|p| project(k, p)).collect())?
            }
        };
        out.push((d, pts));
    }
    Ok(out)
}

/// `pts` sorted, without repeats, each with its reference `A` (for kernel `k`'s errors).
fn with_reference(k: &IndexEntry, mut pts: Vec<Point>) -> Result<Checked, GateError> {
    pts.sort_by(|a, b| (a.tau, a.gamma, a.rho, a.g).partial_cmp(&(b.tau, b.gamma, b.rho, b.g)).expect("no NaN"));
    pts.dedup();
    let values = airlight_truth::parallel::map(&pts, |p| reference::airlight(*p), &|_, _| {});
    pts.into_iter()
        .zip(values)
        .map(|(p, v)| v.map(|a| (p, a)).map_err(|e| GateError::Input(format!("{}: {e}", k.name))))
        .collect()
}

/// The end of kernel `k`'s sampled domains in τ.
fn tau_max(k: &IndexEntry) -> f64 {
    k.domains.iter().filter(|&&d| d != Domain::Extreme).map(|d| d.tau_range().1).fold(0.0, f64::max)
}

/// The canonical edge set of kernel `k` (issue 23): the exact axis (γ = 0, and π
/// as f64 and f32 round it), γ from 1e-37 (near f32's smallest normal number; the f32
/// contract ends there) up, γ within 1e-6 of π, surfaces just
/// before, at and beyond the light and out to 1e300 and ∞, at three optical
/// depths and the ends of its `g` range; projected onto what `k` takes. Errors
/// count wherever the value is within f32's range and `τ` within its domains;
/// the ray through the light must give ∞ (f32: `HUGE`).
// 3.14159265358979 is the γ a user typed in issue 23 (π − 3.2e-15), not π.
#[allow(clippy::approx_constant)]
pub fn edge_points(k: &IndexEntry) -> Result<Vec<(Point, f64)>, GateError> {
    use std::f64::consts::PI;
    let gammas = [
        0.0,
        1e-37,
        1e-33,
        1e-30,
        1e-20,
        1e-10,
        1e-6,
        1e-3,
        1.0,
        PI / 2.0,
        PI - 1e-3,
        PI - 1e-6,
        3.141_592_653_589_79,
        PI,
    ];
    let rhos = [0.5, 1.0 - 1.0 / 1_048_576.0, 1.0, 2.0, 1e4, 1e30, 1e300, f64::INFINITY];
    let mut pts = Vec::new();
    for tau in [0.0, 0.5, tau_max(k).min(5.0)] {
        for &gamma in &gammas {
            for &rho in &rhos {
                for g in [k.g[0], k.g[1]] {
                    pts.push(project(k, Point { tau, gamma, rho, g }));
                }
            }
        }
    }
    with_reference(k, pts)
}

/// Rays realising canonical points at world scales from 1e-3 to 1e4 units.
pub const PHYSICAL_RAYS: usize = 2000;

/// `n` random placements of viewer, light and ray for kernel `k`: each realises a
/// point of its domains (projected onto what it takes) at a scale `D` log-uniform
/// in [1e-3, 1e4], the viewer up to 10·D from the origin, a random direction and
/// medium. Returns the rays with the canonical point of their f32 inputs (computed
/// in f64) and the expected radiance `σs·I/D·A` from the reference.
pub fn physical_rays(k: &IndexEntry, n: usize, seed: u64) -> Result<Vec<(crate::Ray, Point, f64)>, GateError> {
    placements(k, n, seed)?
        .into_iter()
        .map(|(ray, real, scale)| {
            let a = reference::airlight(real).map_err(|e| GateError::Input(format!("{}: {e}", k.name)))?;
            Ok((ray, real, scale * a))
        })
        .collect()
}

/// The rays of [`physical_rays`] with the canonical point of their f32 inputs
/// (projected onto what `k` takes) and the scale `σs·I/D` of their radiance.
fn placements(k: &IndexEntry, n: usize, seed: u64) -> Result<Vec<(crate::Ray, Point, f64)>, GateError> {
    let mut rng = airlight_truth::domains::SplitMix64(seed);
    let unit = |rng: &mut airlight_truth::domains::SplitMix64| loop {
        let v = [2.0 * rng.next_f64() - 1.0, 2.0 * rng.next_f64() - 1.0, 2.0 * rng.next_f64() - 1.0];
        let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if r > 0.1 && r <= 1.0 {
            return [v[0] / r, v[1] / r, v[2] / r];
        }
    };
    let domains: Vec<Domain> = [Domain::Thin, Domain::Dense].into_iter().filter(|d| k.domains.contains(d)).collect();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let d = domains[i % domains.len()];
        let (tlo, thi) = d.tau_range();
        let tau = tlo + (thi - tlo) * rng.next_f64();
        let gamma = 0.01 + (std::f64::consts::PI - 0.02) * rng.next_f64();
        let rho = if rng.next_f64() < 0.2 { f64::INFINITY } else { 0.01 * 1e4f64.powf(rng.next_f64()) };
        let g = k.g[0] + (k.g[1] - k.g[0]) * rng.next_f64();
        let p = project(k, Point { tau, gamma, rho, g });
        let scale = 1e-3 * 1e7f64.powf(rng.next_f64());
        let o = unit(&mut rng);
        let dist = 10.0 * scale * rng.next_f64();
        let origin = [o[0] * dist, o[1] * dist, o[2] * dist];
        let dir = unit(&mut rng);
        // A unit vector perpendicular to dir.
        let a = unit(&mut rng);
        let dot = a[0] * dir[0] + a[1] * dir[1] + a[2] * dir[2];
        let q = [a[0] - dot * dir[0], a[1] - dot * dir[1], a[2] - dot * dir[2]];
        let qn = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
        let perp = [q[0] / qn, q[1] / qn, q[2] / qn];
        let (c, s) = (p.gamma.cos(), p.gamma.sin());
        let light: [f64; 3] = std::array::from_fn(|j| origin[j] + scale * (c * dir[j] + s * perp[j]));
        // Without extinction σt is not an argument (τ = 0 below); σs ≤ σt keeps the
        // medium physical.
        let sigma_s = if p.tau > 0.0 { 0.8 * p.tau / scale } else { 0.5 / scale };
        let sigma_t = if p.tau > 0.0 { p.tau / scale } else { sigma_s };
        let intensity = 1.0 + 999.0 * rng.next_f64();
        let surface = if p.rho.is_infinite() { -1.0 } else { p.rho * scale };
        let ray = crate::Ray {
            origin: origin.map(|x| x as f32),
            dir: dir.map(|x| x as f32),
            surface: surface as f32,
            light: light.map(|x| x as f32),
            intensity: intensity as f32,
            sigma_t: sigma_t as f32,
            sigma_s: sigma_s as f32,
            g: p.g as f32,
        };
        // The canonical point of the f32 inputs, in f64.
        let c =
            ray.physical().to_canonical(f64::from(ray.g)).map_err(|e| GateError::Input(format!("{}: {e}", k.name)))?;
        out.push((ray, project(k, c.point), c.scale));
    }
    Ok(out)
}

/// One spot ray of the gate.
#[derive(Debug, Clone, Copy)]
pub struct SpotCase {
    /// The ray, light and medium.
    pub ray: crate::SpotRay,
    /// The canonical point its error is held at (the lit stretch's).
    pub point: Point,
    /// The reference RGB radiance.
    pub reference: [f64; 3],
    /// The relative change of the reference when the cone's cosines move by one
    /// f32 ulp: how much of the answer the f32 inputs alone leave undetermined.
    pub ulp_change: f64,
}

/// Spot rays whose answer changes by more than this when the cone's cosines move
/// by one f32 ulp (narrow cones, rays grazing an edge) are ill-conditioned in f32
/// itself: there an f32 kernel is held to its limit plus [`SPOT_ULP_FACTOR`] times
/// that change, and its error enters the row's statistics only if it breaks that.
pub const SPOT_ULP_CHANGE: f64 = 1e-5;

/// How many one-ulp changes of the cone's cosines an f32 kernel's spot error may
/// add on ill-conditioned rays (measured: at most 20 on 4,500 rays of three kernels).
pub const SPOT_ULP_FACTOR: f64 = 32.0;

/// Spot rays per kernel with a spot entry.
pub const SPOT_RAYS: usize = 224;

/// The outer half-angles (degrees) of the gate's grid of cones (issue 23: the
/// cones renderers use).
pub const SPOT_GRID_OUTER: [f64; 7] = [5.0, 10.0, 20.0, 30.0, 45.0, 60.0, 80.0];

/// The inner half-angles of the grid, as shares of the outer: from a hard edge
/// (equal) to a quarter.
pub const SPOT_GRID_INNER: [f64; 4] = [1.0, 0.75, 0.5, 0.25];

/// Spot-light rays for kernel `k`'s spot entry: the placements of
/// [`physical_rays`], each light made a spot light aimed at a random point of the
/// ray (or beside it): every fourth the next cone of the grid [`SPOT_GRID_OUTER`] ×
/// [`SPOT_GRID_INNER`] (every eighth turned so that the ray leaves through its
/// penumbra), the others outer half-angle 2°…80° log-uniform, every other one with a
/// smooth edge (inner half-angle 20…95% of the outer), every 16th a point light
/// (`cos_outer = −1`); σt and σs per channel the ray's scaled by 0.4…1; then 28
/// rays on the line through the light and beside it. Returns
/// the rays with the canonical point of their unclipped red channel and the
/// reference RGB radiance (through [`crate::SpotRay::reference`]).
pub fn spot_rays(k: &IndexEntry, n: usize, seed: u64) -> Result<Vec<SpotCase>, GateError> {
    let base = placements(k, n, seed)?;
    let mut rng = airlight_truth::domains::SplitMix64(seed ^ 0x5907);
    let mut rays = Vec::with_capacity(n);
    for (i, (r, p, _)) in base.iter().enumerate() {
        let o = r.origin.map(f64::from);
        let l = r.light.map(f64::from);
        let dn = {
            let d = r.dir.map(f64::from);
            let m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            d.map(|x| x / m)
        };
        let dist = ((l[0] - o[0]).powi(2) + (l[1] - o[1]).powi(2) + (l[2] - o[2]).powi(2)).sqrt();
        let s = 2.0 * dist * rng.next_f64();
        let jitter = 0.3 * dist * rng.next_f64();
        let u = [rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5];
        let mut axis: [f64; 3] = std::array::from_fn(|j| o[j] + s * dn[j] + jitter * u[j] - l[j]);
        let outer = (2.0f64 * 40f64.powf(rng.next_f64())).to_radians();
        let inner = outer * (0.2 + 0.75 * rng.next_f64());
        // Every fourth ray: the next cone of the grid renderers use.
        let (grid_outer, grid_inner) = {
            let j = i / 4;
            let o = SPOT_GRID_OUTER[j % SPOT_GRID_OUTER.len()];
            (o.to_radians(), (o * SPOT_GRID_INNER[(j / SPOT_GRID_OUTER.len()) % SPOT_GRID_INNER.len()]).to_radians())
        };
        if i % 8 == 0 {
            // Every other grid ray leaves through the penumbra: the axis turned from
            // the ray's direction by an angle between the inner and outer half-angles,
            // so that the far end of the ray (ω → π, the backscatter peak and the
            // tail) lies in the smooth edge.
            let frac = 0.2 + 0.6 * rng.next_f64();
            let a = grid_inner + frac * (grid_outer - grid_inner);
            let dot = u[0] * dn[0] + u[1] * dn[1] + u[2] * dn[2];
            let q: [f64; 3] = std::array::from_fn(|j| u[j] - dot * dn[j]);
            let qn = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
            if qn > 0.0 {
                axis = std::array::from_fn(|j| a.cos() * dn[j] + a.sin() * q[j] / qn);
            }
        }
        let (cos_outer, cos_inner) = if i % 16 == 15 {
            (-1.0, -1.0)
        } else if i % 4 == 0 {
            (grid_outer.cos(), grid_inner.cos())
        } else if i % 2 == 0 {
            (outer.cos(), inner.cos())
        } else {
            (outer.cos(), outer.cos())
        };
        let f = [1.0, 0.4 + 0.6 * rng.next_f64(), 0.4 + 0.6 * rng.next_f64()];
        // A kernel that does not take σt (no extinction) is checked in a medium without it:
        // ignoring the transmittance to a stretch is not bounded by its bound on A.
        let takes_sigma_t = k.spot_params.contains(&airlight_shapes::vocab::Arg::SigmaTRgb);
        let sigma_t = if takes_sigma_t { f.map(|x| (x * f64::from(r.sigma_t)) as f32) } else { [0.0; 3] };
        let sigma_s = f.map(|x| (x * f64::from(r.sigma_s)) as f32);
        rays.push((
            crate::SpotRay {
                origin: r.origin,
                dir: r.dir,
                surface: r.surface,
                light: r.light,
                axis: axis.map(|x| x as f32),
                cos_outer: cos_outer as f32,
                cos_inner: cos_inner as f32,
                intensity: r.intensity,
                sigma_t,
                sigma_s,
                g: r.g,
            },
            *p,
        ));
    }
    // The line through the light (issue 23): the light on the ray's line ahead and
    // off it by 1e-9 and 1e-5 of its distance, behind on it and off it by 1e-30 …
    // 1e-7, a smooth 30°/20° and a hard 30° cone aimed along the line either way,
    // surfaces before the light and none. On the line the value is the point
    // light's times the line's weight, and the edge regime holds the point light
    // to the bound at γ = 0 and π exactly: these are held at γ brought into the
    // sampled hull.
    let mut line = Vec::new();
    let mut cases = Vec::new();
    for smooth in [true, false] {
        for toward in [true, false] {
            // Ahead, the cone's cut falls within `h cot ω` of the light's foot; the f64
            // reference places it in distances, which hold `h` from about 1e-9 up.
            for off in [0.0, 1e-9, 1e-5] {
                cases.push((true, off, smooth, toward, toward && off == 0.0));
            }
            for off in [0.0, 1e-30, 1e-12, 1e-7] {
                cases.push((false, off, smooth, toward, false));
            }
        }
    }
    for (i, &(ahead, off, smooth, toward, with_surface)) in cases.iter().enumerate() {
        let (r, p, _) = &base[i % base.len()];
        let dist = {
            let (o, l) = (r.origin.map(f64::from), r.light.map(f64::from));
            ((l[0] - o[0]).powi(2) + (l[1] - o[1]).powi(2) + (l[2] - o[2]).powi(2)).sqrt()
        };
        let side = if ahead { 1.0 } else { -1.0 };
        let co = 30f64.to_radians().cos();
        let ci = if smooth { 20f64.to_radians().cos() } else { co };
        let surface = if with_surface { (0.5 * dist) as f32 } else { -1.0 };
        let takes_sigma_t = k.spot_params.contains(&airlight_shapes::vocab::Arg::SigmaTRgb);
        let sigma_t = if takes_sigma_t { [r.sigma_t, 0.7 * r.sigma_t, 0.4 * r.sigma_t] } else { [0.0; 3] };
        let ray = crate::SpotRay {
            origin: [0.0; 3],
            dir: [1.0, 0.0, 0.0],
            surface,
            light: [(side * dist) as f32, (off * dist) as f32, 0.0],
            axis: [if toward { -side as f32 } else { side as f32 }, 0.0, 0.0],
            cos_outer: co as f32,
            cos_inner: ci as f32,
            intensity: r.intensity,
            sigma_t,
            sigma_s: [r.sigma_s, 0.8 * r.sigma_s, 0.6 * r.sigma_s],
            g: r.g,
        };
        let q = Point { gamma: if ahead { 1e-4 } else { std::f64::consts::PI - 1e-4 }, ..*p };
        line.push((ray, q));
    }
    // The canonical point each error is held at: the lit stretch's own (the
    // viewer moved to where the outer cone begins), where the family's bound applies.
    for (r, p) in rays.iter_mut() {
        let Some(cone) = r.cone() else { continue };
        let ray = r.physical(0);
        if let Some((s0, s1)) = cone.lit(&ray, cone.cos_outer) {
            if let Ok(c) = ray.stretch(s0, s1).0.to_canonical(f64::from(r.g)) {
                *p = project(k, c.point);
            }
        }
    }
    rays.extend(line);
    let refs = airlight_truth::parallel::map(
        &rays,
        |(r, _)| -> Result<([f64; 3], f64), String> {
            let a = |q: Point| reference::airlight(project(k, q)).unwrap_or(f64::NAN);
            let mut out = [0.0; 3];
            for (c, v) in out.iter_mut().enumerate() {
                *v = r.reference(c, &a).map_err(|e| e.to_string())?;
            }
            // The problem's own f32 conditioning: the change when the cone's
            // cosines move by one f32 ulp either way.
            let mut change = 0.0;
            if r.cone().is_some() {
                for step in [-1.0f32, 1.0] {
                    let mut q = *r;
                    let ulp = |x: f32| x + step * x.abs().max(f32::MIN_POSITIVE) * f32::EPSILON;
                    q.cos_outer = ulp(r.cos_outer);
                    q.cos_inner = ulp(r.cos_inner);
                    let v = q.reference(0, &a).map_err(|e| e.to_string())?;
                    change = f64::max(change, (v - out[0]).abs() / out[0].max(f64::MIN_POSITIVE));
                }
            }
            Ok((out, change))
        },
        &|_, _| {},
    );
    rays.into_iter()
        .zip(refs)
        .map(|((ray, point), v)| {
            v.map(|(reference, change)| SpotCase { ray, point, reference, ulp_change: change })
                .map_err(|e| GateError::Input(format!("{}: spot ray: {e}", k.name)))
        })
        .collect()
}

/// Shadowed rays per kernel in the gate.
pub const SHADOWED_RAYS: usize = 96;

/// Of those, how many are also made spot lights (where the kernel has the spot entry).
pub const SHADOWED_SPOT_RAYS: usize = 8;

/// One shadowed ray of the gate: a physical ray among analytic occluders.
#[derive(Debug, Clone)]
pub struct ShadowCase {
    /// The ray, light and medium (f32, as the kernels take them); its surface is
    /// where the view ray ends (its own surface, or the first occluder it hits).
    pub ray: crate::Ray,
    /// The canonical point of the unshadowed ray (where it is reported).
    pub point: Point,
    /// The occluders.
    pub occluders: Vec<airlight_truth::shafts::Occluder>,
    /// The exact lit intervals fed as samples ([`airlight_truth::shafts::exact_samples`]).
    pub samples: Vec<(f64, f64)>,
    /// Visibility changes on the ray (lit intervals' ends inside it).
    pub transitions: usize,
    /// The reference shadowed radiance.
    pub reference: f64,
    /// The reference unshadowed radiance of the same ray.
    pub unshadowed: f64,
}

/// Shadowed rays for kernel `k`: the placements of [`physical_rays`], each with 1
/// to 4 occluders placed between the light and points of the ray (balls of
/// radius 3–15% of the light's distance to their centre's ray point times their
/// place along it, every fourth case one box instead of a ball), so that each
/// casts its shadow across the ray; the view ray ends at the first occluder it
/// hits (as the caller's first hit would); one holding the viewer or the light is
/// left out. Returns the cases with the exact lit intervals and the reference
/// shadowed and unshadowed radiance.
pub fn shadowed_rays(k: &IndexEntry, n: usize, seed: u64) -> Result<Vec<ShadowCase>, GateError> {
    use airlight_truth::shafts::{self, Occluder};
    let base = placements(k, n, seed)?;
    let mut rng = airlight_truth::domains::SplitMix64(seed ^ 0x54AD);
    let mut cases = Vec::with_capacity(n);
    for (i, (r, p, _)) in base.into_iter().enumerate() {
        let phys = r.physical();
        let dn = {
            let d = phys.direction;
            let m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            d.map(|x| x / m)
        };
        let (l, o) = (phys.light, phys.origin);
        let dist = ((l[0] - o[0]).powi(2) + (l[1] - o[1]).powi(2) + (l[2] - o[2]).powi(2)).sqrt();
        let reach = phys.surface_distance.unwrap_or(3.0 * dist).min(3.0 * dist);
        let mut occ = Vec::new();
        for j in 0..1 + i % 4 {
            let s = reach * rng.next_f64();
            let x: [f64; 3] = std::array::from_fn(|c| o[c] + s * dn[c]);
            let u = 0.2 + 0.6 * rng.next_f64();
            let c: [f64; 3] = std::array::from_fn(|q| l[q] + u * (x[q] - l[q]));
            let lx = ((x[0] - l[0]).powi(2) + (x[1] - l[1]).powi(2) + (x[2] - l[2]).powi(2)).sqrt();
            let size = (0.03 + 0.12 * rng.next_f64()) * lx * u;
            if !(size > 0.0 && size.is_finite()) {
                continue;
            }
            let oc = if i % 4 == 3 && j == 0 {
                Occluder::Cuboid { min: c.map(|v| v - size), max: [c[0] + size, c[1] + 0.5 * size, c[2] + 2.0 * size] }
            } else {
                Occluder::Sphere { center: c, radius: size }
            };
            if !oc.contains(o) && !oc.contains(l) {
                occ.push(oc);
            }
        }
        let mut ray = r;
        let end = occ.iter().filter_map(|oc| oc.enters(o, dn)).fold(f64::INFINITY, f64::min);
        if end < phys.surface_distance.unwrap_or(f64::INFINITY) {
            ray.surface = end as f32;
        }
        let phys = ray.physical();
        let lit = shafts::lit_intervals(&phys, &occ);
        let stop = phys.surface_distance.unwrap_or(f64::INFINITY);
        let transitions = lit.iter().map(|&(a, b)| usize::from(a > 0.0) + usize::from(b < stop)).sum();
        let a = |q: Point| reference::airlight(q).unwrap_or(f64::NAN);
        let g = f64::from(ray.g);
        let fail =
            |e: airlight_truth::geometry::GeometryError| GateError::Input(format!("{}: shadowed ray: {e}", k.name));
        let reference = shafts::shadowed_radiance(&phys, None, g, &lit, &a).map_err(fail)?;
        let unshadowed = phys.radiance(g, &a).map_err(fail)?;
        cases.push(ShadowCase {
            ray,
            point: p,
            samples: shafts::exact_samples(&phys, &lit),
            occluders: occ,
            transitions,
            reference,
            unshadowed,
        });
    }
    Ok(cases)
}

/// One kept shadowed ray: `(origin, direction, light, σt, intensity, (centre, radius))`.
pub type KeptShadowed = ([f32; 3], [f32; 3], [f32; 3], f32, f32, ([f64; 3], f64));

/// Shadowed rays kept from issue 37's probe, where the exact lit intervals were
/// once wrong: `(origin, direction, light, σt, intensity, ball)`, σs = σt, no
/// surface. A light on a ball's surface (its tangent plane is the shadow's edge),
/// balls 1e-9 and 1e-10 of their distance across (thin shadow cones the
/// ray runs along for a thousand units), a ball 2e200 across holding the viewer and
/// one 1e-300 across holding the light (the radius squared overflows and underflows).
pub const KEPT_SHADOWED: [KeptShadowed; 7] = [
    ([-1.0, 5.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3], 0.1, 1.0, ([1.0, 0.0, 0.0], 1.0)),
    ([-1.0, 5.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3], 0.1, 1.0, ([3.0, 0.0, 4.0], 5.0)),
    ([-1.0, 5.0, 0.0], [1.0, 0.2, 0.1], [0.0; 3], 0.8, 1.0, ([-3.0, 0.0, -4.0], 5.0)),
    ([1000010.0, 0.002, 0.0], [1.0, -2e-6, 0.0], [0.0; 3], 1e-6, 1e12, ([1e6, 0.0, 0.0], 1e-3)),
    ([1000010.0, 0.002, 0.0], [1.0, -2e-6, 0.0], [0.0; 3], 3e-6, 1e12, ([1e6, 0.0, 0.0], 1e-4)),
    ([0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0.1, 1.0, ([1.9e200, 0.0, 0.0], 2e200)),
    ([0.0; 3], [1.0, 0.0, 0.0], [5.0, 1.0, 0.0], 0.1, 1.0, ([5.0, 1.0, 0.0], 1e-300)),
];

/// The [`KEPT_SHADOWED`] rays kernel `k` takes as they are (its `g` at the middle
/// of its range; left out where the kernel would project the ray's canonical point
/// elsewhere: no extinction).
pub fn kept_shadowed_rays(k: &IndexEntry) -> Result<Vec<ShadowCase>, GateError> {
    use airlight_truth::shafts::{self, Occluder};
    let g = 0.5 * (k.g[0] + k.g[1]);
    let mut out = Vec::new();
    for (origin, dir, light, sigma_t, intensity, (center, radius)) in KEPT_SHADOWED {
        let ray = crate::Ray { origin, dir, surface: -1.0, light, intensity, sigma_t, sigma_s: sigma_t, g: g as f32 };
        let phys = ray.physical();
        let fail = |e: airlight_truth::geometry::GeometryError| {
            GateError::Input(format!("{}: kept shadowed ray: {e}", k.name))
        };
        let point = phys.to_canonical(f64::from(ray.g)).map_err(fail)?.point;
        if project(k, point) != point {
            continue;
        }
        let occluders = vec![Occluder::Sphere { center, radius }];
        let lit = shafts::lit_intervals(&phys, &occluders);
        let transitions = lit.iter().map(|&(a, b)| usize::from(a > 0.0) + usize::from(b.is_finite())).sum();
        let a = |q: Point| reference::airlight(q).unwrap_or(f64::NAN);
        out.push(ShadowCase {
            ray,
            point,
            samples: shafts::exact_samples(&phys, &lit),
            reference: shafts::shadowed_radiance(&phys, None, f64::from(ray.g), &lit, &a).map_err(fail)?,
            unshadowed: phys.radiance(f64::from(ray.g), &a).map_err(fail)?,
            occluders,
            transitions,
        });
    }
    Ok(out)
}

/// A spot light's shadowed ray of the gate: a [`ShadowCase`]'s ray, occluders and
/// samples with the light made a spot light aimed at a point of the ray.
#[derive(Debug, Clone)]
pub struct SpotShadowCase {
    /// The ray, cone and RGB medium (f32).
    pub ray: crate::SpotRay,
    /// The canonical point of the unshadowed red channel (where it is reported).
    pub point: Point,
    /// The exact lit intervals fed as samples.
    pub samples: Vec<(f64, f64)>,
    /// Visibility changes on the ray.
    pub transitions: usize,
    /// The reference shadowed radiance per channel.
    pub reference: [f64; 3],
    /// The reference unshadowed radiance per channel.
    pub unshadowed: [f64; 3],
}

/// Spot rays of the shadowed set: the first `n` of `cases`, each light a spot light
/// aimed from the light at a random point of the ray's first 3 light distances,
/// 40° outer half-angle, smooth (inner 25°) and hard in turn; σt and σs per
/// channel the ray's times 1, 0.7, 0.4 and 1, 0.8, 0.6.
pub fn spot_shadowed_rays(
    k: &IndexEntry,
    cases: &[ShadowCase],
    n: usize,
    seed: u64,
) -> Result<Vec<SpotShadowCase>, GateError> {
    use airlight_truth::shafts;
    let mut rng = airlight_truth::domains::SplitMix64(seed ^ 0x5B0D);
    let takes_sigma_t = k.spot_params.contains(&airlight_shapes::vocab::Arg::SigmaTRgb);
    let mut out = Vec::new();
    for (i, c) in cases.iter().take(n).enumerate() {
        let r = c.ray;
        let phys = r.physical();
        let d = phys.direction;
        let dn = {
            let m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            d.map(|x| x / m)
        };
        let (o, l) = (phys.origin, phys.light);
        let dist = ((l[0] - o[0]).powi(2) + (l[1] - o[1]).powi(2) + (l[2] - o[2]).powi(2)).sqrt();
        let s = phys.surface_distance.unwrap_or(3.0 * dist).min(3.0 * dist) * rng.next_f64();
        let axis: [f64; 3] = std::array::from_fn(|q| o[q] + s * dn[q] - l[q]);
        let co = 40f64.to_radians().cos();
        let ci = if i % 2 == 0 { 25f64.to_radians().cos() } else { co };
        let ray = crate::SpotRay {
            origin: r.origin,
            dir: r.dir,
            surface: r.surface,
            light: r.light,
            axis: axis.map(|x| x as f32),
            cos_outer: co as f32,
            cos_inner: ci as f32,
            intensity: r.intensity,
            sigma_t: if takes_sigma_t { [r.sigma_t, 0.7 * r.sigma_t, 0.4 * r.sigma_t] } else { [0.0; 3] },
            sigma_s: [r.sigma_s, 0.8 * r.sigma_s, 0.6 * r.sigma_s],
            g: r.g,
        };
        let cone = ray.cone();
        let lit = shafts::lit_intervals(&ray.physical(0), &c.occluders);
        let a = |q: Point| reference::airlight(project(k, q)).unwrap_or(f64::NAN);
        let fail = |e: airlight_truth::geometry::GeometryError| {
            GateError::Input(format!("{}: spot shadowed ray: {e}", k.name))
        };
        let mut reference = [0.0; 3];
        let mut unshadowed = [0.0; 3];
        for ch in 0..3 {
            let p = ray.physical(ch);
            reference[ch] = shafts::shadowed_radiance(&p, cone.as_ref(), f64::from(r.g), &lit, &a).map_err(fail)?;
            unshadowed[ch] = ray.reference(ch, &a).map_err(fail)?;
        }
        out.push(SpotShadowCase {
            ray,
            point: c.point,
            samples: c.samples.clone(),
            transitions: c.transitions,
            reference,
            unshadowed,
        });
    }
    Ok(out)
}

/// What a shadowed row holds one value to: the reference, the unshadowed value of
/// the same ray, its visibility changes, and where it is reported.
struct Held {
    point: Point,
    reference: f64,
    unshadowed: f64,
    transitions: usize,
}

impl ShadowCase {
    fn held(&self) -> Held {
        Held {
            point: self.point,
            reference: self.reference,
            unshadowed: self.unshadowed,
            transitions: self.transitions,
        }
    }
}

impl SpotShadowCase {
    fn held(&self) -> [Held; 3] {
        std::array::from_fn(|c| Held {
            point: self.point,
            reference: self.reference[c],
            unshadowed: self.unshadowed[c],
            transitions: self.transitions,
        })
    }
}

/// A shadowed row: each value's error `|Â − A| / (U (1 + transitions))`, `U` the
/// unshadowed value of the same ray, held to `declared` like every row.
fn shadow_row(k: &IndexEntry, target: Option<Target>, items: &[Held], got: &[f64], bound: Bound) -> Row {
    let declared = bound.on(target);
    let mut errs = Vec::with_capacity(items.len());
    let (mut bad, mut first_bad) = (0, None);
    for (c, &v) in items.iter().zip(got) {
        let saturated = target.is_some() && v == f64::INFINITY && c.reference > F32_RANGE.1;
        if !saturated && c.reference.is_finite() && !(v.is_finite() && v >= 0.0) {
            bad += 1;
            first_bad.get_or_insert((c.point, v));
            continue;
        }
        if (F32_RANGE.0..=F32_RANGE.1).contains(&c.unshadowed) && c.reference.is_finite() {
            errs.push((c.point, (v - c.reference).abs() / (c.unshadowed * (1.0 + c.transitions as f64))));
        }
    }
    let stats = airlight_truth::stats::ErrorStats::from_errors(errs);
    Row {
        kernel: k.name.clone(),
        target,
        domain: SHADOWED,
        points: stats.count,
        max: stats.max,
        p99: stats.p99,
        declared,
        worst: stats.worst,
        bad,
        first_bad,
    }
}

/// The hull of a kernel's declared domains: τ up to the end of its sampled
/// domains (`tau_max`), γ and ρ as far as `extreme` reaches (docs/MATH.md §5: γ ∈
/// [1e-4, π − 1e-4], ρ ∈ [1e-4, 1e4] ∪ {∞}): where a physical extreme ray's error
/// is held to the declared bound. Outside it (grazing lights at 1e-30, surfaces
/// at 1e-6 D, τ past the kernel's domains) only the value's sanity is checked.
pub fn in_declared_hull(p: &Point, tau_max: f64) -> bool {
    p.tau <= tau_max
        && (1e-4..=std::f64::consts::PI - 1e-4).contains(&p.gamma)
        && (p.rho.is_infinite() || (1e-4..=1e4).contains(&p.rho))
}

/// The physical extreme set of kernel `k` (issue: "kernels over the whole f32
/// range"): viewer–light distances 1e-4 … 1e30; the light on the ray, off it by
/// 1e-30 … 1e-3 relative (axis-aligned rays from the origin, where f32 holds such
/// offsets exactly), across, behind, and at the viewer; surfaces none, 0,
/// 1e-6 D, D/2, D, 1e3 D, 1e30, `f32::MAX` and `+∞`; unit, tiny (1e-30) and huge
/// (1e20) directions, axis-aligned (so that the tiny offsets survive f32) or not;
/// σt = 0, σs > σt, dense media; projected onto what `k` takes. Deterministic.
/// Returns the rays with the canonical point of their f32 inputs (computed in
/// f64; `ρ = 0`, `γ = 0` for a light at the viewer) and the reference radiance.
pub fn physical_extremes(k: &IndexEntry) -> Result<Vec<(crate::Ray, Point, f64)>, GateError> {
    use std::f64::consts::PI;
    let scales = [1e-4, 1e-2, 1.0, 1e3, 1e6, 1e12, 1e20, 1e30];
    // γ, or the relative offset of the light from the ray (as `ε`, γ ≈ ε).
    let angles: [f64; 11] = [0.0, 1e-30, 1e-20, 1e-10, 1e-6, 1e-3, 1.0, PI / 2.0, 2.5, PI - 1e-3, PI];
    // A ray in a general direction from a general viewer: its positions round in
    // f32, so the light's offset from it is known only to that rounding, ~1e-7
    // relative (the Rust kernel resolves what the rounded inputs say exactly; a
    // shader compiler may reassociate the error-free sums that do it): its
    // angles stay where the f32 inputs determine the value.
    let general: [f64; 11] = [1e-3, 1e-2, 0.1, 0.5, 1.0, PI / 2.0, 2.0, 2.5, 3.0, PI - 1e-2, PI - 1e-3];
    let surfaces: [&dyn Fn(f64) -> f64; 9] = [
        &|_| -1.0,
        &|_| 0.0,
        &|d| 1e-6 * d,
        &|d| 0.5 * d,
        &|d| d,
        &|d| 1e3 * d,
        &|_| 1e30,
        &|_| f64::from(f32::MAX),
        &|_| f64::INFINITY,
    ];
    // (σt·D, σs·D): clear with scattering, thin, σs > σt, dense.
    let media = [(0.0, 1.0), (1e-3, 1e-3), (0.5, 0.4), (2.0, 3.0), (20.0, 16.0)];
    let gs: Vec<f64> = if k.g[0] == k.g[1] { vec![k.g[0]] } else { vec![k.g[0], 0.5 * (k.g[0] + k.g[1]), k.g[1]] };
    let mut rays = Vec::new();
    let mut i = 0usize;
    for &d in &scales {
        for (&a_axis, &a_general) in angles.iter().zip(&general) {
            for surface in &surfaces {
                i += 1;
                let axis = i.is_multiple_of(2);
                let a = if axis { a_axis } else { a_general };
                let (dir, perp): ([f64; 3], [f64; 3]) =
                    if axis { ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]) } else { ([0.6, 0.64, 0.48], [0.8, -0.48, -0.36]) };
                let dscale = [1.0, 1e-30, 1e20][i % 3];
                let (st, ss) = media[i % media.len()];
                let g = gs[i % gs.len()];
                let origin = if axis { [0.0; 3] } else { [3.0 * d, -5.0 * d, 0.25 * d] };
                let (c, sn) = (a.cos(), a.sin());
                let light: [f64; 3] = std::array::from_fn(|j| origin[j] + d * (c * dir[j] + sn * perp[j]));
                let ray = crate::Ray {
                    origin: origin.map(|x| x as f32),
                    dir: dir.map(|x| (x * dscale) as f32),
                    surface: if k.surfaces { surface(d) as f32 } else { -1.0 },
                    light: light.map(|x| x as f32),
                    intensity: 100.0,
                    sigma_t: if k.extinction { (st / d) as f32 } else { 0.0 },
                    sigma_s: (ss / d) as f32,
                    g: g as f32,
                };
                rays.push(ray);
            }
        }
    }
    // The light at the viewer, with and without scattering.
    for (j, &d) in scales.iter().enumerate() {
        let o = [d as f32, -(d as f32), 0.5 * d as f32];
        let sigma_s = if j.is_multiple_of(2) { (1.0 / d) as f32 } else { 0.0 };
        rays.push(crate::Ray {
            origin: o,
            dir: [0.0, 0.0, 1.0],
            surface: -1.0,
            light: o,
            intensity: 100.0,
            sigma_t: if k.extinction { (1.0 / d) as f32 } else { 0.0 },
            sigma_s,
            g: gs[0] as f32,
        });
    }
    let expected = airlight_truth::parallel::map(
        &rays,
        |r| {
            let phys = r.physical();
            let v = phys.radiance(f64::from(r.g), &|p| reference::airlight(p).unwrap_or(f64::NAN));
            let point = phys.to_canonical(f64::from(r.g)).map(|c| c.point).unwrap_or(Point {
                tau: 0.0,
                gamma: 0.0,
                rho: 0.0,
                g: f64::from(r.g),
            });
            v.map(|v| (point, v))
        },
        &|_, _| {},
    );
    rays.into_iter()
        .zip(expected)
        .map(|(r, e)| {
            let (p, v) = e.map_err(|e| GateError::Input(format!("{}: physical extreme set: {e}", k.name)))?;
            if v.is_nan() {
                return Err(GateError::Input(format!("{}: the reference failed at {p:?}", k.name)));
            }
            Ok((r, p, v))
        })
        .collect()
}

/// The f64 model of kernel `k` at a canonical point: its fitted model, or the
/// closed form for a kernel without one (the no-extinction family is exact
/// there, the reference's own value).
fn f64_model<'m>(k: &IndexEntry, models: &'m [ModelFile]) -> Result<Box<dyn Fn(Point) -> f64 + Sync + 'm>, GateError> {
    Ok(match model_file(k, models)? {
        Some(m) => Box::new(move |p| airlight_fit::model::Model::eval_unchecked(&m.model, p)),
        None => Box::new(|p| airlight_fit::family::CLOSED_FORM.eval(p)),
    })
}

/// The coefficient file of kernel `k`'s model (`None`: the closed form, which
/// has none).
fn model_file<'m>(k: &IndexEntry, models: &'m [ModelFile]) -> Result<Option<&'m ModelFile>, GateError> {
    let Some(name) = &k.model else { return Ok(None) };
    models
        .iter()
        .find(|m| &m.model.name == name)
        .map(Some)
        .ok_or_else(|| GateError::Input(format!("kernel {}: no coefficient file for model {name}", k.name)))
}

/// Statistics of one kernel's values against the reference.
fn row(
    k: &IndexEntry,
    target: Option<Target>,
    domain: &'static str,
    pts: &[(Point, f64)],
    got: &[f64],
    bound: Bound,
    ulp_change: Option<&[f64]>,
) -> Row {
    let declared = bound.on(target);
    let tau_max = tau_max(k);
    let mut errs = Vec::with_capacity(pts.len());
    let (mut bad, mut first_bad) = (0, None);
    for (i, (&(p, exact), &v64)) in pts.iter().zip(got).enumerate() {
        // An f32 kernel's HUGE (read as ∞) is right where the value is ∞ or
        // beyond f32's checked range (it saturates there); anywhere else it is bad.
        let saturated = target.is_some() && v64 == f64::INFINITY && exact > F32_RANGE.1;
        // On the edge set the ray through the light must give ∞ too.
        let missed = domain == EDGE && exact.is_infinite() && v64 != f64::INFINITY;
        if missed || (!saturated && exact.is_finite() && !(v64.is_finite() && v64 >= 0.0)) {
            bad += 1;
            first_bad.get_or_insert((p, v64));
            continue;
        }
        let hull = domain != PHYS_EXTREME && domain != SPOT;
        if (F32_RANGE.0..=F32_RANGE.1).contains(&exact) && (hull || in_declared_hull(&p, tau_max)) {
            let err = (v64 - exact).abs() / exact;
            // An item ill-conditioned in f32 counts only where it breaks its widened limit.
            let change = ulp_change.map_or(0.0, |u| u[i]);
            if change <= SPOT_ULP_CHANGE || (target.is_some() && err > f32_limit(declared) + SPOT_ULP_FACTOR * change) {
                errs.push((p, err));
            }
        }
    }
    let stats = airlight_truth::stats::ErrorStats::from_errors(errs);
    Row {
        kernel: k.name.clone(),
        target,
        domain,
        points: stats.count,
        max: stats.max,
        p99: stats.p99,
        declared,
        worst: stats.worst,
        bad,
        first_bad,
    }
}

/// The largest declared bound of `k` over its domains (0 for the closed form).
pub fn declared_max(k: &IndexEntry, models: &[ModelFile]) -> Result<f64, GateError> {
    k.domains.iter().try_fold(0.0f64, |m, &d| Ok(m.max(declared(k, models, d)?)))
}

/// The declared bound of `k` on `domain`: its model's (over the band of `g` a
/// kernel with `g` baked in lies in, [`ModelFile::bound_at`]), 0 for the closed form.
/// On the extreme set, the limits of `thin` and `dense` (γ → 0 and π, τ → 0 and
/// beyond 20), at least the model's bound over the whole of both: a band's bound is
/// measured with γ ≥ 0.01, and a rule's error on the axis at a baked `g` can lie a
/// little above it (`lite-5` at g = 0.8: 3.64e-3 against the band's 3.5e-3).
fn declared(k: &IndexEntry, models: &[ModelFile], domain: Domain) -> Result<f64, GateError> {
    let Some(m) = model_file(k, models)? else { return Ok(0.0) };
    let baked = (k.g[0] == k.g[1]).then_some(k.g[0]);
    let missing = |d: Domain| GateError::Input(format!("model {}: no declared error on {d}", m.model.name));
    let own = m.bound_at(domain, baked).ok_or_else(|| missing(domain))?;
    if domain != Domain::Extreme {
        return Ok(own);
    }
    [Domain::Thin, Domain::Dense]
        .iter()
        .try_fold(own, |b, &d| Ok(b.max(m.bound_at(d, None).ok_or_else(|| missing(d))?)))
}

/// One kernel under the gate: its index entry, its f64 model, its compiled Rust
/// kernel (if the Rust target is checked) and its shader sources (if a GPU is).
struct Subject<'a> {
    k: &'a IndexEntry,
    model: Box<dyn Fn(Point) -> f64 + Sync + 'a>,
    compiled: Option<&'a CompiledKernel>,
    shaders: Vec<(Target, KernelSource<'a>)>,
    gpu: Option<&'a Gpu>,
    /// Whether it is the uniform ray march (the engines' method), which cannot
    /// see the divergence on the ray through the light.
    marches: bool,
}

impl Subject<'_> {
    /// A GPU failure of this kernel on `target`.
    fn gpu_error(&self, target: Target) -> impl Fn(GpuError) -> GateError + '_ {
        move |e| GateError::Gpu(format!("{} ({})", self.k.name, target.name()), e)
    }

    /// The canonical entry on `pts`, one row per target (the f64 model, the Rust
    /// kernel, each shader), labelled `label` and held to `bound`.
    fn point_rows(&self, label: &'static str, pts: &Checked, bound: Bound) -> Result<Vec<Row>, GateError> {
        let (k, mut rows) = (self.k, Vec::new());
        let raw: Vec<[f64; 4]> = pts.iter().map(|(p, _)| [p.tau, p.gamma, p.rho, p.g]).collect();
        let f64s = airlight_truth::parallel::map(pts, |(p, _)| (self.model)(*p), &|_, _| {});
        rows.push(row(k, None, label, pts, &f64s, bound, None));
        if let Some(rk) = self.compiled {
            let got: Vec<f64> = pts.iter().map(|(p, _)| rust_at(rk.airlight, *p)).collect();
            rows.push(row(k, Some(Target::Rust), label, pts, &got, bound, None));
        }
        if let Some(gpu) = self.gpu {
            for (target, src) in &self.shaders {
                let got = gpu.airlight(src, &raw).map_err(self.gpu_error(*target))?;
                let got: Vec<f64> = got.into_iter().map(crate::from_kernel).collect();
                rows.push(row(k, Some(*target), label, pts, &got, bound, None));
            }
        }
        Ok(rows)
    }

    /// The canonical entry on the edge set ([`edge_points`]), held to `hull`.
    fn edge_rows(&self, hull: Bound) -> Result<Vec<Row>, GateError> {
        let mut pts = edge_points(self.k)?;
        if self.marches {
            // A uniform march's midpoints never land on the light: its finite value
            // on the ray through it is the engines' method, tolerated and stated.
            pts.retain(|(_, a)| a.is_finite());
        }
        self.point_rows(EDGE, &pts, hull)
    }

    /// The physical entry: random placements at world scales 1e-3 … 1e4, and the
    /// physical extreme set; both bounded by the largest declared bound (the
    /// extreme set where its canonical point lies in the declared hull).
    fn physical_rows(&self, sampled: Bound, hull: Bound) -> Result<Vec<Row>, GateError> {
        let (k, mut rows) = (self.k, Vec::new());
        let physical = physical_rays(k, PHYSICAL_RAYS, VALIDATION_SEED ^ 0x9A15)?;
        let extremes = physical_extremes(k)?;
        for (label, rays, bound) in [(PHYSICAL, &physical, sampled), (PHYS_EXTREME, &extremes, hull)] {
            let expected: Vec<(Point, f64)> = rays.iter().map(|r| (r.1, r.2)).collect();
            let f64s = airlight_truth::parallel::map(
                rays,
                |(r, _, _)| r.physical().radiance(f64::from(r.g), &|p| (self.model)(p)).unwrap_or(f64::NAN),
                &|_, _| {},
            );
            rows.push(row(k, None, label, &expected, &f64s, bound, None));
            if let Some(rk) = self.compiled {
                let got: Vec<f64> = rays.iter().map(|(r, _, _)| crate::from_kernel(r.radiance_of(rk))).collect();
                rows.push(row(k, Some(Target::Rust), label, &expected, &got, bound, None));
            }
            let Some(gpu) = self.gpu else { continue };
            let plain: Vec<crate::Ray> = rays.iter().map(|r| r.0).collect();
            for (target, src) in &self.shaders {
                let got = gpu.radiance(src, &plain).map_err(self.gpu_error(*target))?;
                let got: Vec<f64> = got.into_iter().map(crate::from_kernel).collect();
                rows.push(row(k, Some(*target), label, &expected, &got, bound, None));
            }
        }
        Ok(rows)
    }

    /// The spot entry: spot lights and RGB media, bounded like the physical entry.
    fn spot_rows(&self, sampled: Bound) -> Result<Vec<Row>, GateError> {
        let (k, mut rows) = (self.k, Vec::new());
        let cases = spot_rays(k, SPOT_RAYS, VALIDATION_SEED ^ 0x5B07)?;
        let expected: Vec<(Point, f64)> = cases.iter().flat_map(|c| c.reference.map(|v| (c.point, v))).collect();
        let held: Vec<f64> = cases.iter().flat_map(|c| [c.ulp_change; 3]).collect();
        let f64s: Vec<f64> = airlight_truth::parallel::map(
            &cases,
            |c| [0, 1, 2].map(|ch| c.ray.reference(ch, &|p| (self.model)(p)).unwrap_or(f64::NAN)),
            &|_, _| {},
        )
        .into_iter()
        .flatten()
        .collect();
        rows.push(row(k, None, SPOT, &expected, &f64s, sampled, Some(&held)));
        if let Some(rk) = self.compiled {
            let got: Vec<f64> =
                cases.iter().flat_map(|c| c.ray.spot_of(rk).unwrap_or([f32::NAN; 3])).map(crate::from_kernel).collect();
            rows.push(row(k, Some(Target::Rust), SPOT, &expected, &got, sampled, Some(&held)));
        }
        if let Some(gpu) = self.gpu {
            let plain: Vec<crate::SpotRay> = cases.iter().map(|c| c.ray).collect();
            for (target, src) in &self.shaders {
                let got = gpu.spot(src, &plain).map_err(self.gpu_error(*target))?;
                let got: Vec<f64> = got.into_iter().flatten().map(crate::from_kernel).collect();
                rows.push(row(k, Some(*target), SPOT, &expected, &got, sampled, Some(&held)));
            }
        }
        Ok(rows)
    }
}

impl Subject<'_> {
    /// The shafts accumulator fed the exact lit intervals of rays among
    /// occluders, held to `bound` relative to each ray's unshadowed value times
    /// one plus its visibility changes.
    fn shadowed_rows(&self, bound: Bound) -> Result<Vec<Row>, GateError> {
        let k = self.k;
        let mut cases = shadowed_rays(k, SHADOWED_RAYS, VALIDATION_SEED ^ 0x54AD)?;
        let spots = if k.has(Entry::Spot) {
            spot_shadowed_rays(k, &cases, SHADOWED_SPOT_RAYS, VALIDATION_SEED ^ 0x54AD)?
        } else {
            Vec::new()
        };
        cases.extend(kept_shadowed_rays(k)?);
        let mut held: Vec<Held> = cases.iter().map(ShadowCase::held).collect();
        held.extend(spots.iter().flat_map(SpotShadowCase::held));
        let f32s = |s: &[(f64, f64)]| s.iter().map(|&(a, b)| [a as f32, b as f32]).collect::<Vec<_>>();
        // The f64 model through the f64 accumulator.
        let mut f64s: Vec<f64> = airlight_truth::parallel::map(
            &cases,
            |c| {
                let phys = c.ray.physical();
                airlight_truth::shafts::evaluate(
                    &phys,
                    None,
                    f64::from(c.ray.g),
                    &c.samples,
                    &|p| (self.model)(p),
                    false,
                )
                .map_or(f64::NAN, |v| v.0)
            },
            &|_, _| {},
        );
        f64s.extend(
            airlight_truth::parallel::map(
                &spots,
                |c| {
                    let cone = c.ray.cone();
                    [0, 1, 2].map(|ch| {
                        let p = c.ray.physical(ch);
                        airlight_truth::shafts::evaluate(
                            &p,
                            cone.as_ref(),
                            f64::from(c.ray.g),
                            &c.samples,
                            &|q| (self.model)(q),
                            false,
                        )
                        .map_or(f64::NAN, |v| v.0)
                    })
                },
                &|_, _| {},
            )
            .into_iter()
            .flatten(),
        );
        let mut rows = vec![shadow_row(k, None, &held, &f64s, bound)];
        let samples: Vec<Vec<[f32; 2]>> = cases.iter().map(|c| f32s(&c.samples)).collect();
        let spot_samples: Vec<Vec<[f32; 2]>> = spots.iter().map(|c| f32s(&c.samples)).collect();
        if let Some(f) = self.compiled.and_then(|rk| rk.shadowed) {
            let mut got: Vec<f64> = cases
                .iter()
                .zip(&samples)
                .map(|(c, s)| {
                    let r = &c.ray;
                    crate::from_kernel(f(
                        s,
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
            if let Some(fs) = self.compiled.and_then(|rk| rk.spot_shadowed) {
                for (c, s) in spots.iter().zip(&spot_samples) {
                    let r = &c.ray;
                    let v = fs(
                        s,
                        r.surface,
                        r.origin,
                        r.dir,
                        r.light,
                        r.axis,
                        r.cos_outer,
                        r.cos_inner,
                        r.intensity,
                        r.sigma_t,
                        r.sigma_s,
                        r.g,
                    );
                    got.extend(v.map(crate::from_kernel));
                }
            }
            rows.push(shadow_row(k, Some(Target::Rust), &held, &got, bound));
        }
        if let Some(gpu) = self.gpu {
            let plain: Vec<crate::Ray> = cases.iter().map(|c| c.ray).collect();
            let spot_plain: Vec<crate::SpotRay> = spots.iter().map(|c| c.ray).collect();
            for (target, src) in &self.shaders {
                let mut got: Vec<f64> = gpu
                    .shadowed(src, &plain, &samples)
                    .map_err(self.gpu_error(*target))?
                    .into_iter()
                    .map(crate::from_kernel)
                    .collect();
                if !spots.is_empty() {
                    let v = gpu.spot_shadowed(src, &spot_plain, &spot_samples).map_err(self.gpu_error(*target))?;
                    got.extend(v.into_iter().flatten().map(crate::from_kernel));
                }
                rows.push(shadow_row(k, Some(*target), &held, &got, bound));
            }
        }
        Ok(rows)
    }
}

/// The shader files of `k` under `generated` that a GPU runs (WGSL, GLSL).
fn shader_texts(generated: &Path, k: &IndexEntry) -> Result<Vec<(Target, String)>, GateError> {
    let mut texts = Vec::new();
    for target in Target::ALL.into_iter().filter(|t| t.is_shader()) {
        if let Some(f) = k.file(target) {
            let path = generated.join(f);
            let text = std::fs::read_to_string(&path)
                .map_err(|e| GateError::Input(format!("{}: cannot read: {e}", path.display())))?;
            texts.push((target, text));
        }
    }
    Ok(texts)
}

/// The kernels of the index the gate runs (all, or those in `only`).
fn selected<'i>(index: &'i Index, only: &[String], generated: &Path) -> Result<Vec<&'i IndexEntry>, GateError> {
    if let Some(missing) = only.iter().find(|n| !index.kernel.iter().any(|k| &&k.name == n)) {
        return Err(GateError::Input(format!("no kernel '{missing}' in {}/kernels.toml", generated.display())));
    }
    Ok(index.kernel.iter().filter(|k| only.is_empty() || only.iter().any(|n| n == &k.name)).collect())
}

/// Runs the gate over the kernels under `generated` (all, or those in `only`):
/// the compiled Rust kernels in `rust` (they must be the ones under `generated`;
/// empty: the Rust target is not checked), the WGSL and GLSL files when `gpu` is
/// given, each f32 target held to the f32 bound `kernels.toml` declares.
/// `progress` gets a line per step.
pub fn run(
    generated: &Path,
    gpu: Option<&Gpu>,
    rust: &[CompiledKernel],
    only: &[String],
    progress: &dyn Fn(&str),
) -> Result<Vec<Row>, GateError> {
    Ok(run_with(generated, gpu, rust, only, false, progress)?.0)
}

/// [`run`], but measuring each kernel's f32 bounds first ([`F32Bound`]: what
/// `airlight check --record` writes) and holding the f32 targets to those.
pub fn run_measuring(
    generated: &Path,
    gpu: Option<&Gpu>,
    rust: &[CompiledKernel],
    only: &[String],
    progress: &dyn Fn(&str),
) -> Result<(Vec<Row>, Vec<F32Bound>), GateError> {
    run_with(generated, gpu, rust, only, true, progress)
}

fn run_with(
    generated: &Path,
    gpu: Option<&Gpu>,
    rust: &[CompiledKernel],
    only: &[String],
    measuring: bool,
    progress: &dyn Fn(&str),
) -> Result<(Vec<Row>, Vec<F32Bound>), GateError> {
    let index = load_index(generated)?;
    let models = catalog::load(&generated.join("coefficients")).map_err(|e| GateError::Input(e.to_string()))?;
    let kernels = selected(&index, only, generated)?;
    let mut ranges: Vec<(f64, f64)> = kernels.iter().filter(|k| k.scene.is_none()).map(|k| (k.g[0], k.g[1])).collect();
    ranges.sort_by(|a, b| a.partial_cmp(b).expect("no NaN"));
    ranges.dedup();
    progress("reference values on the validation sets");
    let validations = catalog::validations(&ranges, &|_, _| {});
    let (mut rows, mut bounds) = (Vec::new(), Vec::new());
    for k in kernels {
        progress(&k.name);
        let texts = shader_texts(generated, k)?;
        let table = crate::load_table(generated, k).map_err(|e| GateError::Input(e.to_string()))?;
        let compiled = match (rust.is_empty(), &k.rust) {
            (false, Some(_)) => Some(rust.iter().find(|r| r.name == k.name).ok_or_else(|| {
                GateError::Input(format!("kernel {} is not in the compiled airlight-kernels (rebuild)", k.name))
            })?),
            _ => None,
        };
        let subject = Subject {
            k,
            model: f64_model(k, &models)?,
            compiled,
            shaders: texts
                .iter()
                .map(|(t, text)| (*t, KernelSource::of(k, *t, text).with_table(table.as_ref())))
                .collect(),
            gpu,
            marches: model_file(k, &models)?.is_some_and(|m| matches!(m.model.body, Body::RayMarch(_))),
        };
        let sets = point_sets(k, &validations)?;
        // Each domain's bound: the model's, and the kernel's f32 bound (on the
        // extreme set, which it is not measured on, the model's).
        let mut domain_bounds = Vec::new();
        for d in Domain::ALL.into_iter().filter(|d| k.domains.contains(d) || *d == Domain::Extreme) {
            let model = declared(k, &models, d)?;
            let f32 = match (d, measuring) {
                (Domain::Extreme, _) | (_, true) => model,
                (d, false) => k.f32_bound(d).ok_or_else(|| {
                    let path = generated.join(airlight_shapes::vocab::INDEX_FILE);
                    let text = std::fs::read_to_string(&path).unwrap_or_default();
                    let n = index.kernel.iter().position(|e| e.name == k.name).unwrap_or(0);
                    let line = airlight_truth::tomlfile::locate_nth(&text, "kernel", n, &format!("f32_{d}_max_rel"));
                    GateError::Input(format!(
                        "{}:{line}: kernel {}: no f32_{d}_max_rel (its f32 bound on {d}): the gate record does not \
                         cover these kernel sources; run `airlight check --record`, then `airlight generate`",
                        path.display(),
                        k.name
                    ))
                })?,
            };
            domain_bounds.push((d, Bound { model, f32 }));
        }
        let bound_of = |d: Domain, b: &[(Domain, Bound)]| b.iter().find(|x| x.0 == d).map(|x| x.1);
        let mut canonical = Vec::new();
        for (d, pts) in &sets {
            let b = bound_of(*d, &domain_bounds).expect("one bound per checked domain");
            canonical.extend(subject.point_rows(d.name(), pts, b)?);
        }
        if measuring {
            let found = subject.f32_bounds(&sets, &canonical, &validations, &domain_bounds)?;
            for b in &found {
                if let Some(x) = domain_bounds.iter_mut().find(|x| x.0.name() == b.domain) {
                    x.1.f32 = b.max_rel;
                }
                for r in canonical.iter_mut().filter(|r| r.target.is_some() && r.domain == b.domain) {
                    r.declared = b.max_rel;
                }
            }
            bounds.extend(found);
        }
        rows.extend(canonical);
        let zero = Bound { model: 0.0, f32: 0.0 };
        let sampled = k.domains.iter().filter_map(|&d| bound_of(d, &domain_bounds)).fold(zero, Bound::max);
        let hull = sampled.max(bound_of(Domain::Extreme, &domain_bounds).unwrap_or(zero));
        rows.extend(subject.edge_rows(hull)?);
        rows.extend(subject.physical_rows(sampled, hull)?);
        if k.has(Entry::Spot) {
            rows.extend(subject.spot_rows(sampled)?);
        }
        // The march looks visibility up at its own steps: its error is not the
        // family's bound (docs/MATH.md §8), so it has no shadowed rows.
        if k.shafts && !subject.marches {
            rows.extend(subject.shadowed_rows(hull)?);
        }
    }
    Ok((rows, bounds))
}

/// A compiled Rust f32 kernel's canonical entry as a [`airlight_fit::model::Model`],
/// so that the declared-bound search ([`catalog::measure_within`]) can run on it.
struct F32Kernel<'a> {
    name: &'a str,
    g_range: (f64, f64),
    f: airlight_shapes::vocab::CanonicalFn,
}

impl airlight_fit::model::Model for F32Kernel<'_> {
    fn name(&self) -> &str {
        self.name
    }
    fn summary(&self) -> &str {
        "a compiled f32 kernel"
    }
    fn g_range(&self) -> (f64, f64) {
        self.g_range
    }
    fn eval_unchecked(&self, p: Point) -> f64 {
        rust_at(self.f, p)
    }
}

/// A compiled Rust kernel's canonical entry at `p` (arguments rounded to f32).
fn rust_at(f: airlight_shapes::vocab::CanonicalFn, p: Point) -> f64 {
    crate::from_kernel(f(p.tau as f32, p.gamma as f32, crate::rho_arg(p.rho), p.g as f32))
}

impl Subject<'_> {
    /// The kernel's f32 bound on each of `thin` and `dense` ([`F32Bound`]): the
    /// largest error of its f32 targets on the domain's set (`rows`, already
    /// measured), of the Rust f32 kernel over the declared-bound search (the
    /// validation set's face grids, held-out rounds and local searches; a scene
    /// kernel's on its projected set, searched within its subspace), and of each
    /// GPU target at the worst point that search found; never below the model's.
    fn f32_bounds(
        &self,
        sets: &[(Domain, Checked)],
        rows: &[Row],
        validations: &[Validation],
        bounds: &[(Domain, Bound)],
    ) -> Result<Vec<F32Bound>, GateError> {
        let k = self.k;
        let domains: Vec<&(Domain, Checked)> = sets.iter().filter(|(d, _)| *d != Domain::Extreme).collect();
        // The Rust kernel's searches, one domain per thread.
        let searched: Vec<Option<(f64, Point)>> = airlight_truth::parallel::map(
            &domains,
            |(d, pts)| {
                let rk = self.compiled?;
                let model = F32Kernel { name: &k.name, g_range: (k.g[0], k.g[1]), f: rk.airlight };
                let general = validations.iter().find(|v| v.domain == *d && v.g_range == (k.g[0], k.g[1]));
                let own;
                let v = match (k.scene.is_some(), general) {
                    (false, Some(v)) => v,
                    _ => {
                        own = Validation {
                            domain: *d,
                            g_range: (k.g[0], k.g[1]),
                            points: pts.clone(),
                            faces: Vec::new(),
                            held_out: Vec::new(),
                        };
                        &own
                    }
                };
                let e = catalog::measure_within(&model, v, &|p| project(k, p));
                Some((e.max_rel, e.worst))
            },
            &|_, _| {},
        );
        let mut out = Vec::new();
        for ((d, _), search) in domains.iter().zip(searched) {
            let model = bounds.iter().find(|b| b.0 == *d).map_or(0.0, |b| b.1.model);
            let mut best: (f64, &str, Option<Point>) = (model, "f64", None);
            // Every error found counts with the margin of a declared bound (the Rust
            // search's measure already carries it).
            let margin = 1.0 + catalog::DECLARED_MARGIN;
            for r in rows.iter().filter(|r| r.target.is_some() && r.domain == d.name()) {
                if r.max * margin > best.0 {
                    best = (r.max * margin, target_label(r.target), r.worst);
                }
            }
            if let Some((max_rel, worst)) = search {
                if max_rel > best.0 {
                    best = (max_rel, target_label(Some(Target::Rust)), Some(worst));
                }
                if let (Some(gpu), Ok(exact)) = (self.gpu, reference::airlight(worst)) {
                    let raw = [[worst.tau, worst.gamma, worst.rho, worst.g]];
                    for (target, src) in &self.shaders {
                        let got = gpu.airlight(src, &raw).map_err(self.gpu_error(*target))?;
                        let e = airlight_truth::stats::rel_error(crate::from_kernel(got[0]), exact) * margin;
                        if e > best.0 {
                            best = (e, target_label(Some(*target)), Some(worst));
                        }
                    }
                }
            }
            let at = best.2.map(|p| [p.tau, p.gamma, if p.rho.is_finite() { p.rho } else { -1.0 }, p.g]);
            out.push(F32Bound {
                kernel: k.name.clone(),
                domain: d.name().to_string(),
                max_rel: best.0,
                f64_max_rel: model,
                set_by: best.1.to_string(),
                at,
            });
        }
        Ok(out)
    }
}

/// The gate's rows as `generated/gate.toml` holds them, tied by digest to the
/// kernel sources under `generated` that were measured.
pub fn record(
    generated: &Path,
    rows: &[Row],
    f32_bounds: Vec<F32Bound>,
    adapter: String,
) -> Result<airlight_shapes::record::GateRecord, String> {
    let mut files = Vec::new();
    for dir in ["wgsl", "wgsl/bevy", "glsl", "airlight-kernels/src"] {
        let entries = std::fs::read_dir(generated.join(dir))
            .map_err(|e| format!("{}: cannot read: {e}", generated.join(dir).display()))?;
        for e in entries.flatten() {
            if e.path().is_file() {
                let bytes =
                    std::fs::read(e.path()).map_err(|err| format!("{}: cannot read: {err}", e.path().display()))?;
                files.push((format!("{dir}/{}", e.file_name().to_string_lossy()), bytes));
            }
        }
    }
    Ok(airlight_shapes::record::GateRecord {
        adapter,
        kernels_digest: airlight_shapes::record::digest(&files),
        rows: rows
            .iter()
            .map(|r| airlight_shapes::record::GateRow {
                kernel: r.kernel.clone(),
                target: target_label(r.target).to_string(),
                domain: r.domain.to_string(),
                points: r.points,
                max_rel: r.max,
                p99_rel: r.p99,
                limit: r.limit(),
                bad: r.bad,
            })
            .collect(),
        f32_bounds,
    })
}

/// The line `airlight check` prints after its rows: kernels, targets, rows, the
/// limit, and how much of the f32 allowance the worst row uses (negative: within
/// the f64 bound).
pub fn summary(rows: &[Row]) -> String {
    let kernels: std::collections::BTreeSet<&str> = rows.iter().map(|r| r.kernel.as_str()).collect();
    let targets: std::collections::BTreeSet<&str> = rows.iter().map(|r| target_label(r.target)).collect();
    let worst = rows
        .iter()
        .filter(|r| r.target.is_some())
        .map(|r| (r.max - r.declared) / (r.limit() - r.declared))
        .fold(f64::NEG_INFINITY, f64::max);
    format!(
        "check: {} kernels × {{{}}} × domains = {} rows; f32 targets on thin and dense: limit = f32 bound × (1 + {:.0e}) + {:.1e}, elsewhere = bound × (1 + {:.0e}) + {:.0e}; the worst row uses {:.1}% of its allowance",
        kernels.len(),
        targets.into_iter().collect::<Vec<_>>().join(", "),
        rows.len(),
        F32_REL_ALLOWANCE,
        F32_ADAPTER_ALLOWANCE,
        F32_REL_ALLOWANCE,
        F32_ALLOWANCE,
        100.0 * worst
    )
}

/// The table `airlight check` prints: every row, or only failures.
pub fn table(rows: &[Row], failures_only: bool) -> String {
    let mut out = format!(
        "{:<20} {:<8} {:<8} {:>6} {:>9} {:>9} {:>9}  {:<6} worst point\n",
        "kernel", "target", "domain", "points", "max", "p99", "limit", "status"
    );
    for r in rows.iter().filter(|r| !failures_only || !r.passes()) {
        let worst = match (&r.first_bad, &r.worst) {
            (Some((p, v)), _) => format!("{} bad value(s), first {v} at {}", r.bad, fmt_point(p)),
            (None, Some(p)) => fmt_point(p),
            (None, None) => "—".into(),
        };
        out.push_str(&format!(
            "{:<20} {:<8} {:<8} {:>6} {:>9.2e} {:>9.2e} {:>9.2e}  {:<6} {worst}\n",
            r.kernel,
            target_label(r.target),
            r.domain,
            r.points,
            r.max,
            r.p99,
            r.limit(),
            if r.passes() { "ok" } else { "FAIL" }
        ));
    }
    out
}

fn fmt_point(p: &Point) -> String {
    format!(
        "(τ {:.6}, γ {:.6}, ρ {}, g {:.4})",
        p.tau,
        p.gamma,
        if p.rho.is_infinite() { "∞".into() } else { format!("{:.6}", p.rho) },
        p.g
    )
}

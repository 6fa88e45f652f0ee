//! The gate's point and ray sets: each kernel's validation sets projected onto
//! what it takes, the edge points, the physical rays placed to hit chosen
//! canonical points, and the physical extreme set.

use super::*;
use airlight_fit::catalog::Validation;
use airlight_shapes::vocab::IndexEntry;
use airlight_truth::domains::{Domain, VALIDATION_POINTS, VALIDATION_SEED};
use airlight_truth::reference::{self, Point};

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
pub(crate) type Checked = Vec<(Point, f64)>;

/// The points and reference values a kernel is checked on, per domain.
pub(crate) fn point_sets(k: &IndexEntry, validations: &[Validation]) -> Result<Vec<(Domain, Checked)>, GateError> {
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
pub(crate) fn with_reference(k: &IndexEntry, mut pts: Vec<Point>) -> Result<Checked, GateError> {
    pts.sort_by(|a, b| (a.tau, a.gamma, a.rho, a.g).partial_cmp(&(b.tau, b.gamma, b.rho, b.g)).expect("no NaN"));
    pts.dedup();
    let values = airlight_truth::parallel::map(&pts, |p| reference::airlight(*p), &|_, _| {});
    pts.into_iter()
        .zip(values)
        .map(|(p, v)| v.map(|a| (p, a)).map_err(|e| GateError::Input(format!("{}: {e}", k.name))))
        .collect()
}

/// The end of kernel `k`'s sampled domains in τ.
pub(crate) fn tau_max(k: &IndexEntry) -> f64 {
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
pub(crate) fn placements(k: &IndexEntry, n: usize, seed: u64) -> Result<Vec<(crate::Ray, Point, f64)>, GateError> {
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

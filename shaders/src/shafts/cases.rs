//! The gate's shadowed cases: rays among occluders with the exact lit intervals the
//! shadowed reference finds, the kept rays (`KEPT_SHADOWED`) and the spot cases,
//! and the rows that hold a kernel's shafts accumulator to its bound on them.

use crate::gate::subject::Subject;
use crate::gate::*;
use airlight_shapes::vocab::{Entry, IndexEntry};
use airlight_truth::domains::VALIDATION_SEED;
use airlight_truth::reference::{self, Point};

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
pub(crate) struct Held {
    pub(crate) point: Point,
    pub(crate) reference: f64,
    pub(crate) unshadowed: f64,
    pub(crate) transitions: usize,
}

impl ShadowCase {
    pub(crate) fn held(&self) -> Held {
        Held {
            point: self.point,
            reference: self.reference,
            unshadowed: self.unshadowed,
            transitions: self.transitions,
        }
    }
}

impl SpotShadowCase {
    pub(crate) fn held(&self) -> [Held; 3] {
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
pub(crate) fn shadow_row(k: &IndexEntry, target: Option<Target>, items: &[Held], got: &[f64], bound: Bound) -> Row {
    shadow_row_in(SHADOWED, k, target, items, got, bound)
}

/// [`shadow_row`] in the regime `domain`.
pub(crate) fn shadow_row_in(
    domain: &'static str,
    k: &IndexEntry,
    target: Option<Target>,
    items: &[Held],
    got: &[f64],
    bound: Bound,
) -> Row {
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

impl Subject<'_> {
    /// The shafts accumulator fed the exact lit intervals of rays among
    /// occluders, held to `bound` relative to each ray's unshadowed value times
    /// one plus its visibility changes.
    pub(crate) fn shadowed_rows(&self, bound: Bound) -> Result<Vec<Row>, GateError> {
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
        let f64s = self.shadowed_f64(&cases, &spots);
        let mut rows = vec![shadow_row(k, None, &held, &f64s, bound)];
        let samples: Vec<Vec<[f32; 2]>> = cases.iter().map(|c| f32s(&c.samples)).collect();
        let spot_samples: Vec<Vec<[f32; 2]>> = spots.iter().map(|c| f32s(&c.samples)).collect();
        if let Some(got) = self.shadowed_rust(&cases, &samples, &spots, &spot_samples) {
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

    /// The f64 model through the f64 accumulator: one value per point case, then
    /// three (R, G, B) per spot case.
    fn shadowed_f64(&self, cases: &[ShadowCase], spots: &[SpotShadowCase]) -> Vec<f64> {
        let mut f64s: Vec<f64> = airlight_truth::parallel::map(
            cases,
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
                spots,
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
        f64s
    }

    /// The compiled Rust kernel's accumulator on the same samples, where it has one.
    fn shadowed_rust(
        &self,
        cases: &[ShadowCase],
        samples: &[Vec<[f32; 2]>],
        spots: &[SpotShadowCase],
        spot_samples: &[Vec<[f32; 2]>],
    ) -> Option<Vec<f64>> {
        let f = self.compiled.and_then(|rk| rk.shadowed)?;
        let mut got: Vec<f64> = cases
            .iter()
            .zip(samples)
            .map(|(c, s)| {
                let r = &c.ray;
                crate::from_kernel(f(s, r.surface, r.origin, r.dir, r.light, r.intensity, r.sigma_t, r.sigma_s, r.g))
            })
            .collect();
        if let Some(fs) = self.compiled.and_then(|rk| rk.spot_shadowed) {
            for (c, s) in spots.iter().zip(spot_samples) {
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
        Some(got)
    }
}

//! One kernel under the gate ([`Subject`]): its f64 model, its compiled Rust kernel
//! and its shaders, measured row by row on each set, and its f32 bounds.

use super::*;
use crate::{Gpu, GpuError, KernelSource};
use airlight_fit::catalog::{self, Validation};
use airlight_fit::coeffs::ModelFile;
use airlight_shapes::vocab::{CompiledKernel, IndexEntry};
use airlight_truth::domains::{Domain, VALIDATION_SEED};
use airlight_truth::reference::{self, Point};

/// The f64 model of kernel `k` at a canonical point: its fitted model, or the
/// closed form for a kernel without one (the no-extinction family is exact
/// there, the reference's own value).
pub(crate) fn f64_model<'m>(
    k: &IndexEntry,
    models: &'m [ModelFile],
) -> Result<Box<dyn Fn(Point) -> f64 + Sync + 'm>, GateError> {
    Ok(match model_file(k, models)? {
        Some(m) => Box::new(move |p| airlight_fit::model::Model::eval_unchecked(&m.model, p)),
        None => Box::new(|p| airlight_fit::family::CLOSED_FORM.eval(p)),
    })
}

/// The coefficient file of kernel `k`'s model (`None`: the closed form, which
/// has none).
pub(crate) fn model_file<'m>(k: &IndexEntry, models: &'m [ModelFile]) -> Result<Option<&'m ModelFile>, GateError> {
    let Some(name) = &k.model else { return Ok(None) };
    models
        .iter()
        .find(|m| &m.model.name == name)
        .map(Some)
        .ok_or_else(|| GateError::Input(format!("kernel {}: no coefficient file for model {name}", k.name)))
}

/// Statistics of one kernel's values against the reference.
pub(crate) fn row(
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
pub(crate) fn declared(k: &IndexEntry, models: &[ModelFile], domain: Domain) -> Result<f64, GateError> {
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
pub(crate) struct Subject<'a> {
    pub(crate) k: &'a IndexEntry,
    pub(crate) model: Box<dyn Fn(Point) -> f64 + Sync + 'a>,
    pub(crate) compiled: Option<&'a CompiledKernel>,
    pub(crate) shaders: Vec<(Target, KernelSource<'a>)>,
    pub(crate) gpu: Option<&'a Gpu>,
    /// The shadow-map walk's generated sources.
    pub(crate) walk: crate::shafts::WalkSources<'a>,
    /// Whether it is the uniform ray march (the engines' method), which cannot
    /// see the divergence on the ray through the light.
    pub(crate) marches: bool,
}

impl Subject<'_> {
    /// A GPU failure of this kernel on `target`.
    pub(crate) fn gpu_error(&self, target: Target) -> impl Fn(GpuError) -> GateError + '_ {
        move |e| GateError::Gpu(format!("{} ({})", self.k.name, target.name()), e)
    }

    /// The canonical entry on `pts`, one row per target (the f64 model, the Rust
    /// kernel, each shader), labelled `label` and held to `bound`.
    pub(crate) fn point_rows(&self, label: &'static str, pts: &Checked, bound: Bound) -> Result<Vec<Row>, GateError> {
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
    pub(crate) fn edge_rows(&self, hull: Bound) -> Result<Vec<Row>, GateError> {
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
    pub(crate) fn physical_rows(&self, sampled: Bound, hull: Bound) -> Result<Vec<Row>, GateError> {
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
    pub(crate) fn spot_rows(&self, sampled: Bound) -> Result<Vec<Row>, GateError> {
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

/// A compiled Rust f32 kernel's canonical entry as a [`airlight_fit::model::Model`],
/// so that the declared-bound search ([`catalog::measure_within`]) can run on it.
pub(crate) struct F32Kernel<'a> {
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
pub(crate) fn rust_at(f: airlight_shapes::vocab::CanonicalFn, p: Point) -> f64 {
    crate::from_kernel(f(p.tau as f32, p.gamma as f32, crate::rho_arg(p.rho), p.g as f32))
}

impl Subject<'_> {
    /// The kernel's f32 bound on each of `thin` and `dense` ([`F32Bound`]): the
    /// largest error of its f32 targets on the domain's set (`rows`, already
    /// measured), of the Rust f32 kernel over the declared-bound search (the
    /// validation set's face grids, held-out rounds and local searches; a scene
    /// kernel's on its projected set, searched within its subspace), and of each
    /// GPU target at the worst point that search found; never below the model's.
    pub(crate) fn f32_bounds(
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

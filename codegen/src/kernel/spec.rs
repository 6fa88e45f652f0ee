//! What each kernel needs: a [`KernelSpec`], computed from a coefficient file
//! and, for scenes, the scene's plan — its phase handling, what it keeps, its
//! declared bound and its entry points' arguments.

use crate::scene::{Choice, Plan, Scene, ScenePhase};
use airlight_fit::approx::Body;
use airlight_fit::coeffs::ModelFile;
use airlight_fit::family::CLOSED_FORM;
use airlight_shapes::cost::{Cost, PhaseShape, Shape};
pub use airlight_shapes::template::KernelPhase;
use airlight_shapes::template::WantPhase;
use airlight_shapes::vocab::{Arg, Domain, Entry, Target};
use airlight_truth::stats::fmt_err;

/// Gauss–Legendre nodes per piece of a penumbra stretch of a soft-edged spot
/// light (the spot entry's only approximation beyond its family's).
pub const SPOT_EDGE_NODES: usize = 8;

/// The pieces of a penumbra stretch, as fractions of it: graded towards both
/// ends, where the integrand gathers (the phase peaks, the transmittance's tail
/// to infinity, its fast decay in dense media). With the control variate of the
/// spot entry (then the weight at the peak's end times the family's exact `A`; now
/// the smaller end weight, docs/MATH.md §7), measured in
/// f64 on 16,882 random stretches (γ down to 1e-4, |g| to 0.999, τ to 20): median
/// 1.3e-14, p99 1.4e-8, max 7.9e-6 of the stretch's own integral; the single
/// 8-point rule it replaces reached 100% there (issue 23).
pub const SPOT_EDGE_PIECES: [f64; 6] = [0.0, 1.0 / 32.0, 0.25, 0.75, 31.0 / 32.0, 1.0];

/// Everything that shapes one kernel.
#[derive(Debug, Clone)]
pub struct KernelSpec {
    /// `segments-8`, `scene-fog-street`.
    pub name: String,
    /// The model, or `None` for the no-extinction closed form.
    pub model: Option<ModelFile>,
    /// Phase handling.
    pub phase: KernelPhase,
    /// Whether rays can end on a surface.
    pub surfaces: bool,
    /// Whether it has the spot entry (spot lights, RGB media); needs `surfaces`,
    /// since a cone ends the lit stretch.
    pub spot: bool,
    /// Whether it has the shafts accumulator (shadowed in-scattering, docs/MATH.md
    /// §8); needs `surfaces`, since each lit run ends like a surface.
    pub shafts: bool,
    /// Whether extinction is modelled (false: τ = 0).
    pub extinction: bool,
    /// Whether the backward part (beyond the foot point) is kept.
    pub backscatter: bool,
    /// The declared bound, as one line.
    pub bound: String,
    /// Where it came from: `None` for a model kernel, the scene file for scenes.
    pub scene: Option<String>,
    /// Error domains its bound is taken over.
    pub domains: Vec<Domain>,
    /// The `g` it serves: the model's range, or the scene's (`g` outside it may
    /// fall outside the bands a scene kernel keeps).
    pub g_range: (f64, f64),
    /// Targets to emit.
    pub targets: Vec<Target>,
    /// Its f32 bound on each of its sampled domains, as the gate record
    /// (`generated/gate.toml`) measured it on these very sources; empty when the
    /// record is missing or measured other sources.
    pub f32: Vec<(Domain, f64)>,
    /// Its general kernel's measured cost, where `generated/bench.json` has it
    /// (filled by `render_all`; the engine packages quote it).
    pub measured: Option<Measured>,
}

/// A kernel's cost as `airlight bench` measured it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    /// CPU ns per evaluation of the f32 Rust kernel (median, random points).
    pub cpu_ns: f64,
    /// GPU-path ns per evaluation over frame-coherent points (WGSL through wgpu
    /// on the bench's adapter); `None` where not measured.
    pub gpu_ns: Option<f64>,
}

/// The declared max of `m` on each of `domains`, as `thin 9.8e-6, dense 2.8e-6`.
pub fn domain_bound(m: &ModelFile, domains: &[Domain], g_range: (f64, f64)) -> String {
    let baked = (g_range.0 == g_range.1).then_some(g_range.0);
    let band = baked.is_some_and(|g| m.bands.iter().any(|b| b.g.0 <= g && g <= b.g.1));
    let text = domains
        .iter()
        .filter_map(|&d| m.bound_at(d, baked).map(|e| format!("{d} {}", fmt_err(e))))
        .collect::<Vec<_>>()
        .join(", ");
    if band {
        format!("{text} (over the band of g holding g = {})", g_range.0)
    } else {
        text
    }
}

impl KernelSpec {
    /// The general kernel of a model: surfaces, extinction, backscatter, and its whole `g` range.
    pub fn for_model(m: &ModelFile) -> KernelSpec {
        let phase = m.model.body.kernel_phase(m.model.g_range, WantPhase::General);
        KernelSpec {
            name: m.model.name.clone(),
            bound: format!(
                "max relative error of A (f64 model): {}",
                domain_bound(m, &[Domain::Thin, Domain::Dense], m.model.g_range)
            ),
            model: Some(m.clone()),
            phase,
            surfaces: true,
            spot: true,
            shafts: true,
            extinction: true,
            backscatter: true,
            scene: None,
            domains: vec![Domain::Thin, Domain::Dense],
            g_range: m.model.g_range,
            targets: Target::ALL.to_vec(),
            f32: Vec::new(),
            measured: None,
        }
    }

    /// The specialised kernel of a scene, from its plan.
    pub fn for_scene(scene: &Scene, plan: &Plan, models: &[ModelFile], scene_file: &str) -> KernelSpec {
        let name = format!("scene-{}", scene.name);
        let common = |model: Option<ModelFile>, phase: KernelPhase, bound: String| KernelSpec {
            name: name.clone(),
            model,
            phase,
            surfaces: scene.surfaces,
            spot: scene.spot,
            shafts: scene.shadows,
            extinction: scene.extinction,
            backscatter: scene.backscatter,
            bound,
            scene: Some(scene_file.to_string()),
            domains: plan.domains.clone(),
            g_range: scene.phase.g_range(),
            targets: scene.targets.clone(),
            f32: Vec::new(),
            measured: None,
        };
        match &plan.choice {
            Choice::NoExtinction => {
                common(None, KernelPhase::Isotropic, "exact (closed form); f32 rounding only".into())
            }
            Choice::Model { name: model, .. } => {
                let m = models.iter().find(|m| &m.model.name == model).expect("the plan names a loaded model").clone();
                let want = match scene.phase {
                    ScenePhase::Isotropic => WantPhase::Isotropic,
                    ScenePhase::Fixed(g) => WantPhase::Fixed(g),
                    ScenePhase::Range(lo, hi) => WantPhase::Range(lo, hi),
                };
                let phase = m.model.body.kernel_phase(m.model.g_range, want);
                let mut bound = format!(
                    "max relative error of A (f64 model, over {}): {}",
                    join_domains(&plan.domains),
                    domain_bound(&m, &plan.domains, scene.phase.g_range())
                );
                if !scene.backscatter {
                    bound.push_str("; without the backward part (by request): up to 100% looking away from a light");
                }
                common(Some(m), phase, bound)
            }
        }
    }

    /// The `g` baked into the kernel, if one is (`None`: `g` at run time).
    pub fn baked_g(&self) -> Option<f64> {
        (self.g_range.0 == self.g_range.1).then_some(self.g_range.0)
    }

    /// Its model's declared bound on `domain`: over the band of `g` holding a
    /// baked `g` where the model has bands ([`ModelFile::bound_at`]); `None` for
    /// the closed form or a domain the model does not declare.
    pub fn declared(&self, domain: Domain) -> Option<f64> {
        self.model.as_ref().and_then(|m| m.bound_at(domain, self.baked_g()))
    }

    /// Its recorded f32 bound on `domain` ([`KernelSpec::f32`]).
    pub fn f32_bound(&self, domain: Domain) -> Option<f64> {
        self.f32.iter().find(|(d, _)| *d == domain).map(|&(_, e)| e)
    }

    /// Error domains its declared bound is taken over.
    pub fn domains(&self) -> &[Domain] {
        &self.domains
    }

    /// The kernel's name as an identifier.
    pub fn ident(&self) -> String {
        self.name.replace('-', "_")
    }

    /// The prefix of every item in the plain WGSL and GLSL kernels (the index's).
    pub fn prefix(&self) -> String {
        format!("airlight_{}_", self.ident())
    }

    /// Whether `g` is a run-time parameter.
    pub fn g_param(&self) -> bool {
        matches!(self.phase, KernelPhase::Banded(_) | KernelPhase::Exact)
    }

    /// Whether τ (and σt) are arguments: extinction modelled by a fitted model.
    pub fn takes_tau(&self) -> bool {
        self.extinction && self.body().extinction()
    }

    /// Arguments of the canonical entry `airlight`, in order.
    pub fn params(&self) -> Vec<Arg> {
        self.args(Entry::Canonical)
    }

    /// Arguments of `entry`, in order: the entry's arguments less those this
    /// kernel was specialised away from.
    pub fn args(&self, entry: Entry) -> Vec<Arg> {
        if entry == Entry::Spot && !self.spot {
            return Vec::new();
        }
        entry
            .all_args()
            .iter()
            .copied()
            .filter(|a| match a {
                Arg::Tau | Arg::SigmaT | Arg::SigmaTRgb => self.takes_tau(),
                Arg::Rho | Arg::Surface => self.surfaces,
                Arg::G => self.g_param(),
                _ => true,
            })
            .collect()
    }

    /// Arguments of the physical entry `radiance`, in order.
    pub fn radiance_params(&self) -> Vec<Arg> {
        self.args(Entry::Radiance)
    }

    /// The family values it evaluates: its model's, or the closed form's.
    pub fn body(&self) -> &Body {
        self.model.as_ref().map_or(&CLOSED_FORM, |m| &m.model.body)
    }

    /// What the kernel keeps, as far as its cost goes.
    pub fn shape(&self) -> Shape {
        let phase = match self.phase {
            KernelPhase::Isotropic => PhaseShape::Isotropic,
            _ => self.body().phase_shape(),
        };
        Shape { phase, backscatter: self.backscatter, surfaces: self.surfaces }
    }

    /// Worst-case operation count of one evaluation of this f32 kernel (the
    /// canonical entry), from its family (`ops` of its `Family`).
    pub fn op_count(&self) -> Cost {
        self.body().ops(self.shape())
    }
}

/// What a kernel was specialised to, in words.
pub fn specialisations(spec: &KernelSpec) -> String {
    let mut s = Vec::new();
    s.push(match &spec.phase {
        KernelPhase::Isotropic => "isotropic, P = 1/(4π) folded into constants".to_string(),
        KernelPhase::Fixed(g) => format!("Henyey–Greenstein at g = {g} baked in"),
        KernelPhase::Banded(b) => format!("g at run time ({} band{})", b.len(), if b.len() == 1 { "" } else { "s" }),
        KernelPhase::Exact => "g at run time, Henyey–Greenstein exact".to_string(),
    });
    s.push(if spec.surfaces { "rays may end early (ρ argument)".into() } else { "rays run to infinity".into() });
    if !spec.extinction {
        s.push("no extinction (τ = 0)".into());
    }
    if !spec.backscatter {
        s.push("no backward part".into());
    }
    s.join(", ")
}

/// Domains as prose: `thin and dense`.
pub fn join_domains(domains: &[Domain]) -> String {
    domains.iter().map(|d| d.name()).collect::<Vec<_>>().join(" and ")
}

//! Shader and Rust kernels: what each kernel needs (a [`KernelSpec`], computed from
//! a coefficient file and, for scenes, the scene's specialisations), and their
//! rendering through the templates under `codegen/templates/kernels/` as listed in
//! the output table `codegen/outputs.toml`.
//!
//! Names, f32 literals and every derived constant are computed here; the templates
//! only lay code out. Constants are rounded once, from the exact f64 coefficients,
//! to the nearest f32 and printed with 9 significant digits (which reads back as
//! the same f32 in WGSL, GLSL and Rust).

use crate::output::Output;
use crate::scene::{Choice, Plan, Scene, ScenePhase};
use airlight_fit::approx::{Body, PhaseModel, Split};
use airlight_fit::coeffs::ModelFile;
use airlight_fit::cost::{Cost, PhaseShape, Shape};
use airlight_fit::family::baseline::{FAR_PLANE, MARCH_CUTOFF};
use airlight_fit::family::closed::NoExtinction;
use airlight_fit::family::expsum::{LOCAL_RATIO, SPLIT};
use airlight_fit::family::phase_exp::ExpPhase;
use airlight_fit::vocab::{Arg, ArgType, Domain, Entry, Target};
pub use airlight_fit::vocab::{Index, IndexEntry};
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

/// Gauss–Legendre nodes per penumbra stretch of a soft-edged spot light (the
/// spot entry's only approximation beyond its family's).
pub const SPOT_EDGE_NODES: usize = 8;

/// The output table (`codegen/outputs.toml`).
pub const OUTPUT_TABLE: &str = include_str!("../outputs.toml");

/// Templates, by file name.
pub const TEMPLATES: [(&str, &str); 27] = [
    ("spot.rs.tera", include_str!("../templates/kernels/spot.rs.tera")),
    ("spot.wgsl.tera", include_str!("../templates/kernels/spot.wgsl.tera")),
    ("spot.glsl.tera", include_str!("../templates/kernels/spot.glsl.tera")),
    ("phi.rs.tera", include_str!("../templates/kernels/phi.rs.tera")),
    ("phi.wgsl.tera", include_str!("../templates/kernels/phi.wgsl.tera")),
    ("phi.glsl.tera", include_str!("../templates/kernels/phi.glsl.tera")),
    ("sun.rs.tera", include_str!("../templates/kernels/sun.rs.tera")),
    ("sun.wgsl.tera", include_str!("../templates/kernels/sun.wgsl.tera")),
    ("sun.glsl.tera", include_str!("../templates/kernels/sun.glsl.tera")),
    ("march.rs.tera", include_str!("../templates/kernels/march.rs.tera")),
    ("march.wgsl.tera", include_str!("../templates/kernels/march.wgsl.tera")),
    ("march.glsl.tera", include_str!("../templates/kernels/march.glsl.tera")),
    ("equiangular.rs.tera", include_str!("../templates/kernels/equiangular.rs.tera")),
    ("equiangular.wgsl.tera", include_str!("../templates/kernels/equiangular.wgsl.tera")),
    ("equiangular.glsl.tera", include_str!("../templates/kernels/equiangular.glsl.tera")),
    ("plan.md.tera", include_str!("../templates/kernels/plan.md.tera")),
    ("kernel.rs.tera", include_str!("../templates/kernels/kernel.rs.tera")),
    ("closed.rs.tera", include_str!("../templates/kernels/closed.rs.tera")),
    ("kernel.wgsl.tera", include_str!("../templates/kernels/kernel.wgsl.tera")),
    ("closed.wgsl.tera", include_str!("../templates/kernels/closed.wgsl.tera")),
    ("kernel.glsl.tera", include_str!("../templates/kernels/kernel.glsl.tera")),
    ("closed.glsl.tera", include_str!("../templates/kernels/closed.glsl.tera")),
    ("math.wgsl.tera", include_str!("../templates/kernels/math.wgsl.tera")),
    ("math.glsl.tera", include_str!("../templates/kernels/math.glsl.tera")),
    ("Cargo.toml.tera", include_str!("../templates/kernels/Cargo.toml.tera")),
    ("lib.rs.tera", include_str!("../templates/kernels/lib.rs.tera")),
    ("math.rs.tera", include_str!("../templates/kernels/math.rs.tera")),
];

/// One row of the kernel table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KernelOutput {
    /// The language.
    pub target: Target,
    /// The template of each family, by its kind (`Body::kind`).
    pub templates: std::collections::BTreeMap<String, String>,
    /// Output path pattern.
    pub path: String,
    /// Prefix of every item (pattern).
    pub prefix: String,
    /// `#define_import_path` (pattern), for naga_oil modules.
    #[serde(default)]
    pub import_path: Option<String>,
    /// What this variant is.
    pub variant: String,
}

/// A file rendered once.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileOutput {
    /// Template.
    pub template: String,
    /// Output path (pattern, for plans).
    pub path: String,
}

/// The whole table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputTable {
    /// Per-kernel outputs.
    pub kernel: Vec<KernelOutput>,
    /// Files of the Rust crate.
    pub crate_file: Vec<FileOutput>,
    /// Per-scene plan.
    pub plan: Vec<FileOutput>,
    /// Per-kernel translations of a rendered kernel by naga.
    pub translation: Vec<Translation>,
}

/// A kernel file translated from another by one of naga's back ends.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Translation {
    /// The rendered file it translates (pattern).
    pub from: String,
    /// naga's back end.
    pub backend: crate::translate::Backend,
    /// Output path pattern.
    pub path: String,
    /// What this variant is (pattern).
    pub variant: String,
}

impl OutputTable {
    /// The committed table.
    pub fn standard() -> OutputTable {
        toml::from_str(OUTPUT_TABLE).expect("codegen/outputs.toml parses (checked by a test)")
    }
}

/// The nearest f32 to `x`, printed with 9 significant digits (round-trips in every target).
pub fn lit(x: f64) -> String {
    let v = x as f32;
    if v == 0.0 {
        return "0.0".into();
    }
    format!("{v:.8e}")
}

/// How a kernel evaluates the phase function.
#[derive(Debug, Clone, PartialEq)]
pub enum KernelPhase {
    /// `1/(4π)`: no phase code.
    Isotropic,
    /// One `g`, its terms baked in.
    Fixed(f64),
    /// `g` at run time, over these bands of `|g|` (a band search).
    Banded(Vec<usize>),
    /// `g` at run time, Henyey–Greenstein evaluated exactly (the baselines).
    Exact,
}

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
}

/// Whether the model evaluates Henyey–Greenstein exactly with `g` at run time
/// (the baselines that take `g`), rather than through fitted phase terms.
fn exact_phase(m: &ModelFile) -> bool {
    m.model.split().is_none() && m.model.g_range != (0.0, 0.0)
}

fn domain_bound(m: &ModelFile, domains: &[Domain]) -> String {
    domains
        .iter()
        .filter_map(|&d| m.error(d).map(|e| format!("{d} {}", crate::report::fmt_err(e.max_rel))))
        .collect::<Vec<_>>()
        .join(", ")
}

impl KernelSpec {
    /// The general kernel of a model: surfaces, extinction, backscatter, and its whole `g` range.
    pub fn for_model(m: &ModelFile) -> KernelSpec {
        let phase = match m.model.split().map(|s| &s.phase) {
            None if exact_phase(m) => KernelPhase::Exact,
            None | Some(PhaseModel::Isotropic) => KernelPhase::Isotropic,
            Some(PhaseModel::Exp(e)) => KernelPhase::Banded((0..e.bands.len()).collect()),
        };
        KernelSpec {
            name: m.model.name.clone(),
            bound: format!("max relative error of A (f64 model): {}", domain_bound(m, &[Domain::Thin, Domain::Dense])),
            model: Some(m.clone()),
            phase,
            surfaces: true,
            spot: true,
            extinction: true,
            backscatter: true,
            scene: None,
            domains: vec![Domain::Thin, Domain::Dense],
            g_range: m.model.g_range,
            targets: Target::ALL.to_vec(),
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
            extinction: scene.extinction,
            backscatter: scene.backscatter,
            bound,
            scene: Some(scene_file.to_string()),
            domains: plan.domains.clone(),
            g_range: scene.phase.g_range(),
            targets: scene.targets.clone(),
        };
        match &plan.choice {
            Choice::NoExtinction => {
                common(None, KernelPhase::Isotropic, "exact (closed form); f32 rounding only".into())
            }
            Choice::Model { name: model, .. } => {
                let m = models.iter().find(|m| &m.model.name == model).expect("the plan names a loaded model").clone();
                let exact = exact_phase(&m);
                let phase = match (m.model.split().map(|s| &s.phase), &scene.phase) {
                    (_, ScenePhase::Isotropic) => KernelPhase::Isotropic,
                    (None, ScenePhase::Fixed(g)) if exact => KernelPhase::Fixed(*g),
                    (None, ScenePhase::Range(..)) if exact => KernelPhase::Exact,
                    (None | Some(PhaseModel::Isotropic), _) => KernelPhase::Isotropic,
                    (Some(PhaseModel::Exp(_)), ScenePhase::Fixed(g)) => KernelPhase::Fixed(*g),
                    (Some(PhaseModel::Exp(e)), ScenePhase::Range(lo, hi)) => {
                        let (alo, ahi) = if *lo <= 0.0 && *hi >= 0.0 {
                            (0.0, lo.abs().max(hi.abs()))
                        } else {
                            (lo.abs().min(hi.abs()), lo.abs().max(hi.abs()))
                        };
                        KernelPhase::Banded(
                            (0..e.bands.len())
                                .filter(|&i| {
                                    let b = &e.bands[i];
                                    // the band search takes the first band whose top reaches |g|
                                    let below = if i == 0 { f64::NEG_INFINITY } else { e.bands[i - 1].g_hi };
                                    (b.g_hi >= alo || i + 1 == e.bands.len()) && below < ahi
                                })
                                .collect(),
                        )
                    }
                };
                let mut bound = format!(
                    "max relative error of A (f64 model, over {}): {}",
                    join_domains(&plan.domains),
                    domain_bound(&m, &plan.domains)
                );
                if !scene.backscatter {
                    bound.push_str("; without the backward part (by request): up to 100% looking away from a light");
                }
                common(Some(m), phase, bound)
            }
        }
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
        static CLOSED: Body = Body::NoExtinction(NoExtinction);
        self.model.as_ref().map_or(&CLOSED, |m| &m.model.body)
    }

    /// The split family of its model, if that is what it evaluates.
    fn split(&self) -> Option<&Split> {
        self.model.as_ref()?.model.split()
    }

    fn exp_phase(&self) -> Option<&ExpPhase> {
        match &self.split()?.phase {
            PhaseModel::Exp(e) => Some(e),
            PhaseModel::Isotropic => None,
        }
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
    /// canonical entry), from its family ([`Body::ops`]).
    pub fn op_count(&self) -> Cost {
        self.body().ops(self.shape())
    }
}

#[derive(Serialize)]
struct E2Term {
    p: String,
    q: String,
}

#[derive(Serialize)]
struct Seg {
    lo: String,
    hi: String,
    slope: String,
    icpt: String,
}

#[derive(Serialize)]
struct Term {
    c: String,
    s: String,
}

#[derive(Serialize)]
struct BandCtx {
    g_hi: String,
    g_mid: String,
    a: Vec<Vec<String>>,
    b: Vec<Vec<String>>,
}

#[derive(Serialize)]
struct FixedCtx {
    c: Vec<String>,
    b: Vec<String>,
    mirrored: bool,
}

#[derive(Serialize)]
struct RatioCtx {
    f: Vec<String>,
    g: Vec<String>,
    h: Vec<String>,
}

fn lits(xs: &[f64]) -> Vec<String> {
    xs.iter().map(|&x| lit(x)).collect()
}

/// Comment lines of a generated file's header (without comment markers).
fn header_lines(spec: &KernelSpec, out: &KernelOutput, template: &str) -> Vec<String> {
    let mut h = vec![
        format!("airlight kernel `{}` — {}.", spec.name, out.variant.replace("{ident}", &spec.ident())),
        "Generated by `airlight generate` — edit the template, not this file.".to_string(),
        format!("template: codegen/templates/kernels/{template}"),
    ];
    match &spec.model {
        Some(m) => {
            h.push(format!("model: {}; coefficients: generated/coefficients/{}.toml", m.model.name, m.model.name))
        }
        None => h.push("model: none (exact closed form without extinction, seed 003)".into()),
    }
    if let Some(s) = &spec.scene {
        h.push(format!("scene: {s}; plan: generated/plans/{}.md", spec.name));
    }
    h.push(format!("declared bound: {}", spec.bound));
    h
}

fn comment(lines: &[String], marker: &str) -> String {
    lines.iter().map(|l| format!("{marker} {l}")).collect::<Vec<_>>().join("\n")
}

/// Renders one kernel for one table row.
fn render_kernel(tera: &tera::Tera, spec: &KernelSpec, out: &KernelOutput) -> Result<Output, tera::Error> {
    let ident = spec.ident();
    let kind = spec.body().kind();
    let template = out.templates.get(kind).ok_or_else(|| {
        tera::Error::msg(format!("codegen/outputs.toml: no {} template for the family '{kind}'", out.target))
    })?;
    let lang = out.target;
    let mut ctx = tera::Context::new();
    let header = comment(&header_lines(spec, out, template), "//");
    let header = match &out.import_path {
        Some(p) => format!("#define_import_path {}\n\n{header}", p.replace("{ident}", &ident)),
        None => header,
    };
    ctx.insert("header", &header);
    ctx.insert("p", &out.prefix.replace("{ident}", &ident));
    ctx.insert("title", &spec.name);
    ctx.insert("surfaces", &spec.surfaces);
    ctx.insert("extinction", &spec.extinction);
    ctx.insert("backscatter", &spec.backscatter);
    ctx.insert("g_param", &spec.g_param());
    ctx.insert("p_iso", &lit(1.0 / (4.0 * PI)));
    let iso = spec.phase == KernelPhase::Isotropic;
    ctx.insert("iso", &iso);
    let split = matches!(spec.body(), Body::Split(_));
    ctx.insert("uses_phi", &(split && spec.backscatter));
    ctx.insert("closed", &!split);

    // Signatures, per language.
    let (f, v3_ty) = match lang {
        Target::Rust => ("f32", "[f32; 3]"),
        Target::Wgsl => ("f32", "vec3<f32>"),
        Target::Glsl => ("float", "vec3"),
    };
    let param = |name: &str, ty: &str| match lang {
        Target::Glsl => format!("{ty} {name}"),
        _ => format!("{name}: {ty}"),
    };
    let typed = |args: Vec<Arg>| -> String {
        args.into_iter()
            .map(|a| param(a.name(), if a.ty() == ArgType::Vec3 { v3_ty } else { f }))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let params = spec.params();
    let mut args = params
        .iter()
        .filter_map(|p| match p {
            Arg::Tau => Some("τ"),
            Arg::Gamma => Some("γ"),
            Arg::Rho => Some("ρ"),
            _ => None,
        })
        .collect::<Vec<_>>()
        .join(", ");
    if spec.g_param() {
        args.push_str("; g");
    }
    ctx.insert("canonical_params", &typed(params));
    ctx.insert("canonical_args", &args);
    let rad = typed(spec.radiance_params());
    ctx.insert("radiance_params", &rad);
    // The spot entry (shared by every family through its `along`).
    ctx.insert("spot", &spec.spot);
    let v3 = |a: Arg| a.ty() == ArgType::Vec3;
    let spot_params = spec
        .args(Entry::Spot)
        .into_iter()
        .map(|a| param(a.name(), if v3(a) { v3_ty } else { f }))
        .collect::<Vec<_>>()
        .join(", ");
    ctx.insert("spot_params", &spot_params);
    ctx.insert("takes_tau", &spec.takes_tau());
    // Families whose core shares its nodes across channels (τ enters only the
    // transmittances) emit an RGB variant of it for the spot entry.
    let shared_rgb = spec.spot && matches!(spec.body(), Body::Equiangular(_));
    ctx.insert("shared_rgb", &shared_rgb);
    ctx.insert("geometry_variants", &if shared_rgb { vec![false, true] } else { vec![false] });
    ctx.insert(
        "spot_g",
        &match spec.phase {
            KernelPhase::Fixed(g) => lit(g),
            _ => lit(0.0),
        },
    );
    let (ex, ew) = airlight_fit::quad::gauss_legendre(SPOT_EDGE_NODES);
    ctx.insert("edge_x", &lits(&ex));
    ctx.insert("edge_w", &lits(&ew));

    // The family's own data for its templates: one arm per family.
    match (spec.body(), &spec.model) {
        (Body::Split(sp), Some(m)) => split_context(&mut ctx, spec, sp, m, out),
        (Body::NoExtinction(_), None) => ctx.insert("summary", "isotropic scattering without extinction, exact."),
        (Body::NoExtinction(_), Some(m)) => {
            ctx.insert("summary", &format!("{} ({}).", m.model.summary, specialisations(spec)))
        }
        (Body::RayMarch(r), Some(m)) => {
            baseline_context(&mut ctx, spec, m);
            ctx.insert("steps", &r.steps);
            ctx.insert("far", &lit(FAR_PLANE));
            ctx.insert("far_doc", &FAR_PLANE);
            ctx.insert("ln_cutoff", &lit((1.0 / MARCH_CUTOFF).ln()));
            ctx.insert("cutoff_doc", &format!("{MARCH_CUTOFF:e}"));
        }
        (Body::Equiangular(q), Some(m)) => {
            baseline_context(&mut ctx, spec, m);
            ctx.insert("nodes", &lits(&q.x));
            ctx.insert("weights", &lits(&q.w));
        }
        (Body::Sun2005(t), Some(m)) => {
            baseline_context(&mut ctx, spec, m);
            use airlight_fit::family::sun::{U_MAX, V_MAX};
            let n = (t.res - 1) as f64;
            ctx.insert("res", &t.res);
            ctx.insert("res_m1", &(t.res - 1));
            ctx.insert("bytes", &t.bytes());
            ctx.insert("table_path", &table_path(&m.model.name));
            ctx.insert("u_scale", &lit(n / U_MAX));
            ctx.insert("v_scale", &lit(n / V_MAX));
            ctx.insert("u_max_doc", &U_MAX);
        }
        (Body::Phi(r), Some(m)) => {
            baseline_context(&mut ctx, spec, m);
            ctx.insert("head_x", &lits(&r.head.x));
            ctx.insert("head_w", &lits(&r.head.w));
            ctx.insert("far_x", &lits(&r.far.x));
            ctx.insert("far_w", &lits(&r.far.w));
            ctx.insert("tail_x", &lits(&r.tail.x));
            ctx.insert("tail_w", &lits(&r.tail.w));
            ctx.insert("cut", &lit(r.cut));
            ctx.insert("cut_doc", &r.cut);
            ctx.insert("exp_neg_cut", &lit((-r.cut).exp()));
            ctx.insert("far_cut", &lit(r.far_cut));
            ctx.insert("far_tmax", &lit(r.far_tmax));
            ctx.insert("short", &lit(r.short));
            ctx.insert("far_from", &lit(r.far_from));
            ctx.insert("euler", &lit(airlight_fit::family::phi::EULER_GAMMA));
            ctx.insert("ein", &lits(&r.e2.ein));
            ctx.insert("e2p", &lits(&r.e2.p));
            ctx.insert("e2q", &lits(&r.e2.q));
            let rev: Vec<E2Term> =
                r.e2.p.iter().zip(&r.e2.q).rev().map(|(&p, &q)| E2Term { p: lit(p), q: lit(q) }).collect();
            ctx.insert("e2_rev", &rev);
        }
        (Body::Split(_) | Body::RayMarch(_) | Body::Equiangular(_) | Body::Sun2005(_) | Body::Phi(_), None) => {
            unreachable!("a fitted or baseline kernel comes from a model")
        }
    }
    let mut text = tera.render(template, &ctx)?;
    if !text.ends_with('\n') {
        text.push('\n');
    }
    Ok(Output::text(out.path.replace("{name}", &spec.name).replace("{ident}", &ident), text))
}

/// Where a model's table lives under `generated/`.
pub fn table_path(model: &str) -> String {
    format!("tables/{model}.f32")
}

/// What the quadrature families' templates share (the baselines' and φ's): the
/// summary and how the phase is taken.
fn baseline_context(ctx: &mut tera::Context, spec: &KernelSpec, m: &ModelFile) {
    ctx.insert("summary", &format!("{} ({}).", m.model.summary, specialisations(spec)));
    ctx.insert("phase_iso", &(spec.phase == KernelPhase::Isotropic));
    ctx.insert("phase_exact", &(spec.phase == KernelPhase::Exact));
    let fixed = match spec.phase {
        KernelPhase::Fixed(g) => Some(g),
        _ => None,
    };
    ctx.insert("phase_fixed", &fixed.is_some());
    ctx.insert("fixed_g", &fixed.map_or(String::new(), |g| format!("{g}")));
    ctx.insert("fixed_g_lit", &fixed.map_or(String::new(), lit));
}

/// What the split family's templates need: segments re-expressed in α, the
/// backward sums, the ratio, the phase (isotropic, baked or banded), imports.
fn split_context(ctx: &mut tera::Context, spec: &KernelSpec, sp: &Split, m: &ModelFile, out: &KernelOutput) {
    let (lang, ident, iso) = (out.target, spec.ident(), spec.phase == KernelPhase::Isotropic);
    let a = &m.model;
    ctx.insert("summary", &format!("the `{}` model ({}), specialised: {}.", a.name, a.summary, specialisations(spec)));
    // Segments in α = π/2 − θ', increasing in α.
    let s = &sp.forward;
    let segs: Vec<Seg> = (0..s.n())
        .rev()
        .map(|j| Seg {
            lo: lit(FRAC_PI_2 - s.breakpoints[j + 1]),
            hi: lit(FRAC_PI_2 - s.breakpoints[j]),
            slope: lit(-s.slopes[j]),
            icpt: lit(s.intercepts[j] + s.slopes[j] * FRAC_PI_2),
        })
        .collect();
    ctx.insert("segs", &segs);
    let terms = |e: &airlight_fit::family::expsum::ExpSum| -> Vec<Term> {
        e.c.iter().zip(&e.s).map(|(&c, &s)| Term { c: lit(c), s: lit(s) }).collect()
    };
    ctx.insert("near", &terms(&sp.expsum.near));
    ctx.insert("local", &terms(&sp.expsum.local));
    ctx.insert("split", &lit(SPLIT));
    ctx.insert("split_doc", &SPLIT);
    ctx.insert("local_ratio_doc", &LOCAL_RATIO);
    ctx.insert("local_ratio", &lit(LOCAL_RATIO));
    ctx.insert("attenuate", &sp.forward_attenuation);
    let ratio = sp.ratio.as_ref().map(|r| RatioCtx { f: lits(&r.f), g: lits(&r.g), h: lits(&r.h) });
    ctx.insert("ratio", &ratio);
    let (phase, k) = match (&spec.phase, spec.exp_phase()) {
        (KernelPhase::Isotropic | KernelPhase::Exact, _) | (_, None) => ("isotropic", 1),
        (KernelPhase::Fixed(g), Some(e)) => {
            let t = e.terms(*g);
            ctx.insert(
                "fixed",
                &FixedCtx {
                    c: t.terms.iter().map(|x| lit(x.0)).collect(),
                    b: t.terms.iter().map(|x| lit(x.1)).collect(),
                    mirrored: t.mirrored,
                },
            );
            ctx.insert("fixed_g", &format!("{g}"));
            ("fixed", e.k())
        }
        (KernelPhase::Banded(which), Some(e)) => {
            let bands: Vec<BandCtx> = which
                .iter()
                .map(|&i| {
                    let b = &e.bands[i];
                    // Re-centred on the band's middle: the paper's quadratics cancel
                    // to 1e-5 in f32 when evaluated in g itself (b ≈ 7e4 g² − 1.5e5 g + 7e4).
                    let mid = 0.5 * (b.g_lo + b.g_hi);
                    let centre =
                        |r: &[f64; 3]| lits(&[r[0], r[1] + 2.0 * r[0] * mid, r[2] + (r[1] + r[0] * mid) * mid]);
                    BandCtx {
                        g_hi: lit(b.g_hi),
                        g_mid: lit(mid),
                        a: b.a.iter().map(centre).collect(),
                        b: b.b.iter().map(centre).collect(),
                    }
                })
                .collect();
            ctx.insert("bands", &bands);
            ctx.insert("phase_scale", &lit(e.scale));
            ("banded", e.k())
        }
    };
    ctx.insert("phase", phase);
    ctx.insert("k", &k);
    // Rust imports: exactly what the kernel uses.
    let mut math = vec!["atan2", "exp", "exprel", "ray_geometry", "scaled", "sin_cos", "HUGE", "TAU_MAX"];
    if spec.surfaces {
        math.push("RHO_OPEN");
        if spec.backscatter {
            math.push("sqrt");
        }
    }
    let expsum = spec.backscatter;
    if expsum {
        math.push("phi");
        if !iso {
            math.push("atan");
        }
    }
    if spec.backscatter && sp.ratio.is_some() {
        math.push("ln");
    }
    math.sort_by_key(|s| s.to_lowercase());
    ctx.insert("math_imports", &math.join(", "));
    let mut consts = Vec::new();
    if spec.backscatter && sp.ratio.is_some() {
        consts.push("FRAC_PI_2");
    }
    if !iso {
        consts.push("PI");
    }
    ctx.insert("const_imports", &consts.join(", "));
    let (ph_param, ph_arg) = match (iso, lang) {
        (true, _) => (String::new(), String::new()),
        (false, Target::Rust) => (", ph: &Phase".to_string(), ", &ph".to_string()),
        (false, Target::Wgsl) => (format!(", ph: {}Phase", out.prefix.replace("{ident}", &ident)), ", ph".to_string()),
        (false, _) => (format!(", {}Phase ph", out.prefix.replace("{ident}", &ident)), ", ph".to_string()),
    };
    ctx.insert("ph_param", &ph_param);
    ctx.insert("ph_arg", &ph_arg);
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

fn engine() -> Result<tera::Tera, tera::Error> {
    let mut t = tera::Tera::default();
    t.autoescape_on(vec![]);
    t.add_raw_templates(TEMPLATES.iter().copied())?;
    Ok(t)
}

#[derive(Serialize)]
struct CrateKernel {
    name: String,
    ident: String,
    thin: String,
    dense: String,
    scene: bool,
    params: Vec<&'static str>,
    closure: String,
    radiance_params: Vec<&'static str>,
    radiance_closure: String,
    spot_params: Vec<&'static str>,
    spot_closure: String,
    /// The spot call as rustfmt lays it out (one line where it fits).
    spot_call: String,
}

/// Closure parameters of a uniform signature `all`, those the kernel does not
/// take (`used`) marked unused with `_`.
/// The uniform closure's parameters for `entry`: every argument, `_`-prefixed where unused.
fn closure(entry: Entry, used: &[Arg]) -> String {
    entry
        .all_args()
        .iter()
        .map(|p| if used.contains(p) { p.to_string() } else { format!("_{p}") })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Domains as prose: `thin and dense`.
pub fn join_domains(domains: &[Domain]) -> String {
    domains.iter().map(|d| d.name()).collect::<Vec<_>>().join(" and ")
}

fn names(args: &[Arg]) -> Vec<&'static str> {
    args.iter().map(|a| a.name()).collect()
}

/// Every kernel output: per-kernel files from the table, the crate's own files,
/// and the math includes of the shader targets.
pub fn render(specs: &[KernelSpec]) -> Result<Vec<Output>, tera::Error> {
    let table = OutputTable::standard();
    let tera = engine()?;
    let mut out = Vec::new();
    for spec in specs {
        for row in &table.kernel {
            if spec.targets.contains(&row.target) {
                out.push(render_kernel(&tera, spec, row)?);
            }
        }
    }
    // naga's translations of the validated WGSL.
    for spec in specs {
        let name = |p: &str| p.replace("{name}", &spec.name).replace("{ident}", &spec.ident());
        let functions: Vec<String> = Entry::ALL
            .into_iter()
            .filter(|&e| !spec.args(e).is_empty())
            .map(|e| format!("{}{}", spec.prefix(), e.function()))
            .collect();
        for row in &table.translation {
            let from = name(&row.from);
            let Some(src) = out.iter().find(|o| o.path == from) else { continue };
            let wgsl = String::from_utf8_lossy(&src.contents).into_owned();
            let text = crate::translate::translate(&wgsl, row.backend, &functions)
                .map_err(|e| tera::Error::msg(format!("{from} to {}: {e}", row.backend.name())))?;
            let lines = [
                "Generated by `airlight generate` from the validated WGSL: edit its template, not this file."
                    .to_string(),
                format!("source: generated/{from} (its header documents the entry points)"),
                format!("variant: {}", name(&row.variant)),
                "translated by naga 30's back end, so names, arguments and behaviour are the WGSL's".to_string(),
            ];
            out.push(Output::text(name(&row.path), format!("{}\n{text}", comment(&lines, "//"))));
        }
    }
    // Tables (the texture of a table-driven kernel), once per model.
    for spec in specs {
        if let (Some(t), Some(m)) = (spec.body().table(), &spec.model) {
            let path = table_path(&m.model.name);
            if !out.iter().any(|o: &Output| o.path == path) {
                out.push(Output { path, contents: t.to_le_bytes() });
            }
        }
    }
    let kernels: Vec<CrateKernel> = specs
        .iter()
        .filter(|s| s.targets.contains(&Target::Rust))
        .map(|s| {
            let err = |d: Domain| s.model.as_ref().and_then(|m| m.error(d)).map_or(0.0, |e| e.max_rel);
            let (params, radiance_params) = (s.params(), s.radiance_params());
            CrateKernel {
                name: s.name.clone(),
                ident: s.ident(),
                thin: format!("{:e}", err(Domain::Thin)),
                dense: format!("{:e}", err(Domain::Dense)),
                scene: s.scene.is_some(),
                radiance_closure: closure(Entry::Radiance, &radiance_params),
                spot_closure: closure(Entry::Spot, &s.args(Entry::Spot)),
                spot_params: names(&s.args(Entry::Spot)),
                spot_call: {
                    let args = names(&s.args(Entry::Spot)).join(", ");
                    let one = format!("{}::spot({args})", s.ident());
                    if 12 + one.len() <= 120 {
                        one
                    } else {
                        format!("{}::spot(\n                {args},\n            )", s.ident())
                    }
                },
                closure: closure(Entry::Canonical, &params),
                radiance_params: names(&radiance_params),
                params: names(&params),
            }
        })
        .collect();
    for f in &table.crate_file {
        let mut ctx = tera::Context::new();
        let marker = if f.path.ends_with(".toml") { "#" } else { "//" };
        let lines = vec![
            "Generated by `airlight generate` — edit the template, not this file.".to_string(),
            format!("template: codegen/templates/kernels/{}", f.template),
        ];
        ctx.insert("header", &comment(&lines, marker));
        ctx.insert("exp2_table", &exp2_table());
        ctx.insert("ln_table", &ln_table());
        ctx.insert("kernels", &kernels);
        ctx.insert("version", env!("CARGO_PKG_VERSION"));
        out.push(Output::text(f.path.clone(), tera.render(&f.template, &ctx)?));
    }
    Ok(out)
}

/// `2^(j/32)` for `j = 0 … 31` as f64 bit patterns for the Rust kernels' `exp`:
/// `2^(1/32)` by five square roots of 2 (IEEE, correctly rounded: the same bits
/// on every machine), then products. Within 1e-14 of the exact values, far below
/// f32's resolution.
fn exp2_table() -> Vec<String> {
    let mut root = 2.0f64;
    for _ in 0..5 {
        root = root.sqrt();
    }
    let mut v = 1.0f64;
    (0..32)
        .map(|_| {
            let s = format!("0x{:016x}", v.to_bits());
            v *= root;
            s
        })
        .collect()
}

/// `[1/c, ln c]` as f64 bit patterns for the Rust kernels' `ln`, for the 64
/// pieces of `[0.75, 1.5)` equal in bit pattern (from `0x3f400000` in steps of
/// `2^17`): `c` the end of the piece nearer 1 (so the two pieces around 1 have
/// `c = 1` and `ln c = 0` exactly). `ln c = 2 atanh((c − 1)/(c + 1))` summed in f64
/// until the terms vanish: only IEEE arithmetic, the same bits on every machine.
fn ln_table() -> Vec<String> {
    (0u32..64)
        .map(|j| {
            let end = |j: u32| f64::from(f32::from_bits(0x3f40_0000 + (j << 17)));
            let (lo, hi) = (end(j), end(j + 1));
            let c = if hi <= 1.0 { hi } else { lo };
            let s = (c - 1.0) / (c + 1.0);
            let (mut term, mut sum, mut k) = (s, 0.0f64, 1.0f64);
            let s2 = s * s;
            while term != 0.0 && (term / k).abs() > 1e-30 {
                sum += term / k;
                term *= s2;
                k += 2.0;
            }
            format!("[0x{:016x}, 0x{:016x}]", (1.0 / c).to_bits(), (2.0 * sum).to_bits())
        })
        .collect()
}

fn index_entry(spec: &KernelSpec, table: &OutputTable) -> IndexEntry {
    let ident = spec.ident();
    let path = |target: Target, bevy: bool| {
        table
            .kernel
            .iter()
            .filter(|k| k.target == target && k.import_path.is_some() == bevy)
            .find(|k| spec.targets.contains(&k.target))
            .map(|k| k.path.replace("{name}", &spec.name).replace("{ident}", &ident))
    };
    let g = match &spec.phase {
        KernelPhase::Isotropic => [0.0, 0.0],
        KernelPhase::Fixed(g) => [*g, *g],
        KernelPhase::Banded(_) | KernelPhase::Exact => [spec.g_range.0, spec.g_range.1],
    };
    IndexEntry {
        name: spec.name.clone(),
        model: spec.model.as_ref().map(|m| m.model.name.clone()),
        scene: spec.scene.clone(),
        domains: spec.domains.clone(),
        params: spec.params(),
        radiance_params: spec.radiance_params(),
        spot_params: spec.args(Entry::Spot),
        g,
        surfaces: spec.surfaces,
        extinction: spec.extinction,
        backscatter: spec.backscatter,
        wgsl: path(Target::Wgsl, false),
        wgsl_bevy: path(Target::Wgsl, true),
        glsl: path(Target::Glsl, false),
        rust: path(Target::Rust, false),
        prefix: spec.prefix(),
        table: spec.model.as_ref().and_then(|m| {
            m.model.body.table().map(|t| airlight_fit::vocab::TableRef { path: table_path(&m.model.name), size: t.res })
        }),
    }
}

/// `generated/kernels.toml`.
pub fn render_index(specs: &[KernelSpec]) -> Output {
    let table = OutputTable::standard();
    let index = Index { kernel: specs.iter().map(|s| index_entry(s, &table)).collect() };
    let body = toml::to_string(&index).expect("plain data serialises");
    Output::text(
        airlight_fit::vocab::INDEX_FILE,
        format!(
            "# Index of the generated kernels: what each takes and where its files are.\n\
             # Generated by `airlight generate` from codegen/src/kernel.rs; read by the GPU\n\
             # harness and `airlight check`. Edit the generator, not this file.\n\n{body}"
        ),
    )
}

#[derive(Serialize)]
struct Candidate {
    name: String,
    cost: usize,
    bound: String,
    meets: &'static str,
}

/// The plan written next to a scene's kernels: the model and why, the expected
/// error, the operation count, and every model that was considered.
pub fn render_plan(scene: &Scene, plan: &Plan, spec: &KernelSpec, models: &[ModelFile]) -> Result<Output, tera::Error> {
    let table = OutputTable::standard();
    let tera = engine()?;
    let mut ctx = tera::Context::new();
    let row = &table.plan[0];
    ctx.insert(
        "header",
        &format!(
            "Generated by `airlight generate` from codegen/templates/kernels/{} — edit the template, not this file",
            row.template
        ),
    );
    ctx.insert("scene", &scene.name);
    ctx.insert("scene_file", &scene.file);
    let files: Vec<String> = table
        .kernel
        .iter()
        .filter(|k| spec.targets.contains(&k.target))
        .map(|k| format!("generated/{}", k.path.replace("{name}", &spec.name).replace("{ident}", &spec.ident())))
        .collect();
    ctx.insert("files", &files);
    let fmt = crate::report::fmt_err;
    let (model, why, expected) = match &plan.choice {
        Choice::NoExtinction => (
            "none: the exact closed form".to_string(),
            "Isotropic scattering without extinction has an exact closed form (seed 003), cheaper and more accurate than any fit.".to_string(),
            "exact up to f32 rounding".to_string(),
        ),
        Choice::Model { name, bound, cost } => (
            format!("`{name}`"),
            format!(
                "The cheapest model (cost {cost}) whose declared max relative error over the domains the scene reaches ({}) is within the budget.",
                join_domains(&plan.domains)
            ),
            if scene.backscatter {
                format!("≤ {} (declared, f64 model) plus f32 rounding", fmt(*bound))
            } else {
                format!("≤ {} (declared) on the forward part; up to 100% where the backward part dominates", fmt(*bound))
            },
        ),
    };
    let expected = if plan.ignored_extinction > 0.0 {
        format!("{expected}; ignoring extinction adds up to {} (measured)", fmt(plan.ignored_extinction))
    } else {
        expected
    };
    ctx.insert("model", &model);
    ctx.insert("why", &why);
    ctx.insert("expected", &expected);
    ctx.insert("sigma_lo", &scene.sigma_t.0);
    ctx.insert("sigma_hi", &scene.sigma_t.1);
    ctx.insert(
        "phase",
        &match scene.phase {
            ScenePhase::Isotropic => "isotropic".to_string(),
            ScenePhase::Fixed(g) => format!("Henyey–Greenstein, g = {g}"),
            ScenePhase::Range(lo, hi) => format!("Henyey–Greenstein, g ∈ [{lo}, {hi}]"),
        },
    );
    ctx.insert("extinction", &scene.extinction);
    ctx.insert("max_distance", &scene.max_distance);
    ctx.insert("tau_max", &plan.tau_max);
    ctx.insert("surfaces", &scene.surfaces);
    ctx.insert("backscatter", &scene.backscatter);
    ctx.insert("budget", &scene.max_rel_error);
    ctx.insert("ops", &spec.op_count());
    ctx.insert("specialised", &specialisations(spec));
    ctx.insert("domains", &join_domains(&plan.domains));
    let (g_lo, g_hi) = scene.phase.g_range();
    let mut candidates: Vec<Candidate> = if matches!(plan.choice, Choice::NoExtinction) {
        Vec::new()
    } else {
        models
            .iter()
            .filter(|m| m.model.g_range.0 <= g_lo && g_hi <= m.model.g_range.1)
            .map(|m| {
                let b = plan.domains.iter().filter_map(|&d| m.error(d)).map(|e| e.max_rel).fold(0.0, f64::max);
                Candidate {
                    name: m.model.name.clone(),
                    cost: m.model.cost(),
                    bound: fmt(b),
                    meets: if b <= scene.max_rel_error { "yes" } else { "no" },
                }
            })
            .collect()
    };
    candidates.sort_by(|a, b| a.cost.cmp(&b.cost).then(a.name.cmp(&b.name)));
    ctx.insert("candidates", &candidates);
    let text = tera.render(&row.template, &ctx)?;
    Ok(Output::text(row.path.replace("{name}", &spec.name), text))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_parses_and_names_existing_templates() {
        let t = OutputTable::standard();
        let names: Vec<&str> = TEMPLATES.iter().map(|t| t.0).collect();
        for k in &t.kernel {
            // Every family has a template for every target, and it exists.
            for kind in Body::KINDS {
                let template = k.templates.get(kind).unwrap_or_else(|| panic!("{k:?}: no {kind} template"));
                assert!(names.contains(&template.as_str()), "{k:?}");
            }
        }
        for f in &t.crate_file {
            assert!(names.contains(&f.template.as_str()), "{f:?}");
        }
    }

    #[test]
    fn literals_read_back_as_the_same_f32() {
        for x in [0.1, -1.0 / 3.0, 1e-30, 6.02e23, std::f64::consts::PI, 16.0] {
            let s = lit(x);
            assert_eq!(s.parse::<f32>().unwrap(), x as f32, "{s}");
            assert_eq!(s.parse::<f64>().unwrap() as f32, x as f32, "{s}");
        }
        assert_eq!(lit(0.0), "0.0");
    }
}

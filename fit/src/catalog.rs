//! The models airlight ships, kept as data ([`CATALOG`]), and the pipeline that
//! produces their coefficient files: fit each family once, assemble the models,
//! measure every model on the validation sets.

use crate::approx::{Approximation, Body, PhaseModel, Split};
use crate::coeffs::{DomainErrors, ModelFile, Provenance};
use crate::domains::{Domain, VALIDATION_POINTS, VALIDATION_SEED};
use crate::family::expsum::{self, Backward, ExpSumFit, Target};
use crate::family::phase_exp::{self, Band, BandFit, ExpPhase, PAPER_BANDS};
use crate::family::ratio::{self, Ratio, RatioFit};
use crate::family::segments::{self, Segments, SegmentsFit};
use crate::lsq::{self, OUTER_SOLVER};
use crate::model::Model;
use crate::reference::{self, Point, REFERENCE_REL_TOL};
use crate::stats::{rel_error, rms_max};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use toml::Value;

/// Segment counts the forward family is fitted for.
pub const SEGMENT_COUNTS: [usize; 7] = [2, 3, 4, 6, 8, 12, 16];
/// Terms of the backward exponential sums: near (`w` on `[1, 16]`) and local (`1/y²` on `[1, 2]`).
pub const EXPSUM_TERMS: (usize, usize) = (4, 3);
/// Term counts the phase family is fitted for.
pub const TERM_COUNTS: [usize; 3] = [1, 2, 3];
/// `g` range of the paper's table (and of models built on it).
pub const PAPER_G: (f64, f64) = (0.0, 0.99);
/// `g` range of models that mirror negative `g`.
pub const MIRRORED_G: (f64, f64) = (-0.99, 0.99);

/// Seeds of the fit samples (validation uses [`VALIDATION_SEED`]).
pub const FORWARD_SEED: u64 = 0xF17_0000_0000_0001;
/// Seed of the phase fit samples.
pub const PHASE_SEED: u64 = 0xF17_0000_0000_0002;
/// Seed of the backscatter fit samples.
pub const RATIO_SEED: u64 = 0xF17_0000_0000_0003;
/// Low-discrepancy points per domain (thin, dense) in each fit sample.
pub const FORWARD_POINTS: usize = 600;
/// Points per domain per band for the phase fit.
pub const PHASE_POINTS: usize = 200;
/// Points per domain for the ratio fit.
pub const RATIO_POINTS: usize = 600;

/// Where a model's forward kernel comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForwardChoice {
    /// The paper's three printed lines.
    Paper,
    /// The refit with this many segments.
    Refit(usize),
}

/// Where a model's phase function comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PhaseChoice {
    /// Exact isotropic.
    Isotropic,
    /// The paper's table.
    Paper,
    /// The refit with this many terms.
    Refit(usize),
}

/// Where a model's backward part comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BackChoice {
    /// The paper's ratio (γ ≤ π/2), the exponential sum beyond.
    PaperRatio,
    /// The refit ratio (γ ≤ π/2), the exponential sum beyond.
    RefitRatio,
    /// The exponential sum everywhere.
    ExpSum,
}

/// How a shipped model is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Recipe {
    /// A forward + backward composition of fitted families.
    Split {
        /// Forward kernel.
        forward: ForwardChoice,
        /// Phase.
        phase: PhaseChoice,
        /// Backward part.
        backward: BackChoice,
        /// Whether the forward part keeps `e^{−τ cos γ}` (false only as printed).
        forward_attenuation: bool,
    },
    /// A baseline: what a user would pick instead (nothing fitted).
    Baseline(Baseline),
    /// A member of the φ family (whole-A composite rule).
    Phi(PhiTier),
}

/// The parameters of one member of the φ family (`family/phi.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhiTier {
    /// Head nodes (Gauss–Legendre in φ).
    pub head: usize,
    /// Far-correction nodes (Gauss–Legendre in `v = 1/u`).
    pub far: usize,
    /// Tail nodes (Gauss–Laguerre).
    pub tail: usize,
    /// `L`: the head's transmittance cut.
    pub cut: f64,
    /// The far correction's transmittance cut.
    pub far_cut: f64,
}

/// The baselines airlight measures itself against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Baseline {
    /// Seed 003's closed form without extinction: the cost floor.
    NoExtinction,
    /// Uniform midpoint ray marching with this many steps.
    RayMarch(usize),
    /// Gauss–Legendre in the equiangular angle with this many nodes.
    Equiangular(usize),
    /// Sun et al.'s F(u, v) table at this resolution.
    Sun2005(usize),
}

/// One shipped model: its name, its `g` range and how it is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelSpec {
    /// Name.
    pub name: &'static str,
    /// One line for tables.
    pub summary: &'static str,
    /// Supported `g`.
    pub g_range: (f64, f64),
    /// How it is built.
    pub recipe: Recipe,
}

impl ModelSpec {
    /// Whether it is a baseline.
    pub fn is_baseline(&self) -> bool {
        matches!(self.recipe, Recipe::Baseline(_))
    }
}

const fn split(
    name: &'static str,
    summary: &'static str,
    g_range: (f64, f64),
    forward: ForwardChoice,
    phase: PhaseChoice,
    backward: BackChoice,
    forward_attenuation: bool,
) -> ModelSpec {
    ModelSpec { name, summary, g_range, recipe: Recipe::Split { forward, phase, backward, forward_attenuation } }
}

const fn seg(name: &'static str, summary: &'static str, n: usize) -> ModelSpec {
    split(name, summary, (0.0, 0.0), ForwardChoice::Refit(n), PhaseChoice::Isotropic, BackChoice::ExpSum, true)
}

const fn hg(name: &'static str, summary: &'static str, k: usize) -> ModelSpec {
    split(name, summary, MIRRORED_G, ForwardChoice::Refit(8), PhaseChoice::Refit(k), BackChoice::ExpSum, true)
}

const fn march(name: &'static str, n: usize) -> ModelSpec {
    ModelSpec {
        name,
        summary: "baseline; uniform midpoint ray march (the engines' method), exact HG per step, g at run time",
        g_range: MIRRORED_G,
        recipe: Recipe::Baseline(Baseline::RayMarch(n)),
    }
}

const fn equiangular(name: &'static str, n: usize) -> ModelSpec {
    ModelSpec {
        name,
        summary:
            "baseline; Gauss-Legendre in the equiangular angle (Kulla & Fajardo 2012, deterministic), exact HG per node",
        g_range: MIRRORED_G,
        recipe: Recipe::Baseline(Baseline::Equiangular(n)),
    }
}

const fn sun(name: &'static str, res: usize) -> ModelSpec {
    ModelSpec {
        name,
        summary: "baseline; Sun et al. 2005 F(u, v) table (seed 004), bilinear, a texture in shaders; isotropic",
        g_range: (0.0, 0.0),
        recipe: Recipe::Baseline(Baseline::Sun2005(res)),
    }
}

const fn phi(name: &'static str, summary: &'static str, g_range: (f64, f64), t: PhiTier) -> ModelSpec {
    ModelSpec { name, summary, g_range, recipe: Recipe::Phi(t) }
}

const PHI_4: PhiTier = PhiTier { head: 4, far: 2, tail: 2, cut: 3.5, far_cut: 5.0 };
const PHI_6: PhiTier = PhiTier { head: 6, far: 4, tail: 3, cut: 4.0, far_cut: 6.0 };
const PHI_8: PhiTier = PhiTier { head: 8, far: 4, tail: 3, cut: 5.0, far_cut: 8.0 };

/// Every shipped model, in table order: airlight's models, then the baselines.
pub const CATALOG: [ModelSpec; 38] = [
    split(
        "paper-as-printed",
        "isotropic; Pradhan & Kumar as printed: 3 segments and backscatter ratio, forward part lacks e^(-beta d1)",
        (0.0, 0.0),
        ForwardChoice::Paper,
        PhaseChoice::Isotropic,
        BackChoice::PaperRatio,
        false,
    ),
    split(
        "paper",
        "isotropic; Pradhan & Kumar's published segments and backscatter ratio, e^(-beta d1) restored",
        (0.0, 0.0),
        ForwardChoice::Paper,
        PhaseChoice::Isotropic,
        BackChoice::PaperRatio,
        true,
    ),
    split(
        "paper-refit",
        "isotropic; the paper's 3-segment and ratio forms refit by least squares",
        (0.0, 0.0),
        ForwardChoice::Refit(3),
        PhaseChoice::Isotropic,
        BackChoice::RefitRatio,
        true,
    ),
    split(
        "paper-hg",
        "HG g in [0, 0.99]; the paper's model with its appendix table a e^(-b alpha)",
        PAPER_G,
        ForwardChoice::Paper,
        PhaseChoice::Paper,
        BackChoice::PaperRatio,
        true,
    ),
    split(
        "paper-refit-hg",
        "HG g in [0, 0.99]; paper-refit with the one-exponential table refit on the error of A",
        PAPER_G,
        ForwardChoice::Refit(3),
        PhaseChoice::Refit(1),
        BackChoice::RefitRatio,
        true,
    ),
    seg("segments-2", "isotropic; 2-segment forward kernel, 4+3-term backward sums and E1", 2),
    seg("segments-3", "isotropic; 3-segment forward kernel, 4+3-term backward sums and E1", 3),
    seg("segments-4", "isotropic; 4-segment forward kernel, 4+3-term backward sums and E1", 4),
    seg("segments-6", "isotropic; 6-segment forward kernel, 4+3-term backward sums and E1", 6),
    seg("segments-8", "isotropic; 8-segment forward kernel, 4+3-term backward sums and E1", 8),
    seg("segments-12", "isotropic; 12-segment forward kernel, 4+3-term backward sums and E1", 12),
    seg("segments-16", "isotropic; 16-segment forward kernel, 4+3-term backward sums and E1", 16),
    hg(
        "hg-exp1",
        "HG g in [-0.99, 0.99] (mirrored); 1 exponential per band, 8 segments, 4+3-term backward sums and E1",
        1,
    ),
    hg(
        "hg-exp2",
        "HG g in [-0.99, 0.99] (mirrored); 2 exponentials per band, 8 segments, 4+3-term backward sums and E1",
        2,
    ),
    hg(
        "hg-exp3",
        "HG g in [-0.99, 0.99] (mirrored); 3 exponentials per band, 8 segments, 4+3-term backward sums and E1",
        3,
    ),
    phi("phi-iso-4", "isotropic; whole A: 4 nodes in the scattering angle, Gauss-Laguerre tail, exact e^x E2 far part", (0.0, 0.0), PHI_4),
    phi("phi-iso-6", "isotropic; whole A: 6 nodes in the scattering angle, Gauss-Laguerre tail, exact e^x E2 far part", (0.0, 0.0), PHI_6),
    phi("phi-iso-8", "isotropic; whole A: 8 nodes in the scattering angle, Gauss-Laguerre tail, exact e^x E2 far part", (0.0, 0.0), PHI_8),
    phi("phi-4", "HG, g at run time in [-0.99, 0.99]; whole A: 4 nodes in the HG variable phi, Gauss-Laguerre tail, exact e^x E2 far part", MIRRORED_G, PHI_4),
    phi("phi-6", "HG, g at run time in [-0.99, 0.99]; whole A: 6 nodes in the HG variable phi, Gauss-Laguerre tail, exact e^x E2 far part", MIRRORED_G, PHI_6),
    phi("phi-8", "HG, g at run time in [-0.99, 0.99]; whole A: 8 nodes in the HG variable phi, Gauss-Laguerre tail, exact e^x E2 far part", MIRRORED_G, PHI_8),
    ModelSpec {
        name: "no-extinction",
        summary: "baseline; seed 003's exact closed form without extinction (atan2 of the cross product), isotropic, any tau: the cost floor",
        g_range: (0.0, 0.0),
        recipe: Recipe::Baseline(Baseline::NoExtinction),
    },
    march("raymarch-8", 8),
    march("raymarch-16", 16),
    march("raymarch-32", 32),
    march("raymarch-64", 64),
    march("raymarch-128", 128),
    march("raymarch-256", 256),
    march("raymarch-1024", 1024),
    equiangular("equiangular-2", 2),
    equiangular("equiangular-4", 4),
    equiangular("equiangular-8", 8),
    equiangular("equiangular-16", 16),
    equiangular("equiangular-32", 32),
    sun("sun2005-64", 64),
    sun("sun2005-128", 128),
    sun("sun2005-256", 256),
    sun("sun2005-512", 512),
];

/// A family that `airlight fit --family` can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// The forward kernel (all segment counts).
    Segments,
    /// The phase (all term counts and bands).
    Phase,
    /// The backscatter ratio.
    Backscatter,
    /// The φ family's fitted `eˣE₂`.
    Phi,
}

impl Family {
    /// All families.
    pub const ALL: [Family; 4] = [Family::Segments, Family::Phase, Family::Backscatter, Family::Phi];
    /// Name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Family::Segments => "segments",
            Family::Phase => "phase",
            Family::Backscatter => "backscatter",
            Family::Phi => "phi",
        }
    }
    /// Parses a command-line name.
    pub fn from_name(s: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == s)
    }
}

/// Every family fit.
#[derive(Debug, Clone, Default)]
pub struct Fits {
    /// Forward kernels by segment count, with the paper's kernel's errors on the same targets.
    pub segments: BTreeMap<usize, SegmentsFit>,
    /// Forward-integral RMS and max relative error of the paper's kernel on the fit targets.
    pub paper_segments: Option<(f64, f64, usize)>,
    /// Phase bands by term count.
    pub phase: BTreeMap<usize, Vec<BandFit>>,
    /// Largest error of the phase fit's node rule against the reference.
    pub phase_node_error: f64,
    /// Per band: RMS and max relative error of A under the paper's table (same fit points).
    pub paper_phase: Vec<(f64, f64)>,
    /// Backscatter ratio.
    pub ratio: Option<RatioFit>,
    /// Backward exponential sums, near and far.
    pub expsum: Option<(ExpSumFit, ExpSumFit)>,
    /// RMS and max relative error of the paper's ratio on the same targets.
    pub paper_ratio: Option<(f64, f64)>,
    /// The φ family's `eˣE₂`.
    pub e2: Option<crate::family::phi::E2Fit>,
}

enum Job {
    Segments(usize),
    Band(usize, usize),
    Ratio,
    ExpSum(Target),
}

enum JobOut {
    Segments(usize, SegmentsFit),
    Band(usize, usize, BandFit),
    Ratio(RatioFit),
    ExpSum(Target, ExpSumFit),
}

/// Fits the given families (all if `None`). `progress(done, total)` counts fit jobs.
pub fn fit(only: Option<Family>, progress: &(dyn Fn(usize, usize) + Sync)) -> Fits {
    let want = |f: Family| only.is_none_or(|o| o == f);
    let mut fits = Fits::default();
    let fwd_samples = if want(Family::Segments) { segments::samples(FORWARD_POINTS, FORWARD_SEED) } else { vec![] };
    let band_samples: Vec<Vec<phase_exp::PhaseSample>> = if want(Family::Phase) {
        PAPER_BANDS.iter().map(|&(lo, hi)| phase_exp::phase_samples(lo, hi, PHASE_POINTS, PHASE_SEED)).collect()
    } else {
        vec![]
    };
    let ratio_samples = if want(Family::Backscatter) { ratio::ratio_samples(RATIO_POINTS, RATIO_SEED) } else { vec![] };

    let mut jobs = Vec::new();
    if want(Family::Phase) {
        // The slowest jobs first, so two cores finish together.
        for &k in TERM_COUNTS.iter().rev() {
            for b in 0..PAPER_BANDS.len() {
                jobs.push(Job::Band(k, b));
            }
        }
    }
    if want(Family::Segments) {
        jobs.extend(SEGMENT_COUNTS.iter().rev().map(|&n| Job::Segments(n)));
    }
    if want(Family::Backscatter) {
        jobs.insert(0, Job::ExpSum(Target::Local));
        jobs.insert(1, Job::ExpSum(Target::Near));
        jobs.push(Job::Ratio);
    }
    let outs = crate::parallel::map(
        &jobs,
        |job| match *job {
            Job::Segments(n) => JobOut::Segments(n, segments::fit(n, &fwd_samples)),
            Job::Band(k, b) => {
                let (lo, hi) = PAPER_BANDS[b];
                JobOut::Band(k, b, phase_exp::fit_band(lo, hi, &phase_exp::start_decays(b, k), &band_samples[b]))
            }
            Job::Ratio => JobOut::Ratio(ratio::fit(&ratio_samples)),
            Job::ExpSum(target) => JobOut::ExpSum(
                target,
                expsum::fit(target, if target == Target::Near { EXPSUM_TERMS.0 } else { EXPSUM_TERMS.1 }),
            ),
        },
        progress,
    );
    let mut bands: BTreeMap<usize, Vec<(usize, BandFit)>> = BTreeMap::new();
    let (mut near, mut far) = (None, None);
    for o in outs {
        match o {
            JobOut::Segments(n, f) => {
                fits.segments.insert(n, f);
            }
            JobOut::Band(k, b, f) => bands.entry(k).or_default().push((b, f)),
            JobOut::Ratio(f) => fits.ratio = Some(f),
            JobOut::ExpSum(Target::Near, f) => near = Some(f),
            JobOut::ExpSum(Target::Local, f) => far = Some(f),
        }
    }
    if let (Some(n), Some(f)) = (near, far) {
        fits.expsum = Some((n, f));
    }
    for (k, mut v) in bands {
        v.sort_by_key(|(b, _)| *b);
        fits.phase.insert(k, v.into_iter().map(|(_, f)| f).collect());
    }
    if !fwd_samples.is_empty() {
        let (rms, max) = rms_max(&segments::forward_errors(&Segments::paper(), &fwd_samples));
        fits.paper_segments = Some((rms, max, fwd_samples.len()));
    }
    if !band_samples.is_empty() {
        let paper = ExpPhase::paper();
        fits.phase_node_error = band_samples.iter().map(|s| phase_exp::node_rule_error(s)).fold(0.0, f64::max);
        fits.paper_phase = band_samples.iter().map(|s| rms_max(&phase_exp::a_errors(|g| paper.terms(g), s))).collect();
    }
    if !ratio_samples.is_empty() {
        let (rms, max) = rms_max(&ratio::backward_errors(&Ratio::paper(), &ratio_samples));
        fits.paper_ratio = Some((rms, max));
    }
    if want(Family::Phi) {
        fits.e2 = Some(crate::family::phi::ExpE2::fit());
    }
    fits
}

fn s(v: &str) -> Value {
    Value::String(v.to_string())
}
fn i(v: impl TryInto<i64>) -> Value {
    Value::Integer(v.try_into().unwrap_or(i64::MAX))
}
fn f(v: f64) -> Value {
    Value::Float(v)
}
fn kv(pairs: Vec<(&str, Value)>) -> Vec<(String, Value)> {
    pairs.into_iter().map(|(k, v)| (k.to_string(), v)).collect()
}
fn hex_seed(seed: u64) -> Value {
    s(&format!("{seed:#018x}"))
}

/// Builds the model `spec` from `fits` (errors not yet measured).
pub fn assemble(spec: &ModelSpec, fits: &Fits) -> Result<ModelFile, String> {
    let (forward_choice, phase_choice, backward_choice, forward_attenuation) = match spec.recipe {
        Recipe::Split { forward, phase, backward, forward_attenuation } => {
            (forward, phase, backward, forward_attenuation)
        }
        Recipe::Baseline(b) => return Ok(assemble_baseline(spec, b)),
        Recipe::Phi(t) => return assemble_phi(spec, t, fits),
    };
    let mut prov: Vec<Provenance> = Vec::new();
    let mut families = Vec::new();
    let forward = match forward_choice {
        ForwardChoice::Paper => {
            families.push("segments-3 (paper, §3.1)".to_string());
            let (kmax, kat) = Segments::paper().kernel_error();
            let mut v = vec![("source", s("Pradhan & Kumar §3.1, as printed"))];
            v.push(("kernel_max_abs_error", f(kmax)));
            v.push(("kernel_max_abs_error_at", f(kat)));
            if let Some((rms, max, n)) = fits.paper_segments {
                v.push(("forward_integral_rms_rel", f(rms)));
                v.push(("forward_integral_max_rel", f(max)));
                v.push(("targets", i(n)));
                v.push(("targets_seed", hex_seed(FORWARD_SEED)));
            }
            prov.push(("forward.fit".into(), kv(v)));
            Segments::paper()
        }
        ForwardChoice::Refit(n) => {
            let fit = fits.segments.get(&n).ok_or(format!("segments-{n} was not fitted"))?;
            families.push(format!("segments-{n} (refit)"));
            let (kmax, kat) = fit.segments.kernel_error();
            prov.push((
                "forward.fit".into(),
                kv(vec![
                    ("source", s("least squares, this project")),
                    ("objective", s("sum of squared relative errors of the forward integral ∫ e^(-T k) dθ")),
                    ("targets", i(fit.samples)),
                    (
                        "targets_from",
                        s("thin and dense points with a forward part (T = τ sin γ, θ range from γ and ρ)"),
                    ),
                    ("targets_seed", hex_seed(FORWARD_SEED)),
                    ("inner", s("segment values: Gauss-Newton, each step linear least squares by SVD (nalgebra 0.34)")),
                    ("inner_steps", i(fit.inner_steps)),
                    ("outer", s(&format!("breakpoints (softmax widths): {OUTER_SOLVER}"))),
                    ("iterations", i(fit.outcome.iterations)),
                    ("termination", s(&fit.outcome.termination)),
                    ("forward_integral_rms_rel", f(fit.rms_rel)),
                    ("forward_integral_max_rel", f(fit.max_rel)),
                    ("kernel_max_abs_error", f(kmax)),
                    ("kernel_max_abs_error_at", f(kat)),
                ]),
            ));
            fit.segments.clone()
        }
    };
    let phase = match phase_choice {
        PhaseChoice::Isotropic => {
            families.push("isotropic".into());
            PhaseModel::Isotropic
        }
        PhaseChoice::Paper => {
            families.push("hg-exp-1 (paper appendix)".into());
            let mut v = vec![
                ("source", s("Pradhan & Kumar appendix, as printed")),
                ("reading", s("4π·P(α) ≈ a e^(-b α), α in radians: the only reading whose g = 0 row is isotropic")),
            ];
            if !fits.paper_phase.is_empty() {
                v.push(("a_rms_rel_by_band", Value::Array(fits.paper_phase.iter().map(|x| f(x.0)).collect())));
                v.push(("a_max_rel_by_band", Value::Array(fits.paper_phase.iter().map(|x| f(x.1)).collect())));
            }
            prov.push(("phase.fit".into(), kv(v)));
            PhaseModel::Exp(ExpPhase::paper())
        }
        PhaseChoice::Refit(k) => {
            let bands = fits.phase.get(&k).ok_or(format!("hg-exp-{k} was not fitted"))?;
            families.push(format!("hg-exp-{k} (refit)"));
            let arr = |g: &dyn Fn(&BandFit) -> Value| Value::Array(bands.iter().map(g).collect());
            prov.push((
                "phase.fit".into(),
                kv(vec![
                    ("source", s("least squares, this project")),
                    (
                        "objective",
                        s("sum of squared relative errors of A with the exact kernel (fixed 162-node rule per point)"),
                    ),
                    (
                        "negative_g",
                        s(if spec.g_range.0 < 0.0 { "mirror: P_g(α) = P_-g(π - α)" } else { "not supported" }),
                    ),
                    ("node_rule_max_rel_error", f(fits.phase_node_error)),
                    ("targets_per_band", i(bands[0].samples)),
                    ("targets_seed", hex_seed(PHASE_SEED)),
                    ("inner", s("amplitudes: linear least squares by SVD (nalgebra 0.34)")),
                    ("outer", s(&format!("decays (values at band ends and middle): {OUTER_SOLVER}"))),
                    ("iterations_by_band", arr(&|b| i(b.outcome.iterations))),
                    ("termination_by_band", arr(&|b| s(&b.outcome.termination))),
                    ("a_rms_rel_by_band", arr(&|b| f(b.rms_rel))),
                    ("a_max_rel_by_band", arr(&|b| f(b.max_rel))),
                ]),
            ));
            PhaseModel::Exp(ExpPhase { bands: bands.iter().map(|b| b.band.clone()).collect::<Vec<Band>>(), scale: 1.0 })
        }
    };
    let ratio = match backward_choice {
        BackChoice::RefitRatio => {
            let fit = fits.ratio.as_ref().ok_or("the backscatter ratio was not fitted")?;
            families.push("backscatter-ratio (refit; γ ≤ π/2)".into());
            prov.push((
                "backscatter.fit".into(),
                kv(vec![
                    ("source", s("least squares, this project")),
                    (
                        "objective",
                        s("sum of squared relative errors of A: exact forward part plus the ratio's backward part"),
                    ),
                    ("targets", i(fit.samples)),
                    ("targets_seed", hex_seed(RATIO_SEED)),
                    ("inner", s("f: linear least squares by SVD (nalgebra 0.34)")),
                    ("outer", s(&format!("g, h from the paper's values: {OUTER_SOLVER}"))),
                    ("iterations", i(fit.outcome.iterations)),
                    ("termination", s(&fit.outcome.termination)),
                    ("a_rms_rel", f(fit.a_rms_rel)),
                    ("backward_integral_rms_rel", f(fit.rms_rel)),
                    ("backward_integral_max_rel", f(fit.max_rel)),
                ]),
            ));
            Some(fit.ratio.clone())
        }
        BackChoice::PaperRatio => {
            families.push("backscatter-ratio (paper §3.2; γ ≤ π/2)".into());
            let mut v = vec![("source", s("Pradhan & Kumar §3.2, as printed (third row read as h)"))];
            if let Some((rms, max)) = fits.paper_ratio {
                v.push(("backward_integral_rms_rel", f(rms)));
                v.push(("backward_integral_max_rel", f(max)));
            }
            prov.push(("backscatter.fit".into(), kv(v)));
            Some(Ratio::paper())
        }
        BackChoice::ExpSum => None,
    };
    let (near, far) = fits.expsum.as_ref().ok_or("the backward exponential sums were not fitted")?;
    families.push(format!(
        "backscatter-expsum-{}+{}+E1 ({})",
        near.sum.c.len(),
        far.sum.c.len(),
        if ratio.is_some() { "γ > π/2, where the ratio is undefined" } else { "all γ" }
    ));
    prov.push((
        "backscatter.expsum_fit".into(),
        kv(vec![
            ("source", s("this project: near 1/(1 + u²) ≈ Σ c e^(-s u) on [1, split]; beyond, 1/u² integrated exactly with E1 (Abramowitz & Stegun 5.1.53, 5.1.56), or for a far part shorter than local_ratio, 1/y² ≈ Σ c e^(-s y) on [1, local_ratio], y = u/max(u0, split)")),
            ("split", f(expsum::SPLIT)),
            ("local_ratio", f(expsum::LOCAL_RATIO)),
            ("objective", s("max relative error on 400 log-spaced points (amplitudes: Lawson-reweighted least squares by SVD)")),
            ("outer", s(&format!("log rates: {OUTER_SOLVER}, restarted until no gain"))),
            ("near_iterations", i(near.outcome.iterations)),
            ("near_termination", s(&near.outcome.termination)),
            ("near_max_rel", f(near.max_rel.0)),
            ("near_max_rel_at_u", f(near.max_rel.1)),
            ("local_iterations", i(far.outcome.iterations)),
            ("local_termination", s(&far.outcome.termination)),
            ("local_max_rel", f(far.max_rel.0)),
            ("local_max_rel_at_y", f(far.max_rel.1)),
        ]),
    ));
    prov.push(provenance_table(vec![]));
    Ok(ModelFile {
        model: Approximation {
            name: spec.name.into(),
            summary: spec.summary.into(),
            g_range: spec.g_range,
            body: Body::Split(Split {
                forward,
                phase,
                ratio,
                expsum: Backward { near: near.sum.clone(), local: far.sum.clone() },
                forward_attenuation,
            }),
        },
        families,
        errors: vec![],
        provenance: prov,
    })
}

/// A member of the φ family (errors not yet measured): the rules are Gauss's, the
/// splits the tier's, `eˣE₂` fitted.
fn assemble_phi(spec: &ModelSpec, t: PhiTier, fits: &Fits) -> Result<ModelFile, String> {
    use crate::family::phi::{PhiRule, E2_DEGREE, EIN_TERMS};
    let fit = fits.e2.as_ref().ok_or("the phi family's e^x E2 was not fitted")?;
    let rule = PhiRule::new(t.head, t.far, t.tail, t.cut, t.far_cut, fit.e2.clone());
    let iso = spec.g_range == (0.0, 0.0);
    let families = vec![
        format!(
            "phi-{} ({}-point Gauss-Legendre head, {}-point far correction, {}-point Gauss-Laguerre tail)",
            t.head, t.head, t.far, t.tail
        ),
        if iso { "isotropic".into() } else { "HG exact".into() },
    ];
    let prov = vec![
        (
            "e2.fit".into(),
            kv(vec![
                ("source", s("this project: e^x E2(x) = 1 - x e^x E1(x); Ein's Taylor series below x = 1, a rational in t = 1/x beyond")),
                ("target", s("e^x E2(x), x >= 1, through the reference complex E1 (fit/src/e1.rs, about 1e-15)")),
                ("form", s(&format!("t P(t)/Q(t), P, Q of degree {E2_DEGREE} with unit constant terms; Ein to x^{EIN_TERMS}"))),
                ("objective", s("relative error, linearised (Sanathanan-Koerner): each step linear least squares by SVD (nalgebra 0.34), weighted by the previous denominator")),
                ("points", i(fit.points)),
                ("points_from", s("Chebyshev points of t = 1/x in (0, 1]")),
                ("iterations", i(fit.iterations)),
                ("max_rel", f(fit.max_rel.0)),
                ("max_rel_at_x", f(fit.max_rel.1)),
                ("series_max_rel", f(fit.series_max_rel.0)),
                ("series_max_rel_at_x", f(fit.series_max_rel.1)),
            ]),
        ),
        provenance_table(vec![
            ("method", s("whole A in the u form: Gauss-Legendre head in the HG variable phi (u past X or on short intervals) to the transmittance cut e^-L, Gauss-Laguerre tail from both ends; for small T X, C/u^2 exactly through e^x E2 and the rest by Gauss-Legendre in v = 1/u (fit/src/family/phi.rs)")),
            ("fitted", s("e^x E2's rational (see [e2.fit]); node counts and splits are the tier's")),
        ]),
    ];
    Ok(ModelFile {
        model: Approximation {
            name: spec.name.into(),
            summary: spec.summary.into(),
            g_range: spec.g_range,
            body: Body::Phi(rule),
        },
        families,
        errors: vec![],
        provenance: prov,
    })
}

/// A baseline's coefficient file (errors not yet measured): its parameters are
/// the method's, nothing is fitted.
fn assemble_baseline(spec: &ModelSpec, b: Baseline) -> ModelFile {
    use crate::family::baseline::{Equiangular, RayMarch, FAR_PLANE, MARCH_CUTOFF};
    let (body, family, method) = match b {
        Baseline::NoExtinction => (
            Body::NoExtinction(crate::family::closed::NoExtinction),
            "no-extinction (seed 003)".to_string(),
            "A(0, γ, ρ) = atan2(h ρ, 1 − ρ cos γ)/(4π h) whatever τ: exact at τ = 0, error growing with τ".to_string(),
        ),
        Baseline::RayMarch(n) => (
            Body::RayMarch(RayMarch { steps: n }),
            format!("raymarch-{n} (midpoint)"),
            format!(
                "{n} uniform midpoint samples of P e^(-τ(s + t))/t² over [0, ρ]; no surface: to the relative two-leg transmittance {MARCH_CUTOFF}, capped at {FAR_PLANE} light distances"
            ),
        ),
        Baseline::Sun2005(r) => (
            Body::Sun2005(crate::family::sun::SunTable::build(r)),
            format!("sun2005-{r} (F(u, v) table, {r}x{r} f32)"),
            format!("A = e^(-τ cos γ)/(2π sin γ) [F(τ sin γ, ξb) - F(τ sin γ, γ/2)], F bilinear from a {r}x{r} table over u ≤ {}, v ≤ π/2 (Sun et al. 2005; Wyman & Ramsey 2008)", crate::family::sun::U_MAX),
        ),
        Baseline::Equiangular(n) => (
            Body::Equiangular(Equiangular::new(n)),
            format!("equiangular-{n} (Gauss-Legendre)"),
            format!("{n}-point Gauss-Legendre in θ, s = cos γ + sin γ tan θ (ds/t² = dθ/h), nodes by Newton on P_n in f64"),
        ),
    };
    ModelFile {
        model: Approximation { name: spec.name.into(), summary: spec.summary.into(), g_range: spec.g_range, body },
        families: vec![family, if spec.g_range == (0.0, 0.0) { "isotropic".into() } else { "HG exact".into() }],
        errors: vec![],
        provenance: vec![provenance_table(vec![
            ("baseline", s(&method)),
            ("fitted", s("nothing: the method's own parameters")),
        ])],
    }
}

/// The `[provenance]` table every file ends with, after `extra`.
fn provenance_table(extra: Vec<(&str, Value)>) -> Provenance {
    let mut v = extra;
    v.extend([
            ("crate", s(concat!("airlight-fit ", env!("CARGO_PKG_VERSION")))),
            ("reference", s("adaptive Gauss-Kronrod on the u form (fit/src/reference.rs)")),
            ("reference_rel_tol", f(REFERENCE_REL_TOL)),
            ("validation_seed", hex_seed(VALIDATION_SEED)),
            ("validation_points_per_domain", i(VALIDATION_POINTS)),
            ("validation_extra", s("domain corners at the ends of g_range; 48x48 grids on the faces rho = 0.01, rho = inf, tau = min and tau = max; local Nelder-Mead searches inside the domain from the 8 largest over- and 8 largest underestimates (a tenth of the domain apart) and from the 16 largest face errors (3% apart) raise max_rel where they find more")),
    ]);
    ("provenance".into(), kv(v))
}

/// The validation points of one domain and `g` range with their reference values.
pub struct Validation {
    /// The domain.
    pub domain: Domain,
    /// `g` range.
    pub g_range: (f64, f64),
    /// Points and reference `A`.
    pub points: Vec<(Point, f64)>,
    /// Grids on the domain's faces ([`Domain::faces`]) with reference `A`: they
    /// raise the max and start local searches, but are not part of the p99.
    pub faces: Vec<(Point, f64)>,
}

/// Points per side of each face grid.
pub const FACE_GRID: usize = 48;

/// The `g` values of the face grids for a `g` range: its ends and 0 if inside.
fn face_gs(g_range: (f64, f64)) -> Vec<f64> {
    let mut gs = vec![g_range.0];
    if g_range.0 < 0.0 && g_range.1 > 0.0 {
        gs.push(0.0);
    }
    if g_range.1 != g_range.0 {
        gs.push(g_range.1);
    }
    gs
}

/// Reference values for the validation sets of every `(domain, g range)` in `ranges`.
pub fn validations(ranges: &[(f64, f64)], progress: &(dyn Fn(usize, usize) + Sync)) -> Vec<Validation> {
    let mut sets = Vec::new();
    for &r in ranges {
        for d in Domain::ALL {
            sets.push((d, r, d.validation_set(r, VALIDATION_POINTS, VALIDATION_SEED), d.faces(&face_gs(r), FACE_GRID)));
        }
    }
    let all: Vec<Point> = sets.iter().flat_map(|s| s.2.iter().chain(&s.3).copied()).collect();
    let values =
        crate::parallel::map(&all, |p| reference::airlight(*p).expect("validation points are valid"), progress);
    let mut it = values.into_iter();
    let mut with_values = |pts: Vec<Point>| -> Vec<(Point, f64)> {
        pts.into_iter().map(|p| (p, it.next().expect("one value per point"))).collect()
    };
    sets.into_iter()
        .map(|(domain, g_range, pts, faces)| Validation {
            domain,
            g_range,
            points: with_values(pts),
            faces: with_values(faces),
        })
        .collect()
}

/// Clamps a point into a sampled domain's box (keeping `ρ = ∞`).
fn clamp_into(domain: Domain, g_range: (f64, f64), p: Point) -> Point {
    let (tlo, thi) = domain.tau_range();
    Point {
        tau: p.tau.clamp(tlo, thi),
        gamma: p.gamma.clamp(0.01, PI - 0.01),
        rho: if p.rho.is_infinite() { p.rho } else { p.rho.clamp(0.01, 100.0) },
        g: p.g.clamp(g_range.0, g_range.1),
    }
}

/// Points each local search starts from, per direction of the error.
pub const REFINE_STARTS: usize = 8;

/// Measures `model` on `v`: max, p99 and worst point over the validation set, the
/// max then pushed further by a local Nelder–Mead search from the largest over-
/// and underestimates (sampled domains only), so the declared bound is not an
/// accident of sampling.
pub fn measure(model: &dyn Model, v: &Validation) -> DomainErrors {
    let mut errs: Vec<(Point, f64)> = Vec::with_capacity(v.points.len());
    let mut signed: Vec<(Point, f64)> = Vec::with_capacity(v.points.len());
    let (mut non_finite, mut negative) = (0, 0);
    for &(p, exact) in &v.points {
        let a = model.eval_unchecked(p);
        if !a.is_finite() && exact.is_finite() {
            non_finite += 1;
        }
        if a < 0.0 {
            negative += 1;
        }
        errs.push((p, rel_error(a, exact)));
        if a.is_finite() && exact.is_finite() && exact > 0.0 {
            signed.push((p, a / exact - 1.0));
        }
    }
    let stats = crate::stats::ErrorStats::from_errors(errs.iter().copied());
    let mut worst = stats.worst.unwrap_or(Point { tau: 0.0, gamma: 1.0, rho: 1.0, g: 0.0 });
    let mut max = stats.max;
    if v.domain != Domain::Extreme && max.is_finite() {
        // Start the search from the largest over- and under-estimates separately: a
        // model whose worst sampled error is an underestimate near −100% can still
        // overestimate by more elsewhere.
        // Starts are spread out: a model's error often plateaus at one level over a
        // large region (the backward sum's floor), and the largest errors all sit
        // there while a narrow peak elsewhere (a domain edge) goes unvisited.
        signed.sort_by(|a, b| b.1.total_cmp(&a.1));
        let mut starts = diverse(v.domain, signed.iter().map(|s| s.0), REFINE_STARTS, 0.1);
        starts.extend(diverse(v.domain, signed.iter().rev().map(|s| s.0), REFINE_STARTS, 0.1));
        // The face grids: their largest errors count, and start searches too.
        let mut faces: Vec<(Point, f64)> =
            v.faces.iter().map(|&(p, exact)| (p, rel_error(model.eval_unchecked(p), exact))).collect();
        faces.sort_by(|a, b| b.1.total_cmp(&a.1));
        if let Some(&(p, e)) = faces.first() {
            if e > max {
                max = e;
                worst = p;
            }
        }
        // Errors along a face oscillate with the kernel's segments: many nearby starts.
        starts.extend(diverse(v.domain, faces.iter().map(|f| f.0), 2 * REFINE_STARTS, 0.03));
        for start in starts {
            let (found, e) = refine(model, v.domain, v.g_range, start);
            if e > max {
                max = e;
                worst = found;
            }
        }
    }
    DomainErrors {
        domain: v.domain,
        points: v.points.len(),
        max_rel: max,
        p99_rel: stats.p99,
        worst,
        non_finite,
        negative,
    }
}

/// Up to `n` of `points` (taken in order) at least `apart` (a share of the
/// domain) from each other (τ, γ, log ρ and g scaled to the domain's box; ρ = ∞ far from
/// every finite ρ).
fn diverse(domain: Domain, points: impl Iterator<Item = Point>, n: usize, apart: f64) -> Vec<Point> {
    let (tlo, thi) = domain.tau_range();
    let key = |p: &Point| {
        let rho = if p.rho.is_infinite() { 10.0 } else { (p.rho / 0.01).ln() / (1e4f64).ln() };
        [(p.tau - tlo) / (thi - tlo), p.gamma / PI, rho, 0.5 * p.g]
    };
    let mut out: Vec<Point> = Vec::with_capacity(n);
    for p in points {
        if out.len() == n {
            break;
        }
        let k = key(&p);
        let far = out.iter().all(|q| {
            let kq = key(q);
            k.iter().zip(&kq).map(|(a, b)| (a - b) * (a - b)).sum::<f64>() > apart * apart
        });
        if far {
            out.push(p);
        }
    }
    out
}

/// Local search for a larger error near `start`, inside the domain.
fn refine(model: &dyn Model, domain: Domain, g_range: (f64, f64), start: Point) -> (Point, f64) {
    let inf = start.rho.is_infinite();
    let to_point = |x: &[f64]| {
        clamp_into(
            domain,
            g_range,
            Point { tau: x[0], gamma: x[1], rho: if inf { f64::INFINITY } else { x[2].exp() }, g: x[3] },
        )
    };
    let err = |x: &[f64]| {
        let p = to_point(x);
        match reference::airlight(p) {
            Ok(exact) => -rel_error(model.eval_unchecked(p), exact),
            Err(_) => 0.0,
        }
    };
    let x0 = [start.tau, start.gamma, if inf { 0.0 } else { start.rho.ln() }, start.g];
    let (tlo, thi) = domain.tau_range();
    let step = [0.05 * (thi - tlo), 0.05, if inf { 0.0 } else { 0.2 }, if g_range.0 == g_range.1 { 0.0 } else { 0.02 }];
    let out = lsq::nelder_mead(&err, &x0, &step, 1e-12, 200);
    (to_point(&out.param), -out.cost)
}

/// The coefficient files under `dir` in catalog order (files naming no catalog
/// model last, by name).
pub fn load(dir: &std::path::Path) -> Result<Vec<ModelFile>, crate::coeffs::CoeffError> {
    let mut files = crate::coeffs::load_dir(dir)?;
    files.sort_by_key(|f| CATALOG.iter().position(|c| c.name == f.model.name).unwrap_or(usize::MAX));
    Ok(files)
}

/// Assembles every model of [`CATALOG`] from `fits` and measures it on the
/// validation sets: the complete coefficient files, in catalog order.
/// `progress(done, total)` counts reference evaluations, then models.
pub fn build(fits: &Fits, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Vec<ModelFile>, String> {
    let mut files = CATALOG.iter().map(|spec| assemble(spec, fits)).collect::<Result<Vec<_>, _>>()?;
    let mut ranges: Vec<(f64, f64)> = Vec::new();
    for s in CATALOG {
        if !ranges.contains(&s.g_range) {
            ranges.push(s.g_range);
        }
    }
    let sets = validations(&ranges, progress);
    let jobs: Vec<(usize, usize)> = files
        .iter()
        .enumerate()
        .flat_map(|(i, f)| {
            sets.iter()
                .enumerate()
                .filter(|(_, v)| v.g_range == f.model.g_range)
                .map(move |(j, _)| (i, j))
                .collect::<Vec<_>>()
        })
        .collect();
    let measured = crate::parallel::map(&jobs, |&(i, j)| measure(&files[i].model, &sets[j]), progress);
    for (&(i, _), e) in jobs.iter().zip(measured) {
        files[i].errors.push(e);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalog_names_are_unique_and_ranges_valid() {
        let mut names: Vec<&str> = CATALOG.iter().map(|m| m.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), CATALOG.len());
        for m in CATALOG {
            assert!(m.g_range.0 <= m.g_range.1 && m.g_range.1 < 1.0);
            if let Recipe::Split { phase: PhaseChoice::Isotropic, .. } = m.recipe {
                assert_eq!(m.g_range, (0.0, 0.0));
            }
        }
    }
}

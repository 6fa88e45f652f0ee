//! The split family's fit: the forward kernel's segments, the phase's bands and
//! the backscatter ratio and sums (one parallel run of every job), and the
//! assembly of a member from the recipe's choices with the provenance of each
//! part.

use super::dominant::{self, DominantFit};
use super::expsum::{self, Backward, ExpSumFit, Target};
use super::phase_exp::{self, Band, BandFit, ExpPhase, PAPER_BANDS};
use super::ratio::{self, Ratio, RatioFit};
use super::segments::{self, Segments, SegmentsFit};
use super::{PhaseModel, Split};
use crate::family::Assembled;
use crate::lsq::OUTER_SOLVER;
use airlight_truth::stats::rms_max;
use airlight_truth::tomlfile::value::{f, hex_seed, i, kv, s};
use airlight_truth::tomlfile::Provenance;
use std::collections::BTreeMap;
use toml::Value;

/// The part `airlight fit --family segments` names: the forward kernel (all segment counts).
pub const SEGMENTS: &str = "segments";
/// The part `phase`: the phase (all term counts and bands).
pub const PHASE: &str = "phase";
/// The part `backscatter`: the backscatter ratio and the backward sums.
pub const BACKSCATTER: &str = "backscatter";

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
    /// The paper's three segments refit jointly with the ratio to dominate the
    /// published model ([`dominant`]).
    Dominant,
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
    /// The ratio refit jointly with the forward segments to dominate the
    /// published model ([`dominant`]), the exponential sum beyond.
    DominantRatio,
    /// The exponential sum everywhere.
    ExpSum,
}

/// How a member of the split family is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Recipe {
    /// Forward kernel.
    pub forward: ForwardChoice,
    /// Phase.
    pub phase: PhaseChoice,
    /// Backward part.
    pub backward: BackChoice,
    /// Whether the forward part keeps `e^{−τ cos γ}` (false only as printed).
    pub forward_attenuation: bool,
}

/// The split family's fits.
#[derive(Debug, Clone, Default)]
pub struct SplitFits {
    /// Forward kernels by segment count.
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
    /// The paper's form refit jointly to dominate the published coefficients.
    pub dominant: Option<DominantFit>,
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

/// Fits the named parts (`segments`, `phase`, `backscatter`): every job in one
/// parallel run. `progress(done, total)` counts fit jobs.
pub fn fit(parts: &[&str], progress: &(dyn Fn(usize, usize) + Sync)) -> SplitFits {
    let want = |p: &str| parts.contains(&p);
    let mut fits = SplitFits::default();
    let fwd_samples = if want(SEGMENTS) { segments::samples(FORWARD_POINTS, FORWARD_SEED) } else { vec![] };
    let band_samples: Vec<Vec<phase_exp::PhaseSample>> = if want(PHASE) {
        PAPER_BANDS.iter().map(|&(lo, hi)| phase_exp::phase_samples(lo, hi, PHASE_POINTS, PHASE_SEED)).collect()
    } else {
        vec![]
    };
    let ratio_samples = if want(BACKSCATTER) { ratio::ratio_samples(RATIO_POINTS, RATIO_SEED) } else { vec![] };

    let mut jobs = Vec::new();
    if want(PHASE) {
        // The slowest jobs first, so two cores finish together.
        for &k in TERM_COUNTS.iter().rev() {
            for b in 0..PAPER_BANDS.len() {
                jobs.push(Job::Band(k, b));
            }
        }
    }
    if want(SEGMENTS) {
        jobs.extend(SEGMENT_COUNTS.iter().rev().map(|&n| Job::Segments(n)));
    }
    if want(BACKSCATTER) {
        jobs.insert(0, Job::ExpSum(Target::Local));
        jobs.insert(1, Job::ExpSum(Target::Near));
        jobs.push(Job::Ratio);
    }
    let outs = airlight_truth::parallel::map(
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
        // The dominance fit needs the backward sums (its γ > π/2 part).
        let sums = Backward { near: n.sum.clone(), local: f.sum.clone() };
        fits.dominant = Some(dominant::fit(&sums));
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
    fits
}


/// What `airlight fit --family segments|phase|backscatter` prints.
pub fn summary(fits: &SplitFits) -> Vec<String> {
    let mut out = Vec::new();
    if let Some((rms, max, n)) = fits.paper_segments {
        out.push(format!("segments paper (3): forward integral rms {rms:.1e} max {max:.1e} on {n} targets"));
    }
    for (n, f) in &fits.segments {
        out.push(format!(
            "segments refit ({n}): forward integral rms {:.1e} max {:.1e}; kernel max |error| {:.1e}; {} iterations, {}",
            f.rms_rel,
            f.max_rel,
            f.segments.kernel_error().0,
            f.outcome.iterations,
            f.outcome.termination
        ));
    }
    for (k, bands) in &fits.phase {
        let cells: Vec<String> = bands.iter().map(|b| format!("{:.1e}/{:.1e}", b.rms_rel, b.max_rel)).collect();
        out.push(format!("phase {k} exponential(s), A rms/max per band: {}", cells.join(" ")));
    }
    if !fits.paper_phase.is_empty() {
        let cells: Vec<String> = fits.paper_phase.iter().map(|(r, m)| format!("{r:.1e}/{m:.1e}")).collect();
        out.push(format!("phase paper table, A rms/max per band: {}", cells.join(" ")));
    }
    if let (Some(r), Some((prms, pmax))) = (&fits.ratio, fits.paper_ratio) {
        out.push(format!(
            "backscatter ratio: refit rms {:.1e} max {:.1e} ({} iterations, {}); paper rms {prms:.1e} max {pmax:.1e}",
            r.rms_rel, r.max_rel, r.outcome.iterations, r.outcome.termination
        ));
    }
    if let Some(d) = &fits.dominant {
        let cells: Vec<String> = dominant::FIGURES
            .iter()
            .zip(d.figures.iter().zip(&d.paper))
            .map(|(n, (a, b))| format!("{n} {a:.2e}/{b:.2e}"))
            .collect();
        out.push(format!(
            "paper form refit for dominance (refit/paper): {}; worst ratio {:.3} ({} iterations, {})",
            cells.join(", "),
            d.worst_ratio(),
            d.outcome.iterations,
            d.outcome.termination
        ));
    }
    if let Some((n, f)) = &fits.expsum {
        out.push(format!(
            "backward sums: near {} terms max weight error {:.1e}; local {} terms max error {:.1e}",
            n.sum.c.len(),
            n.max_rel.0,
            f.sum.c.len(),
            f.max_rel.0
        ));
    }
    out
}

/// Labels and provenance of the assembly, gathered part by part.
#[derive(Default)]
struct Parts {
    families: Vec<String>,
    prov: Vec<Provenance>,
}

/// The forward kernel: the paper's, or a refit.
fn forward(choice: ForwardChoice, fits: &SplitFits, parts: &mut Parts) -> Result<Segments, String> {
    let (families, prov) = (&mut parts.families, &mut parts.prov);
    Ok(match choice {
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
        ForwardChoice::Dominant => {
            let d = fits.dominant.as_ref().ok_or("the dominance refit was not run")?;
            families.push("segments-3 (paper form, refit with the ratio to dominate the published model)".into());
            prov.push(("forward.fit".into(), kv(dominant_provenance(d))));
            d.forward.clone()
        }
    })
}

/// The provenance of the dominance refit (in `[forward.fit]`; the ratio's table
/// points there).
fn dominant_provenance(d: &DominantFit) -> Vec<(&'static str, Value)> {
    let (kmax, kat) = d.forward.kernel_error();
    let arr = |x: &[f64; dominant::N]| Value::Array(x.iter().map(|&v| f(v)).collect());
    vec![
        ("source", s("this project: the paper's form (3 segments, ratio cubics) refit from its published values")),
        (
            "objective",
            s(&format!(
                "minimax against the published model: the largest ratio of the refit's figure to `paper`'s on the same points, over {} (a soft maximum, power {}, in the search; the hard maximum reported)",
                dominant::FIGURES.join(", "),
                dominant::SOFT_MAX_POWER
            )),
        ),
        ("parameters", s("2 interior breakpoints, 3 slopes, 3 intercepts, f, g, h (20), all at once")),
        ("points", i(d.points)),
        (
            "points_from",
            s(&format!(
                "{} low-discrepancy points inside thin and inside dense each (g = 0, seed below); {n}x{n} grids on each domain's faces, and its corners",
                dominant::DOMINANT_POINTS,
                n = dominant::DOMINANT_FACES
            )),
        ),
        ("points_seed", hex_seed(dominant::DOMINANT_SEED)),
        ("figures", Value::Array(dominant::FIGURES.iter().map(|n| s(n)).collect())),
        ("figures_refit", arr(&d.figures)),
        ("figures_paper", arr(&d.paper)),
        ("worst_ratio", f(d.worst_ratio())),
        ("solver", s(&format!("{OUTER_SOLVER}, restarted until no gain"))),
        ("iterations", i(d.outcome.iterations)),
        ("termination", s(&d.outcome.termination)),
        ("kernel_max_abs_error", f(kmax)),
        ("kernel_max_abs_error_at", f(kat)),
    ]
}

/// The phase: isotropic, the paper's table, or a refit.
fn phase(choice: PhaseChoice, g_range: (f64, f64), fits: &SplitFits, parts: &mut Parts) -> Result<PhaseModel, String> {
    let (families, prov) = (&mut parts.families, &mut parts.prov);
    Ok(match choice {
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
                        s(if g_range.0 < 0.0 { "mirror: P_g(α) = P_-g(π - α)" } else { "not supported" }),
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
    })
}

/// The backscatter ratio, if the recipe keeps one.
fn ratio(choice: BackChoice, fits: &SplitFits, parts: &mut Parts) -> Result<Option<Ratio>, String> {
    let (families, prov) = (&mut parts.families, &mut parts.prov);
    Ok(match choice {
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
        BackChoice::DominantRatio => {
            let d = fits.dominant.as_ref().ok_or("the dominance refit was not run")?;
            families.push("backscatter-ratio (paper form, refit with the segments to dominate the published model; γ ≤ π/2)".into());
            prov.push((
                "backscatter.fit".into(),
                kv(vec![
                    ("source", s("this project: fitted in one search with the forward segments")),
                    ("objective", s("see [forward.fit]")),
                ]),
            ));
            Some(d.ratio.clone())
        }
        BackChoice::ExpSum => None,
    })
}

/// The backward exponential sums (every member has them).
fn backward(has_ratio: bool, fits: &SplitFits, parts: &mut Parts) -> Result<Backward, String> {
    let (families, prov) = (&mut parts.families, &mut parts.prov);
    let (near, far) = fits.expsum.as_ref().ok_or("the backward exponential sums were not fitted")?;
    families.push(format!(
        "backscatter-expsum-{}+{}+E1 ({})",
        near.sum.c.len(),
        far.sum.c.len(),
        if has_ratio { "γ > π/2, where the ratio is undefined" } else { "all γ" }
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
    Ok(Backward { near: near.sum.clone(), local: far.sum.clone() })
}

/// Builds a member from its recipe (errors not yet measured).
pub fn assemble(r: Recipe, g_range: (f64, f64), fits: &SplitFits) -> Result<Assembled<Split>, String> {
    let mut parts = Parts::default();
    let forward = forward(r.forward, fits, &mut parts)?;
    let phase = phase(r.phase, g_range, fits, &mut parts)?;
    let ratio = ratio(r.backward, fits, &mut parts)?;
    let expsum = backward(ratio.is_some(), fits, &mut parts)?;
    Ok(Assembled {
        body: Split { forward, phase, ratio, expsum, forward_attenuation: r.forward_attenuation },
        families: parts.families,
        provenance: parts.prov,
        method: Vec::new(),
    })
}

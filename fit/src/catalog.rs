//! The models airlight ships, kept as data ([`CATALOG`]), and the pipeline that
//! produces their coefficient files: fit each family once ([`Fits::fit`]),
//! assemble the models from their recipes, measure every model on the
//! validation sets.

use crate::approx::Approximation;
use crate::coeffs::ModelFile;
use crate::family::lite::fit::{LiteTier, Objective};
use crate::family::phi::fit::PhiTier;
use crate::family::split::fit::{BackChoice, ForwardChoice, PhaseChoice, MIRRORED_G, PAPER_G};
use crate::family::{split, Fits, Recipe, Role};
use crate::lsq;
use crate::model::Model;
use airlight_truth::domains::{Domain, DomainErrors, VALIDATION_POINTS, VALIDATION_SEED};
use airlight_truth::reference::{self, Point, REFERENCE_REL_TOL};
use airlight_truth::stats::rel_error;
use airlight_truth::tomlfile::value::{f, hex_seed, i, kv, s};
use airlight_truth::tomlfile::Provenance;
use std::f64::consts::PI;
use toml::Value;

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
        self.recipe.role() == Role::Baseline
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
    ModelSpec {
        name,
        summary,
        g_range,
        recipe: Recipe::Split(split::fit::Recipe { forward, phase, backward, forward_attenuation }),
    }
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
        recipe: Recipe::RayMarch(n),
    }
}

const fn equiangular(name: &'static str, n: usize) -> ModelSpec {
    ModelSpec {
        name,
        summary:
            "baseline; Gauss-Legendre in the equiangular angle (Kulla & Fajardo 2012, deterministic), exact HG per node",
        g_range: MIRRORED_G,
        recipe: Recipe::Equiangular(n),
    }
}

const fn sun(name: &'static str, res: usize) -> ModelSpec {
    ModelSpec {
        name,
        summary: "baseline; Sun et al. 2005 F(u, v) table (seed 004), bilinear, a texture in shaders; isotropic",
        g_range: (0.0, 0.0),
        recipe: Recipe::Sun2005(res),
    }
}

const fn phi(name: &'static str, summary: &'static str, g_range: (f64, f64), t: PhiTier) -> ModelSpec {
    ModelSpec { name, summary, g_range, recipe: Recipe::Phi(t) }
}

const fn lite(
    name: &'static str,
    summary: &'static str,
    g_range: (f64, f64),
    nodes: usize,
    objective: Objective,
) -> ModelSpec {
    ModelSpec { name, summary, g_range, recipe: Recipe::Lite(LiteTier { nodes, objective }) }
}

const LITE_ISO: &str = "isotropic; the cheap tiers, one path: e^x E2 of 1/(1+u)^2 and fitted nodes for the rest";
const LITE_HG: &str = "HG, g at run time in [-0.99, 0.99]; the cheap tiers, one path: e^x E2 of a faded C/(kappa+u)^2 and fitted nodes for the rest";

// Head nodes name a member; far and tail nodes are searched up to these counts
// and the split fitted from here (fit/src/family/phi/fit.rs). No isotropic
// 2- and 3-node members: their spot entries broke their bounds in the gate (the
// penumbra rule amplified the rule's error about sixfold on a narrow-edge ray:
// phi-iso-2 2.1e-2 against 3.4e-3), and `phi-2`, `phi-3` serve g = 0 too.
const PHI_2: PhiTier = PhiTier { head: 2, far: 2, tail: 2, cut: 2.5, far_cut: 4.0 };
const PHI_3: PhiTier = PhiTier { head: 3, far: 3, tail: 3, cut: 3.0, far_cut: 5.0 };
const PHI_4: PhiTier = PhiTier { head: 4, far: 4, tail: 3, cut: 3.5, far_cut: 5.0 };
const PHI_6: PhiTier = PhiTier { head: 6, far: 4, tail: 3, cut: 4.0, far_cut: 6.0 };
const PHI_8: PhiTier = PhiTier { head: 8, far: 4, tail: 3, cut: 5.0, far_cut: 8.0 };

/// Every shipped model, in table order: airlight's models, then the baselines.
pub const CATALOG: [ModelSpec; 51] = [
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
        "isotropic; the paper's 3-segment and ratio forms refit together to dominate the published coefficients",
        (0.0, 0.0),
        ForwardChoice::Dominant,
        PhaseChoice::Isotropic,
        BackChoice::DominantRatio,
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
    lite("lite-iso-2", LITE_ISO, (0.0, 0.0), 2, Objective::Max),
    lite("lite-iso-3", LITE_ISO, (0.0, 0.0), 3, Objective::Max),
    lite("lite-iso-4", LITE_ISO, (0.0, 0.0), 4, Objective::Max),
    lite("lite-iso-5", LITE_ISO, (0.0, 0.0), 5, Objective::Max),
    lite(
        "lite-iso-med-7",
        "isotropic; the median tier, one path: e^x E2 of 1/(1+u)^2 and 7 nodes fitted for the median error",
        (0.0, 0.0),
        7,
        Objective::Median,
    ),
    lite("lite-3", LITE_HG, MIRRORED_G, 3, Objective::Max),
    lite("lite-4", LITE_HG, MIRRORED_G, 4, Objective::Max),
    lite("lite-5", LITE_HG, MIRRORED_G, 5, Objective::Max),
    lite("lite-7", LITE_HG, MIRRORED_G, 7, Objective::Max),
    lite("lite-12", LITE_HG, MIRRORED_G, 12, Objective::Max),
    lite(
        "lite-med-7",
        "HG, g at run time in [-0.99, 0.99]; the median tier, one path: e^x E2 of a faded C/(kappa+u)^2 and 7 nodes fitted for the median error",
        MIRRORED_G,
        7,
        Objective::Median,
    ),
    phi("phi-iso-4", "isotropic; whole A: 4 nodes in the scattering angle, Gauss-Laguerre tail, exact e^x E2 far part", (0.0, 0.0), PHI_4),
    phi("phi-iso-6", "isotropic; whole A: 6 nodes in the scattering angle, Gauss-Laguerre tail, exact e^x E2 far part", (0.0, 0.0), PHI_6),
    phi("phi-iso-8", "isotropic; whole A: 8 nodes in the scattering angle, Gauss-Laguerre tail, exact e^x E2 far part", (0.0, 0.0), PHI_8),
    phi("phi-2", "HG, g at run time in [-0.99, 0.99]; whole A: 2 nodes in the HG variable phi, Gauss-Laguerre tail, exact e^x E2 far part", MIRRORED_G, PHI_2),
    phi("phi-3", "HG, g at run time in [-0.99, 0.99]; whole A: 3 nodes in the HG variable phi, Gauss-Laguerre tail, exact e^x E2 far part", MIRRORED_G, PHI_3),
    phi("phi-4", "HG, g at run time in [-0.99, 0.99]; whole A: 4 nodes in the HG variable phi, Gauss-Laguerre tail, exact e^x E2 far part", MIRRORED_G, PHI_4),
    phi("phi-6", "HG, g at run time in [-0.99, 0.99]; whole A: 6 nodes in the HG variable phi, Gauss-Laguerre tail, exact e^x E2 far part", MIRRORED_G, PHI_6),
    phi("phi-8", "HG, g at run time in [-0.99, 0.99]; whole A: 8 nodes in the HG variable phi, Gauss-Laguerre tail, exact e^x E2 far part", MIRRORED_G, PHI_8),
    ModelSpec {
        name: "no-extinction",
        summary: "baseline; seed 003's exact closed form without extinction (atan2 of the cross product), isotropic, any tau: the cost floor",
        g_range: (0.0, 0.0),
        recipe: Recipe::NoExtinction(()),
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

/// Builds the model `spec` from the families' fits (errors not yet measured).
pub fn assemble(spec: &ModelSpec, fits: &Fits) -> Result<ModelFile, String> {
    let a = spec.recipe.assemble(spec.g_range, fits)?;
    let mut provenance = a.provenance;
    provenance.push(provenance_table(a.method));
    Ok(ModelFile {
        model: Approximation {
            name: spec.name.into(),
            summary: spec.summary.into(),
            g_range: spec.g_range,
            body: a.body,
        },
        families: a.families,
        errors: vec![],
        bands: vec![],
        provenance,
    })
}

/// The `[provenance]` table every file ends with, after `extra`.
fn provenance_table(method: Vec<(String, Value)>) -> Provenance {
    let mut v = method;
    v.extend(kv(vec![
            ("crate", s(concat!("airlight-fit ", env!("CARGO_PKG_VERSION")))),
            ("reference", s("adaptive Gauss-Kronrod on the u form (truth/src/reference.rs)")),
            ("reference_rel_tol", f(REFERENCE_REL_TOL)),
            ("validation_seed", hex_seed(VALIDATION_SEED)),
            ("validation_points_per_domain", i(VALIDATION_POINTS)),
            ("validation_extra", s("domain corners at the ends of g_range; 48x48 grids on the faces rho = 0.01, rho = inf, tau = min, tau = max, gamma = 0.01 and gamma = pi - 0.01; local Nelder-Mead searches (300 iterations each) inside the domain from the 8 largest over- and 8 largest underestimates (a tenth of the domain apart) and from the 16 largest face errors (3% apart) raise the max where they find more; then up to 3 held-out rounds, each 384 fresh seeded points per domain (no fit or other measurement uses them) whose 4 largest over- and 4 largest underestimates start more searches, until a round raises nothing; worst cases reported from outside (catalog::KEPT_WORST) are re-measured and searched from; then up to 4 polish searches from the worst point, each on a simplex a quarter of the last, until one finds nothing more. That largest error is searched_max_rel; the declared max_rel is 1.25 times it (catalog::DECLARED_MARGIN). Bands of g: 4000 points, 16x16 face grids, up to 3 held-out rounds, the same searches and margin")),
    ]));
    ("provenance".into(), v)
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
    /// Held-out sets ([`HELD_OUT_ROUNDS`] of [`HELD_OUT_POINTS`], seeds of their
    /// own, used by no fit and by no other measurement) with reference `A`: each
    /// round of the declared-bound search draws on the next one.
    pub held_out: Vec<Vec<(Point, f64)>>,
}

/// Rounds of held-out local search after the validation set's: the search stops at
/// the first round that does not raise the max.
pub const HELD_OUT_ROUNDS: usize = 3;

/// Points per held-out round.
pub const HELD_OUT_POINTS: usize = 384;

/// The seed of held-out round `r` of a validation seeded `seed`.
fn held_out_seed(seed: u64, r: usize) -> u64 {
    seed ^ (0x4E1D_0000_0000_0000 + r as u64)
}

/// Worst cases found outside this project's own searches, kept and re-measured
/// like CORE-MATH's: `(model, domain, [τ, γ, ρ, g])`. Each raises its model's max
/// where it is larger and starts a local search.
pub const KEPT_WORST: &[(&str, Domain, [f64; 4])] = &[
    // Issue 23: 9.877e-6 against the declared thin max 9.813e-6.
    ("phi-8", Domain::Thin, [0.11422951026628728, 3.089430949486637, f64::INFINITY, -0.8548411349565563]),
    // Issue 23: its f32 kernel 1121 against the declared dense max 1025.
    ("sun2005-512", Domain::Dense, [7.424642086029053, 3.131592512130737, 0.9999499917030334, 0.0]),
    // Issue 37: lite-12 f64 3.315e-4 against the declared thin 3.1655e-4 (γ on its face).
    ("lite-12", Domain::Thin, [0.05660171263305316, 0.010000134952970816, 1.205996610115852, -0.99]),
    // Issue 37: lite-12's f32 kernel 1.056x, its WGSL and GLSL 1.048x the gate's thin limit.
    ("lite-12", Domain::Thin, [0.011313774721434192, 0.04994668352428118, 2.019590545303462, -0.9899041316043273]),
    ("lite-12", Domain::Thin, [0.02166436602256801, 0.027915906104834867, 1.5467141578519668, -0.9894783174698888]),
    // Issue 37: lite-12's bands [-0.5, -0.3] (1.173x), [-0.9, -0.7] (1.113x) thin, and
    // 9.27e-5 at g = -0.4999 against the README's 8.1e-5 for g >= -0.5.
    ("lite-12", Domain::Thin, [0.8551922341167062, 0.04412488223776162, 0.9796112467422934, -0.495]),
    ("lite-12", Domain::Thin, [0.4128808677611597, 0.015308563884602644, 1.0266675794444007, -0.895]),
    ("lite-12", Domain::Thin, [0.9048, 0.04124, 0.98059, -0.4999]),
    // Issue 37: lite-7 dense 1.0012x its declared bound.
    ("lite-7", Domain::Dense, [10.35528, 0.0104536, 1.2335, -0.95623]),
];

/// The margin of every declared bound: a bound is the largest error the searches
/// found (validation set, face grids, local searches, held-out rounds, the kept
/// worst cases, and the polish from the worst point) times `1 + DECLARED_MARGIN`.
/// Issue 37's hostile search, run on bounds declared with no margin, found up to
/// 1.17x a band's bound; an error a search of ours never saw must exceed ours by
/// this much to break a bound.
pub const DECLARED_MARGIN: f64 = 0.25;

/// Nelder–Mead iterations of each local search.
pub const SEARCH_ITERATIONS: u64 = 300;

/// Polish rounds from the worst point found, each a local search with its simplex
/// a quarter of the last one's; they stop at the first that finds nothing more.
pub const POLISH_ROUNDS: usize = 4;

/// Points per side of each face grid.
pub const FACE_GRID: usize = 48;

/// Validation points per band and domain (the bands' sets are smaller than the
/// whole range's; the faces, local searches and a held-out round are the same).
pub const BAND_POINTS: usize = 4000;
/// Points per side of each band's face grids.
pub const BAND_FACE_GRID: usize = 16;
/// Held-out rounds per band.
pub const BAND_HELD_OUT_ROUNDS: usize = 3;
/// Seed of the bands' sets (their held-out rounds derive from it as the whole
/// range's do from [`VALIDATION_SEED`]).
pub const BAND_SEED: u64 = VALIDATION_SEED ^ 0xBA4D_0000_0000_0000;

/// The bands of `g_range` ([`crate::coeffs::G_BANDS`] cut to it; none for a single `g`).
pub fn bands_of(g_range: (f64, f64)) -> Vec<(f64, f64)> {
    if g_range.0 >= g_range.1 {
        return Vec::new();
    }
    crate::coeffs::G_BANDS
        .windows(2)
        .map(|w| (w[0].max(g_range.0), w[1].min(g_range.1)))
        .filter(|(lo, hi)| lo < hi)
        .collect()
}

/// How big a validation is.
struct Sizes {
    domains: &'static [Domain],
    points: usize,
    face_grid: usize,
    held_out_rounds: usize,
    seed: u64,
}

/// Reference values for the validation sets of every `(domain, g range)` in `ranges`.
pub fn validations(ranges: &[(f64, f64)], progress: &(dyn Fn(usize, usize) + Sync)) -> Vec<Validation> {
    let sizes = Sizes {
        domains: &Domain::ALL,
        points: VALIDATION_POINTS,
        face_grid: FACE_GRID,
        held_out_rounds: HELD_OUT_ROUNDS,
        seed: VALIDATION_SEED,
    };
    validations_sized(ranges, &sizes, progress)
}

/// Reference values for the band validations ([`bands_of`]) of `bands`: `thin`
/// and `dense` only.
pub fn band_validations(bands: &[(f64, f64)], progress: &(dyn Fn(usize, usize) + Sync)) -> Vec<Validation> {
    let sizes = Sizes {
        domains: &[Domain::Thin, Domain::Dense],
        points: BAND_POINTS,
        face_grid: BAND_FACE_GRID,
        held_out_rounds: BAND_HELD_OUT_ROUNDS,
        seed: BAND_SEED,
    };
    validations_sized(bands, &sizes, progress)
}

fn validations_sized(
    ranges: &[(f64, f64)],
    sizes: &Sizes,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Vec<Validation> {
    let mut sets = Vec::new();
    for &r in ranges {
        for &d in sizes.domains {
            let held: Vec<Vec<Point>> = if d == Domain::Extreme {
                Vec::new()
            } else {
                (0..sizes.held_out_rounds)
                    .map(|k| d.validation_set(r, HELD_OUT_POINTS, held_out_seed(sizes.seed, k)))
                    .collect()
            };
            sets.push((
                d,
                r,
                d.validation_set(r, sizes.points, sizes.seed),
                [
                    d.faces(&crate::fitset::face_gs(r), sizes.face_grid),
                    d.gamma_faces(&crate::fitset::face_gs(r), sizes.face_grid),
                ]
                .concat(),
                held,
            ));
        }
    }
    let all: Vec<Point> =
        sets.iter().flat_map(|s| s.2.iter().chain(&s.3).chain(s.4.iter().flatten()).copied()).collect();
    let values = airlight_truth::parallel::map(
        &all,
        |p| reference::airlight(*p).expect("validation points are valid"),
        progress,
    );
    let mut it = values.into_iter();
    let mut with_values = |pts: Vec<Point>| -> Vec<(Point, f64)> {
        pts.into_iter().map(|p| (p, it.next().expect("one value per point"))).collect()
    };
    sets.into_iter()
        .map(|(domain, g_range, pts, faces, held)| Validation {
            domain,
            g_range,
            points: with_values(pts),
            faces: with_values(faces),
            held_out: held.into_iter().map(&mut with_values).collect(),
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
    measure_within(model, v, &|p| p)
}

/// [`measure`] for a model that takes only part of the domain (a scene kernel: a
/// fixed `g`, no surfaces or no extinction): every point the local searches visit
/// is `project`ed onto what it takes before the model and the reference see it.
/// The validation set's points must already lie there.
pub fn measure_within(model: &dyn Model, v: &Validation, project: &(dyn Fn(Point) -> Point + Sync)) -> DomainErrors {
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
    let stats = airlight_truth::stats::ErrorStats::from_errors(errs.iter().copied());
    let mut worst = stats.worst.unwrap_or(Point { tau: 0.0, gamma: 1.0, rho: 1.0, g: 0.0 });
    let mut max = stats.max;
    if v.domain != Domain::Extreme && max.is_finite() {
        // Start the search from the largest over- and under-estimates separately: a
        // model whose worst sampled error is an underestimate near −100% can still
        // overestimate by more elsewhere.
        // Starts are spread out: a model's error often plateaus at one level over a
        // large region (the backward sum's floor), and the largest errors all sit
        // there while a narrow peak elsewhere (a domain edge) goes unvisited.
        let mut starts = extremes(v.domain, &mut signed, REFINE_STARTS);
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
        // Worst cases kept from elsewhere: measured, and searched from.
        for &(name, d, [tau, gamma, rho, g]) in KEPT_WORST {
            let p = Point { tau, gamma, rho, g };
            if name == model.name() && d == v.domain && (v.g_range.0..=v.g_range.1).contains(&g) {
                if let Ok(exact) = reference::airlight(p) {
                    let e = rel_error(model.eval_unchecked(p), exact);
                    if e > max {
                        (max, worst) = (e, p);
                    }
                }
                starts.push(p);
            }
        }
        search(model, v, project, &starts, &mut max, &mut worst);
        // Held-out rounds: each a fresh seeded set, its largest over- and
        // underestimates searched from; the first round that raises nothing ends it.
        for set in &v.held_out {
            let before = max;
            let mut signed: Vec<(Point, f64)> = Vec::with_capacity(set.len());
            for &(p, exact) in set {
                let a = model.eval_unchecked(p);
                let e = rel_error(a, exact);
                if e > max {
                    (max, worst) = (e, p);
                }
                if a.is_finite() && exact.is_finite() && exact > 0.0 {
                    signed.push((p, a / exact - 1.0));
                }
            }
            search(model, v, project, &extremes(v.domain, &mut signed, REFINE_STARTS / 2), &mut max, &mut worst);
            if max <= before {
                break;
            }
        }
        // Polish: local searches from the worst point on ever smaller simplices,
        // until one finds nothing more.
        let mut scale = 1.0;
        for _ in 0..POLISH_ROUNDS {
            scale *= 0.25;
            let (found, e) = refine(model, v.domain, v.g_range, project, worst, scale);
            if e.is_nan() || e <= max {
                break;
            }
            (max, worst) = (e, found);
        }
    }
    DomainErrors {
        domain: v.domain,
        points: v.points.len(),
        max_rel: if max.is_finite() { max * (1.0 + DECLARED_MARGIN) } else { max },
        searched_max_rel: Some(max),
        p99_rel: stats.p99,
        worst,
        non_finite,
        negative,
    }
}

/// Up to `n` of the largest over- and `n` of the largest underestimates among
/// `signed` (point, signed relative error), a tenth of the domain apart; sorts
/// `signed` by the error, largest first.
fn extremes(domain: Domain, signed: &mut [(Point, f64)], n: usize) -> Vec<Point> {
    signed.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut starts = diverse(domain, signed.iter().map(|s| s.0), n, 0.1);
    starts.extend(diverse(domain, signed.iter().rev().map(|s| s.0), n, 0.1));
    starts
}

/// A local search from each of `starts`, raising `max` (and moving `worst`)
/// wherever one finds more.
fn search(
    model: &dyn Model,
    v: &Validation,
    project: &(dyn Fn(Point) -> Point + Sync),
    starts: &[Point],
    max: &mut f64,
    worst: &mut Point,
) {
    for &start in starts {
        let (found, e) = refine(model, v.domain, v.g_range, project, start, 1.0);
        if e > *max {
            (*max, *worst) = (e, found);
        }
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

/// Local search for a larger error near `start`, inside the domain, on a simplex
/// `scale` times the default.
fn refine(
    model: &dyn Model,
    domain: Domain,
    g_range: (f64, f64),
    project: &(dyn Fn(Point) -> Point + Sync),
    start: Point,
    scale: f64,
) -> (Point, f64) {
    let inf = start.rho.is_infinite();
    let to_point = |x: &[f64]| {
        project(clamp_into(
            domain,
            g_range,
            Point { tau: x[0], gamma: x[1], rho: if inf { f64::INFINITY } else { x[2].exp() }, g: x[3] },
        ))
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
    let step = [0.05 * (thi - tlo), 0.05, if inf { 0.0 } else { 0.2 }, if g_range.0 == g_range.1 { 0.0 } else { 0.02 }]
        .map(|x| x * scale);
    let out = lsq::nelder_mead(&err, &x0, &step, 1e-12, SEARCH_ITERATIONS);
    (to_point(&out.param), -out.cost)
}

/// The coefficient files under `dir` in catalog order (files naming no catalog
/// model last, by name).
pub fn load(dir: &std::path::Path) -> Result<Vec<ModelFile>, crate::coeffs::CoeffError> {
    let mut files = crate::coeffs::load_dir(dir)?;
    files.sort_by_key(|f| CATALOG.iter().position(|c| c.name == f.model.name).unwrap_or(usize::MAX));
    Ok(files)
}

/// Measures every model of `files` on each validation of `sets` that `belongs`
/// to it, in one parallel run: `(file, set, errors)` in file order.
fn measure_on(
    files: &[ModelFile],
    sets: &[Validation],
    belongs: impl Fn(&ModelFile, &Validation) -> bool,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Vec<(usize, usize, DomainErrors)> {
    let jobs: Vec<(usize, usize)> = files
        .iter()
        .enumerate()
        .flat_map(|(i, f)| {
            sets.iter().enumerate().filter(|(_, v)| belongs(f, v)).map(move |(j, _)| (i, j)).collect::<Vec<_>>()
        })
        .collect();
    let measured = airlight_truth::parallel::map(&jobs, |&(i, j)| measure(&files[i].model, &sets[j]), progress);
    jobs.into_iter().zip(measured).map(|((i, j), e)| (i, j, e)).collect()
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
    for (i, _, e) in measure_on(&files, &sets, |f, v| v.g_range == f.model.g_range, progress) {
        files[i].errors.push(e);
    }
    // The bands of every model whose g is a run-time argument.
    let mut bands: Vec<(f64, f64)> = Vec::new();
    for f in &files {
        for b in bands_of(f.model.g_range) {
            if !bands.contains(&b) {
                bands.push(b);
            }
        }
    }
    let band_sets = band_validations(&bands, progress);
    let own = |f: &ModelFile, v: &Validation| bands_of(f.model.g_range).contains(&v.g_range);
    for (i, j, e) in measure_on(&files, &band_sets, own, progress) {
        files[i].bands.push(crate::coeffs::BandErrors { g: band_sets[j].g_range, errors: e });
    }
    for f in &mut files {
        f.bands.sort_by(|a, b| a.g.0.total_cmp(&b.g.0).then(a.errors.domain.cmp(&b.errors.domain)));
        // The whole range's bound holds in every band: where a band's set found a
        // larger error than the whole range's set (lite-5 at g < −0.9: 7.5e-3 against
        // 4.1e-3), that error and its point are the whole range's.
        for e in &mut f.errors {
            let worst_band = f
                .bands
                .iter()
                .filter(|b| b.errors.domain == e.domain)
                .max_by(|a, b| a.errors.max_rel.total_cmp(&b.errors.max_rel));
            if let Some(b) = worst_band {
                if b.errors.max_rel > e.max_rel {
                    e.max_rel = b.errors.max_rel;
                    e.searched_max_rel = b.errors.searched_max_rel;
                    e.worst = b.errors.worst;
                }
            }
        }
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
            if let Recipe::Split(split::fit::Recipe { phase: PhaseChoice::Isotropic, .. }) = m.recipe {
                assert_eq!(m.g_range, (0.0, 0.0));
            }
        }
    }
}

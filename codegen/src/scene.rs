//! Scene specifications (`codegen/scenes/*.toml`) and the choice of model for a
//! scene: the cheapest model whose declared error bound meets the scene's budget
//! over the part of the error domains the scene can reach, cheapest by the cost
//! measured where the scene's kernels run ([`Ranking`]).

use crate::front::CostMeasure;
use airlight_fit::coeffs::ModelFile;
use airlight_shapes::bench::Bench;
use airlight_shapes::vocab::{Domain, Target};
use airlight_truth::tomlfile::{deny_unknown, field_error, parse_table, FieldError};
use std::fmt;

/// The phase function a scene's medium needs.
#[derive(Debug, Clone, PartialEq)]
pub enum ScenePhase {
    /// Isotropic scattering (`g = 0`).
    Isotropic,
    /// Henyey–Greenstein with one `g`.
    Fixed(f64),
    /// Henyey–Greenstein with `g` anywhere in `[lo, hi]` (a runtime parameter).
    Range(f64, f64),
}

impl ScenePhase {
    /// The `g` range the phase function needs.
    pub fn g_range(&self) -> (f64, f64) {
        match *self {
            ScenePhase::Isotropic => (0.0, 0.0),
            ScenePhase::Fixed(g) => (g, g),
            ScenePhase::Range(lo, hi) => (lo, hi),
        }
    }
}

/// A parsed scene file.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// File stem.
    pub name: String,
    /// The file, as named in messages.
    pub file: String,
    /// Extinction coefficient range `[lo, hi]` (1/length).
    pub sigma_t: (f64, f64),
    /// Phase function.
    pub phase: ScenePhase,
    /// Whether extinction matters (false: the exact no-extinction closed form).
    pub extinction: bool,
    /// Farthest light from the viewer (length units of `sigma_t`).
    pub max_distance: f64,
    /// Whether surfaces bound the view rays.
    pub surfaces: bool,
    /// Whether the lights are spot lights (`kind = "spot"`): the kernel gets the
    /// spot entry, with RGB `sigma_t` and `sigma_s`.
    pub spot: bool,
    /// Whether occluders shadow the lights (`[lights] shadows`, default false):
    /// the kernel gets the shafts accumulator. Needs surfaces.
    pub shadows: bool,
    /// Whether light scattered from beyond the foot point matters.
    pub backscatter: bool,
    /// Accuracy budget: largest relative error of the airlight.
    pub max_rel_error: f64,
    /// Languages to emit.
    pub targets: Vec<Target>,
    /// The file's text (for locating fields in plan errors).
    pub text: String,
}

impl Scene {
    /// A plan error as a one-line error naming this file, the line and the field
    /// that would have to change.
    pub fn plan_error(&self, e: &PlanError) -> SceneError {
        let (table, key) = match e {
            PlanError::OutsideDomains { .. } => ("lights", "max_distance"),
            PlanError::NoBackscatter { .. } => ("ray", "backscatter"),
            PlanError::IgnoredExtinction { .. } => ("medium", "extinction"),
            PlanError::Budget { best: None, .. } => ("medium", "phase"),
            PlanError::Budget { .. } => ("accuracy", "max_rel_error"),
        };
        field_error(&self.file, &self.text, table, key, e.to_string())
    }
}

/// A scene file that cannot be used (file, line, field, message).
pub type SceneError = FieldError;

/// The tables of a scene file, read with one-line errors naming file, line and field.
struct Fields<'a> {
    file: &'a str,
    text: &'a str,
    doc: toml::Table,
}

impl Fields<'_> {
    fn err(&self, table: &str, key: &str, msg: String) -> SceneError {
        field_error(self.file, self.text, table, key, msg)
    }

    fn table(&self, name: &str) -> Result<&toml::Table, SceneError> {
        self.doc.get(name).and_then(toml::Value::as_table).ok_or_else(|| SceneError {
            file: self.file.into(),
            line: 1,
            field: name.into(),
            message: "missing table".into(),
        })
    }

    fn get(&self, t: &str, k: &str) -> Result<&toml::Value, SceneError> {
        self.table(t)?.get(k).ok_or_else(|| self.err(t, k, "missing".into()))
    }

    fn num(&self, t: &str, k: &str) -> Result<f64, SceneError> {
        let v = self.get(t, k)?;
        v.as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .ok_or_else(|| self.err(t, k, "must be a number".into()))
    }

    fn boolean(&self, t: &str, k: &str) -> Result<bool, SceneError> {
        self.get(t, k)?.as_bool().ok_or_else(|| self.err(t, k, "must be true or false".into()))
    }

    fn pair(&self, t: &str, k: &str) -> Result<(f64, f64), SceneError> {
        let a = self
            .get(t, k)?
            .as_array()
            .filter(|a| a.len() == 2)
            .ok_or_else(|| self.err(t, k, "must be [lo, hi]".into()))?;
        let f = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
        match (f(&a[0]), f(&a[1])) {
            (Some(lo), Some(hi)) if lo <= hi => Ok((lo, hi)),
            _ => Err(self.err(t, k, "must be [lo, hi] with lo <= hi".into())),
        }
    }

    /// `[medium] phase`, with `g` or `g_range` for `"hg"`.
    fn phase(&self) -> Result<ScenePhase, SceneError> {
        Ok(match self.get("medium", "phase")?.as_str() {
            Some("isotropic") => {
                let m = self.table("medium")?;
                for k in ["g", "g_range"] {
                    if m.contains_key(k) {
                        return Err(self.err(
                            "medium",
                            k,
                            format!("an isotropic medium takes no {k} (for Henyey-Greenstein write phase = \"hg\")"),
                        ));
                    }
                }
                ScenePhase::Isotropic
            }
            Some("hg") => {
                let m = self.table("medium")?;
                match (m.get("g"), m.get("g_range")) {
                    (Some(_), None) => {
                        let g = self.num("medium", "g")?;
                        if !(g > -1.0 && g < 1.0) {
                            return Err(self.err("medium", "g", format!("g = {g} is outside (-1, 1)")));
                        }
                        ScenePhase::Fixed(g)
                    }
                    (None, Some(_)) => {
                        let (lo, hi) = self.pair("medium", "g_range")?;
                        if !(lo > -1.0 && hi < 1.0) {
                            return Err(self.err("medium", "g_range", "must lie inside (-1, 1)".into()));
                        }
                        ScenePhase::Range(lo, hi)
                    }
                    _ => return Err(self.err("medium", "phase", "\"hg\" needs exactly one of g or g_range".into())),
                }
            }
            _ => return Err(self.err("medium", "phase", "must be \"isotropic\" or \"hg\"".into())),
        })
    }

    /// `[lights] kind` (whether spot) and `[ray] surfaces`, which a spot light needs.
    fn spot_and_surfaces(&self) -> Result<(bool, bool), SceneError> {
        let spot = match self.get("lights", "kind")?.as_str() {
            Some("point") => false,
            Some("spot") => true,
            _ => return Err(self.err("lights", "kind", "must be \"point\" or \"spot\"".into())),
        };
        let surfaces = self.boolean("ray", "surfaces")?;
        if spot && !surfaces {
            return Err(self.err(
                "ray",
                "surfaces",
                "a spot light's cone ends the lit stretch like a surface: kind = \"spot\" needs surfaces = true".into(),
            ));
        }
        Ok((spot, surfaces))
    }

    /// `[output] targets`: at least one.
    fn targets(&self) -> Result<Vec<Target>, SceneError> {
        let targets = self
            .get("output", "targets")?
            .as_array()
            .ok_or_else(|| self.err("output", "targets", "must be a list".into()))?
            .iter()
            .map(|v| {
                v.as_str()
                    .ok_or_else(|| "entries are strings".to_string())
                    .and_then(|t| t.parse::<Target>().map_err(|e| e.to_string()))
                    .map_err(|e| self.err("output", "targets", e))
            })
            .collect::<Result<Vec<_>, _>>()?;
        if targets.is_empty() {
            return Err(self.err("output", "targets", "name at least one target".into()));
        }
        Ok(targets)
    }
}

/// Parses a scene file.
pub fn parse(file: &str, text: &str) -> Result<Scene, SceneError> {
    let doc = parse_table(file, text)?;
    // Every key the planner reads; anything else is a misspelling, not a comment.
    const KEYS: [(&str, &[&str]); 5] = [
        ("medium", &["sigma_t", "phase", "g", "g_range", "extinction"]),
        ("lights", &["kind", "max_distance", "shadows"]),
        ("ray", &["surfaces", "backscatter"]),
        ("accuracy", &["max_rel_error"]),
        ("output", &["targets"]),
    ];
    deny_unknown(file, text, &doc, "", &KEYS.map(|k| k.0))?;
    for (t, keys) in KEYS {
        if let Some(t2) = doc.get(t).and_then(toml::Value::as_table) {
            deny_unknown(file, text, t2, t, keys)?;
        }
    }
    let f = Fields { file, text, doc };
    let sigma_t = f.pair("medium", "sigma_t")?;
    if sigma_t.0 < 0.0 || !sigma_t.1.is_finite() {
        return Err(f.err("medium", "sigma_t", "must be finite and non-negative".into()));
    }
    let phase = f.phase()?;
    let extinction = f.boolean("medium", "extinction")?;
    let (spot, surfaces) = f.spot_and_surfaces()?;
    let shadows = match f.table("lights")?.get("shadows") {
        None => false,
        Some(_) => f.boolean("lights", "shadows")?,
    };
    if shadows && !surfaces {
        return Err(f.err(
            "lights",
            "shadows",
            "shafts are summed run by run up to each run's end like a surface: shadows = true needs [ray] surfaces = true"
                .into(),
        ));
    }
    let max_distance = f.num("lights", "max_distance")?;
    if !(max_distance > 0.0 && max_distance.is_finite()) {
        return Err(f.err("lights", "max_distance", "must be a positive distance".into()));
    }
    let max_rel_error = f.num("accuracy", "max_rel_error")?;
    if max_rel_error.is_nan() || max_rel_error <= 0.0 {
        return Err(f.err("accuracy", "max_rel_error", "must be positive".into()));
    }
    let targets = f.targets()?;
    let name =
        std::path::Path::new(file).file_stem().map_or_else(|| file.to_string(), |s| s.to_string_lossy().into_owned());
    Ok(Scene {
        name,
        file: file.to_string(),
        text: text.to_string(),
        sigma_t,
        phase,
        extinction,
        max_distance,
        surfaces,
        spot,
        shadows,
        backscatter: f.boolean("ray", "backscatter")?,
        max_rel_error,
        targets,
    })
}

/// Every scene file in `dir` (`*.toml`), sorted by name (none if `dir` does not
/// exist); `shown` is how the directory is named in messages.
pub fn load_dir(dir: &std::path::Path, shown: &str) -> Result<Vec<Scene>, SceneError> {
    if !dir.exists() {
        return Ok(Vec::new());
    }
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .map_err(|e| SceneError { file: shown.into(), line: 1, field: "(directory)".into(), message: e.to_string() })?
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    paths
        .iter()
        .map(|p| {
            let file = format!("{shown}/{}", p.file_name().unwrap_or_default().to_string_lossy());
            let text = std::fs::read_to_string(p).map_err(|e| SceneError {
                file: file.clone(),
                line: 1,
                field: "(file)".into(),
                message: e.to_string(),
            })?;
            parse(&file, &text)
        })
        .collect()
}

/// What the scene gets and why.
#[derive(Debug, Clone, PartialEq)]
pub enum Choice {
    /// Isotropic without extinction: the exact closed form of seed 003 (two `atan`s).
    NoExtinction,
    /// A fitted model.
    Model {
        /// Its name.
        name: String,
        /// Its declared bound over the domains the scene reaches.
        bound: f64,
        /// Its cost as the plan ranked it.
        cost: ModelCost,
    },
}

/// What the planner ranks models by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ranking {
    /// Measured ns/eval of each model's general kernel on the scene's target
    /// (`generated/bench.json`): for a scene with WGSL or GLSL kernels the GPU
    /// path's over frame-coherent points where measured, else over random points;
    /// for a Rust-only scene the CPU's. Models the bench did not measure rank
    /// after every measured one, by their counted calls.
    Measured(CostMeasure),
    /// No bench: transcendental calls on the worst path, counted per family.
    Counted,
}

impl Ranking {
    /// The ranking for a scene emitting `targets`, given the bench (if any).
    pub fn for_targets(targets: &[Target], bench: Option<&Bench>) -> Ranking {
        let Some(b) = bench else { return Ranking::Counted };
        let shader = targets.iter().any(|t| matches!(t, Target::Wgsl | Target::Glsl));
        let order: &[CostMeasure] = if shader {
            &[CostMeasure::GpuFrame, CostMeasure::GpuRandom, CostMeasure::Cpu]
        } else {
            &[CostMeasure::Cpu]
        };
        order.iter().copied().find(|m| m.measured(b)).map_or(Ranking::Counted, Ranking::Measured)
    }

    /// In words, for the plans.
    pub fn describe(self) -> String {
        match self {
            Ranking::Measured(m) => format!(
                "measured ns per evaluation, {} (`generated/bench.json`, each model's general kernel); models it did not measure rank after, by counted calls",
                m.title()
            ),
            Ranking::Counted => {
                "transcendental calls (exp, log, atan, sqrt, sin_cos) on the worst path of the model's general f32 kernel, counted by its family (no bench)".into()
            }
        }
    }
}

/// A model's cost as a plan ranks it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelCost {
    /// Measured ns/eval on the plan's measure, if the bench has it.
    pub ns: Option<f64>,
    /// Transcendental calls on the worst path (counted).
    pub calls: usize,
}

impl ModelCost {
    fn of(m: &ModelFile, ranking: Ranking, bench: Option<&Bench>) -> ModelCost {
        let ns = match (ranking, bench) {
            (Ranking::Measured(measure), Some(b)) => b.model(&m.model.name).and_then(|bm| measure.ns(bm)),
            _ => None,
        };
        ModelCost { ns, calls: m.model.cost() }
    }

    /// The ranking order: measured before unmeasured, then by ns, then by calls.
    pub fn rank(&self, o: &ModelCost) -> std::cmp::Ordering {
        match (self.ns, o.ns) {
            (Some(a), Some(b)) => a.total_cmp(&b).then(self.calls.cmp(&o.calls)),
            (Some(_), None) => std::cmp::Ordering::Less,
            (None, Some(_)) => std::cmp::Ordering::Greater,
            (None, None) => self.calls.cmp(&o.calls),
        }
    }

    /// As the plans print it.
    pub fn describe(&self) -> String {
        match self.ns {
            Some(ns) if ns >= 100.0 => format!("{ns:.0} ns ({} calls)", self.calls),
            Some(ns) => format!("{ns:.1} ns ({} calls)", self.calls),
            None => format!("not measured ({} calls)", self.calls),
        }
    }
}

/// One model the plan weighed.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// Model name.
    pub name: String,
    /// Its cost.
    pub cost: ModelCost,
    /// Its declared bound over the plan's domains.
    pub bound: f64,
}

/// The plan for a scene: the choice and the domains it was made over.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The model.
    pub choice: Choice,
    /// Largest optical distance to a light the scene can produce.
    pub tau_max: f64,
    /// Error domains the bound was taken over.
    pub domains: Vec<Domain>,
    /// With `extinction = false`: the largest relative error of ignoring it at
    /// `σt·D` up to the scene's largest (measured, [`NoExtinction`'s grid]); 0 otherwise.
    ///
    /// [`NoExtinction`'s grid]: airlight_fit::analysis::extinction_error
    pub ignored_extinction: f64,
    /// What the models were ranked by.
    pub ranking: Ranking,
    /// Every model covering the scene's phase, in the ranking's order (none for
    /// the closed form).
    pub candidates: Vec<Candidate>,
}

/// Why a scene has no model.
#[derive(Debug, Clone, PartialEq)]
pub enum PlanError {
    /// The scene reaches optical distances no model was measured at.
    OutsideDomains {
        /// σt_max · max_distance.
        tau_max: f64,
    },
    /// `backscatter = false` drops the backward part, which is all of `A` when
    /// looking away from a light: only a budget of at least 100% allows it.
    NoBackscatter {
        /// The scene's budget.
        budget: f64,
    },
    /// `extinction = false`, but at the scene's optical distances ignoring
    /// extinction is off by more than the budget.
    IgnoredExtinction {
        /// σt_max · max_distance.
        tau_max: f64,
        /// The measured error of ignoring extinction there.
        error: f64,
        /// The scene's budget.
        budget: f64,
    },
    /// No model meets the budget; the best bound there is, and whose.
    Budget {
        /// The scene's budget.
        budget: f64,
        /// The smallest declared bound among models that cover the scene, if any.
        best: Option<(String, f64)>,
        /// The scene's `g` range (`[0, 0]`: isotropic), which a model must cover.
        g: (f64, f64),
        /// The widest `g` range any model covers.
        widest: (f64, f64),
    },
}

impl fmt::Display for PlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlanError::OutsideDomains { tau_max } => write!(
                f,
                "the scene reaches τ = σt·D = {} but models are measured only up to τ = 20 (the dense domain)",
                airlight_truth::tomlfile::short(*tau_max)
            ),
            PlanError::Budget { budget, best: Some((name, bound)), .. } => write!(
                f,
                "no model meets max_rel_error = {budget}; the best achievable for this scene is {bound:.2e} (`{name}`)"
            ),
            PlanError::NoBackscatter { budget } => write!(
                f,
                "backscatter = false leaves out the backward part, which is 100% of A looking away from a light; \
                 max_rel_error = {budget} cannot hold (it needs >= 1)"
            ),
            PlanError::IgnoredExtinction { tau_max, error, budget } => write!(
                f,
                "extinction = false, but at σt·D up to {} ignoring extinction is off by up to {} (measured), \
                 beyond max_rel_error = {budget}: set extinction = true, or a budget of at least {}",
                airlight_truth::tomlfile::short(*tau_max),
                airlight_truth::tomlfile::short(*error),
                airlight_truth::tomlfile::short(*error)
            ),
            PlanError::Budget { budget, best: None, g: (lo, hi), widest: (wlo, whi) } => {
                let g = if lo == hi { format!("g = {lo}") } else { format!("g in [{lo}, {hi}]") };
                write!(f, "no model covers {g}: the models together cover g in [{wlo}, {whi}] (budget {budget})")
            }
        }
    }
}

impl std::error::Error for PlanError {}

/// Measured costs within this fraction of each other are equal to the planner:
/// two clean runs of `airlight bench` here differed by up to 8% on one model's
/// GPU figure, so a smaller difference decides nothing.
pub const COST_TIE: f64 = 0.1;

/// Upper end of the `dense` domain's τ.
const TAU_DENSE_MAX: f64 = 20.0;
/// Upper end of the `thin` domain's τ.
const TAU_THIN_MAX: f64 = 2.0;

/// Chooses the cheapest model whose declared bound meets the scene's budget over
/// every error domain the scene reaches (ties go to the smaller bound), cheapest
/// by [`Ranking::for_targets`] with `bench` (`None`: counted calls).
pub fn plan(scene: &Scene, models: &[ModelFile], bench: Option<&Bench>) -> Result<Plan, PlanError> {
    let ranking = Ranking::for_targets(&scene.targets, bench);
    let tau_max = scene.sigma_t.1 * scene.max_distance;
    if !scene.backscatter && scene.max_rel_error < 1.0 {
        return Err(PlanError::NoBackscatter { budget: scene.max_rel_error });
    }
    // Ignoring extinction is a choice with an error of its own: measured, and
    // refused beyond the budget (the kernels then take τ = 0).
    let ignored_extinction = if scene.extinction {
        0.0
    } else {
        let (g_lo, g_hi) = scene.phase.g_range();
        let gs: Vec<f64> = if g_lo == g_hi { vec![g_lo] } else { vec![g_lo, 0.0f64.clamp(g_lo, g_hi), g_hi] };
        let error = airlight_fit::analysis::extinction_error(tau_max, scene.surfaces, &gs);
        if error > scene.max_rel_error {
            return Err(PlanError::IgnoredExtinction { tau_max, error, budget: scene.max_rel_error });
        }
        error
    };
    if !scene.extinction && scene.phase == ScenePhase::Isotropic {
        return Ok(Plan {
            choice: Choice::NoExtinction,
            tau_max: 0.0,
            domains: vec![Domain::Thin],
            ignored_extinction,
            ranking,
            candidates: Vec::new(),
        });
    }
    let tau_max = if scene.extinction { tau_max } else { 0.0 };
    if tau_max > TAU_DENSE_MAX {
        return Err(PlanError::OutsideDomains { tau_max });
    }
    // Lights can be at any distance up to max_distance, so τ starts at 0: `thin`
    // always applies.
    let mut domains = vec![Domain::Thin];
    if tau_max > TAU_THIN_MAX {
        domains.push(Domain::Dense);
    }
    let (g_lo, g_hi) = scene.phase.g_range();
    // A baked g takes each model's bound over its band of g (where it has bands).
    let baked = if let ScenePhase::Fixed(g) = scene.phase { Some(g) } else { None };
    let mut candidates: Vec<Candidate> = models
        .iter()
        .filter(|m| m.model.g_range.0 <= g_lo && g_hi <= m.model.g_range.1)
        .filter_map(|m| {
            let bounds: Option<Vec<f64>> = domains.iter().map(|&d| m.bound_at(d, baked)).collect();
            bounds.map(|b| Candidate {
                name: m.model.name.clone(),
                cost: ModelCost::of(m, ranking, bench),
                bound: b.into_iter().fold(0.0, f64::max),
            })
        })
        .collect();
    candidates.sort_by(|a, b| a.cost.rank(&b.cost).then(a.bound.total_cmp(&b.bound)).then(a.name.cmp(&b.name)));
    // The first in the ranking's order that meets the budget; measured costs
    // within COST_TIE of its own count as equal (the bench's run-to-run spread),
    // and among those the smallest bound wins.
    let mut meets = candidates.iter().filter(|c| c.bound <= scene.max_rel_error).peekable();
    let best = meets.peek().copied().map(|first| {
        let tied = |c: &&Candidate| match (first.cost.ns, c.cost.ns) {
            (Some(a), Some(b)) => b <= a * (1.0 + COST_TIE),
            _ => c.name == first.name,
        };
        // `first` is tied with itself, so the minimum exists.
        meets.filter(tied).min_by(|a, b| a.bound.total_cmp(&b.bound)).unwrap_or(first).clone()
    });
    match best {
        Some(c) => Ok(Plan {
            choice: Choice::Model { name: c.name, bound: c.bound, cost: c.cost },
            tau_max,
            domains,
            ignored_extinction,
            ranking,
            candidates,
        }),
        None => Err(PlanError::Budget {
            budget: scene.max_rel_error,
            best: candidates.iter().min_by(|a, b| a.bound.total_cmp(&b.bound)).map(|c| (c.name.clone(), c.bound)),
            g: scene.phase.g_range(),
            widest: models
                .iter()
                .fold((0.0, 0.0), |(lo, hi), m| (m.model.g_range.0.min(lo), m.model.g_range.1.max(hi))),
        }),
    }
}

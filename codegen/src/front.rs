//! The speed/accuracy front from one `airlight bench` run (`generated/bench.json`):
//! per `g` and per cost measure ([`CostMeasure`]: CPU ns/eval of the f32 Rust
//! kernel, or the GPU path's time per evaluation over random or frame-coherent
//! points), each model's cost against its error (max and median over
//! `thin ∪ dense`), which methods are dominated, airlight's own front, and the
//! headline ratios the report quotes. The pictures (`plots::pareto`) and
//! the report's tables both read this, so they cannot disagree.

use airlight_shapes::bench::{Bench, BenchModel};

/// What a method's cost is measured by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CostMeasure {
    /// CPU ns per evaluation of the f32 Rust kernel (throughput loop, median).
    Cpu,
    /// The GPU path over random points (every lane on its own branch):
    /// ns per evaluation as the inverse of the measured throughput.
    GpuRandom,
    /// The GPU path over frame-coherent points (every pixel of rendered frames,
    /// in pixel order), the same way.
    GpuFrame,
}

impl CostMeasure {
    /// Every measure, in the report's order.
    pub const ALL: [CostMeasure; 3] = [CostMeasure::Cpu, CostMeasure::GpuRandom, CostMeasure::GpuFrame];

    /// The measure's cost of `m` in ns per evaluation, if measured.
    pub fn ns(self, m: &BenchModel) -> Option<f64> {
        let rate = |r: f64| (r > 0.0).then(|| 1e9 / r);
        match self {
            CostMeasure::Cpu => (m.cpu_ns_per_eval > 0.0).then_some(m.cpu_ns_per_eval),
            CostMeasure::GpuRandom => rate(m.gpu_evals_per_s),
            CostMeasure::GpuFrame => rate(m.gpu_frame_evals_per_s),
        }
    }

    /// As file names end: `""` (the CPU figures keep the plain names), `-gpu-random`, `-gpu-frame`.
    pub fn suffix(self) -> &'static str {
        match self {
            CostMeasure::Cpu => "",
            CostMeasure::GpuRandom => "-gpu-random",
            CostMeasure::GpuFrame => "-gpu-frame",
        }
    }

    /// A short heading.
    pub fn title(self) -> &'static str {
        match self {
            CostMeasure::Cpu => "CPU (f32 Rust kernel)",
            CostMeasure::GpuRandom => "GPU path, random points",
            CostMeasure::GpuFrame => "GPU path, frame-coherent points",
        }
    }

    /// The cost axis as the plots label it.
    pub fn axis(self) -> &'static str {
        match self {
            CostMeasure::Cpu => "CPU ns per evaluation (f32 Rust kernel, median)",
            CostMeasure::GpuRandom => "GPU ns per evaluation (1 / throughput, random points)",
            CostMeasure::GpuFrame => "GPU ns per evaluation (1 / throughput, frame-coherent)",
        }
    }

    /// Whether any model of `b` has this measure.
    pub fn measured(self, b: &Bench) -> bool {
        b.models.iter().any(|m| self.ns(m).is_some())
    }
}

/// Max-error levels of the headline table.
pub const MAX_LEVELS: [f64; 4] = [1e-1, 1e-2, 1e-3, 1e-4];
/// Median-error levels of the headline table.
pub const MEDIAN_LEVELS: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// One method at one `g`.
#[derive(Debug, Clone, PartialEq)]
pub struct Method {
    /// Model name.
    pub name: String,
    /// A baseline (what a user would pick instead) rather than an airlight model.
    pub baseline: bool,
    /// ns/eval on the measure the methods were taken with ([`CostMeasure`]).
    pub ns: f64,
    /// Max relative error over thin ∪ dense.
    pub max: f64,
    /// The larger of the two domains' median relative errors.
    pub median: f64,
    /// Some other method is at least as fast and at least as accurate (on the
    /// panel's measure), and strictly better in one.
    pub dominated_max: bool,
    /// The same on the median panel.
    pub dominated_median: bool,
}

/// Every method measured at `g` on the CPU, in the bench's order.
pub fn methods(b: &Bench, g: f64) -> Vec<Method> {
    methods_by(b, g, CostMeasure::Cpu)
}

/// Every method measured at `g` whose cost `measure` has, in the bench's order.
pub fn methods_by(b: &Bench, g: f64, measure: CostMeasure) -> Vec<Method> {
    let mut out: Vec<Method> = b
        .models
        .iter()
        .filter_map(|m: &BenchModel| {
            let e = m.at(g)?;
            Some(Method {
                name: m.name.clone(),
                baseline: m.kind == airlight_shapes::vocab::Role::Baseline,
                ns: measure.ns(m)?,
                max: e.max_rel.max(),
                median: e.p50_rel.max(),
                dominated_max: false,
                dominated_median: false,
            })
        })
        .collect();
    let dominated = |i: usize, f: &dyn Fn(&Method) -> f64, ms: &[Method]| {
        ms.iter().enumerate().any(|(j, o)| j != i && dominates(o, &ms[i], f))
    };
    let flags: Vec<(bool, bool)> =
        (0..out.len()).map(|i| (dominated(i, &|m| m.max, &out), dominated(i, &|m| m.median, &out))).collect();
    for (m, (a, b)) in out.iter_mut().zip(flags) {
        m.dominated_max = a;
        m.dominated_median = b;
    }
    out
}

/// Whether `o` is at least as fast and as accurate as `m` on the measure `f`, and
/// strictly better in one (a method never dominates itself).
fn dominates(o: &Method, m: &Method, f: &dyn Fn(&Method) -> f64) -> bool {
    beats((o.ns, f(o)), (m.ns, f(m)))
}

/// Whether `(cost, error)` pair `o` is at most `m` in both and below it in one:
/// the one dominance test of the front and of the report's recommendations.
pub fn beats(o: (f64, f64), m: (f64, f64)) -> bool {
    o.0 <= m.0 && o.1 <= m.1 && (o.0 < m.0 || o.1 < m.1)
}

/// Airlight's own front on a measure: its models no other airlight model beats
/// in both cost and error, by increasing cost.
pub fn airlight_front<'a>(ms: &'a [Method], f: &dyn Fn(&Method) -> f64) -> Vec<&'a Method> {
    let own: Vec<&Method> = ms.iter().filter(|m| !m.baseline).collect();
    let mut front: Vec<&Method> = own.iter().filter(|m| !own.iter().any(|o| dominates(o, m, f))).copied().collect();
    front.sort_by(|a, b| a.ns.total_cmp(&b.ns));
    front
}

/// The fastest method of a kind (`baseline` or not) whose measure is at most `level`.
pub fn fastest<'a>(ms: &'a [Method], baseline: bool, level: f64, f: &dyn Fn(&Method) -> f64) -> Option<&'a Method> {
    ms.iter().filter(|m| m.baseline == baseline && f(m) <= level).min_by(|a, b| a.ns.total_cmp(&b.ns))
}

/// One row of the headline table: at a level, the fastest airlight kernel and
/// the fastest baseline that reach it.
#[derive(Debug, Clone, PartialEq)]
pub struct Headline {
    /// `max` or `median`.
    pub measure: &'static str,
    /// The level.
    pub level: f64,
    /// The fastest airlight kernel reaching it.
    pub airlight: Option<Method>,
    /// The fastest baseline reaching it.
    pub baseline: Option<Method>,
}

impl Headline {
    /// Baseline ns over airlight ns (> 1: airlight is faster), if both reach the level.
    pub fn speedup(&self) -> Option<f64> {
        Some(self.baseline.as_ref()?.ns / self.airlight.as_ref()?.ns)
    }
    /// Who wins the level.
    pub fn verdict(&self) -> Verdict {
        match (&self.airlight, &self.baseline) {
            (None, None) => Verdict::Nobody,
            (Some(_), None) => Verdict::AirlightOnly,
            (None, Some(_)) => Verdict::BaselineOnly,
            (Some(a), Some(b)) if a.ns < b.ns => Verdict::Airlight,
            (Some(_), Some(_)) => Verdict::Baseline,
        }
    }
}

/// Who wins a level of the headline table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Neither airlight nor a baseline reaches it.
    Nobody,
    /// Only airlight reaches it.
    AirlightOnly,
    /// Only a baseline reaches it.
    BaselineOnly,
    /// Both reach it; airlight's fastest is faster.
    Airlight,
    /// Both reach it; a baseline is at least as fast.
    Baseline,
}

impl Verdict {
    /// As the report's table writes it.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Nobody => "none reaches it",
            Verdict::AirlightOnly => "airlight (no baseline reaches it)",
            Verdict::BaselineOnly => "baseline (no airlight kernel reaches it)",
            Verdict::Airlight => "airlight",
            Verdict::Baseline => "baseline",
        }
    }

    /// Whether airlight loses the level (a baseline is faster, or alone reaches it).
    pub fn airlight_loses(self) -> bool {
        matches!(self, Verdict::Baseline | Verdict::BaselineOnly)
    }
}

/// The headline rows at `g`: every max level, then every median level.
pub fn headlines(ms: &[Method]) -> Vec<Headline> {
    let max = |m: &Method| m.max;
    let med = |m: &Method| m.median;
    let mut out = Vec::new();
    for level in MAX_LEVELS {
        out.push(Headline {
            measure: "max",
            level,
            airlight: fastest(ms, false, level, &max).cloned(),
            baseline: fastest(ms, true, level, &max).cloned(),
        });
    }
    for level in MEDIAN_LEVELS {
        out.push(Headline {
            measure: "median",
            level,
            airlight: fastest(ms, false, level, &med).cloned(),
            baseline: fastest(ms, true, level, &med).cloned(),
        });
    }
    out
}

/// The `g` values measured by the bench, in [`BENCH_GS`](airlight_fit::bench::BENCH_GS)'s order.
pub fn gs(b: &Bench) -> Vec<f64> {
    let measured = |g: f64| b.models.iter().any(|m| m.at(g).is_some());
    let mut gs: Vec<f64> = airlight_fit::bench::BENCH_GS.iter().copied().filter(|&g| measured(g)).collect();
    // Any other g a bench file holds, after the standard ones.
    for m in &b.models {
        for e in &m.errors {
            if !gs.contains(&e.g) {
                gs.push(e.g);
            }
        }
    }
    gs
}

/// A `g` as written in file names and headings: `0`, `-0.95`, `0.5`.
pub fn g_label(g: f64) -> String {
    format!("{g}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(name: &str, baseline: bool, ns: f64, max: f64) -> Method {
        Method {
            name: name.into(),
            baseline,
            ns,
            max,
            median: max / 10.0,
            dominated_max: false,
            dominated_median: false,
        }
    }

    /// Each cost measure's methods carry that measure's ns (the GPU's as the
    /// inverse of its throughput) and leave out models it did not measure.
    #[test]
    fn every_cost_measure_reads_its_own_figure() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated/bench.json");
        let b = Bench::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
        for measure in CostMeasure::ALL {
            let ms = methods_by(&b, 0.0, measure);
            for m in &ms {
                let bm = b.model(&m.name).unwrap();
                let want = match measure {
                    CostMeasure::Cpu => bm.cpu_ns_per_eval,
                    CostMeasure::GpuRandom => 1e9 / bm.gpu_evals_per_s,
                    CostMeasure::GpuFrame => 1e9 / bm.gpu_frame_evals_per_s,
                };
                assert_eq!(m.ns, want, "{measure:?} {}", m.name);
                assert!(m.ns.is_finite() && m.ns > 0.0);
            }
            let measured = b.models.iter().filter(|m| m.at(0.0).is_some() && measure.ns(m).is_some()).count();
            assert_eq!(ms.len(), measured, "{measure:?}");
        }
    }

    #[test]
    fn fronts_and_headlines_follow_the_figures() {
        let ms = vec![
            m("a1", false, 10.0, 1e-2),
            m("a2", false, 20.0, 1e-3),
            m("a3", false, 30.0, 2e-2),
            m("b1", true, 5.0, 5e-2),
            m("b2", true, 15.0, 1e-3),
        ];
        let front: Vec<&str> = airlight_front(&ms, &|m| m.max).iter().map(|m| m.name.as_str()).collect();
        assert_eq!(front, ["a1", "a2"]);
        let h = headlines(&ms);
        assert_eq!(h[0].airlight.as_ref().unwrap().name, "a1");
        assert_eq!(h[0].baseline.as_ref().unwrap().name, "b1");
        assert_eq!(h[0].verdict(), Verdict::Baseline);
        assert_eq!(h[2].baseline.as_ref().unwrap().name, "b2");
        assert!((h[2].speedup().unwrap() - 0.75).abs() < 1e-12);
        assert_eq!(h[3].verdict(), Verdict::Nobody);
    }
}

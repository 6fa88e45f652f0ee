//! The speed/accuracy front from one `airlight bench` run (`generated/bench.json`):
//! per `g`, each model's cost (ns/eval of its f32 Rust kernel) against its error
//! (max and median over `thin ∪ dense`), which methods are dominated, airlight's
//! own front, and the headline ratios the report quotes. The pictures
//! ([`crate::plots::pareto`]) and the report's tables both read this, so they
//! cannot disagree.

use airlight_fit::bench::{Bench, BenchModel};

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
    /// ns/eval, CPU, median of the repeats.
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

/// Every method measured at `g`, in the bench's order.
pub fn methods(b: &Bench, g: f64) -> Vec<Method> {
    let mut out: Vec<Method> = b
        .models
        .iter()
        .filter_map(|m: &BenchModel| {
            let e = m.at(g)?;
            Some(Method {
                name: m.name.clone(),
                baseline: m.kind == airlight_fit::vocab::Role::Baseline,
                ns: m.cpu_ns_per_eval,
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

//! `eˣE₂(x)` on one path: `(N₁(x) − x ln(1 + 1/x) N₂(x)) / D(x)`, `N₁`, `N₂`, `D`
//! polynomials with unit constant terms and non-negative coefficients (degrees 3, 2, 4).
//! `x ln(1 + 1/x)` carries the `x ln x` at 0 (the `T ln T` of an open ray) and tends
//! to 1 at infinity, where `N₁/D ~ 1/x`; `D ≥ 1` for `x ≥ 0` (no pole),
//! so a GPU pays one `log` and two divisions, with no branch. The φ family's
//! the φ family's `ExpE2` (a series below 1, a rational beyond) is more
//! accurate and branches; this one is fitted to the lite family's budget.

use crate::family::uform::{exp_e2_exact, horner1};
use crate::lsq::{self, Outcome, OUTER_SOLVER};
use airlight_truth::tomlfile::value::{f, i, kv, s};
use airlight_truth::tomlfile::{FieldError, Reader, Provenance};
use toml::Table;

/// Degrees of `N₁`, `N₂`, `D`.
pub const DEGREES: [usize; 3] = [3, 2, 4];
/// The fitting points: log-spaced `x` in `[1e-10, 1e4]`.
pub const FIT_POINTS: usize = 1500;
/// The check grid (finer, wider: `[1e-12, 1e5]`).
pub const CHECK_POINTS: usize = 20000;
/// Nelder–Mead iterations per run, and restarts.
pub const ITERS: u64 = 20000;
/// Restarts.
pub const RESTARTS: usize = 6;

/// The fitted form.
#[derive(Debug, Clone, PartialEq)]
pub struct LogE2 {
    /// `N₁`'s coefficients of `x¹ … x³`.
    pub n1: Vec<f64>,
    /// `N₂`'s coefficients of `x¹, x²`.
    pub n2: Vec<f64>,
    /// `D`'s coefficients of `x¹ … x⁴`.
    pub d: Vec<f64>,
}

/// How it was fitted.
#[derive(Debug, Clone, PartialEq)]
pub struct LogE2Fit {
    /// The result.
    pub e2: LogE2,
    /// What the search did.
    pub outcome: Outcome,
    /// Largest relative error on the check grid, and where.
    pub max_rel: (f64, f64),
}

fn log_grid(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..n).map(|k| 10f64.powf(lo + (hi - lo) * k as f64 / (n - 1) as f64)).collect()
}

impl LogE2 {
    /// Evaluates it (`x ≥ 0`; `x` is taken at least 1e-30, where `x ln(1 + 1/x)` is 0 to f32).
    pub fn eval(&self, x: f64) -> f64 {
        let x = x.max(1e-30);
        let l = x * ((1.0 + x) / x).ln();
        (horner1(&self.n1, x) - l * horner1(&self.n2, x)) / horner1(&self.d, x)
    }

    fn from_logs(p: &[f64]) -> LogE2 {
        let e: Vec<f64> = p.iter().map(|v| v.exp()).collect();
        let (a, b) = (DEGREES[0], DEGREES[0] + DEGREES[1]);
        LogE2 { n1: e[..a].to_vec(), n2: e[a..b].to_vec(), d: e[b..].to_vec() }
    }

    /// Fits the coefficients: least squares of the relative error over
    /// [`FIT_POINTS`] log-spaced points, in the logarithms of the coefficients (so
    /// that none is negative and `D ≥ 1` on `x ≥ 0`), by Nelder–Mead
    /// from all coefficients 1, restarted; the max is then taken on a finer, wider grid.
    pub fn fit() -> LogE2Fit {
        let xs = log_grid(FIT_POINTS, -10.0, 4.0);
        let want: Vec<f64> = xs.iter().map(|&x| exp_e2_exact(x)).collect();
        let cost = |p: &[f64]| {
            let e = LogE2::from_logs(p);
            let ss: f64 = xs.iter().zip(&want).map(|(&x, &w)| (e.eval(x) / w - 1.0).powi(2)).sum();
            (ss / xs.len() as f64).sqrt()
        };
        let n: usize = DEGREES.iter().sum();
        let outcome = lsq::nelder_mead_restarted(&cost, &vec![0.0; n], &vec![0.5; n], 1e-14, ITERS, RESTARTS);
        let e2 = LogE2::from_logs(&outcome.param);
        let max_rel = log_grid(CHECK_POINTS, -12.0, 5.0)
            .into_iter()
            .map(|x| ((e2.eval(x) / exp_e2_exact(x) - 1.0).abs(), x))
            .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a });
        LogE2Fit { e2, outcome, max_rel }
    }

    /// Writes the `[e2]` table of a coefficient file (its provenance `e2.fit` by `prov`).
    pub fn render_toml(&self, o: &mut String, prov: &dyn Fn(&mut String, &str)) {
        o.push_str("\n[e2]\nform = \"e^x E2(x) = (N1(x) - x ln(1 + 1/x) N2(x)) / D(x), N1 = 1 + sum n1_k x^k, N2 = 1 + sum n2_k x^k, D = 1 + sum d_k x^k\"\n");
        airlight_truth::tomlfile::hex_list(o, "n1", &self.n1);
        airlight_truth::tomlfile::hex_list(o, "n2", &self.n2);
        airlight_truth::tomlfile::hex_list(o, "d", &self.d);
        prov(o, "e2.fit");
    }

    /// Reads the `[e2]` table: the degrees above, every coefficient finite and non-negative.
    pub fn parse_toml(r: &Reader, doc: &Table) -> Result<LogE2, FieldError> {
        let t = r.table(doc, "e2")?;
        r.deny(t, "e2", &["form", "n1", "n2", "d", "fit"])?;
        let mut out = Vec::new();
        for (key, deg) in [("n1", DEGREES[0]), ("n2", DEGREES[1]), ("d", DEGREES[2])] {
            let c = r.hexes(t, "e2", key, Some(deg))?;
            if c.iter().any(|&v| !(v.is_finite() && v >= 0.0)) {
                return Err(r.err("e2", key, "every coefficient must be finite and non-negative (D >= 1 on x >= 0)"));
            }
            out.push(c);
        }
        let d = out.pop().expect("three");
        let n2 = out.pop().expect("three");
        let n1 = out.pop().expect("three");
        Ok(LogE2 { n1, n2, d })
    }
}

/// The fit's provenance table.
pub fn provenance(fit: &LogE2Fit) -> Provenance {
    (
        "e2.fit".into(),
        kv(vec![
            ("form", s("(N1 - x ln(1 + 1/x) N2) / D, degrees 3, 2, 4, unit constant terms, every coefficient non-negative (fitted through their logarithms)")),
            ("target", s("e^x E2(x) = 1 - x e^x E1(x) through the reference complex E1 (truth/src/e1.rs)")),
            ("objective", s(&format!("least squares of the relative error over {FIT_POINTS} log-spaced points, x in [1e-10, 1e4]"))),
            ("solver", s(&format!("{OUTER_SOLVER}, from all coefficients 1, restarted up to {RESTARTS} times, {ITERS} iterations a run"))),
            ("iterations", i(fit.outcome.iterations)),
            ("termination", s(&fit.outcome.termination)),
            ("check", s(&format!("{CHECK_POINTS} log-spaced points, x in [1e-12, 1e5]"))),
            ("max_rel", f(fit.max_rel.0)),
            ("max_rel_at_x", f(fit.max_rel.1)),
        ]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_reaches_the_lite_budget_with_no_pole() {
        let f = LogE2::fit();
        assert!(f.max_rel.0 < 5e-5, "{:?}", f);
        assert!(f.e2.n1.iter().chain(&f.e2.n2).chain(&f.e2.d).all(|&c| c >= 0.0), "{f:?}");
        // The x ln x at 0 and 1/x at infinity.
        assert!((f.e2.eval(0.0) - 1.0).abs() < 1e-12);
        assert!((f.e2.eval(1e8) * 1e8 - 1.0).abs() < 1e-3);
    }
}

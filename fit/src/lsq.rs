//! The two solvers every fit uses: linear least squares by nalgebra's SVD (never
//! the normal equations) and Nelder–Mead from argmin for the nonlinear outer
//! parameters, with its iteration count and termination reason kept as provenance.

use argmin::core::{CostFunction, Error, Executor, State};
use argmin::solver::neldermead::NelderMead;
use nalgebra::{DMatrix, DVector};

/// Minimiser of `‖A x − b‖₂` (minimum-norm where `A` is rank-deficient: singular
/// values below `1e-13 · σ_max` are dropped). `None` if the SVD fails.
pub fn solve(a: DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    let svd = a.svd(true, true);
    let eps = 1e-13 * svd.singular_values.max();
    svd.solve(b, eps).ok()
}

/// What the outer solver did: kept in coefficient files as provenance.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Best parameters found.
    pub param: Vec<f64>,
    /// Cost at `param`.
    pub cost: f64,
    /// Iterations run.
    pub iterations: u64,
    /// Why it stopped, in argmin's words.
    pub termination: String,
}

/// Solver name for provenance.
pub const OUTER_SOLVER: &str = "argmin 0.11 Nelder-Mead";

struct Problem<'a> {
    cost: &'a (dyn Fn(&[f64]) -> f64 + Sync),
}

impl CostFunction for Problem<'_> {
    type Param = DVector<f64>;
    type Output = f64;
    fn cost(&self, x: &DVector<f64>) -> Result<f64, Error> {
        let c = (self.cost)(x.as_slice());
        // Nelder–Mead only compares costs: a non-finite cost is simply worst.
        Ok(if c.is_finite() { c } else { f64::MAX })
    }
}

/// Minimises `cost` by Nelder–Mead from `start`, with an initial simplex of steps
/// `step[i]` along each axis, stopping when the spread of the simplex's costs falls
/// below `sd_tol` or after `max_iters` iterations. Deterministic.
pub fn nelder_mead(
    cost: &(dyn Fn(&[f64]) -> f64 + Sync),
    start: &[f64],
    step: &[f64],
    sd_tol: f64,
    max_iters: u64,
) -> Outcome {
    let n = start.len();
    if n == 0 {
        return Outcome { param: vec![], cost: cost(&[]), iterations: 0, termination: "nothing to optimise".into() };
    }
    let x0 = DVector::from_column_slice(start);
    let mut simplex = vec![x0.clone()];
    for i in 0..n {
        let mut v = x0.clone();
        v[i] += step[i];
        simplex.push(v);
    }
    let solver = NelderMead::new(simplex).with_sd_tolerance(sd_tol).expect("tolerance is non-negative");
    let result = Executor::new(Problem { cost }, solver).configure(|s| s.max_iters(max_iters)).run();
    match result {
        Ok(res) => {
            let state = res.state();
            let param = state.get_best_param().map(|p| p.as_slice().to_vec()).unwrap_or_else(|| start.to_vec());
            Outcome {
                cost: cost(&param),
                param,
                iterations: state.get_iter(),
                termination: state.get_termination_status().to_string(),
            }
        }
        Err(e) => {
            Outcome { param: start.to_vec(), cost: cost(start), iterations: 0, termination: format!("failed: {e}") }
        }
    }
}

/// [`nelder_mead`] restarted from its own best point with a fresh simplex (steps
/// halved each time) while a restart improves the cost by more than 1%, at most
/// `restarts` times: Nelder–Mead stalls in long valleys otherwise. Iterations add up;
/// the termination reason is the last run's, with the number of runs.
pub fn nelder_mead_restarted(
    cost: &(dyn Fn(&[f64]) -> f64 + Sync),
    start: &[f64],
    step: &[f64],
    sd_tol: f64,
    max_iters: u64,
    restarts: usize,
) -> Outcome {
    let mut best = nelder_mead(cost, start, step, sd_tol, max_iters);
    let mut runs = 1;
    let mut scale = 0.5;
    for _ in 0..restarts {
        let steps: Vec<f64> = step.iter().map(|s| s * scale).collect();
        let again = nelder_mead(cost, &best.param, &steps, sd_tol, max_iters);
        runs += 1;
        scale *= 0.5;
        let improved = again.cost < 0.99 * best.cost;
        let iterations = best.iterations + again.iterations;
        best = if again.cost < best.cost { Outcome { iterations, ..again } } else { Outcome { iterations, ..best } };
        if !improved {
            break;
        }
    }
    best.termination = format!("{} ({runs} runs)", best.termination);
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn least_squares_recovers_a_line() {
        let xs: Vec<f64> = (0..20).map(|i| i as f64 / 19.0).collect();
        let a = DMatrix::from_fn(20, 2, |i, j| if j == 0 { 1.0 } else { xs[i] });
        let b = DVector::from_iterator(20, xs.iter().map(|x| 0.5 - 2.0 * x));
        let sol = solve(a, &b).unwrap();
        assert!((sol[0] - 0.5).abs() < 1e-13 && (sol[1] + 2.0).abs() < 1e-13);
    }

    #[test]
    fn nelder_mead_finds_the_rosenbrock_minimum() {
        let f = |x: &[f64]| (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2);
        let out = nelder_mead(&f, &[-1.2, 1.0], &[0.5, 0.5], 1e-14, 5000);
        assert!((out.param[0] - 1.0).abs() < 1e-4 && (out.param[1] - 1.0).abs() < 1e-4, "{out:?}");
        assert!(out.iterations > 10);
    }
}

//! A deterministic cost of a kernel: the operations in the naga IR of its WGSL
//! function, two ways — on its worst path, and on every branch at once. Every
//! arithmetic, comparison, conversion, select and built-in call counts one; calls
//! count their callee's cost; `if` and `switch` count their costliest branch (worst
//! path) or all of their branches (every branch: what a GPU wave pays when its
//! lanes take different branches, or when the compiler flattens the branches into
//! selects); a loop counts its body times its trip count where that is a constant
//! bound (`for (var i = 0u; i < N; i++)`), once otherwise. Transcendental built-ins
//! (exp, log, sqrt, pow, trigonometry) are also counted apart: the polynomial
//! `sin_cos` and `atan` the kernels carry count as the arithmetic they are. The
//! bench records the worst path (`bench.json`'s `ops`); the report sets the GPU
//! path's measured cost beside both.

use naga::{Block, Expression, Function, Handle, MathFunction, Module, Statement};
use std::collections::HashMap;

/// Operation counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IrCost {
    /// Every operation.
    pub ops: usize,
    /// Of those, transcendental built-ins.
    pub transcendentals: usize,
}

impl IrCost {
    fn add(self, o: IrCost) -> IrCost {
        IrCost { ops: self.ops + o.ops, transcendentals: self.transcendentals + o.transcendentals }
    }
    fn times(self, n: usize) -> IrCost {
        IrCost { ops: self.ops * n, transcendentals: self.transcendentals * n }
    }
    fn worse(self, o: IrCost) -> IrCost {
        if o.ops > self.ops {
            o
        } else {
            self
        }
    }
}

fn transcendental(f: MathFunction) -> bool {
    use MathFunction as M;
    matches!(
        f,
        M::Exp
            | M::Exp2
            | M::Log
            | M::Log2
            | M::Pow
            | M::Sqrt
            | M::InverseSqrt
            | M::Sin
            | M::Cos
            | M::Tan
            | M::Asin
            | M::Acos
            | M::Atan
            | M::Atan2
            | M::Sinh
            | M::Cosh
            | M::Tanh
    )
}

fn expr_cost(e: &Expression) -> IrCost {
    match e {
        Expression::Math { fun, .. } => IrCost { ops: 1, transcendentals: usize::from(transcendental(*fun)) },
        Expression::Binary { .. }
        | Expression::Unary { .. }
        | Expression::Select { .. }
        | Expression::As { .. }
        | Expression::Relational { .. }
        | Expression::ImageLoad { .. }
        | Expression::ImageSample { .. } => IrCost { ops: 1, transcendentals: 0 },
        _ => IrCost::default(),
    }
}

struct Walker<'m> {
    module: &'m Module,
    /// Every branch counted (else the costliest).
    every: bool,
    memo: HashMap<Handle<Function>, IrCost>,
}

impl Walker<'_> {
    fn function(&mut self, h: Handle<Function>) -> IrCost {
        if let Some(c) = self.memo.get(&h) {
            return *c;
        }
        let f = &self.module.functions[h];
        let c = self.block(f, &f.body);
        self.memo.insert(h, c);
        c
    }

    /// The constant `N` of a loop that starts `if !(i < N) { break; }`.
    fn trip_count(&self, f: &Function, body: &Block) -> Option<usize> {
        let Some(Statement::If { condition, accept, reject }) = body.iter().find(|s| !matches!(s, Statement::Emit(_)))
        else {
            return None;
        };
        if !(accept.is_empty() && matches!(reject.first(), Some(Statement::Break))) {
            return None;
        }
        let Expression::Binary { op: naga::BinaryOperator::Less, right, .. } = f.expressions[*condition] else {
            return None;
        };
        let literal = |e: &Expression| match e {
            Expression::Literal(naga::Literal::U32(n)) => Some(*n as usize),
            Expression::Literal(naga::Literal::I32(n)) => usize::try_from(*n).ok(),
            _ => None,
        };
        match &f.expressions[right] {
            Expression::Constant(c) => literal(&self.module.global_expressions[self.module.constants[*c].init]),
            e => literal(e),
        }
    }

    fn block(&mut self, f: &Function, b: &Block) -> IrCost {
        let mut c = IrCost::default();
        for s in b.iter() {
            c = c.add(match s {
                Statement::Emit(range) => {
                    range.clone().map(|h| expr_cost(&f.expressions[h])).fold(IrCost::default(), IrCost::add)
                }
                Statement::Block(inner) => self.block(f, inner),
                Statement::If { accept, reject, .. } => {
                    let (a, r) = (self.block(f, accept), self.block(f, reject));
                    if self.every {
                        a.add(r)
                    } else {
                        a.worse(r)
                    }
                }
                Statement::Switch { cases, .. } => {
                    let every = self.every;
                    let each = cases.iter().map(|k| self.block(f, &k.body));
                    if every {
                        each.fold(IrCost::default(), IrCost::add)
                    } else {
                        each.fold(IrCost::default(), IrCost::worse)
                    }
                }
                Statement::Loop { body, continuing, .. } => {
                    let n = self.trip_count(f, body).unwrap_or(1);
                    self.block(f, body).add(self.block(f, continuing)).times(n)
                }
                Statement::Call { function, .. } => self.function(*function),
                _ => IrCost::default(),
            });
        }
        c
    }
}

/// The cost of `function` in the WGSL `source` on its worst path.
pub fn ir_cost(source: &str, function: &str) -> Result<IrCost, String> {
    Ok(ir_costs(source, function)?.0)
}

/// Both costs of `function` in the WGSL `source`, from one parse: (worst path,
/// every branch).
pub fn ir_costs(source: &str, function: &str) -> Result<(IrCost, IrCost), String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let (h, _) = module
        .functions
        .iter()
        .find(|(_, f)| f.name.as_deref() == Some(function))
        .ok_or_else(|| format!("no function '{function}'"))?;
    let walk = |every| Walker { module: &module, every, memo: HashMap::new() }.function(h);
    Ok((walk(false), walk(true)))
}

/// How well an operation count predicts a measured cost: `ns ≈ intercept + slope ·
/// ops`, fitted by least squares on relative residuals (every kernel weighs alike,
/// short or long), and the residuals' root mean square and largest magnitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CostFit {
    /// ns per operation.
    pub slope: f64,
    /// ns of a kernel with no operations (the dispatch's own cost).
    pub intercept: f64,
    /// Root mean square of `predicted / measured − 1`.
    pub rms: f64,
    /// Largest `|predicted / measured − 1|`.
    pub max: f64,
}

/// [`CostFit`] over `(ops, ns)` pairs; `None` with fewer than three or where the
/// least squares fail.
pub fn fit_cost(points: &[(f64, f64)]) -> Option<CostFit> {
    use nalgebra::{DMatrix, DVector};
    let pts: Vec<(f64, f64)> = points.iter().copied().filter(|(x, y)| x.is_finite() && *y > 0.0).collect();
    if pts.len() < 3 {
        return None;
    }
    let a = DMatrix::from_fn(pts.len(), 2, |i, j| if j == 0 { pts[i].0 / pts[i].1 } else { 1.0 / pts[i].1 });
    // Linear least squares by SVD, singular values below 1e-13 of the largest dropped.
    let svd = a.svd(true, true);
    let eps = 1e-13 * svd.singular_values.max();
    let c = svd.solve(&DVector::from_element(pts.len(), 1.0), eps).ok()?;
    let dev: Vec<f64> = pts.iter().map(|(x, y)| (c[0] * x + c[1]) / y - 1.0).collect();
    Some(CostFit {
        slope: c[0],
        intercept: c[1],
        rms: (dev.iter().map(|d| d * d).sum::<f64>() / dev.len() as f64).sqrt(),
        max: dev.iter().fold(0.0, |m, d| m.max(d.abs())),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_loops_by_their_trip_count_and_branches_by_the_worse() {
        let src = "const N: u32 = 10u;\n\
            fn f(x: f32) -> f32 { var s = 0.0; for (var i = 0u; i < N; i++) { s += exp(x * f32(i)); } \
            if x > 0.0 { return s + 1.0; } else { return sqrt(s) * 2.0 + 1.0; } }";
        let c = ir_cost(src, "f").unwrap();
        // per trip: <, f32(i), *, exp, += and i++ (6); the else branch: sqrt, *, + (3); the test x > 0 (1).
        assert_eq!(c.transcendentals, 11);
        assert_eq!(c.ops, 6 * 10 + 3 + 1);
        // Every branch: the then branch's + (1) as well.
        let (w, e) = ir_costs(src, "f").unwrap();
        assert_eq!(w, c);
        assert_eq!((e.ops, e.transcendentals), (6 * 10 + 3 + 1 + 1, 11));
    }

    #[test]
    fn a_cost_fit_recovers_a_line_and_measures_its_misses() {
        let exact: Vec<(f64, f64)> = [100.0, 300.0, 800.0, 2000.0].iter().map(|&x| (x, 4.0 + 0.02 * x)).collect();
        let f = fit_cost(&exact).unwrap();
        assert!((f.slope - 0.02).abs() < 1e-12 && (f.intercept - 4.0).abs() < 1e-9 && f.max < 1e-12, "{f:?}");
        // One point 10% off the line: the fit misses some point.
        let mut off = exact.clone();
        off[1].1 *= 1.1;
        assert!(fit_cost(&off).unwrap().max > 0.01);
        assert!(fit_cost(&exact[..2]).is_none());
    }
}

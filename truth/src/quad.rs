//! Quadrature rules used by the reference: adaptive Gauss–Kronrod (G10/K21) and
//! tanh–sinh. Both integrate a closure over a finite interval in f64.
//!
//! The Gauss–Kronrod integrator is *globally* adaptive: it keeps every subinterval
//! with its own error estimate `|K21 − G10|` and always bisects the worst one, until
//! the summed estimate falls below `rel_tol · |I|` (QUADPACK's QAG strategy without
//! the extrapolation). Callers seed it with breakpoints where they know the
//! integrand has structure, so the first estimates are already honest.

// The published 33-digit values are kept as printed; f64 rounds them.
#[allow(clippy::excessive_precision)]
/// Abscissae of the 21-point Kronrod rule on [−1, 1] (positive half; the odd
/// indices 1, 3, 5, 7, 9 are the 10-point Gauss abscissae). QUADPACK's values.
const XGK: [f64; 11] = [
    0.995_657_163_025_808_080_735_527_280_689_003,
    0.973_906_528_517_171_720_077_964_012_084_452,
    0.930_157_491_355_708_226_001_207_180_059_508,
    0.865_063_366_688_984_510_732_096_688_423_493,
    0.780_817_726_586_416_897_063_717_578_345_042,
    0.679_409_568_299_024_406_234_327_365_114_874,
    0.562_757_134_668_604_683_339_000_099_272_694,
    0.433_395_394_129_247_190_799_265_943_165_784,
    0.294_392_862_701_460_198_131_126_603_103_866,
    0.148_874_338_981_631_210_884_826_001_129_720,
    0.0,
];
#[allow(clippy::excessive_precision)]
/// Weights of the 21-point Kronrod rule, matching [`XGK`].
const WGK: [f64; 11] = [
    0.011_694_638_867_371_874_278_064_396_062_192,
    0.032_558_162_307_964_727_478_818_972_459_390,
    0.054_755_896_574_351_996_031_381_300_244_580,
    0.075_039_674_810_919_952_767_043_140_916_190,
    0.093_125_454_583_697_605_535_065_465_083_366,
    0.109_387_158_802_297_641_899_210_590_325_805,
    0.123_491_976_262_065_851_077_958_109_831_074,
    0.134_709_217_311_473_325_928_054_001_771_707,
    0.142_775_938_577_060_080_797_094_273_138_717,
    0.147_739_104_901_338_491_374_841_515_972_068,
    0.149_445_554_002_916_905_664_936_468_389_821,
];
#[allow(clippy::excessive_precision)]
/// Weights of the 10-point Gauss rule at `XGK[1], XGK[3], …, XGK[9]`.
const WG: [f64; 5] = [
    0.066_671_344_308_688_137_593_568_809_893_332,
    0.149_451_349_150_580_593_145_776_339_657_697,
    0.219_086_362_515_982_043_995_534_934_228_163,
    0.269_266_719_309_996_355_091_226_921_569_469,
    0.295_524_224_714_752_870_173_892_994_651_338,
];

/// One application of the G10/K21 pair on `[a, b]`: (Kronrod value, |K − G|).
fn gk21<F: FnMut(f64) -> f64>(f: &mut F, a: f64, b: f64) -> (f64, f64) {
    let half = 0.5 * (b - a);
    let centre = a + half;
    let fc = f(centre);
    let mut k = WGK[10] * fc;
    let mut g = 0.0;
    for j in 0..10 {
        let dx = half * XGK[j];
        let pair = f(centre - dx) + f(centre + dx);
        k += WGK[j] * pair;
        if j % 2 == 1 {
            g += WG[j / 2] * pair;
        }
    }
    (k * half, ((k - g) * half).abs())
}

/// Result of an adaptive integration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quadrature {
    /// The integral.
    pub value: f64,
    /// The summed `|K21 − G10|` estimate over the final subintervals. This is the
    /// error of the 10-point Gauss rule; the Kronrod value returned is far better
    /// for smooth integrands, so this is a pessimistic bound.
    pub error: f64,
    /// Number of subintervals in the final partition.
    pub intervals: usize,
    /// Number of integrand evaluations.
    pub evaluations: usize,
    /// Whether `error ≤ rel_tol · |value|` was reached within the interval budget.
    pub converged: bool,
}

/// Globally adaptive G10/K21 integration of `f` over the partition given by the
/// sorted `breakpoints` (at least two; equal neighbours are skipped).
///
/// Stops when the summed error estimate is at most `rel_tol · |I|` or
/// `max_intervals` subintervals exist.
pub fn gauss_kronrod<F: FnMut(f64) -> f64>(
    mut f: F,
    breakpoints: &[f64],
    rel_tol: f64,
    max_intervals: usize,
) -> Quadrature {
    // (a, b, value, error)
    let mut parts: Vec<(f64, f64, f64, f64)> = Vec::with_capacity(32);
    let mut evaluations = 0;
    for w in breakpoints.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b > a {
            let (v, e) = gk21(&mut f, a, b);
            evaluations += 21;
            parts.push((a, b, v, e));
        }
    }
    loop {
        let value: f64 = parts.iter().map(|p| p.2).sum();
        let error: f64 = parts.iter().map(|p| p.3).sum();
        let converged = error <= rel_tol * value.abs();
        if converged || parts.len() >= max_intervals || parts.is_empty() {
            return Quadrature {
                value,
                error,
                intervals: parts.len(),
                evaluations,
                converged: converged || parts.is_empty(),
            };
        }
        let (worst, _) =
            parts.iter().enumerate().fold((0, -1.0), |best, (i, p)| if p.3 > best.1 { (i, p.3) } else { best });
        let (a, b, _, _) = parts[worst];
        let m = 0.5 * (a + b);
        if !(m > a && m < b) {
            // The interval cannot be split any further in f64: accept it.
            return Quadrature { value, error, intervals: parts.len(), evaluations, converged: false };
        }
        let (vl, el) = gk21(&mut f, a, m);
        let (vr, er) = gk21(&mut f, m, b);
        evaluations += 42;
        parts[worst] = (a, m, vl, el);
        parts.push((m, b, vr, er));
    }
}

/// Tanh–sinh (double-exponential) quadrature over an interval of length
/// `width`, refined level by level (halving the step) until two successive levels
/// agree to `rel_tol`.
///
/// `f` receives each node as `(da, db)`, its distances from the two endpoints
/// (`da + db = width`); the smaller of the two is exact, so the caller can place
/// the node relative to the nearer endpoint without cancellation. Independent of
/// the Gauss–Kronrod path: different rule, different nodes, different error
/// control.
pub fn tanh_sinh<F: FnMut(f64, f64) -> f64>(mut f: F, width: f64, rel_tol: f64) -> Quadrature {
    use std::f64::consts::FRAC_PI_2;
    let half = 0.5 * width;
    if half <= 0.0 {
        return Quadrature { value: 0.0, error: 0.0, intervals: 1, evaluations: 0, converged: true };
    }
    // Beyond |t| = 4 the weights are below 1e-35 of the centre's.
    const T_MAX: f64 = 4.0;
    let mut evaluations = 0;
    let mut node = |t: f64| -> f64 {
        let s = FRAC_PI_2 * t.sinh();
        let c = s.cosh();
        let w = FRAC_PI_2 * t.cosh() / (c * c);
        // 1 − tanh|s| = 2 / (1 + e^{2|s|}) without cancellation.
        let near = half * (2.0 / (1.0 + (2.0 * s.abs()).exp()));
        if near <= 0.0 {
            return 0.0;
        }
        let far = width - near;
        let v = if s >= 0.0 { f(far, near) } else { f(near, far) };
        v * w
    };
    let mut step = 1.0;
    let mut sum = node(0.0);
    evaluations += 1;
    let mut k = 1;
    while (k as f64) * step <= T_MAX {
        let t = k as f64 * step;
        sum += node(t) + node(-t);
        evaluations += 2;
        k += 1;
    }
    let mut estimate = sum * step * half;
    let mut error = f64::INFINITY;
    for _level in 0..12 {
        step *= 0.5;
        let mut k = 1;
        while (k as f64) * step <= T_MAX {
            let t = k as f64 * step;
            sum += node(t) + node(-t);
            evaluations += 2;
            k += 2;
        }
        let next = sum * step * half;
        error = (next - estimate).abs();
        estimate = next;
        if error <= rel_tol * estimate.abs() {
            return Quadrature { value: estimate, error, intervals: 1, evaluations, converged: true };
        }
    }
    Quadrature { value: estimate, error, intervals: 1, evaluations, converged: false }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_kronrod_integrates_known_functions() {
        let q = gauss_kronrod(|x: f64| x.exp(), &[0.0, 1.0], 1e-14, 100);
        assert!((q.value - (1f64.exp() - 1.0)).abs() < 1e-15);
        // A narrow peak: 1/(1e-6 + x²) on [−1, 1], integral 2·atan(1000)/1e-3.
        let q = gauss_kronrod(|x: f64| 1.0 / (1e-6 + x * x), &[-1.0, 1.0], 1e-13, 500);
        let exact = 2.0 * 1000f64.atan() / 1e-3;
        assert!(q.converged);
        assert!(((q.value - exact) / exact).abs() < 1e-12, "{q:?} vs {exact}");
    }

    #[test]
    fn tanh_sinh_handles_endpoint_singularities() {
        // ∫₀¹ ln x dx = −1, ∫₀¹ x^{-1/2} dx = 2 and ∫₀¹ (1 − x)^{-1/2} dx = 2,
        // the last through the exact distance to the upper endpoint.
        let q = tanh_sinh(|x, _| x.ln(), 1.0, 1e-14);
        assert!((q.value + 1.0).abs() < 1e-13, "{q:?}");
        let q = tanh_sinh(|x, _| 1.0 / x.sqrt(), 1.0, 1e-14);
        assert!((q.value - 2.0).abs() < 1e-10, "{q:?}");
        let q = tanh_sinh(|_, d| 1.0 / d.sqrt(), 1.0, 1e-14);
        assert!(q.converged);
        assert!((q.value - 2.0).abs() < 1e-10, "{q:?}");
        // A smooth integrand converges to full precision: ∫₀^π sin = 2.
        let q = tanh_sinh(|x, _| x.sin(), std::f64::consts::PI, 1e-15);
        assert!((q.value - 2.0).abs() < 4e-15, "{q:?}");
    }
}

/// Nodes and weights of the `n`-point Gauss–Legendre rule on [−1, 1] (Newton on
/// the Legendre recurrence; exact for polynomials of degree `2n − 1`).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut xs = vec![0.0; n];
    let mut ws = vec![0.0; n];
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 1 { x } else { p1 };
            let pm = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (x * pn - pm) / (x * x - 1.0);
            let dx = pn / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        xs[i] = x;
        ws[i] = 2.0 / ((1.0 - x * x) * dp * dp);
    }
    (xs, ws)
}

#[cfg(test)]
mod legendre_tests {
    #[test]
    fn integrates_polynomials_exactly() {
        for n in [1, 2, 5, 8, 12] {
            let (x, w) = super::gauss_legendre(n);
            for deg in 0..2 * n {
                let got: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(deg as i32)).sum();
                let exact = if deg % 2 == 1 { 0.0 } else { 2.0 / (deg + 1) as f64 };
                assert!((got - exact).abs() < 1e-14, "n {n} deg {deg}: {got}");
            }
        }
    }
}

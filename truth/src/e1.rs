//! The exponential integral of complex argument, scaled: `e^z · E1(z)` for
//! `Re z ≥ 0`, and the exact isotropic airlight built on it (docs/MATH.md §3).
//!
//! Power series for `|z| ≤ 2`, the even continued fraction (modified Lentz)
//! beyond, as in Pegoraro & Slusallek, "On the Evaluation of the Complex-Valued
//! Exponential Integral" (JGT 2011). Used to cross-check the quadrature.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A complex number in f64 (only what the exponential integral needs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Complex {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

impl Complex {
    /// `re + i·im`.
    pub const fn new(re: f64, im: f64) -> Self {
        Complex { re, im }
    }
    /// Modulus, without overflow.
    pub fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    /// `e^z`.
    pub fn exp(self) -> Self {
        let m = self.re.exp();
        Complex::new(m * self.im.cos(), m * self.im.sin())
    }
    /// Principal logarithm.
    pub fn ln(self) -> Self {
        Complex::new(self.abs().ln(), self.im.atan2(self.re))
    }
    /// `1 / z`, scaled to avoid overflow.
    pub fn recip(self) -> Self {
        Complex::new(1.0, 0.0) / self
    }
}

impl Add for Complex {
    type Output = Complex;
    fn add(self, o: Complex) -> Complex {
        Complex::new(self.re + o.re, self.im + o.im)
    }
}
impl Sub for Complex {
    type Output = Complex;
    fn sub(self, o: Complex) -> Complex {
        Complex::new(self.re - o.re, self.im - o.im)
    }
}
impl Mul for Complex {
    type Output = Complex;
    fn mul(self, o: Complex) -> Complex {
        Complex::new(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }
}
impl Mul<f64> for Complex {
    type Output = Complex;
    fn mul(self, k: f64) -> Complex {
        Complex::new(self.re * k, self.im * k)
    }
}
impl Neg for Complex {
    type Output = Complex;
    fn neg(self) -> Complex {
        Complex::new(-self.re, -self.im)
    }
}
impl Div for Complex {
    type Output = Complex;
    /// Smith's algorithm.
    fn div(self, o: Complex) -> Complex {
        if o.re.abs() >= o.im.abs() {
            let r = o.im / o.re;
            let d = o.re + o.im * r;
            Complex::new((self.re + self.im * r) / d, (self.im - self.re * r) / d)
        } else {
            let r = o.re / o.im;
            let d = o.re * r + o.im;
            Complex::new((self.re * r + self.im) / d, (self.im * r - self.re) / d)
        }
    }
}

const EULER_GAMMA: f64 = 0.577_215_664_901_532_860_606_512_090_082_402_431;

/// `e^z · E1(z)` for `Re z ≥ 0`, `z ≠ 0`. Relative accuracy about 1e-15.
pub fn exp_e1(z: Complex) -> Complex {
    debug_assert!(z.re >= 0.0, "exp_e1 needs Re z ≥ 0, got {z:?}");
    if z.abs() <= 2.0 {
        series(z)
    } else {
        continued_fraction(z)
    }
}

/// `e^z E1(z)` by the power series; accurate for `|z| ≲ 2` (the terms grow like
/// `e^{|z|}` while the result falls like `e^{−Re z}`).
fn series(z: Complex) -> Complex {
    {
        // E1(z) = −γ − ln z − Σ_{k≥1} (−z)^k / (k · k!)
        let mut term = Complex::new(1.0, 0.0); // (−z)^k / k!
        let mut sum = Complex::new(0.0, 0.0);
        for k in 1..200 {
            term = term * (-z) * (1.0 / k as f64);
            let add = term * (1.0 / k as f64);
            sum = sum + add;
            if add.abs() <= 1e-17 * sum.abs() {
                break;
            }
        }
        let e1 = Complex::new(-EULER_GAMMA, 0.0) - z.ln() - sum;
        z.exp() * e1
    }
}

/// `e^z E1(z)` by the even continued fraction; converges for `Re z ≥ 0`, fast
/// for `|z| ≳ 2`.
fn continued_fraction(z: Complex) -> Complex {
    {
        // e^z E1(z) = 1/(z+1 − 1²/(z+3 − 2²/(z+5 − …))), modified Lentz.
        let tiny = Complex::new(1e-300, 0.0);
        let mut b = z + Complex::new(1.0, 0.0);
        let mut c = Complex::new(1e300, 0.0);
        let mut d = b.recip();
        let mut h = d;
        for i in 1..100_000 {
            let an = -((i * i) as f64);
            b = b + Complex::new(2.0, 0.0);
            d = d * an + b;
            if d.abs() < 1e-300 {
                d = tiny;
            }
            d = d.recip();
            c = b + Complex::new(an, 0.0) / c;
            if c.abs() < 1e-300 {
                c = tiny;
            }
            let del = c * d;
            h = h * del;
            if (del - Complex::new(1.0, 0.0)).abs() < 1e-16 {
                break;
            }
        }
        h
    }
}

/// `∫_{ua}^{ub} e^{−T (u − ua)} / (1 + u²) du` exactly, through `E1`:
/// `Im[ f(T(ua − i)) − e^{−T (ub − ua)} f(T(ub − i)) ]` with `f(z) = e^z E1(z)`.
/// `delta = ub − ua` is passed separately so that short intervals keep their
/// digits; `ub` may be `∞`. Returns the value and its condition number (the sum
/// of the magnitudes of the two terms over the result), which bounds how many
/// digits the subtraction can lose.
pub fn isotropic_kernel_integral(t: f64, ua: f64, ub: f64, delta: f64) -> (f64, f64) {
    if t == 0.0 {
        // atan(ub) − atan(ua) without cancellation.
        let v = if ub.is_infinite() { (1.0 / ua).atan() } else { (delta / (1.0 + ua * ub)).atan() };
        return (v, 1.0);
    }
    let fa = exp_e1(Complex::new(t * ua, -t));
    let fb =
        if ub.is_infinite() { Complex::new(0.0, 0.0) } else { exp_e1(Complex::new(t * ub, -t)) * (-t * delta).exp() };
    let v = fa.im - fb.im;
    let cond = (fa.im.abs() + fb.im.abs()) / v.abs();
    (v, cond)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Complex, b: Complex, tol: f64) -> bool {
        (a - b).abs() <= tol * b.abs()
    }

    #[test]
    #[allow(clippy::excessive_precision)] // tabulated digits kept as published
    fn known_values() {
        // E1(1) = 0.21938393439552027368, E1(2), E1(5) (Abramowitz & Stegun 5.1).
        for (x, e1) in [
            (1.0, 0.219_383_934_395_520_273_68),
            (2.0, 0.048_900_510_708_061_119_567),
            (5.0, 0.001_148_295_591_275_325_7),
            (0.01, 4.037_929_576_538_113_6),
        ] {
            let f = exp_e1(Complex::new(x, 0.0));
            let want = Complex::new(e1 * f64::exp(x), 0.0);
            assert!(close(f, want, 1e-14), "x = {x}: {f:?} vs {want:?}");
        }
        // E1(i x) = −Ci(x) + i (Si(x) − π/2); Ci(1), Si(1) and Ci(3), Si(3).
        for (x, ci, si) in [
            (1.0, 0.337_403_922_900_968_134_66, 0.946_083_070_367_183_014_94),
            (3.0, 0.119_629_786_008_000_327_63, 1.848_652_527_999_468_256_4),
        ] {
            let z = Complex::new(0.0, x);
            let e1 = Complex::new(-ci, si - std::f64::consts::FRAC_PI_2);
            let want = z.exp() * e1;
            let f = exp_e1(z);
            assert!(close(f, want, 1e-14), "x = {x}: {f:?} vs {want:?}");
        }
    }

    #[test]
    fn series_and_continued_fraction_agree_at_the_seam() {
        for k in 0..64 {
            let phi = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * k as f64 / 63.0;
            let z = Complex::new(2.0 * phi.cos(), 2.0 * phi.sin());
            let (a, b) = (series(z), continued_fraction(z));
            assert!(close(a, b, 2e-14), "φ = {phi}: {a:?} vs {b:?}");
        }
    }
}

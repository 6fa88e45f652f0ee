//! The Sun et al. (2005) table baseline (seed 004, as reorganised by Wyman &
//! Ramsey): the half-angle form (docs/MATH.md §3)
//!
//! `A = e^{−τ x0} / (2π h) · [F(T, ξb) − F(T, γ/2)]`, `F(u, v) = ∫₀^v e^{−u tan ξ} dξ`,
//!
//! `T = τ h`, `ξb = π/4 + ½ atan((ρ − x0)/h)` (`π/2` without a surface), with `F`
//! precomputed on an `R × R` grid over `u ∈ [0, U_MAX]`, `v ∈ [0, π/2]` and looked
//! up bilinearly — a texture in the shaders. Isotropic only (the table has no
//! phase function). The table is derived data: rebuilt from its parameters by
//! [`SunTable::build`] (8-point Gauss–Legendre per cell, cumulative in `v`,
//! checked against the adaptive reference quadrature in the tests), stored as
//! f32, which is what every evaluator — this f64 one included — reads.

use airlight_shapes::cost::{Cost, PhaseShape, Shape};
use crate::family::{baseline_method, phase_label, Assembled, Family, Role, Texture};
use airlight_truth::reference::Point;
use airlight_shapes::template::{lit, Context, KernelView, Templates};
use airlight_truth::tomlfile::{FieldError, Reader};
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt::Write;
use toml::Table;

/// The largest `u = τ sin γ` the table covers: the `dense` domain's τ.
pub const U_MAX: f64 = 20.0;
/// The largest `v`: `π/2`.
pub const V_MAX: f64 = FRAC_PI_2;

/// The table of `F(u, v)`, `res × res` f32 texels, row `j` at `v_j = V_MAX j/(res − 1)`,
/// column `i` at `u_i = U_MAX i/(res − 1)`.
#[derive(Debug, Clone, PartialEq)]
pub struct SunTable {
    /// Texels per side.
    pub res: usize,
    /// `F` at the texels, row-major (`v` rows, `u` columns).
    pub texels: Vec<f32>,
}

/// `F(u, v)` at every `v_j` for one `u`, cumulative: 8-point Gauss–Legendre per cell.
fn column(u: f64, res: usize, x: &[f64], w: &[f64]) -> Vec<f64> {
    let dv = V_MAX / (res - 1) as f64;
    let mut out = Vec::with_capacity(res);
    let mut sum = 0.0;
    out.push(0.0);
    for j in 0..res - 1 {
        let (a, half) = (j as f64 * dv, 0.5 * dv);
        let cell: f64 = x.iter().zip(w).map(|(&x, &w)| w * (-u * (a + half * (1.0 + x)).tan()).exp()).sum();
        sum += half * cell;
        out.push(sum);
    }
    out
}

impl SunTable {
    /// Builds the `res × res` table.
    pub fn build(res: usize) -> SunTable {
        let (x, w) = airlight_truth::quad::gauss_legendre(8);
        let cols: Vec<Vec<f64>> = (0..res).map(|i| column(U_MAX * i as f64 / (res - 1) as f64, res, &x, &w)).collect();
        let mut texels = vec![0.0f32; res * res];
        for (i, c) in cols.iter().enumerate() {
            for (j, &f) in c.iter().enumerate() {
                texels[j * res + i] = f as f32;
            }
        }
        SunTable { res, texels }
    }

    /// The table as the texture its kernels read.
    pub fn as_texture(&self) -> Texture<'_> {
        Texture { res: self.res, texels: &self.texels }
    }

    /// The table's size in bytes (f32 texels).
    pub fn bytes(&self) -> usize {
        self.as_texture().bytes()
    }

    /// FNV-1a of the texels' bits: which table a file was measured with.
    pub fn digest(&self) -> String {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in self.as_texture().to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
        format!("{h:016x}")
    }

    /// Bilinear lookup at `(u, v)`, clamped to the table (as a texture's clamp-to-edge).
    pub fn lookup(&self, u: f64, v: f64) -> f64 {
        let n = (self.res - 1) as f64;
        let x = (u / U_MAX * n).clamp(0.0, n);
        let y = (v / V_MAX * n).clamp(0.0, n);
        let (i, j) = ((x.floor() as usize).min(self.res - 2), (y.floor() as usize).min(self.res - 2));
        let (tx, ty) = (x - i as f64, y - j as f64);
        let t = |i: usize, j: usize| f64::from(self.texels[j * self.res + i]);
        let lo = t(i, j) + tx * (t(i + 1, j) - t(i, j));
        let hi = t(i, j + 1) + tx * (t(i + 1, j + 1) - t(i, j + 1));
        lo + ty * (hi - lo)
    }

    /// `F(u, b) − F(u, a)` on the same bilinear surface as two [`lookup`](Self::lookup)s,
    /// formed as the kernels form it, from texel differences in one column pair:
    /// `[F(b) − row(jb)] + [row(jb) − row(ja+1)] + [row(ja+1) − F(a)]`. Two lookups in the
    /// same or neighbouring cells (γ → π) then do not cancel.
    pub fn lookup_diff(&self, u: f64, a: f64, b: f64) -> f64 {
        let n = (self.res - 1) as f64;
        let x = (u / U_MAX * n).clamp(0.0, n);
        let ya = (a / V_MAX * n).clamp(0.0, n);
        let yb = (b / V_MAX * n).clamp(0.0, n);
        let i = (x.floor() as usize).min(self.res - 2);
        let (ja, jb) = ((ya.floor() as usize).min(self.res - 2), (yb.floor() as usize).min(self.res - 2));
        let tx = x - i as f64;
        let t = |i: usize, j: usize| f64::from(self.texels[j * self.res + i]);
        let rows = |j: usize, k: usize| {
            let d0 = t(i, j) - t(i, k);
            d0 + tx * ((t(i + 1, j) - t(i + 1, k)) - d0)
        };
        if ja == jb {
            return (yb - ya) * rows(ja + 1, ja);
        }
        (yb - jb as f64) * rows(jb + 1, jb) + rows(jb, ja + 1) + ((ja + 1) as f64 - ya) * rows(ja + 1, ja)
    }
}

impl Family for SunTable {
    const KIND: &'static str = "sun2005";
    const DIR: &'static str = "sun";
    const ROLE: Role = Role::Baseline;
    const TABLES: &'static [&'static str] = &["table"];
    const TEMPLATES: Templates = airlight_shapes::core_templates!();
    /// The table's resolution.
    type Recipe = usize;
    type Fit = ();

    fn assemble(r: usize, g_range: (f64, f64), _: &()) -> Result<Assembled<SunTable>, String> {
        Ok(Assembled {
            body: SunTable::build(r),
            families: vec![format!("sun2005-{r} (F(u, v) table, {r}x{r} f32)"), phase_label(g_range)],
            provenance: Vec::new(),
            method: baseline_method(&format!("A = e^(-τ cos γ)/(2π sin γ) [F(τ sin γ, ξb) - F(τ sin γ, γ/2)], F bilinear from a {r}x{r} table over u ≤ {U_MAX}, v ≤ π/2 (Sun et al. 2005; Wyman & Ramsey 2008)")),
        })
    }

    fn phase_shape(&self) -> PhaseShape {
        PhaseShape::Isotropic
    }

    fn texture(&self) -> Option<Texture<'_>> {
        Some(self.as_texture())
    }

    fn kernel_context(&self, k: &KernelView) -> Context {
        let mut ctx = Context::quadrature(k);
        let n = (self.res - 1) as f64;
        ctx.insert("res", &self.res);
        ctx.insert("res_m1", &(self.res - 1));
        ctx.insert("bytes", &self.bytes());
        ctx.insert("u_scale", &lit(n / U_MAX));
        ctx.insert("v_scale", &lit(n / V_MAX));
        ctx.insert("u_max_doc", &U_MAX);
        ctx
    }

    /// `A` at a valid point (isotropic: the table has no phase function).
    fn eval(&self, p: Point) -> f64 {
        let (h, x0) = (p.gamma.sin(), p.gamma.cos());
        if h <= 0.0 {
            // On the axis behind, the half-angle form degenerates, as in its kernels:
            // the closed form without extinction, attenuated by the viewer–light leg.
            if x0 > 0.0 {
                // Towards the light: divergent through it; before it the form's own
                // limit, which it has reached by γ = 1e-8.
                return if p.rho * x0 >= 1.0 { f64::INFINITY } else { self.eval(Point { gamma: 1e-12, ..p }) };
            }
            return airlight_truth::reference::no_extinction(p.gamma, p.rho) * (-p.tau).exp();
        }
        let t = p.tau * h;
        // ξb = π/4 + ½ atan((ρ − x0)/h) = ½ atan2(h, x0 − ρ): no cancellation as h → 0.
        let xb = if p.rho.is_finite() { 0.5 * h.atan2(x0 - p.rho) } else { FRAC_PI_2 };
        let f = self.lookup_diff(t, 0.5 * p.gamma, xb).max(0.0);
        if f == 0.0 {
            return 0.0;
        }
        // `e^{−τ x0}` passes f64's range behind the viewer in dense media (τ |x0| > 709)
        // where the table's difference is its rounding: in logarithms, and like the
        // kernels' saturating `exp`, never beyond the largest finite value.
        // A ≤ e^{−τ} P (π − γ)/h (s + t ≥ 1, and the closed form without extinction):
        // where the two look-ups cancel (γ → π) their difference is rounding, which
        // e^{−τ x0}/h would carry far past A; as the kernels, the form is held to it.
        let bound = (-p.tau).exp() * h.atan2(-x0) / (4.0 * PI * h);
        ((f.ln() - p.tau * x0).exp() / (2.0 * PI * h)).min(bound).min(f64::MAX)
    }

    /// Two bilinear lookups (8 texel loads), one `exp`, one `atan`, one `sin_cos`.
    fn ops(&self, _shape: Shape) -> Cost {
        Cost { exp: 1, log: 0, atan: 1, sqrt: 0, div: 4, sincos: 1 }
    }

    /// Writes its table's parameters (the texels are rebuilt from them).
    fn render_toml(&self, _g_range: (f64, f64), o: &mut String, _prov: &dyn Fn(&mut String, &str)) {
        o.push_str("\n[table]\nfunction = \"F(u, v) = integral of exp(-u tan xi) over xi in [0, v]\"\n");
        let _ = writeln!(o, "resolution = {}", self.res);
        let _ = writeln!(o, "u_max = {}", airlight_truth::tomlfile::dec(U_MAX));
        let _ = writeln!(o, "v_max = {} # pi/2", airlight_truth::tomlfile::dec(V_MAX));
        o.push_str("texel = \"r32float\"\nlookup = \"bilinear, clamped to the edges\"\n");
        o.push_str("built = \"8-point Gauss-Legendre per cell, cumulative in v, f64, rounded to f32\"\n");
        let _ = writeln!(o, "bytes = {}", self.bytes());
        let _ = writeln!(o, "digest = \"{}\" # FNV-1a of the f32 texels this file was measured with", self.digest());
    }

    /// Reads its table's parameters and rebuilds the texels.
    fn parse_toml(r: &Reader, doc: &Table, g_range: &[f64]) -> Result<SunTable, FieldError> {
        let t = r.table(doc, "table")?;
        r.deny(
            t,
            "table",
            &["function", "resolution", "u_max", "v_max", "texel", "lookup", "built", "bytes", "digest"],
        )?;
        if g_range != [0.0, 0.0] {
            return Err(r.err("model", "g_range", "the Sun table is isotropic: [0.0, 0.0] only"));
        }
        let res = r.uint(t, "table", "resolution")?;
        if !(2..=4096).contains(&res) {
            return Err(r.err("table", "resolution", "must be 2..=4096"));
        }
        if r.float(t, "table", "u_max")? != U_MAX || r.float(t, "table", "v_max")? != V_MAX {
            return Err(r.err("table", "u_max", &format!("this airlight builds tables over u <= {U_MAX}, v <= pi/2")));
        }
        Ok(SunTable::build(res))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_the_integral_and_the_form_is_the_reference() {
        let t = SunTable::build(64);
        for &(u, v) in &[(0.0, 1.0), (0.5, 0.7), (3.0, 1.5), (19.0, 0.2)] {
            let q = airlight_truth::quad::gauss_kronrod(|x: f64| (-u * x.tan()).exp(), &[0.0, v], 1e-13, 200);
            // Bilinear between texels: the table's own interpolation error, not the build's.
            let n = 63.0;
            let (i, j) = ((u / U_MAX * n).round(), (v / V_MAX * n).round());
            let (uu, vv) = (U_MAX * i / n, V_MAX * j / n);
            let exact = airlight_truth::quad::gauss_kronrod(|x: f64| (-uu * x.tan()).exp(), &[0.0, vv], 1e-13, 200).value;
            let got = f64::from(t.texels[j as usize * 64 + i as usize]);
            assert!((got - exact).abs() <= 1e-7 * exact.max(1e-3), "F({uu}, {vv}) = {got} vs {exact}");
            assert!(q.value > 0.0);
        }
        // The half-angle form with a fine table agrees with the reference where it is well conditioned.
        let fine = SunTable::build(512);
        let p = Point { tau: 0.5, gamma: 1.0, rho: 3.0, g: 0.0 };
        let exact = airlight_truth::reference::airlight(p).unwrap();
        assert!((fine.eval(p) / exact - 1.0).abs() < 2e-3, "{} vs {exact}", fine.eval(p));
        assert_eq!(t.bytes(), 64 * 64 * 4);
    }

    #[test]
    fn the_difference_lookup_is_the_difference_of_two_lookups() {
        let t = SunTable::build(64);
        let cell = V_MAX / 63.0;
        let cases = [
            (0.3, 1.0, 1.0 + 0.2 * cell),
            (0.3, 1.0 + 0.2 * cell, 1.0),
            (2.0, 0.5, 0.5 + 1.5 * cell),
            (7.0, 0.1, 1.5),
            (19.9, 1.5, 0.01),
            (25.0, 1.56, V_MAX),
            (0.074, V_MAX - 0.005, V_MAX - 0.0025),
            (-1.0, -0.2, 2.0),
        ];
        for &(u, a, b) in &cases {
            let want = t.lookup(u, b) - t.lookup(u, a);
            let got = t.lookup_diff(u, a, b);
            assert!((got - want).abs() <= 1e-12, "F({u}, {b}) - F({u}, {a}): {got} vs {want}");
        }
    }
}

//! From a physical description of a view ray, a point light and a homogeneous
//! medium to the canonical `(τ, γ, ρ)` of docs/MATH.md §2 and back.
//!
//! `La = (σs · I / D) · A(τ, γ, ρ)`, with `D` the viewer–light distance. The angle
//! γ is taken from `atan2(|d × L|, d · L)`: the cross product keeps the distance
//! from the light to the ray (`h = D sin γ`) accurate at grazing angles, where
//! `1 − cos²γ` would lose every digit.

use crate::reference::Point;
use std::fmt;

/// A 3-vector in world units.
pub type Vec3 = [f64; 3];

pub(crate) fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(crate) fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(crate) fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
/// Euclidean length without overflow or underflow for any finite input.
pub(crate) fn norm(a: Vec3) -> f64 {
    a[0].hypot(a[1]).hypot(a[2])
}

/// One view ray through a homogeneous medium lit by one point light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysicalRay {
    /// Viewer (ray origin), world units.
    pub origin: Vec3,
    /// Ray direction; any non-zero length.
    pub direction: Vec3,
    /// Distance along the ray to the first surface, world units; `None` if the
    /// ray escapes.
    pub surface_distance: Option<f64>,
    /// Light position, world units.
    pub light: Vec3,
    /// Light intensity (radiant intensity, W/sr or any consistent unit).
    pub intensity: f64,
    /// Extinction coefficient σt, 1/world unit.
    pub sigma_t: f64,
    /// Scattering coefficient σs, 1/world unit (physically ≤ σt).
    pub sigma_s: f64,
}

/// The canonical form of a [`PhysicalRay`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Canonical {
    /// `(τ, γ, ρ)`; `g` is copied from the medium.
    pub point: Point,
    /// `D`, the viewer–light distance, world units.
    pub distance: f64,
    /// `σs · I / D`: radiance = `scale · A`.
    pub scale: f64,
}

/// A physical description that does not define an airlight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GeometryError {
    /// The direction has zero length or is not finite.
    Direction,
    /// The light sits at the viewer (D = 0) or a position is not finite.
    LightAtViewer,
    /// σt or σs negative, infinite or NaN.
    Medium,
    /// The surface distance is not > 0.
    Surface,
    /// The intensity is negative or NaN.
    Intensity,
    /// A spot cone's axis is zero or its outer cosine is not in [0, 1].
    Cone,
}

impl fmt::Display for GeometryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            GeometryError::Direction => "ray direction must be finite and non-zero",
            GeometryError::LightAtViewer => "light and viewer positions must be finite and distinct",
            GeometryError::Medium => "medium needs finite sigma_t ≥ 0 and sigma_s ≥ 0",
            GeometryError::Surface => "surface distance must be > 0",
            GeometryError::Intensity => "light intensity must be ≥ 0",
            GeometryError::Cone => "spot cone needs a non-zero axis and an outer half-angle up to 90°",
        })
    }
}

impl std::error::Error for GeometryError {}

impl PhysicalRay {
    /// Canonical parameters for a medium with Henyey–Greenstein asymmetry `g`.
    pub fn to_canonical(&self, g: f64) -> Result<Canonical, GeometryError> {
        let dir_len = norm(self.direction);
        if !(dir_len > 0.0 && dir_len.is_finite()) {
            return Err(GeometryError::Direction);
        }
        let to_light = sub(self.light, self.origin);
        let distance = norm(to_light);
        if !(distance > 0.0 && distance.is_finite()) {
            return Err(GeometryError::LightAtViewer);
        }
        // σs > σt is unphysical (a medium scatters no more than it extinguishes),
        // but the radiance is still σs·I/D·A: kernels take it, so the reference does.
        if !(self.sigma_t.is_finite() && self.sigma_t >= 0.0 && self.sigma_s.is_finite() && self.sigma_s >= 0.0) {
            return Err(GeometryError::Medium);
        }
        if self.intensity.is_nan() || self.intensity < 0.0 {
            return Err(GeometryError::Intensity);
        }
        let rho = match self.surface_distance {
            None => f64::INFINITY,
            Some(dp) if dp > 0.0 => dp / distance,
            Some(_) => return Err(GeometryError::Surface),
        };
        // Both terms scale with |d| |L|, which cancels in atan2.
        let d = self.direction;
        let gamma = norm(cross(d, to_light)).atan2(dot(d, to_light));
        Ok(Canonical {
            point: Point { tau: self.sigma_t * distance, gamma, rho, g },
            distance,
            scale: self.sigma_s * self.intensity / distance,
        })
    }

    /// The in-scattered radiance `σs·I/D·A` over every input the kernels' physical
    /// entry takes, `a` evaluating `A` at a canonical point (the reference or a
    /// model): 0 without scattering or light, or with a surface at the viewer;
    /// `+∞` with the light at the viewer or on the ray ahead (`A` diverges).
    /// Errors only for what defines no ray: a zero or non-finite direction,
    /// non-finite positions, a negative or non-finite medium or intensity.
    pub fn radiance(&self, g: f64, a: &dyn Fn(Point) -> f64) -> Result<f64, GeometryError> {
        let dir_len = norm(self.direction);
        if !(dir_len > 0.0 && dir_len.is_finite()) {
            return Err(GeometryError::Direction);
        }
        if !(self.origin.iter().chain(&self.light).all(|x| x.is_finite())) {
            return Err(GeometryError::LightAtViewer);
        }
        if !(self.sigma_t.is_finite() && self.sigma_t >= 0.0 && self.sigma_s.is_finite() && self.sigma_s >= 0.0) {
            return Err(GeometryError::Medium);
        }
        if !(self.intensity.is_finite() && self.intensity >= 0.0) {
            return Err(GeometryError::Intensity);
        }
        if self.sigma_s == 0.0 || self.intensity == 0.0 || self.surface_distance == Some(0.0) {
            return Ok(0.0);
        }
        if norm(sub(self.light, self.origin)) == 0.0 {
            return Ok(f64::INFINITY);
        }
        let c = self.to_canonical(g)?;
        let v = a(c.point);
        Ok(if v.is_infinite() { v } else { c.scale * v })
    }

    /// A physical ray realising the canonical point at viewer–light distance
    /// `distance`: viewer at the origin, light on +z, ray in the x–z plane.
    /// `σt = τ / D`; σs and the intensity are the caller's.
    pub fn from_canonical(p: Point, distance: f64, sigma_s: f64, intensity: f64) -> PhysicalRay {
        PhysicalRay {
            origin: [0.0; 3],
            direction: [p.gamma.sin(), 0.0, p.gamma.cos()],
            surface_distance: if p.rho.is_finite() { Some(p.rho * distance) } else { None },
            light: [0.0, 0.0, distance],
            intensity,
            sigma_t: p.tau / distance,
            sigma_s,
        }
    }
}

/// A spot light's cone: lit where the direction from the light makes an angle
/// with `axis` whose cosine is at least `cos_outer`; fully lit from `cos_inner`
/// on, with the weight linear in that cosine between (`cos_inner <= cos_outer`:
/// a hard edge). Half-angles up to 90°: `0 ≤ cos_outer ≤ 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cone {
    /// The cone's axis, from the light; any non-zero length.
    pub axis: Vec3,
    /// Cosine of the outer half-angle (weight 0 beyond).
    pub cos_outer: f64,
    /// Cosine of the inner half-angle (weight 1 within).
    pub cos_inner: f64,
}

impl Cone {
    /// The weight of the direction `r` from the light (0 ≤ w ≤ 1).
    pub fn weight(&self, r: Vec3) -> f64 {
        let c = dot(r, self.axis) / (norm(r) * norm(self.axis));
        if self.cos_inner <= self.cos_outer {
            return if c >= self.cos_outer { 1.0 } else { 0.0 };
        }
        ((c - self.cos_outer) / (self.cos_inner - self.cos_outer)).clamp(0.0, 1.0)
    }

    /// The stretch `[s0, s1]` of `ray` (distances along it, world units; `s1`
    /// may be `∞`) inside the cone of cut-off cosine `c` and before the surface;
    /// `None` where the ray misses it. Solved about the ray's closest point to the
    /// light, so that the coefficients scale with the light's distance `h` from the
    /// ray and nothing cancels near it; the cone is convex (`c ≥ 0`; at `c = 0` a
    /// half-space), so the lit set is one interval.
    pub fn lit(&self, ray: &PhysicalRay, c: f64) -> Option<(f64, f64)> {
        let d = ray.direction.map(|x| x / norm(ray.direction));
        let n = self.axis.map(|x| x / norm(self.axis));
        let to_light = sub(ray.light, ray.origin);
        let sc = dot(to_light, d);
        // m: from the light to the closest point, |m| = h (as a cross product, exact near the ray).
        let perp = cross(d, to_light);
        let m = cross(perp, d).map(|x| -x);
        let h = norm(perp);
        let (p, k) = (dot(d, n), dot(m, n));
        // f(t) = t p + k − c √(t² + h²) ≥ 0 (concave); its roots are those of
        // a2 t² + 2 b t + c0 with t p + k ≥ 0.
        let f = |t: f64| t * p + k - c * t.hypot(h);
        let (a2, b, c0) = (p * p - c * c, p * k, k * k - c * c * h * h);
        let disc = c * c * (k * k + a2 * h * h);
        // No real root: f keeps one sign (clamping disc to 0 would invent two).
        let mut roots: Vec<f64> = if disc < 0.0 {
            vec![]
        } else if a2 == 0.0 {
            if b == 0.0 {
                vec![]
            } else {
                vec![-c0 / (2.0 * b)]
            }
        } else {
            let q = -(b + b.signum() * disc.sqrt());
            if q == 0.0 {
                vec![0.0]
            } else {
                vec![q / a2, c0 / q]
            }
        };
        roots.retain(|&t| t.is_finite() && t * p + k >= 0.0);
        roots.sort_by(f64::total_cmp);
        roots.dedup();
        let (lo, hi) = match roots.as_slice() {
            [r1, r2, ..] => (*r1, *r2),
            [r] if p > c => (*r, f64::INFINITY),
            [r] if p < -c => (f64::NEG_INFINITY, *r),
            [r] => (*r, *r),
            [] if f(0.0) >= 0.0 => (f64::NEG_INFINITY, f64::INFINITY),
            [] => return None,
        };
        let end = ray.surface_distance.unwrap_or(f64::INFINITY);
        let (s0, s1) = ((sc + lo).max(0.0), (sc + hi).min(end));
        (s0 < s1).then_some((s0, s1))
    }
}

impl PhysicalRay {
    /// The stretch `[s0, s1]` of the ray as a ray of its own: the viewer moved to
    /// `s0` (the phase angle at a point does not depend on where the viewer is on
    /// the ray), the surface at `s1 − s0`, and the transmittance `e^(−σt s0)` of
    /// the part skipped, by which its radiance is multiplied. Exact for every
    /// family: the integral over the stretch is never a difference of two.
    pub fn stretch(&self, s0: f64, s1: f64) -> (PhysicalRay, f64) {
        let len = norm(self.direction);
        let origin = [0, 1, 2].map(|i| self.origin[i] + s0 * (self.direction[i] / len));
        let surface_distance = s1.is_finite().then_some(s1 - s0);
        (PhysicalRay { origin, surface_distance, ..*self }, (-self.sigma_t * s0).exp())
    }

    /// The radiance from a spot light of cone `cone`, or from a point light (`None`):
    /// [`PhysicalRay::spot_radiance`] or [`PhysicalRay::radiance`].
    pub fn light_radiance(&self, cone: Option<&Cone>, g: f64, a: &dyn Fn(Point) -> f64) -> Result<f64, GeometryError> {
        match cone {
            Some(c) => self.spot_radiance(c, g, a),
            None => self.radiance(g, a),
        }
    }

    /// The radiance from a spot light of cone `cone`: the lit stretch through
    /// [`Cone::lit`] and [`PhysicalRay::stretch`]; a smooth edge as the mean of hard
    /// cones over the cut-off cosine (the linear weight is exactly that mean),
    /// integrated adaptively. `a` evaluates `A` as in [`PhysicalRay::radiance`].
    pub fn spot_radiance(&self, cone: &Cone, g: f64, a: &dyn Fn(Point) -> f64) -> Result<f64, GeometryError> {
        let hard = |c: f64| -> Result<f64, GeometryError> {
            match cone.lit(self, c) {
                None => Ok(0.0),
                Some((s0, s1)) => {
                    let (ray, t) = self.stretch(s0, s1);
                    Ok(t * ray.radiance(g, a)?)
                }
            }
        };
        if !(cone.cos_outer >= 0.0 && cone.cos_outer <= 1.0 && norm(cone.axis) > 0.0) {
            return Err(GeometryError::Cone);
        }
        if cone.cos_inner <= cone.cos_outer {
            return hard(cone.cos_outer);
        }
        let ci = cone.cos_inner.min(1.0);
        // The first error of any hard cone is the error (they share the ray).
        let failed = std::cell::Cell::new(None);
        let q = crate::quad::gauss_kronrod(
            |c| {
                hard(c).unwrap_or_else(|e| {
                    failed.set(Some(e));
                    f64::NAN
                })
            },
            &[cone.cos_outer, ci],
            1e-10,
            400,
        );
        match failed.get() {
            Some(e) => Err(e),
            None => Ok(q.value / (cone.cos_inner - cone.cos_outer)),
        }
    }
}

// Where a march with no surface stops: the raymarch family marches to it, and the
// shadowed reference looks visibility up along the same extent.

/// The relative two-leg transmittance `e^{−τ(s + t − 1)}` at which a march with
/// no surface stops: beyond it the rest of the ray adds less than this share of
/// the light's unattenuated contribution.
pub const MARCH_CUTOFF: f64 = 1e-4;
/// The far plane of a march with no surface, in light distances `D`.
pub const FAR_PLANE: f64 = 1000.0;

/// Where a march with no surface ends: the distance at which the relative
/// two-leg transmittance `e^{−τ(s + t − 1)}` reaches [`MARCH_CUTOFF`], capped by
/// [`FAR_PLANE`]. `s + t` grows with `s` (`(s + t)' = 1 + (s − x0)/t ≥ 0`) and
/// `s + t = K` at `s = (K² − 1) / (2 (K − x0))`.
pub fn march_end(tau: f64, x0: f64) -> f64 {
    let k = 1.0 + (1.0 / MARCH_CUTOFF).ln() / tau;
    let s = (k * k - 1.0) / (2.0 * (k - x0));
    if s.is_finite() {
        s.min(FAR_PLANE)
    } else {
        FAR_PLANE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_over_scales() {
        for &dist in &[1e-4, 1.0, 3.7e2, 1e6] {
            for &gamma in &[1e-6, 1e-3, 0.7, 1.5, 3.0, std::f64::consts::PI - 1e-6] {
                let p = Point { tau: 2.5, gamma, rho: 0.75, g: 0.3 };
                let mut ray = PhysicalRay::from_canonical(p, dist, 0.2 / dist, 10.0);
                // Move everything away from the origin, and use an unnormalised direction.
                let offset = [dist * 3.0, -dist * 5.0, dist * 0.25];
                ray.origin = [offset[0], offset[1], offset[2]];
                ray.light = [ray.light[0] + offset[0], ray.light[1] + offset[1], ray.light[2] + offset[2]];
                ray.direction = [ray.direction[0] * 7.0, 0.0, ray.direction[2] * 7.0];
                let c = ray.to_canonical(0.3).unwrap();
                let rel = |a: f64, b: f64| ((a - b) / b).abs();
                assert!(rel(c.distance, dist) < 1e-15);
                assert!(rel(c.point.tau, 2.5) < 1e-14);
                assert!(rel(c.point.rho, 0.75) < 1e-14);
                // γ to a few ulps of γ even at 1e-6 rad: offsets cost ~ulp(|offset|)/D.
                assert!(rel(c.point.gamma, gamma) < 1e-9, "D = {dist}, γ = {gamma}: {}", c.point.gamma);
                assert!(rel(c.scale, 0.2 / dist * 10.0 / dist) < 1e-14);
            }
        }
    }

    #[test]
    fn grazing_angle_from_cross_product() {
        // A light 1e-7 units off a ray at distance 1e3: γ = 1e-10 exactly (to f64).
        let ray = PhysicalRay {
            origin: [0.0; 3],
            direction: [1.0, 0.0, 0.0],
            surface_distance: None,
            light: [1e3, 1e-7, 0.0],
            intensity: 1.0,
            sigma_t: 0.1,
            sigma_s: 0.05,
        };
        let c = ray.to_canonical(0.0).unwrap();
        assert!(((c.point.gamma - 1e-10) / 1e-10).abs() < 1e-12, "{}", c.point.gamma);
    }

    #[test]
    fn bad_descriptions_are_errors() {
        let good = PhysicalRay::from_canonical(Point { tau: 1.0, gamma: 1.0, rho: 2.0, g: 0.0 }, 1.0, 0.5, 1.0);
        assert!(good.to_canonical(0.0).is_ok());
        let mut r = good;
        r.direction = [0.0; 3];
        assert_eq!(r.to_canonical(0.0), Err(GeometryError::Direction));
        let mut r = good;
        r.light = r.origin;
        assert_eq!(r.to_canonical(0.0), Err(GeometryError::LightAtViewer));
        let mut r = good;
        r.sigma_s = -2.0;
        assert_eq!(r.to_canonical(0.0), Err(GeometryError::Medium));
        // σs > σt is unphysical but defined.
        r.sigma_s = 2.0;
        assert!(r.to_canonical(0.0).is_ok());
        // The edges of the physical entry: the light at the viewer, a surface at it.
        let one = |_: Point| 1.0;
        let mut r = good;
        r.light = r.origin;
        assert_eq!(r.radiance(0.0, &one), Ok(f64::INFINITY));
        r.sigma_s = 0.0;
        assert_eq!(r.radiance(0.0, &one), Ok(0.0));
        let mut r = good;
        r.surface_distance = Some(0.0);
        assert_eq!(r.radiance(0.0, &one), Ok(0.0));
        let mut r = good;
        r.surface_distance = Some(0.0);
        assert_eq!(r.to_canonical(0.0), Err(GeometryError::Surface));
    }

    /// The spot radiance through the lit stretch and the reference `A` against
    /// the physical integral along the ray, weighted by the cone, integrated directly.
    #[test]
    fn spot_light_matches_the_weighted_integral_along_the_ray() {
        use crate::phase::Phase;
        let a = |p: Point| crate::reference::airlight(p).unwrap();
        let cases = [
            // (origin, dir, surface, light, axis, cos_outer, cos_inner, g)
            ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], None, [1.0, 0.5, 10.0], [0.0, -1.0, 0.2], 0.3, 0.3, 0.0),
            ([0.0, 0.0, 0.0], [0.1, 0.0, 1.0], Some(30.0), [1.0, 2.0, 10.0], [0.0, -1.0, 0.0], 0.85, 0.95, 0.6),
            ([2.0, 0.0, -3.0], [0.0, 0.05, 1.0], None, [0.0, 0.3, 5.0], [0.3, -1.0, 1.0], 0.5, 0.65, -0.3),
            // The viewer inside the cone, looking along the axis.
            ([0.0, 0.0, 2.0], [0.0, 0.0, 1.0], None, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 0.9, 0.97, 0.8),
        ];
        for (i, &(origin, direction, surface_distance, light, axis, co, ci, g)) in cases.iter().enumerate() {
            let ray = PhysicalRay {
                origin,
                direction,
                surface_distance,
                light,
                intensity: 20.0,
                sigma_t: 0.15,
                sigma_s: 0.1,
            };
            let cone = Cone { axis, cos_outer: co, cos_inner: ci };
            let got = ray.spot_radiance(&cone, g, &a).unwrap();
            let phase = Phase::from_g(g);
            let d = direction.map(|x| x / norm(direction));
            let integrand = |s: f64| {
                let x = [0, 1, 2].map(|j| origin[j] + s * d[j]);
                let r = sub(x, light);
                let dist = norm(r);
                let cos_alpha = (-dot(r, d) / dist).clamp(-1.0, 1.0);
                ray.sigma_s * ray.intensity * (-ray.sigma_t * (s + dist)).exp() * phase.eval(cos_alpha.acos())
                    / (dist * dist)
                    * cone.weight(r)
            };
            let end = surface_distance.unwrap_or(400.0);
            let mut breaks = vec![0.0, end];
            for c in [co, ci] {
                if let Some((s0, s1)) = cone.lit(&ray, c) {
                    breaks.extend([s0, s1.min(end)]);
                }
            }
            breaks.push(dot(sub(light, origin), d).clamp(0.0, end));
            breaks.sort_by(f64::total_cmp);
            let want = crate::quad::gauss_kronrod(integrand, &breaks, 1e-12, 2000).value;
            assert!(want > 0.0, "case {i}: the ray is lit");
            assert!(((got - want) / want).abs() < 1e-7, "case {i}: {got} vs {want}");
        }
        // A ray that misses the cone.
        let ray = PhysicalRay {
            origin: [0.0; 3],
            direction: [0.0, 0.0, 1.0],
            surface_distance: None,
            light: [0.0, 5.0, 10.0],
            intensity: 1.0,
            sigma_t: 0.1,
            sigma_s: 0.1,
        };
        let up = Cone { axis: [0.0, 1.0, 0.0], cos_outer: 0.9, cos_inner: 0.95 };
        assert_eq!(ray.spot_radiance(&up, 0.0, &a).unwrap(), 0.0);
        // A narrow cone the ray passes beside (the gate found it): the squared
        // equation has no real root, and clamping its discriminant to 0 invented
        // a lit stretch. No point of the ray is within the cone.
        let ray = PhysicalRay {
            origin: [0.080497354, 1.7816542, -1.5254824],
            direction: [0.8506645, 0.16470253, 0.4992424],
            surface_distance: Some(2.635322),
            light: [0.54826003, 1.9187979, -1.1982974],
            intensity: 261.76,
            sigma_t: 13.379121,
            sigma_s: 10.703297,
        };
        let narrow = Cone { axis: [-0.41114482, -0.15633109, -0.27928278], cos_outer: 0.9987269, cos_inner: 0.9987269 };
        let d = ray.direction.map(|x| x / norm(ray.direction));
        let lit = (0..=10_000).any(|i| {
            let s = 2.635322 * f64::from(i) / 1e4;
            narrow.weight(sub([0, 1, 2].map(|j| ray.origin[j] + s * d[j]), ray.light)) > 0.0
        });
        assert!(!lit);
        assert_eq!(narrow.lit(&ray, narrow.cos_outer), None);
        assert_eq!(ray.spot_radiance(&narrow, 0.0, &a).unwrap(), 0.0);
    }
}

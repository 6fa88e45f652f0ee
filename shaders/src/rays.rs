//! Rays as the GPU takes them: the physical entry's [`Ray`] and the spot entry's
//! [`SpotRay`], each packed into `vec4` slots by its arguments.

use crate::{Arg, Entry};

/// One view ray and its light and medium, for the physical entry point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Ray origin (the viewer).
    pub origin: [f32; 3],
    /// Ray direction (need not be normalised).
    pub dir: [f32; 3],
    /// Distance to the first surface along the ray; negative: none.
    pub surface: f32,
    /// Light position.
    pub light: [f32; 3],
    /// Radiant intensity.
    pub intensity: f32,
    /// Extinction coefficient.
    pub sigma_t: f32,
    /// Scattering coefficient.
    pub sigma_s: f32,
    /// Henyey–Greenstein asymmetry.
    pub g: f32,
}

impl Ray {
    /// An `eval` CSV row as the physical entry takes it (f32; no surface: −1).
    pub fn from_row(r: &airlight_truth::points_csv::RayRow) -> Ray {
        let f = |v: [f64; 3]| v.map(|x| x as f32);
        Ray {
            origin: f(r.ray.origin),
            dir: f(r.ray.direction),
            surface: r.ray.surface_distance.map_or(-1.0, |s| s as f32),
            light: f(r.ray.light),
            intensity: r.ray.intensity as f32,
            sigma_t: r.ray.sigma_t as f32,
            sigma_s: r.ray.sigma_s as f32,
            g: r.g as f32,
        }
    }

    /// The same ray in f64, for the reference (`surface < 0`: none).
    pub fn physical(&self) -> airlight_truth::geometry::PhysicalRay {
        let f = |v: [f32; 3]| v.map(f64::from);
        airlight_truth::geometry::PhysicalRay {
            origin: f(self.origin),
            direction: f(self.dir),
            surface_distance: (self.surface >= 0.0).then_some(f64::from(self.surface)),
            light: f(self.light),
            intensity: f64::from(self.intensity),
            sigma_t: f64::from(self.sigma_t),
            sigma_s: f64::from(self.sigma_s),
        }
    }

    /// A compiled Rust kernel's physical entry on this ray.
    pub fn radiance_of(&self, k: &airlight_shapes::vocab::CompiledKernel) -> f32 {
        (k.radiance)(
            self.origin,
            self.dir,
            self.surface,
            self.light,
            self.intensity,
            self.sigma_t,
            self.sigma_s,
            self.g,
        )
    }

    /// The arguments in their packing slots ([`Arg::slot`]).
    pub(crate) fn pack(&self) -> [f32; 16] {
        pack_slots(Entry::Radiance, |a| match a {
            Arg::Origin => &self.origin,
            Arg::Dir => &self.dir,
            Arg::Light => &self.light,
            Arg::Surface => std::slice::from_ref(&self.surface),
            Arg::Intensity => std::slice::from_ref(&self.intensity),
            Arg::SigmaT => std::slice::from_ref(&self.sigma_t),
            Arg::SigmaS => std::slice::from_ref(&self.sigma_s),
            Arg::G => std::slice::from_ref(&self.g),
            other => unreachable!("{other} is not an argument of radiance"),
        })
    }
}

/// One view ray with a spot light and an RGB medium, for the spot entry point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpotRay {
    /// Ray origin (the viewer).
    pub origin: [f32; 3],
    /// Ray direction (need not be normalised).
    pub dir: [f32; 3],
    /// Distance to the first surface along the ray; negative: none.
    pub surface: f32,
    /// Light position.
    pub light: [f32; 3],
    /// The cone's axis, from the light.
    pub axis: [f32; 3],
    /// Cosine of the outer half-angle (`<= -1`: a point light).
    pub cos_outer: f32,
    /// Cosine of the inner half-angle (`<= cos_outer`: a hard edge).
    pub cos_inner: f32,
    /// Radiant intensity.
    pub intensity: f32,
    /// Extinction coefficient per channel.
    pub sigma_t: [f32; 3],
    /// Scattering coefficient per channel.
    pub sigma_s: [f32; 3],
    /// Henyey–Greenstein asymmetry.
    pub g: f32,
}

impl SpotRay {
    /// An `eval` CSV row as the spot entry takes it (f32; no surface: −1; a point
    /// light: `cos_outer` −1).
    pub fn from_row(r: &airlight_truth::points_csv::SpotRow) -> SpotRay {
        let f = |v: [f64; 3]| v.map(|x| x as f32);
        let ray = &r.rays[0];
        let (axis, co, ci) = match &r.cone {
            Some(c) => (f(c.axis), c.cos_outer as f32, c.cos_inner as f32),
            None => ([0.0, 0.0, 1.0], -1.0, -1.0),
        };
        SpotRay {
            origin: f(ray.origin),
            dir: f(ray.direction),
            surface: ray.surface_distance.map_or(-1.0, |s| s as f32),
            light: f(ray.light),
            axis,
            cos_outer: co,
            cos_inner: ci,
            intensity: ray.intensity as f32,
            sigma_t: r.rays.each_ref().map(|x| x.sigma_t as f32),
            sigma_s: r.rays.each_ref().map(|x| x.sigma_s as f32),
            g: r.g as f32,
        }
    }

    /// Channel `c` of the ray in f64, as a point-light ray (`surface < 0`: none).
    pub fn physical(&self, c: usize) -> airlight_truth::geometry::PhysicalRay {
        let ray = Ray {
            origin: self.origin,
            dir: self.dir,
            surface: self.surface,
            light: self.light,
            intensity: self.intensity,
            sigma_t: self.sigma_t[c],
            sigma_s: self.sigma_s[c],
            g: self.g,
        };
        ray.physical()
    }

    /// The cone in f64; `None` for a point light (`cos_outer <= -1`).
    pub fn cone(&self) -> Option<airlight_truth::geometry::Cone> {
        (self.cos_outer > -1.0).then(|| airlight_truth::geometry::Cone {
            axis: self.axis.map(f64::from),
            cos_outer: f64::from(self.cos_outer),
            cos_inner: f64::from(self.cos_inner),
        })
    }

    /// The reference radiance of channel `c`, `A` by `a` (the f64 reference or a
    /// model): through the cone's lit stretch, or the whole ray for a point light.
    pub fn reference(
        &self,
        c: usize,
        a: &dyn Fn(airlight_truth::reference::Point) -> f64,
    ) -> Result<f64, airlight_truth::geometry::GeometryError> {
        self.physical(c).light_radiance(self.cone().as_ref(), f64::from(self.g), a)
    }

    /// A compiled Rust kernel's spot entry on this ray, where it has one.
    pub fn spot_of(&self, k: &airlight_shapes::vocab::CompiledKernel) -> Option<[f32; 3]> {
        k.spot.map(|f| {
            f(
                self.origin,
                self.dir,
                self.surface,
                self.light,
                self.axis,
                self.cos_outer,
                self.cos_inner,
                self.intensity,
                self.sigma_t,
                self.sigma_s,
                self.g,
            )
        })
    }

    /// The arguments in their packing slots ([`Arg::slot`]).
    pub(crate) fn pack(&self) -> [f32; 24] {
        pack_slots(Entry::Spot, |a| match a {
            Arg::Origin => &self.origin,
            Arg::Dir => &self.dir,
            Arg::Light => &self.light,
            Arg::Axis => &self.axis,
            Arg::SigmaTRgb => &self.sigma_t,
            Arg::SigmaSRgb => &self.sigma_s,
            Arg::Surface => std::slice::from_ref(&self.surface),
            Arg::CosOuter => std::slice::from_ref(&self.cos_outer),
            Arg::CosInner => std::slice::from_ref(&self.cos_inner),
            Arg::Intensity => std::slice::from_ref(&self.intensity),
            Arg::G => std::slice::from_ref(&self.g),
            other => unreachable!("{other} is not an argument of spot"),
        })
    }
}

/// `entry`'s arguments in their packing slots ([`Arg::slot`]), `N` = 4 ×
/// [`Entry::packed_vec4s`]; `value` gives each argument's lanes.
pub(crate) fn pack_slots<'a, const N: usize>(entry: Entry, value: impl Fn(Arg) -> &'a [f32]) -> [f32; N] {
    debug_assert_eq!(N, 4 * entry.packed_vec4s());
    let mut out = [0.0; N];
    for &a in entry.all_args() {
        let (v, lane) = a.slot(entry).expect("every argument of an entry has a slot");
        let values = value(a);
        out[4 * v + lane..4 * v + lane + values.len()].copy_from_slice(values);
    }
    out
}

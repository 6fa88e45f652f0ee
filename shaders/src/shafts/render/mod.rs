//! The light-shafts render (issue 24; docs/MATH.md §8): a spot light above a
//! pergola shines down through its grid of beams into a smoky courtyard room,
//! past two pillars and a stone ball. As an engine would draw it:
//!
//! 1. a depth pass from the light (a perspective shadow map of the occluders'
//!    triangles, slope-scaled depth bias);
//! 2. a full-screen pass that finds each pixel's first surface (walls, floor,
//!    ceiling, beams, pillars, ball), walks the view ray to it in `N` equal steps,
//!    looks the shadow map up at each step's midpoint (a comparison sampler with
//!    linear filtering: 2×2 PCF, so visibility is fractional at edges) and sums the
//!    fog either with the scene kernel's shafts accumulator (fed the viewer's and
//!    the surface's visibility too) or with `raymarch-64`'s march functions (the
//!    engines' march, any step count); the surface is lit by the spot's direct
//!    light, attenuated by the medium and shadowed by the same map.
//!
//! The reference frame takes each pixel's ray to the same surface (the GPU
//! frame's distance) and sums the reference in-scattering (airlight_truth::reference, per
//! channel) over the ray's exact lit intervals among the analytic occluders
//! (airlight_truth::shafts); its surfaces are lit with exact visibility.
//!
//! One concept per file: `scene` (the room, light, camera and medium), `frame` (a
//! frame on the GPU), `reference` (the exact frame), `errors` (a frame against it).

mod errors;
mod frame;
mod reference;
mod scene;

pub use errors::*;
pub use frame::*;
pub use reference::*;
pub use scene::*;

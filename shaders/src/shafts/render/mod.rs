//! The light-shafts renders (issues 24 and 39; docs/MATH.md §8–9), one per
//! [`Stage`]: `window-shafts` (a spot light above a pergola shines down through
//! its grid of beams into a smoky room, past two pillars and a stone ball) and
//! `street-lamp` (a point light behind an iron railing, a bench and a ball, with a
//! cube shadow map). As an engine would draw them:
//!
//! 1. a depth pass per face of the light's map (the occluders' triangles; one
//!    perspective face for a spot, six 90° faces in one array for a point light;
//!    a constant depth bias);
//! 2. a full-screen pass that finds each pixel's first surface (walls, floor,
//!    ceiling, occluders) and sums the fog along the view ray to it by a
//!    [`Method`]: the exact walk (the shipped pyramid pass over the same depth
//!    map, the shipped walk's lit runs to the scene kernel's accumulator), the
//!    sampled accumulator (`N` look-ups at step midpoints through a comparison
//!    sampler with linear filtering, 2×2 PCF, each change bisected), or
//!    `raymarch-64`'s march functions (the engines' march, any step count); the
//!    surface is lit by the light's direct light, attenuated by the medium and
//!    shadowed by the same map at a normal offset.
//!
//! The reference frame takes each pixel's ray to the same surface (the GPU
//! frame's distance) and sums the reference in-scattering (airlight_truth::reference, per
//! channel) over the ray's exact lit intervals among the analytic occluders
//! (airlight_truth::shafts); its surfaces are lit with exact visibility.
//!
//! One concept per file: `scene` (the stages: room, light, camera, medium),
//! `frame` (a frame on the GPU), `reference` (the exact frame), `errors` (a frame
//! against it: errors, leak pixels).

mod errors;
mod frame;
mod reference;
mod scene;

pub use errors::*;
pub use frame::*;
pub use reference::*;
pub use scene::*;

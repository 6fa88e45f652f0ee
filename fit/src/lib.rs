//! airlight-fit: the reference single-scattering airlight integral, the geometry
//! that maps a scene onto it, and (later) the model families fitted against it.
//!
//! Everything here is f64 and follows `MATH.md`: `A(τ, γ, ρ; P)` is the canonical,
//! dimensionless airlight, and every error figure is a relative error of `A`.

#![warn(missing_docs)]

pub mod domains;
pub mod e1;
pub mod geometry;
pub mod phase;
pub mod quad;
pub mod reference;
pub mod stats;

pub use phase::Phase;
pub use reference::{airlight, airlight_detailed, Param, ParamError, Point};

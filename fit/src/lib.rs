//! airlight-fit: the reference single-scattering airlight integral, the geometry
//! that maps a scene onto it, the models that approximate it, and the error
//! analysis that measures them.
//!
//! Everything here is f64 and follows `docs/MATH.md`: `A(τ, γ, ρ; P)` is the canonical,
//! dimensionless airlight, and every error figure is a relative error of `A`.
//! Nothing here prints or exits; errors are values.

#![warn(missing_docs)]

pub mod analysis;
pub mod approx;
pub mod bench;
pub mod catalog;
pub mod coeffs;
pub mod cost;
pub mod domains;
pub mod e1;
pub mod family;
pub mod figure;
pub mod fitset;
pub mod fixtures;
pub mod geometry;
pub mod hexf;
pub mod io;
pub mod ircost;
pub mod lsq;
pub mod model;
pub mod parallel;
pub mod phase;
pub mod points_csv;
pub mod quad;
pub mod record;
pub mod reference;
pub mod selfcheck;
pub mod shafts;
pub mod stats;
pub mod template;
pub mod tomlfile;
pub mod vocab;

pub use phase::Phase;
pub use reference::{airlight, airlight_detailed, Param, ParamError, Point};

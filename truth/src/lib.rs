//! airlight-truth: the single-scattering airlight integral itself — the reference
//! quadrature and its special functions, the phase functions, the geometry that
//! maps a scene onto the canonical `A(τ, γ, ρ; P)`, the error domains and
//! statistics, the shadowed reference with its occluders, the self-check and the
//! 30-digit fixtures — and the file formats these are read from and written to.
//!
//! It depends on no model: the families (`airlight-fit`) are measured against it,
//! never the other way round. Everything is f64 and follows `docs/MATH.md`; nothing
//! here prints or exits; errors are values.

#![warn(missing_docs)]

pub mod domains;
pub mod e1;
pub mod fixtures;
pub mod geometry;
pub mod hexf;
pub mod io;
pub mod parallel;
pub mod phase;
pub mod points_csv;
pub mod quad;
pub mod reference;
pub mod selfcheck;
pub mod shafts;
pub mod stats;
pub mod tomlfile;

pub use phase::Phase;
pub use reference::{airlight, airlight_detailed, Param, ParamError, Point};

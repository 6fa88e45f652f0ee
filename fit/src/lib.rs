//! airlight-fit: the models that approximate the airlight integral — the families
//! (`family/`), their fits, the catalog of shipped members with their declared
//! bounds, and the speed/accuracy bench of the CPU kernels.
//!
//! The integral's truth (reference, geometry, domains, the shadowed reference) is
//! `airlight-truth`; the shapes the crates share (vocabulary, template contexts,
//! costs, figures, the gate record) are `airlight-shapes`. Everything here is f64
//! and follows `docs/MATH.md`; nothing here prints or exits; errors are values.

#![warn(missing_docs)]

pub mod analysis;
pub mod approx;
pub mod bench;
pub mod catalog;
pub mod coeffs;
pub mod family;
pub mod fitset;
pub mod lsq;
pub mod model;
pub mod roles;

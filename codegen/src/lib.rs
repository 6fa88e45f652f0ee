//! airlight-codegen: everything under `generated/` is rendered here, from tera
//! templates and data computed in Rust, and written (or checked) as one set of
//! outputs.
//!
//! Templates are compiled into the binary (`include_str!`), so the generator
//! works from any directory; each output names its template in its header.

#![warn(missing_docs)]

pub mod output;
pub mod report;

pub use output::{check, write_all, Difference, Output};

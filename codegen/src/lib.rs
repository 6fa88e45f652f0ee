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

use airlight_fit::selfcheck::SelfCheck;

/// Every file under `generated/`, rendered from the measurements. This list is
/// the generator's table of outputs: a file not in it is orphaned.
pub fn render_all(check: &SelfCheck) -> Result<Vec<Output>, tera::Error> {
    Ok(vec![report::render(check)?])
}

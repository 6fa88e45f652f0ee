//! What every part of the bench is given: its size, its inputs (the index, the
//! compiled kernels, the GPU), its progress callback and its error.

use crate::{Gpu, Ray, SpotRay};
use airlight_shapes::vocab::{Index, IndexEntry, Target};
use std::path::Path;

/// How much is measured.
#[derive(Debug, Clone, Copy)]
pub struct BenchSize {
    /// Points per `(g, domain)` for the errors.
    pub points: usize,
    /// Points (and rays) in the timing batch.
    pub batch: usize,
    /// Timing repeats.
    pub repeats: usize,
}

/// Why the bench could not run: bad input (exit 2), or a failure (exit 1).
#[derive(Debug)]
pub enum BenchError {
    /// A size of zero, a missing kernel or file entry.
    Input(String),
    /// A file that cannot be read, a GPU failure.
    Failed(String),
}

/// Where the bench is, for a progress display: what, done, of how many.
pub type Progress<'a> = dyn Fn(&str, usize, usize) + Sync + 'a;

/// Everything one model's row needs that the loop shares.
pub(crate) struct Inputs<'a> {
    pub(crate) generated: &'a Path,
    pub(crate) index: &'a Index,
    pub(crate) gpu: Option<&'a Gpu>,
    pub(crate) batch64: Vec<[f64; 4]>,
    /// The frame-coherent points at each `g` a model takes them at ([`frame_g`]),
    /// built once (empty without a GPU).
    pub(crate) frames: Vec<(f64, Vec<[f64; 4]>)>,
    pub(crate) rgb_scalar: Vec<Ray>,
    pub(crate) rgb_spots: Vec<SpotRay>,
    pub(crate) repeats: usize,
}

/// A model's WGSL kernel: its index entry and source.
pub(crate) fn wgsl_of<'i>(
    inputs: &Inputs<'i>,
    name: &str,
) -> Result<(&'i IndexEntry, std::path::PathBuf, String), BenchError> {
    let entry = inputs.index.get(name).map_err(BenchError::Input)?;
    let wgsl =
        entry.file(Target::Wgsl).ok_or_else(|| BenchError::Input(format!("kernel '{name}' has no WGSL file")))?;
    let path = inputs.generated.join(wgsl);
    let source = std::fs::read_to_string(&path)
        .map_err(|e| BenchError::Failed(format!("{}: cannot read: {e}", path.display())))?;
    Ok((entry, path, source))
}

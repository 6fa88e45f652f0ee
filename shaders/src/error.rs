//! What can go wrong on the GPU side, as one error type.

use std::fmt;

/// What went wrong on the GPU side.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GpuError {
    /// No adapter could be opened.
    NoAdapter(String),
    /// The adapter refused a device, or the device failed (out of memory, lost).
    Device(String),
    /// The shader did not compile or validate, or the pipeline failed.
    Shader(String),
    /// Reading results back failed.
    Readback(String),
    /// The batch does not fit one dispatch.
    TooLarge(usize),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter(e) => write!(f, "no GPU adapter: {e}"),
            GpuError::Device(e) => write!(f, "the GPU device failed: {e}"),
            GpuError::Shader(e) => write!(f, "shader error: {e}"),
            GpuError::Readback(e) => write!(f, "reading results back failed: {e}"),
            GpuError::TooLarge(n) => write!(f, "{n} points do not fit one dispatch"),
        }
    }
}

impl std::error::Error for GpuError {}

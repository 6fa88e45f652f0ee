//! Light shafts, in one room: what the GPU harness does with a kernel's shafts
//! accumulator (`harness`: wrap, pack, dispatch), the gate's shadowed cases and
//! rows (`cases`), the shafts bench (`bench`), and the headless render of a
//! shadowed scene (`render/`, its scene shader in `render/scene.wgsl`). The shadowed
//! reference and its occluders are `airlight-truth`'s `shafts`; the accumulator's
//! templates are `codegen/templates/kernels/shafts/`. docs/contributing.md, "Adding an
//! accumulator or a visibility source", lists every place a change touches.

pub mod bench;
pub mod cases;
mod harness;
mod mapped;
pub use mapped::{MapSpec, Mapped, PyramidTexture, WalkSources, WalkTexts, WALK_FILES};
pub mod map_bench;
pub mod map_cases;
pub mod render;

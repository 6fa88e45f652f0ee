//! airlight-shapes: the shapes every crate shares, typed once — the vocabulary
//! (targets, kernel arguments, domains by name, the kernel index), what a family's
//! templates are given, operation counts and the IR cost, figures as data, and the
//! two measured records the report quotes: the bench (`generated/bench.json`) and
//! the gate (`generated/gate.toml`).
//!
//! Its writers and readers (the fitter, the generator, the GPU harness, the CLI)
//! all depend on it; it depends only on `airlight-truth`.

#![warn(missing_docs)]

pub mod bench;
pub mod cost;
pub mod figure;
pub mod ircost;
pub mod record;
pub mod template;
pub mod vocab;

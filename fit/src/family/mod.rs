//! The approximation families of the paper, each with its own representation,
//! evaluation and least-squares fit. Models (see [`crate::approx`]) assemble them.

pub mod expsum;
pub mod phase_exp;
pub mod ratio;
pub mod segments;

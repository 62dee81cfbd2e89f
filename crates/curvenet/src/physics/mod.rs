//! Physical answers about a network in the physical mode: stresses in the equilibrium the rods
//! were bent into ([`stress`]).
//!
//! Every number is in the scene's consistent unit system (N, ℓ, s; see [`crate::units`]) until
//! it is reported: stresses in MPa, deflections in scene units, frequencies in hertz.

pub mod checks;
pub mod loads;
pub mod stress;

pub use stress::{CurveStress, StressAt, Stresses, assembly_stresses};

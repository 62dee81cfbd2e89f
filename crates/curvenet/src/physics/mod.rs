//! Physical answers about a network in the physical mode: the whole analysis of a structure
//! ([`analysis`]: frequencies, deflections, stresses, utilisation, warnings), the options as a
//! user writes them ([`options`]), the loads and metrics ([`loads`]), stresses in the
//! equilibrium the rods were bent into ([`stress`]), which modes are zero or negative
//! ([`inertia`]), the largest deviation from the design that `--max-deviation` bounds there
//! ([`deviation`]) and the warnings ([`checks`]).
//!
//! Every number is in the scene's consistent unit system (N, ℓ, s; see [`crate::units`]) until
//! it is reported: stresses in MPa, deflections in scene units, frequencies in hertz.

pub mod analysis;
pub mod cases;
pub mod checks;
pub mod deviation;
pub mod inertia;
pub mod loaded;
pub mod loads;
pub mod options;
pub mod stress;

pub use analysis::{
    PhysicalParams, PhysicalReport, PhysicalSummary, PhysicsError, analyze_physical,
};
pub use deviation::DeviationModel;
pub use options::PhysicalOptions;
pub use stress::{CurveStress, StressAt, Stresses, assembly_stresses};

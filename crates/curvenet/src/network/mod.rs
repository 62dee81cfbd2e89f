//! The rod network: curves resampled into rods that share vertices at their crossings
//! (`docs/model.md`, *Network construction*).
//!
//! - [`build`]: from input polylines to a [`Network`]: crossings, joints (`joints`),
//!   resampling and locking (`resample`);
//! - [`crossings`]: closest-approach crossing detection through a spatial grid;
//! - [`checks`]: input sanity checks (curves far from the mesh, mesh defects, curves that run
//!   together, tiny edges) whose findings are warnings, not errors;
//! - [`Network`]: the locked rest state every later stage works from (its type lives in
//!   [`crate::rod::network`], below the energy built from it).

pub mod build;
pub mod checks;
pub mod crossings;
mod joints;
mod resample;
pub mod subnet;

pub use build::{BuildInfo, BuildParams, build_network};

pub use crate::rod::network::{EdgeLengthStats, Joint, Network, Rod};

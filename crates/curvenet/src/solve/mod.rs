//! Numerical solvers: sparse Cholesky on a fixed pattern, Newton equilibrium, eigenpairs.
//!
//! - [`factor`]: symbolic analysis once per network, numeric factorization per matrix;
//! - [`newton`]: equilibrium of any structure (SPEC §4);

pub mod factor;
pub mod newton;

pub use factor::{Cholesky, NotPositiveDefinite, SymbolicFactor};
pub use newton::{NewtonInfo, NewtonParams, NewtonStop, relax};

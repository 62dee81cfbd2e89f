//! Numerical solvers: sparse Cholesky on a fixed pattern, Newton equilibrium, eigenpairs.
//!
//! - [`factor`]: symbolic analysis once per network, numeric factorization per matrix;
//! - `supernodal`: the numeric factorization, independent subtrees of the elimination tree in
//!   parallel;
//! - [`newton`]: equilibrium of any structure (SPEC §4);
//! - [`ordering`]: fill-reducing orderings (AMD, nested dissection with METIS);
//! - [`lanczos`]: thick-restart block Lanczos for the largest eigenpairs of an operator;
//! - [`eigen`]: shift-and-invert driver giving the smallest eigenpairs of a Hessian (SPEC §5).

pub mod eigen;
pub mod factor;
pub mod lanczos;
pub mod newton;
pub mod ordering;
mod supernodal;

pub use eigen::{
    EigenError, EigenParams, Spectrum, smallest_eigenpairs, smallest_eigenpairs_factored,
};
pub use factor::{Cholesky, NotPositiveDefinite, Reuse, SymbolicFactor};
pub use newton::{NewtonInfo, NewtonParams, NewtonStop, relax, relax_assembled};

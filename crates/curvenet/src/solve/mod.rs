//! Numerical solvers: sparse Cholesky on a fixed pattern, Newton equilibrium, eigenpairs.
//!
//! - [`factor`]: symbolic analysis once per network, numeric factorization per matrix, on a
//!   [`Backend`] chosen per analysis;
//! - `supernodal`: the numeric factorization and substitutions with independent subtrees of
//!   the elimination tree in parallel;
//! - [`newton`]: the equilibrium of any structure (`docs/model.md`, *Equilibrium*);
//! - [`pcg`]: conjugate gradients preconditioned by a nearby matrix's factor (Newton's steps
//!   near an equilibrium);
//! - [`ordering`]: fill-reducing orderings (AMD, nested dissection with METIS);
//! - [`lanczos`]: thick-restart block Lanczos for the largest eigenpairs of an operator;
//! - [`eigen`]: the shift-and-invert driver giving the smallest eigenpairs of a Hessian
//!   (`docs/model.md`, *Stability*);
//! - [`tuning`]: the solvers' speed knobs, apart from the parameters that define a result.

pub mod eigen;
pub mod factor;
pub mod lanczos;
pub mod newton;
pub mod ordering;
pub mod pcg;
mod supernodal;
pub mod tuning;

pub use eigen::{
    Eigen, EigenError, EigenOptions, EigenParams, MAX_EIGEN_COUNT, Shift, Spectrum, Start,
    smallest_eigenpairs,
};
pub use factor::{Backend, Cholesky, NotPositiveDefinite, Reuse, Schedule, SymbolicFactor};
pub use newton::{Equilibrium, NewtonInfo, NewtonParams, NewtonStop, NewtonSummary, Relaxed};
pub use tuning::SolverTuning;

//! Worst-case stability of a network or of any set of its curves: the one facade every search
//! asks (`docs/model.md`, *Stability*).
//!
//! An [`Analyzer`] owns one network's energy model, its symbolic factorization and a cache of
//! evaluated sets. The searches (`simplify`: greedy, local, exhaustive, random, exact,
//! certificate) ask it for numbers and never see a factorization, a symbolic analysis, a
//! sparsity pattern or a local Hessian; what they decide (which set next, which candidate to
//! bound or score, what to prune, who wins) is theirs.
//!
//! # What it offers
//!
//! | question | entry point | for |
//! |---|---|---|
//! | `λ_eq` of a structure, with its mode's curves and gravity deflection | [`Analyzer::analyze`] | reports |
//! | `λ_eq` of a structure, warm-started, to a preset's accuracy | [`Analyzer::evaluate`] ([`Warm`], [`Preset`], [`Prepare`]) | the greedy's iterations |
//! | `λ_eq` of any set, relaxed from the drawn state, by connected parts, cached (with each part's largest displacement) | [`Analyzer::lambda_eq`], [`Analyzer::lambda_eq_parts`], [`Analyzer::parts_of`], [`Analyzer::deviation`] | local, exhaustive, random searches |
//! | `λ_eq` of a structure one edit away from one analysed, warm-started from its equilibrium and modes | [`Analyzer::analyze_edit`] ([`EditStart`], [`Edit`], [`EditFrom`]) | the interactive server |
//! | the equilibrium alone; the spectrum at given displacements (`λ_fix`) | [`Analyzer::relax`], [`Analyzer::spectrum`] | tests, the certificate's start |
//! | bounds, scores and inertia tests of one structure's candidate removals | [`candidates::Candidates`] ([`candidates::Test`], [`candidates::Outcome`], [`candidates::Carried`]) | the greedy's candidate search |
//! | `λ_fix` of any set at the full network's equilibrium; certified bounds on nodes of subsets; the relaxation of a node | [`fixed::FixedProblem`] ([`fixed::Node`], [`fixed::Rayleigh`]) | the certificate, the exact search |
//! | the network's curves: count, lengths, connected parts, sets | [`Analyzer::curve_count`], [`Analyzer::lengths`], [`Analyzer::components`], [`Analyzer::set`] | every search |
//!
//! Parameters: [`StabilityParams`] (material, Newton, eigen solver, gravity) with the
//! speed-only [`Tuning`] apart (benchmarks switch its techniques off by name: [`Technique`]);
//! the eigen solver's accuracy per use is one of the named [`Preset`]s. The set type is
//! [`ActiveSet`]; the searches' budget is [`Budget`].
//!
//! Every answer is deterministic: parallel work is split in fixed groups, and which
//! factorization or starting vector a computation uses depends only on its inputs.
//!
//! # Where the next features go
//!
//! - **Constraints every search honours** (groups of curves removed together, symmetry,
//!   connectivity): they decide which sets are feasible, which is the searches' business
//!   (`simplify`). The facade evaluates any set it is given; a candidate removal is one curve
//!   today ([`candidates::Candidates::test`] takes a curve id), and a group removed together
//!   is the same computation on the group's curves (its loose vertices, its terms), so a group
//!   candidate belongs in [`candidates`], keyed by the group.
//! - **Another objective** (the first natural frequency `μ_min` of `H v = μ M v` with a
//!   diagonal lumped mass): every spectrum is computed through a [`Preset`] on a Hessian the
//!   facade assembles; the mass scaling `M^{-1/2} H M^{-1/2}` (as the relaxation already
//!   scales by `P(α)` in [`fixed`]) goes where the facade assembles, and the searches keep
//!   asking for "the objective of this set".

mod analysis;
mod analyzer;
pub mod candidates;
mod edit;
mod evaluate;
pub mod fixed;
mod numerics;
mod params;
mod presets;
mod subsets;
#[cfg(test)]
mod test_support;

pub use analysis::{Analysis, CurveShare, GravityDeflection};
pub use analyzer::Analyzer;
pub use edit::{Edit, EditFrom, EditStart};
pub use evaluate::{Evaluation, Prepare, Warm, Work};
pub use params::{Budget, GravityParams, Objective, StabilityParams, Technique, Tuning};
pub use presets::{EDIT_PAIRS, Preset, SCORE_TOL, SPECTRUM_TOL, SPECTRUM_TRAILING_TOL};
pub use subsets::Part;

pub use crate::rod::ActiveSet;
pub use crate::solve::eigen::{EigenParams, Spectrum};
pub use crate::solve::{NewtonInfo, NewtonSummary};

/// Why a stability computation failed.
#[derive(Debug, thiserror::Error)]
pub enum StabilityError {
    /// Eigen solver failure.
    #[error(transparent)]
    Eigen(#[from] crate::solve::eigen::EigenError),
    /// The structure has no curves.
    #[error("the structure has no curves")]
    Empty,
    /// Invalid parameters or inputs.
    #[error("{0}")]
    Params(crate::words::Message),
    /// The computation was cancelled ([`crate::cancel::Cancel`]).
    #[error("cancelled")]
    Cancelled,
}

impl From<crate::cancel::Cancelled> for StabilityError {
    fn from(_: crate::cancel::Cancelled) -> Self {
        StabilityError::Cancelled
    }
}

//! The solvers' speed knobs: settings that change how the work is done, never what is
//! computed (the same equilibrium and spectrum, up to the round-off of another path).
//!
//! They are kept apart from the parameters that define a result ([`super::NewtonParams`],
//! [`super::EigenParams`]). Each default was measured (`docs/benchmarks.md`); a benchmark
//! switches a technique off by setting its knob to the value named in its documentation.

use super::factor::Backend;
use crate::words::Message;
use serde::{Deserialize, Serialize};

/// Speed knobs of the factorizations and of Newton's method.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SolverTuning {
    /// The numeric factorization and substitution ([`Backend`]): chosen per symbolic
    /// analysis, so every factor of that analysis uses it.
    pub backend: Backend,
    /// Below this gradient (relative to the convergence scale, see [`super::newton`]) Newton is
    /// in its quadratic phase, and a step after one that cut `‖∇E‖` sixteenfold (fourfold for
    /// such a step) reuses the last factorization ("chord" step, judged by the same line
    /// search as any step). The Hessian has then moved by the last step's length only, so the
    /// old factor shrinks the residual nearly as much as a fresh one, and near the round-off
    /// floor a fresh factorization would be spent on the step that finds the floor. Along a
    /// soft mode full steps do not cut `‖∇E‖` that much, and an old factor's steps wander. 0
    /// factors afresh for every step.
    pub chord_below: f64,
    /// Within this factor of the tolerance, one iteration that neither halves `‖∇E‖` nor moves
    /// the energy beyond round-off ends the solve at the round-off floor (quadratic
    /// convergence would have passed the tolerance); farther away it takes
    /// [`super::NewtonParams::stall_iterations`] of them. 1 always waits for those.
    pub floor_near: f64,
    /// Near a saddle (the Hessian indefinite, the step from the projected Hessian) a full step
    /// that lowers the energy is doubled up to this many times while the energy keeps
    /// falling: the projected model's curvature along the escape direction is far above the
    /// true, negative one, so its steps creep away from the saddle. 0 never extends a step;
    /// steps from the exact Hessian never are.
    pub escape_doublings: usize,
    /// Factors storing more values than this split each substitution of a Krylov step (a
    /// chain of one-column solves that leaves the other cores idle) across the cores
    /// ([`super::Schedule::Subtrees`], bit-identical to one sequential substitution). Beyond the
    /// caches a substitution is bound by one core's memory bandwidth, and the split adds the
    /// other cores'; within them it gains little on an idle machine and waits on the cores
    /// when they are busy. A function of the structure's size only; `usize::MAX` never splits.
    pub split_solves_above: usize,
}

impl Default for SolverTuning {
    fn default() -> Self {
        SolverTuning {
            backend: Backend::default(),
            chord_below: 1e-6,
            floor_near: 100.0,
            escape_doublings: 30,
            split_solves_above: 4_000_000,
        }
    }
}

impl SolverTuning {
    /// Checks the knobs.
    pub fn validate(&self) -> Result<(), Message> {
        if !(self.chord_below >= 0.0 && self.chord_below < 1.0) {
            return Err(format!(
                "Newton's chord_below must lie in [0, 1), got {}",
                self.chord_below
            )
            .into());
        }
        if !(self.floor_near >= 1.0 && self.floor_near.is_finite()) {
            return Err(format!(
                "Newton's floor_near must be a finite factor of at least 1, got {}",
                self.floor_near
            )
            .into());
        }
        Ok(())
    }
}

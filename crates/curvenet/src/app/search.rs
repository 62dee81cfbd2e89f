//! [`Search`]: what a search starts from — a budget, a keep list and design constraints on a
//! network, turned into the greedy's parameters and the constraints bound to them — once for
//! a run ([`super::execute`]) and for the server's greedy and local search alike.

use super::observer::Observer;
use crate::app::AppError;
use crate::constraints::{ConstraintError, ConstraintParams, Constraints};
use crate::io::TriMesh;
use crate::network::Network;
use crate::simplify::local::LocalParams;
use crate::simplify::{Budget, GreedyParams};

/// A search's parameters, checked and bound to its network.
#[derive(Debug)]
pub struct Search {
    /// The greedy's parameters (budget, keep list).
    pub greedy: GreedyParams,
    /// The design constraints bound to the network, the budget and the keep list
    /// ([`Constraints::none`] when none is in force: every search treats both alike).
    pub constraints: Constraints,
    /// The constraint settings in force (a front end's own defaults left out where nothing
    /// can meet them).
    pub settings: ConstraintParams,
    /// The budget as a length (scene units).
    pub budget_length: f64,
}

impl Search {
    /// The search of `budget` and `keep` on `network` under `constraints` (the surface `mesh`
    /// measures the largest gap; in the physical mode, `unit` the scene's length unit, the
    /// largest deviation is the physical model's): the greedy's parameters checked, the
    /// constraints bound, and what binding them found told to `observer` as notes. Constraints nothing within the
    /// budget can meet are a usage error saying why; when they are a front end's own
    /// `defaults`, they are left out instead, with a note. Without constraints a budget
    /// nothing meets is no error: the greedy runs as ever.
    pub fn new(
        network: &Network,
        mesh: Option<&TriMesh>,
        budget: Budget,
        keep: Vec<usize>,
        mut constraints: ConstraintParams,
        defaults: bool,
        unit: Option<&str>,
        observer: &dyn Observer,
    ) -> Result<Search, AppError> {
        let n = network.rods.len();
        let greedy = GreedyParams {
            keep,
            ..GreedyParams::new(budget)
        };
        greedy.validate(n).map_err(AppError::Usage)?;
        let total = network.total_length(&(0..n).collect::<Vec<_>>());
        let budget_length = budget.length(total);
        let keep = &greedy.keep;
        let mut bound = if constraints.is_default() {
            Constraints::none(network, budget_length, keep)
        } else {
            match Constraints::new(network, mesh, &constraints, budget_length, keep) {
                Ok(c) => c,
                Err(e) if defaults => {
                    observer.note(&e.message().prefixed([
                        "the default constraints are left out on this network: ".into(),
                    ]));
                    constraints = ConstraintParams::default();
                    Constraints::none(network, budget_length, keep)
                }
                Err(ConstraintError::Usage(m)) => return Err(AppError::Usage(m)),
                Err(ConstraintError::Infeasible(m)) => {
                    return Err(AppError::Usage(
                        m.prefixed(["the constraints cannot be met: ".into()]),
                    ));
                }
            }
        };
        if let Some(u) = unit {
            bound.deviation_measured_physically(u);
        }
        for note in bound.notes() {
            observer.note(note);
        }
        Ok(Search {
            greedy,
            constraints: bound,
            settings: constraints,
            budget_length,
        })
    }

    /// The local search's parameters: the same budget and keep list, its default moves
    /// (descent with part steps, then variable-depth chains).
    pub fn local(&self) -> LocalParams {
        LocalParams {
            keep: self.greedy.keep.clone(),
            ..LocalParams::new(self.greedy.budget)
        }
    }
}

//! `curvenet simplify`: the greedy on a user's own mesh and curves.

use super::greedy_run::{GreedyJob, run_greedy};
use super::{check_curve_ids, load_setup};
use crate::args::SimplifyArgs;

pub fn run(a: SimplifyArgs) -> anyhow::Result<()> {
    let (inputs, physical, params) = load_setup(&a.input, &a.physics, &a.physical, a.objective)?;
    check_curve_ids("--keep", &a.greedy.keep, inputs.curves.len())?;
    let constraints = super::constraint_params(&a.greedy.constraints, inputs.groups)?;
    run_greedy(GreedyJob {
        curves: inputs.curves,
        build: inputs.build,
        stability: params,
        physical_options: physical
            .is_some()
            .then(|| super::physical_options(&a.physics, &a.physical)),
        physical,
        input: inputs.description,
        budget: super::greedy_run::budget_of(&a.greedy, None)?,
        keep: a.greedy.keep.clone(),
        out: a.out.clone(),
        certificate: a.greedy.after.certify,
        certificate_nodes: a.greedy.after.certificate_nodes,
        local_search: a.greedy.after.local_search || a.greedy.after.alternatives > 0,
        alternatives: a.greedy.after.alternatives,
        resume: a.greedy.resume,
        force: a.greedy.force,
        mesh: inputs.mesh,
        constraints,
        default_constraints: false,
    })
}

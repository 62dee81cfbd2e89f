//! `curvenet simplify`: the greedy on a user's own mesh and curves.

use super::greedy_run::{GreedyJob, run_greedy};
use super::{load_inputs, physical_mode, print_warnings, stability_params};
use crate::args::SimplifyArgs;

pub fn run(a: SimplifyArgs) -> anyhow::Result<()> {
    let inputs = load_inputs(&a.input, &a.physics)?;
    print_warnings(&inputs.warnings);
    let (physical, paper) = physical_mode(
        &a.physics,
        &a.physical,
        inputs.file_units.as_deref(),
        &inputs.specs,
    )?;
    let mut params = stability_params(&paper)?;
    params.objective = a.objective;
    let n = inputs.curves.len();
    if let Some(&bad) = a.greedy.keep.iter().find(|&&c| c >= n) {
        return Err(crate::exit::usage(format!(
            "--keep names curve {bad}, but the input has {n} curves (ids 0..{})",
            n.saturating_sub(1)
        )));
    }
    let constraints = super::constraint_params(&a.greedy.constraints, inputs.groups)?;
    run_greedy(GreedyJob {
        curves: inputs.curves,
        build: inputs.build,
        stability: params,
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

//! `curvenet simplify`: the greedy on a user's own mesh and curves.

use crate::args::SimplifyArgs;
use curvenet::simplify::Budget;

pub fn run(a: SimplifyArgs) -> anyhow::Result<()> {
    let input = super::input_spec(&a.input, &a.physics);
    let mut setup = super::setup(&input, &super::model_options(&a.physics, &a.physical))?;
    let g = &a.greedy;
    let budget = g
        .budget
        .map(Budget::Fraction)
        .or(g.budget_length.map(Budget::Length));
    let spec = super::run_spec(
        a.out.clone(),
        budget,
        Some(g.keep.clone()),
        &g.constraints,
        &g.after,
        (g.resume, g.force),
    );
    super::execute(&mut setup, &spec)
}

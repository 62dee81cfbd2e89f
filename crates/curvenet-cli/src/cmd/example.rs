//! `curvenet example NAME`: the paper's examples with their reference set-ups.

use crate::args::ExampleArgs;
use curvenet::simplify::Budget;
use std::path::PathBuf;
use std::time::Instant;

pub fn run(a: ExampleArgs) -> anyhow::Result<()> {
    let Some(name) = a.name.clone() else {
        print!(
            "The paper's example data embedded in curvenet (the meshes and curves published \
             with the implementation of \"Stability-Aware Simplification of Curve Networks\", \
             SIGGRAPH 2022) is distributed under this licence:\n\n{}",
            curvenet::paper::data::LICENSE
        );
        return Ok(());
    };
    let start = Instant::now();
    let input = super::example_spec(&name, a.data.as_deref(), &a.physics);
    let mut setup = super::setup(&input, &super::model_options(&a.physics, &a.physical))?;
    if a.analyze_only {
        let ex = setup.inputs.example.as_ref().expect("an example");
        let header = format!(
            "example {} (paper: {} curves, {} vertices)",
            ex.name, ex.paper.curves_in, ex.paper.vertices
        );
        return super::print_analysis(&mut setup, &[], a.json, Some(header), start);
    }
    let spec = super::run_spec(
        a.out
            .clone()
            .unwrap_or_else(|| PathBuf::from("out").join(&name)),
        a.budget.map(Budget::Fraction),
        None,
        &a.constraints,
        &a.after,
        (a.resume, a.force),
    );
    super::execute(&mut setup, &spec)
}

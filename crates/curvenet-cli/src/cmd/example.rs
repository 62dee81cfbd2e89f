//! `curvenet example NAME`: the paper's examples with their reference set-ups.

use crate::args::ExampleArgs;
use crate::front::fail;
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
        let out = curvenet::app::analyze(&mut setup, &[], &crate::front::Flags).map_err(fail)?;
        let shown = setup.inputs.warnings.len();
        super::print_warnings(out.report.warnings.get(shown..).unwrap_or_default());
        if let Some(p) = &out.physical {
            crate::front::print_messages(&p.warnings);
        }
        if a.json {
            println!("{}", out.to_json());
        } else {
            let ex = setup.inputs.example.as_ref().expect("an example");
            println!(
                "example {} (paper: {} curves, {} vertices)",
                ex.name, ex.paper.curves_in, ex.paper.vertices
            );
            print!("{}", out.to_text());
            println!("time: {:.3} s", start.elapsed().as_secs_f64());
        }
        return Ok(());
    }
    let spec = curvenet::app::RunSpec {
        resume: a.resume,
        force: a.force,
        ..super::run_spec(
            a.out
                .clone()
                .unwrap_or_else(|| PathBuf::from("out").join(&name)),
            a.budget.map(Budget::Fraction),
            None,
            &a.constraints,
            &a.after,
        )
    };
    super::execute(&mut setup, &spec)
}

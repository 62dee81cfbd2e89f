//! `curvenet example NAME`: the paper's examples with their reference set-ups.

use super::{print_warnings, stability_params};
use crate::args::ExampleArgs;
use crate::exit::usage;
use curvenet::network::BuildParams;
use curvenet::{paper, pipeline};
use std::time::Instant;

pub fn run(a: ExampleArgs) -> anyhow::Result<()> {
    let data = match a.data.clone().or_else(paper::default_data_dir) {
        Some(d) => d,
        None => {
            return Err(usage(
                "no --data folder given and ../shared/reference-data not found; pass --data DIR",
            ));
        }
    };
    let start = Instant::now();
    let supports = a.physics.supports.unwrap_or_default();
    let ex = paper::load(&a.name, &data, supports)?;
    let params = stability_params(&a.physics)?;
    let build = BuildParams {
        merge_joints_below: a.physics.merge_joints,
        ..ex.build.clone()
    };
    let warnings: Vec<String> = ex.warnings.iter().map(|w| w.to_string()).collect();
    if !a.analyze_only {
        return Err(usage(
            "simplification is not available yet in this build; use --analyze-only",
        ));
    }
    let out = pipeline::analyze(&ex.curves, &build, &params, &[], warnings)?;
    print_warnings(&out.report.warnings);
    if a.json {
        println!("{}", serde_json::to_string(&out.report)?);
    } else {
        println!(
            "example {} (paper: {} curves, {} vertices)",
            ex.setup.name, ex.setup.paper.curves_in, ex.setup.paper.vertices
        );
        print!("{}", out.report.to_text());
        println!("time: {:.3} s", start.elapsed().as_secs_f64());
    }
    Ok(())
}

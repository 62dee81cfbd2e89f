//! `curvenet example NAME`: the paper's examples with their reference set-ups.

use super::greedy_run::{GreedyJob, run_greedy};
use super::{print_warnings, stability_params};
use crate::args::ExampleArgs;
use crate::exit::usage;
use curvenet::network::BuildParams;
use curvenet::run_folder::InputDescription;
use curvenet::simplify::Budget;
use curvenet::{paper, pipeline};
use std::path::PathBuf;
use std::time::Instant;

pub fn run(a: ExampleArgs) -> anyhow::Result<()> {
    let Some(name) = a.name.clone() else {
        print!(
            "The paper's example data embedded in curvenet (the meshes and curves published \
             with the implementation of \"Stability-Aware Simplification of Curve Networks\", \
             SIGGRAPH 2022) is distributed under this licence:\n\n{}",
            paper::data::LICENSE
        );
        return Ok(());
    };
    let data = super::data_source(a.data.as_deref())?;
    let start = Instant::now();
    let supports = a.physics.supports.unwrap_or_default();
    let ex = paper::load_from(&name, &data, supports)?;
    let (physical, paper) = super::physical_mode(&a.physics, &a.physical, None, &[])?;
    let mut params = stability_params(&paper)?;
    let build = BuildParams {
        merge_joints_below: a.physics.merge_joints,
        ..ex.build.clone()
    };
    let warnings: Vec<String> = ex.warnings.iter().map(|w| w.to_string()).collect();
    // What the searches maximise, and what --analyze-only reports.
    params.objective = a.objective;
    if a.analyze_only {
        let out = pipeline::analyze(
            &ex.curves,
            &build,
            &params,
            physical.as_ref(),
            &[],
            warnings,
        )?;
        print_warnings(&out.report.warnings);
        let physical = match &physical {
            Some(pp) => {
                let net = out.analyzer.network();
                let all = curvenet::rod::ActiveSet::all(net.rods.len());
                Some(super::analyze::physical_report(net, pp, &all)?)
            }
            None => None,
        };
        if a.json {
            println!(
                "{}",
                super::analyze::report_json(&out.report, physical.as_ref())?
            );
        } else {
            println!(
                "example {} (paper: {} curves, {} vertices)",
                ex.setup.name, ex.setup.paper.curves_in, ex.setup.paper.vertices
            );
            print!("{}", out.report.to_text());
            if let Some(r) = &physical {
                print!("{}", r.to_text());
            }
            println!("time: {:.3} s", start.elapsed().as_secs_f64());
        }
        return Ok(());
    }
    print_warnings(&warnings);
    let budget = Budget::Fraction(a.budget.unwrap_or(ex.setup.budget_fraction));
    budget.validate().map_err(usage)?;
    run_greedy(GreedyJob {
        curves: ex.curves,
        build,
        stability: params,
        physical_options: physical
            .is_some()
            .then(|| super::physical_options(&a.physics, &a.physical)),
        physical,
        input: InputDescription {
            example: Some(ex.setup.name.to_string()),
            mesh: Some(format!("meshes/{}", ex.setup.mesh)),
            curve_files: ex
                .setup
                .curves
                .iter()
                .map(|(f, _)| format!("curves/{f}"))
                .collect(),
            scale: ex.setup.mesh_scale,
        },
        budget,
        keep: ex.setup.keep.clone(),
        out: a
            .out
            .clone()
            .unwrap_or_else(|| PathBuf::from("out").join(&name)),
        certificate: a.after.certify,
        certificate_nodes: a.after.certificate_nodes,
        local_search: a.after.local_search || a.after.alternatives > 0,
        alternatives: a.after.alternatives,
        resume: a.resume,
        force: a.force,
        mesh: Some(ex.mesh),
        constraints: super::constraint_params(&a.constraints, Vec::new())?,
        default_constraints: false,
    })
}

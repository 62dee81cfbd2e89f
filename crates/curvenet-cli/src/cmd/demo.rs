//! `curvenet demo`: the whole pipeline on a built-in scene, no files needed.

use super::greedy_run::{GreedyJob, run_greedy};
use super::stability_params;
use crate::args::DemoArgs;
use crate::exit::usage;
use curvenet::builtin;
use curvenet::network::BuildParams;
use curvenet::simplify::Budget;
use curvenet::simplify::result::InputDescription;

pub fn run(a: DemoArgs) -> anyhow::Result<()> {
    let scene = builtin::scene(&a.scene).ok_or_else(|| {
        usage(format!(
            "unknown built-in scene '{}' (known: {})",
            a.scene,
            builtin::NAMES.join(", ")
        ))
    })?;
    let budget = Budget::Fraction(a.budget);
    budget.validate().map_err(usage)?;
    println!(
        "demo: {} built-in curves over the '{}' surface, budget {} of the total length",
        scene.curves.len(),
        scene.name,
        a.budget
    );
    run_greedy(GreedyJob {
        curves: scene.curves,
        build: BuildParams {
            edge_length: scene.edge_length,
            supports: a.physics.supports.unwrap_or_default(),
            merge_joints_below: a.physics.merge_joints,
            ..BuildParams::default()
        },
        stability: stability_params(&a.physics)?,
        input: InputDescription {
            example: Some(format!("builtin:{}", scene.name)),
            mesh: None,
            curve_files: Vec::new(),
            scale: 1.0,
        },
        budget,
        keep: Vec::new(),
        out: a.out,
        resume: false,
        prune: Default::default(),
        mesh: Some(scene.mesh),
    })
}

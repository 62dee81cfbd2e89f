//! `curvenet demo`: the whole pipeline with no input files: random geodesics traced on a
//! built-in surface (as the reference's command-line scenes: largest extent 4000, h = 100),
//! then the greedy to the budget, with every output a real run writes.

use super::greedy_run::{GreedyJob, run_greedy};
use super::stability_params;
use crate::args::DemoArgs;
use crate::exit::usage;
use curvenet::network::BuildParams;
use curvenet::run_folder::InputDescription;
use curvenet::simplify::Budget;
use curvenet::trace::{Generator, SURFACE_NAMES, builtin_surface, generate, scale_to_extent};

pub fn run(a: DemoArgs) -> anyhow::Result<()> {
    let surface = builtin_surface(&a.surface).ok_or_else(|| {
        usage(format!(
            "unknown built-in surface '{}' (known: {})",
            a.surface,
            SURFACE_NAMES.join(", ")
        ))
    })?;
    let budget = Budget::Fraction(a.budget);
    budget.validate().map_err(usage)?;
    let (mesh, _) = scale_to_extent(&surface, 4000.0);
    let traced = generate(
        &mesh,
        &Generator::Random {
            count: a.geodesics,
            seed: a.seed,
        },
    )
    .map_err(|e| usage(format!("builtin:{}: {e}", a.surface)))?;
    if traced.curves.is_empty() {
        return Err(usage(format!(
            "builtin:{}: no geodesic could be traced",
            a.surface
        )));
    }
    super::print_warnings(
        super::network_size_warning(&traced.curves, a.edge_length, true, 1.0).as_slice(),
    );
    println!(
        "demo: {} random geodesics (seed {}) on the built-in '{}' surface, budget {} of the total length",
        traced.curves.len(),
        a.seed,
        a.surface,
        a.budget
    );
    run_greedy(GreedyJob {
        curves: traced.curves,
        build: BuildParams {
            edge_length: a.edge_length,
            supports: a.physics.supports.unwrap_or_default(),
            merge_joints_below: a.physics.merge_joints,
            ..BuildParams::default()
        },
        stability: curvenet::stability::StabilityParams {
            objective: a.objective,
            ..stability_params(&a.physics)?
        },
        physical: None,
        physical_options: None,
        input: InputDescription {
            example: Some(format!("demo:{}:{}:{}", a.surface, a.geodesics, a.seed)),
            mesh: Some(format!("builtin:{}", a.surface)),
            curve_files: Vec::new(),
            scale: 1.0,
        },
        budget,
        keep: Vec::new(),
        out: a.out,
        certificate: a.after.certify,
        certificate_nodes: a.after.certificate_nodes,
        local_search: a.after.local_search || a.after.alternatives > 0,
        alternatives: a.after.alternatives,
        resume: false,
        force: a.force,
        mesh: Some(mesh),
        constraints: super::constraint_params(&a.constraints, Vec::new())?,
    })
}

//! `curvenet demo`: the whole pipeline with no input files: random geodesics traced on a
//! built-in surface (as the reference's command-line scenes: largest extent 4000, h = 100),
//! then the greedy to the budget, on the default dome under design constraints (the demo's
//! own, [`DEFAULT_GAP`] and one connected structure, unless the user gives any or
//! `--unconstrained`), with every output a real run writes.

use super::greedy_run::{GreedyJob, run_greedy};
use super::stability_params;
use crate::args::DemoArgs;
use crate::exit::usage;
use curvenet::network::BuildParams;
use curvenet::run_folder::InputDescription;
use curvenet::simplify::Budget;
use curvenet::trace::{Generator, SURFACE_NAMES, builtin_surface, generate, scale_to_extent};

/// The demo's default largest gap (scene units; the surfaces' largest extent is 4000): on the
/// default dome it makes the greedy keep a curve near every part of the surface (its
/// unconstrained answer leaves a gap of about 1450).
pub const DEFAULT_GAP: f64 = 900.0;

pub fn run(a: DemoArgs) -> anyhow::Result<()> {
    let given = a.constraints.groups.is_some()
        || a.constraints.symmetry.is_some()
        || a.constraints.connected
        || a.constraints.min_curves.is_some()
        || a.constraints.max_gap.is_some()
        || a.constraints.max_deviation.is_some();
    // On the dome, the default surface: elsewhere the gap and connectivity they ask can leave
    // the greedy no network to end on (tent, stadium), so the demo there runs unconstrained.
    let defaults = !given && !a.unconstrained && a.surface == "dome";
    let mut constraints = super::constraint_params(&a.constraints, Vec::new())?;
    if defaults {
        constraints.connected = true;
        constraints.max_gap = Some(DEFAULT_GAP);
    }
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
    if defaults {
        println!(
            "design constraints (the demo's defaults; --unconstrained leaves them out): one \
             connected structure (--connected) and no point of the surface farther than \
             {DEFAULT_GAP} from a kept curve (--max-gap {DEFAULT_GAP})"
        );
    }
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
        constraints,
        default_constraints: defaults,
    })
}

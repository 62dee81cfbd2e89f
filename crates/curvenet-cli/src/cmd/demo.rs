//! `curvenet demo`: the whole pipeline with no input files: random geodesics traced on a
//! built-in surface (as the reference's command-line scenes: largest extent 4000, h = 100),
//! then the greedy to the budget, on the default dome under design constraints (the demo's
//! own, [`DEFAULT_GAP`] and one connected structure, unless the user gives any or
//! `--unconstrained`), with every output a real run writes.

use crate::args::DemoArgs;
use curvenet::app::{CurveSource, InputSpec};
use curvenet::simplify::Budget;

/// The demo's default largest gap (scene units; the surfaces' largest extent is 4000): on the
/// default dome it makes the greedy keep a curve near every part of the surface (its
/// unconstrained answer leaves a gap of about 1450).
pub const DEFAULT_GAP: f64 = 900.0;

pub fn run(a: DemoArgs) -> anyhow::Result<()> {
    let c = &a.constraints;
    let given = c.groups.is_some()
        || c.symmetry.is_some()
        || c.connected
        || c.min_curves.is_some()
        || c.max_gap.is_some()
        || c.max_deviation.is_some();
    // On the dome, the default surface: elsewhere the gap and connectivity they ask can leave
    // the greedy no network to end on (tent, stadium), so the demo there runs unconstrained.
    let defaults = !given && !a.unconstrained && a.surface == "dome";
    let geodesics = CurveSource::geodesics(&a.surface, a.geodesics, a.seed);
    let input = InputSpec {
        edge_length: Some(a.edge_length),
        ..super::curves_spec(geodesics, &a.physics)
    };
    let model = super::model_options(&a.physics, &Default::default());
    let mut setup = super::setup(&input, &model)?;
    println!(
        "demo: {} random geodesics (seed {}) on the built-in '{}' surface, budget {} of the total length",
        setup.curve_count(),
        a.seed,
        a.surface,
        a.budget
    );
    let budget = Some(Budget::Fraction(a.budget));
    let mut spec = super::run_spec(a.out.clone(), budget, None, c, &a.after, (false, a.force));
    if defaults {
        spec.default_constraints = true;
        spec.constraints.connected = true;
        spec.constraints.max_gap = Some(DEFAULT_GAP);
        println!(
            "design constraints (the demo's defaults; --unconstrained leaves them out): one \
             connected structure (--connected) and no point of the surface farther than \
             {DEFAULT_GAP} from a kept curve (--max-gap {DEFAULT_GAP})"
        );
    }
    super::execute(&mut setup, &spec)
}

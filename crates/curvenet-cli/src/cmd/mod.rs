//! One module per subcommand, plus the option handling they share.

mod analyze;
pub(crate) mod bench;
mod compare;
mod demo;
mod example;
mod export;
#[cfg(feature = "serve")]
mod serve;
mod simplify;
mod slide;
mod trace;
mod view;

use crate::args::{
    AfterGreedyArgs, Cli, Command, ConstraintArgs, InputArgs, PhysicalModeArgs, PhysicsArgs,
};
use crate::exit::usage;
pub use crate::front::print_warnings;
use crate::front::{Console, fail, say};
use crate::signals;
use curvenet::app::{self, CurveSource, InputSpec, MeshSource, ModelOptions, RunSpec, Setup};
use curvenet::constraints::ConstraintParams;
use curvenet::physics::PhysicalOptions;
use curvenet::simplify::Budget;
use std::path::PathBuf;

/// Runs the parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Analyze(a) => analyze::run(a),
        Command::Simplify(a) => simplify::run(a),
        Command::Example(a) => example::run(a),
        Command::Demo(a) => demo::run(a),
        Command::Trace(a) => trace::run(a),
        Command::Compare(a) => compare::run(a),
        Command::View(a) => view::run(a),
        Command::Export(a) => export::run(a),
        Command::Slide(a) => slide::run(a),
        Command::Bench(a) => bench::run(a),
        #[cfg(feature = "serve")]
        Command::Serve(a) => serve::run(a),
    }
}

/// Opens `what` (a URL or a file) in the default browser without waiting for it; a failure
/// is a warning saying what to open by hand.
pub fn open_in_browser(what: &str) {
    if let Err(e) = open::that_detached(what) {
        eprintln!("warning: could not open a browser ({e}); open {what} in one");
    }
}

/// The inputs of the options.
pub fn input_spec(input: &InputArgs, physics: &PhysicsArgs) -> InputSpec {
    InputSpec {
        mesh: input.mesh.clone().map(MeshSource::Path),
        scale: input.scale,
        edge_length: input.edge_length,
        ..curves_spec(CurveSource::Files(input.curves.clone()), physics)
    }
}

/// The inputs of `curves` with the options' supports and joint merging.
pub fn curves_spec(curves: CurveSource, physics: &PhysicsArgs) -> InputSpec {
    InputSpec {
        supports: physics.supports,
        supports_file: physics.supports_file.clone(),
        merge_joints: physics.merge_joints,
        ..InputSpec::new(curves)
    }
}

/// The paper's example `name` (from `data`, else the embedded copies) with the options'
/// supports and joint merging.
pub fn example_spec(name: &str, data: Option<&std::path::Path>, p: &PhysicsArgs) -> InputSpec {
    let (name, data) = (name.into(), data.map(|d| d.to_path_buf()));
    curves_spec(CurveSource::Example { name, data }, p)
}

/// The model of the options.
pub fn model_options(physics: &PhysicsArgs, p: &PhysicalModeArgs) -> ModelOptions {
    ModelOptions {
        radius: physics.radius,
        young: physics.young.clone(),
        anchor_weight: physics.anchor_weight,
        eigen_count: physics.eigen_count,
        objective: physics.objective,
        physical: PhysicalOptions {
            units: p.units.clone(),
            material: p.material.clone(),
            density: p.density.clone(),
            strength: p.strength.clone(),
            tube: p.tube.clone(),
            load: p.load.clone(),
            gravity: p.gravity.clone(),
            loads: p.loads.as_ref().map(|f| f.display().to_string()),
            deflection_limit: p.deflection_limit.clone(),
            buckling_factor: p.buckling_factor.clone(),
            ..PhysicalOptions::default()
        },
    }
}

/// The set-up of `input` and `model`, the inputs' warnings printed.
pub fn setup(input: &InputSpec, model: &ModelOptions) -> anyhow::Result<Setup> {
    let setup = Setup::new(input, model).map_err(fail)?;
    for w in &setup.inputs.warnings {
        print_warnings(&[say(w)]);
    }
    Ok(setup)
}

/// Analyses `setup` without `remove` and prints the outcome: the warnings the inputs' did not
/// already show, then one JSON line (`json`) or the text, after `header`, with the time since
/// `start`.
pub fn print_analysis(
    setup: &mut Setup,
    remove: &[usize],
    json: bool,
    header: Option<String>,
    start: std::time::Instant,
) -> anyhow::Result<()> {
    // The input's warnings were printed before the (possibly long) analysis; it adds its own.
    let shown = setup.inputs.warnings.len();
    let out = app::analyze(setup, remove, &crate::front::Flags).map_err(fail)?;
    print_warnings(out.report.warnings.get(shown..).unwrap_or_default());
    if let Some(p) = &out.physical {
        crate::front::print_messages(&p.warnings);
    }
    if json {
        println!("{}", out.to_json());
    } else {
        header.iter().for_each(|h| println!("{h}"));
        print!("{}", out.to_text());
        println!("time: {:.3} s", start.elapsed().as_secs_f64());
    }
    Ok(())
}

/// The run of the options: folder, budget, keep list, constraints, steps after the greedy,
/// and whether it resumes and may run into a foreign folder.
pub fn run_spec(
    out: PathBuf,
    budget: Option<Budget>,
    keep: Option<Vec<usize>>,
    c: &ConstraintArgs,
    after: &AfterGreedyArgs,
    (resume, force): (bool, bool),
) -> RunSpec {
    RunSpec {
        resume,
        force,
        budget,
        keep,
        constraints: ConstraintParams {
            symmetry: c.symmetry.unwrap_or_default(),
            connected: c.connected,
            min_curves: c.min_curves,
            max_gap: c.max_gap,
            max_deviation: c.max_deviation,
            ..ConstraintParams::default()
        },
        groups_file: c.groups.clone(),
        local_search: after.local_search,
        alternatives: after.alternatives,
        certify: after.certify,
        certificate_nodes: after.certificate_nodes,
        slide: after.slide.then(|| slide::spec(&out, &out, &after.sliding)),
        ..RunSpec::new(out)
    }
}

/// Runs `spec` on `setup` with the console's progress and the signals' token, and prints
/// the summary.
pub fn execute(setup: &mut Setup, spec: &RunSpec) -> anyhow::Result<()> {
    let console = Console::new();
    let outcome = app::execute(setup, spec, &console, &signals::token()).map_err(fail)?;
    if outcome.already_complete {
        eprintln!("{}: the run is already complete", outcome.folder.display());
    }
    print!("{}", app::run_summary(&outcome));
    Ok(())
}

/// A length with seven significant digits (`curvenet::fmt::length`).
pub use curvenet::fmt::length as fmt_length;

/// The mesh `arg` names (an OBJ file or a built-in surface) and its name (the path or
/// `builtin:NAME`), its reading warnings printed.
pub fn mesh_arg(arg: &std::path::Path) -> anyhow::Result<(curvenet::io::TriMesh, String)> {
    let (mesh, name, warnings) =
        app::inputs::read_mesh(&MeshSource::Path(arg.to_path_buf())).map_err(fail)?;
    print_warnings(&warnings);
    Ok((mesh, name))
}

/// Takes the shared lock of the run folder `dir` for `command` (`view`, `export`), which write
/// into it beside other such commands: refused while a run is writing there.
pub fn hold_run_folder(
    dir: &std::path::Path,
    command: &str,
) -> anyhow::Result<Option<curvenet::run_folder::folder::FolderLock>> {
    curvenet::run_folder::folder::FolderLock::hold_shared(dir).map_err(|_| {
        usage(format!(
            "{}: a curvenet run is writing in this folder; wait for it to end before `curvenet \
             {command}`",
            dir.display()
        ))
    })
}

/// Checks, before any work, that `path` (the value of `option`) can be written.
pub fn writable_file(option: &str, path: &std::path::Path) -> anyhow::Result<()> {
    curvenet::io::check_writable(path).map_err(|e| usage(format!("{option} {e}")))
}

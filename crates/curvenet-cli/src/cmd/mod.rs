//! One module per subcommand, plus the option handling they share.

mod analyze;
mod bench;
mod compare;
mod demo;
mod example;
mod greedy_run;
mod simplify;
mod surface;
mod trace;

use crate::args::{Cli, Command, InputArgs, PhysicsArgs};
use crate::exit::usage;
use curvenet::io::{self, Polyline};
use curvenet::network::BuildParams;
use curvenet::pipeline;
use curvenet::rod::Material;
use curvenet::simplify::result::InputDescription;
use curvenet::stability::StabilityParams;

/// Runs the parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Analyze(a) => analyze::run(a),
        Command::Simplify(a) => simplify::run(a),
        Command::Example(a) => example::run(a),
        Command::Demo(a) => demo::run(a),
        Command::Trace(a) => trace::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Bench(a) => bench::run(a),
    }
}

/// Stability parameters from the shared options (defaults where unset).
pub fn stability_params(p: &PhysicsArgs) -> anyhow::Result<StabilityParams> {
    let mut s = StabilityParams::default();
    let d = Material::default();
    s.material = Material {
        radius: p.radius.unwrap_or(d.radius),
        young: p.young.unwrap_or(d.young),
        anchor_weight: p.anchor_weight.unwrap_or(d.anchor_weight),
    };
    s.eigen.count = p.eigen_count;
    s.eigen.max_basis = s
        .eigen
        .max_basis
        .max(p.eigen_count + 4 * s.eigen.block_size);
    s.validate().map_err(usage)?;
    Ok(s)
}

/// Curves and build parameters from the input options.
pub struct Inputs {
    /// Scaled curves in id order.
    pub curves: Vec<Polyline>,
    /// Network construction.
    pub build: BuildParams,
    /// Reading warnings.
    pub warnings: Vec<String>,
    /// What was read.
    pub description: InputDescription,
    /// The mesh, scaled, if one was given.
    pub mesh: Option<curvenet::io::TriMesh>,
}

/// Reads and scales the inputs.
pub fn load_inputs(a: &InputArgs, p: &PhysicsArgs) -> anyhow::Result<Inputs> {
    if !(a.scale.is_finite() && a.scale > 0.0) {
        return Err(usage(format!(
            "--scale must be a positive number, got {}",
            a.scale
        )));
    }
    let mut warnings = Vec::new();
    let mut mesh = None;
    if let Some(m) = &a.mesh {
        let file = surface::read_mesh_arg(m)?;
        warnings.extend(file.warnings);
        let mut tri = file.mesh;
        for v in &mut tri.vertices {
            *v = *v * a.scale;
        }
        mesh = Some(tri);
    }
    let mut curves = Vec::new();
    for path in &a.curves {
        let f = io::read_curves(path)?;
        warnings.extend(f.warnings.iter().map(|w| w.to_string()));
        curves.extend(f.curves);
    }
    pipeline::scale_curves(&mut curves, a.scale);
    let h = a
        .edge_length
        .unwrap_or_else(|| pipeline::median_segment_length(&curves));
    let build = BuildParams {
        edge_length: h,
        supports: p.supports.unwrap_or_default(),
        merge_joints_below: p.merge_joints,
        ..BuildParams::default()
    };
    build.validate().map_err(|e| usage(e.to_string()))?;
    let description = InputDescription {
        example: None,
        mesh: a.mesh.as_ref().map(|m| m.display().to_string()),
        curve_files: a.curves.iter().map(|c| c.display().to_string()).collect(),
        scale: a.scale,
    };
    Ok(Inputs {
        curves,
        build,
        warnings,
        description,
        mesh,
    })
}

/// Prints warnings on stderr.
pub fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

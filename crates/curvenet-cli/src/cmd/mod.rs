//! One module per subcommand, plus the option handling they share.

mod analyze;
mod example;

use crate::args::{Cli, Command, PhysicsArgs};
use crate::exit::usage;
use curvenet::rod::Material;
use curvenet::stability::StabilityParams;

/// Runs the parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Analyze(a) => analyze::run(a),
        Command::Example(a) => example::run(a),
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

/// Prints warnings on stderr.
pub fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

//! `curvenet analyze`: build, relax and measure one network (or what `--remove` leaves).

use crate::args::AnalyzeArgs;
use crate::front::{Flags, fail};
use std::time::Instant;

pub fn run(a: AnalyzeArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    // The input's warnings are printed now, before the (possibly long) analysis; the analysis
    // adds its own.
    let input = super::input_spec(&a.input, &a.physics);
    let mut setup = super::setup(&input, &super::model_options(&a.physics, &a.physical))?;
    let shown = setup.inputs.warnings.len();
    let out = curvenet::app::analyze(&mut setup, &a.remove, &Flags).map_err(fail)?;
    super::print_warnings(out.report.warnings.get(shown..).unwrap_or_default());
    if let Some(p) = &out.physical {
        crate::front::print_messages(&p.warnings);
    }
    if a.json {
        println!("{}", out.to_json());
    } else {
        print!("{}", out.to_text());
        println!("time: {:.3} s", start.elapsed().as_secs_f64());
    }
    Ok(())
}

//! `curvenet analyze`: build, relax and measure one network (or what `--remove` leaves).

use crate::args::AnalyzeArgs;
use std::time::Instant;

pub fn run(a: AnalyzeArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    let input = super::input_spec(&a.input, &a.physics);
    let mut setup = super::setup(&input, &super::model_options(&a.physics, &a.physical))?;
    super::print_analysis(&mut setup, &a.remove, a.json, None, start)
}

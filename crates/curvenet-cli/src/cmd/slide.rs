//! `curvenet slide`: a run's answer slid on its surface, recorded as a run of its own.

use crate::args::{SlideArgs, SlideCmdArgs};
use crate::front::{Console, fail};
use curvenet::app::{self, SlideSpec};
use std::path::Path;

pub fn run(a: SlideCmdArgs) -> anyhow::Result<()> {
    let mut spec = spec(&a.dir, &a.out, &a.sliding);
    spec.force = a.force;
    let done = app::slide(&spec, &Console::new(), &crate::signals::token()).map_err(fail)?;
    print!("{}", app::slide_summary(&done.record, &spec.out));
    Ok(())
}

/// The slide of the options, from the run in `from` into `out`.
pub fn spec(from: &Path, out: &Path, a: &SlideArgs) -> SlideSpec {
    SlideSpec {
        max_move: a.max_move,
        fixed_ends: a.fixed_ends,
        pin: a.pin.clone(),
        rounds: a.slide_rounds,
        ..SlideSpec::new(from, out)
    }
}

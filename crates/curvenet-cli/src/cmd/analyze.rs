//! `curvenet analyze`: build, relax and measure one network (or what `--remove` leaves).

use super::{load_inputs, print_warnings, stability_params};
use crate::args::AnalyzeArgs;
use crate::exit::usage;
use curvenet::pipeline;
use std::time::Instant;

pub fn run(a: AnalyzeArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    let inputs = load_inputs(&a.input, &a.physics)?;
    let params = stability_params(&a.physics)?;
    // The input's warnings now, before the (possibly long) analysis; the analysis adds its own.
    let shown = inputs.warnings.len();
    print_warnings(&inputs.warnings);
    let n = inputs.curves.len();
    if let Some(&bad) = a.remove.iter().find(|&&c| c >= n) {
        return Err(usage(format!(
            "--remove names curve {bad}, but the input has {n} curves (ids 0..{})",
            n.saturating_sub(1)
        )));
    }
    // A curve named twice is removed once.
    let mut remove = a.remove.clone();
    remove.sort_unstable();
    remove.dedup();
    if remove.len() >= n {
        return Err(usage(
            "--remove would remove every curve; nothing is left to analyse",
        ));
    }
    let out = pipeline::analyze(
        &inputs.curves,
        &inputs.build,
        &params,
        &remove,
        inputs.warnings,
    )?;
    print_warnings(out.report.warnings.get(shown..).unwrap_or_default());
    if a.json {
        println!("{}", serde_json::to_string(&out.report)?);
    } else {
        print!("{}", out.report.to_text());
        println!("time: {:.3} s", start.elapsed().as_secs_f64());
    }
    Ok(())
}

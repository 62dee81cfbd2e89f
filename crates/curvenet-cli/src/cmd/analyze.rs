//! `curvenet analyze`: build, relax and measure one network (or what `--remove` leaves).

use super::{check_curve_ids, load_setup, print_warnings};
use crate::args::AnalyzeArgs;
use crate::exit::usage;
use curvenet::physics::{PhysicalParams, PhysicalReport, analyze_physical};
use curvenet::pipeline;
use curvenet::rod::ActiveSet;
use std::time::Instant;

pub fn run(a: AnalyzeArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    // The input's warnings are printed now, before the (possibly long) analysis; the analysis
    // adds its own.
    let (inputs, physical, params) = load_setup(&a.input, &a.physics, &a.physical, a.objective)?;
    let shown = inputs.warnings.len();
    let n = inputs.curves.len();
    check_curve_ids("--remove", &a.remove, n)?;
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
        physical.as_ref(),
        &remove,
        inputs.warnings,
    )?;
    print_warnings(out.report.warnings.get(shown..).unwrap_or_default());
    let physical = match physical {
        Some(pp) => {
            let mut active = ActiveSet::all(n);
            for &c in &remove {
                active.remove(c);
            }
            Some(physical_report(out.analyzer.network(), &pp, &active)?)
        }
        None => None,
    };
    if a.json {
        println!("{}", report_json(&out.report, physical.as_ref())?);
    } else {
        print!("{}", out.report.to_text());
        if let Some(r) = &physical {
            print!("{}", r.to_text());
        }
        println!("time: {:.3} s", start.elapsed().as_secs_f64());
    }
    Ok(())
}

/// The physical analysis of `active`, its warnings printed.
pub(super) fn physical_report(
    network: &curvenet::rod::Network,
    params: &PhysicalParams,
    active: &ActiveSet,
) -> anyhow::Result<PhysicalReport> {
    let r = analyze_physical(network, params, active)?;
    print_warnings(&r.warnings);
    Ok(r)
}

/// `--json`'s line: the report's own fields in their own order (as in the paper's mode), then
/// the physical object when there is one.
pub(super) fn report_json(
    report: &curvenet::report::AnalysisReport,
    physical: Option<&PhysicalReport>,
) -> anyhow::Result<String> {
    let text = serde_json::to_string(report)?;
    let Some(r) = physical else {
        return Ok(text);
    };
    let body = text.strip_suffix('}').unwrap_or(&text);
    let sep = if body.ends_with('{') { "" } else { "," };
    Ok(format!(
        "{body}{sep}\"physical\":{}}}",
        serde_json::to_string(r)?
    ))
}

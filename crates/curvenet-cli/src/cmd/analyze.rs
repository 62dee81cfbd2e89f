//! `curvenet analyze`: build, relax and measure one network (or what `--remove` leaves).

use super::{load_inputs, print_warnings, stability_params};
use crate::args::AnalyzeArgs;
use crate::exit::usage;
use curvenet::physics::{PhysicalOptions, analyze_physical};
use curvenet::pipeline;
use curvenet::rod::ActiveSet;
use std::time::Instant;

pub fn run(a: AnalyzeArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    let inputs = load_inputs(&a.input, &a.physics)?;
    let p = &a.physical;
    let options = PhysicalOptions {
        units: p.units.clone(),
        material: p.material.clone(),
        young: a.physics.young.clone(),
        density: p.density.clone(),
        strength: p.strength.clone(),
        radius: a.physics.radius.map(|r| r.to_string()),
        tube: p.tube.clone(),
        load: p.load.clone(),
        gravity: p.gravity.clone(),
    };
    let physical = options
        .resolve(inputs.file_units.as_deref(), &inputs.specs)
        .map_err(usage)?;
    // In the physical mode --young is the material's (with a unit); the paper's model keeps
    // its own E.
    let mut paper = a.physics.clone();
    if physical.is_some() {
        paper.young = None;
    }
    let params = stability_params(&paper)?;
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
    let physical = match physical {
        Some(mut pp) => {
            pp.frequencies = a.physics.eigen_count.max(1);
            let mut active = ActiveSet::all(n);
            for &c in &remove {
                active.remove(c);
            }
            let r = analyze_physical(out.analyzer.network(), &pp, &active)?;
            print_warnings(&r.warnings);
            Some(r)
        }
        None => None,
    };
    if a.json {
        match &physical {
            // The report's own fields in their own order, then the physical object.
            Some(r) => {
                let report = serde_json::to_string(&out.report)?;
                let body = report.strip_suffix('}').unwrap_or(&report);
                let sep = if body.ends_with('{') { "" } else { "," };
                println!("{body}{sep}\"physical\":{}}}", serde_json::to_string(r)?);
            }
            None => println!("{}", serde_json::to_string(&out.report)?),
        }
    } else {
        print!("{}", out.report.to_text());
        if let Some(r) = &physical {
            print!("{}", r.to_text());
        }
        println!("time: {:.3} s", start.elapsed().as_secs_f64());
    }
    Ok(())
}

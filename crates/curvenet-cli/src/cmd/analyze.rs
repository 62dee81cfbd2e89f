//! `curvenet analyze`: build, relax and measure one network (or what `--remove` leaves).

use super::{print_warnings, stability_params};
use crate::args::AnalyzeArgs;
use crate::exit::usage;
use curvenet::io;
use curvenet::network::BuildParams;
use curvenet::pipeline;
use std::time::Instant;

pub fn run(a: AnalyzeArgs) -> anyhow::Result<()> {
    if !(a.scale.is_finite() && a.scale > 0.0) {
        return Err(usage(format!(
            "--scale must be a positive number, got {}",
            a.scale
        )));
    }
    let start = Instant::now();
    let mut warnings = Vec::new();
    if let Some(m) = &a.mesh {
        let mesh = io::read_mesh(m)?;
        warnings.extend(mesh.warnings.iter().map(|w| w.to_string()));
    }
    let mut curves = Vec::new();
    for path in &a.curves {
        let f = io::read_curves(path)?;
        warnings.extend(f.warnings.iter().map(|w| w.to_string()));
        curves.extend(f.curves);
    }
    pipeline::scale_curves(&mut curves, a.scale);
    let params = stability_params(&a.physics)?;
    let h = match a.edge_length {
        Some(h) => h,
        None => pipeline::median_segment_length(&curves),
    };
    let build = BuildParams {
        edge_length: h,
        supports: a.physics.supports.unwrap_or_default(),
        merge_joints_below: a.physics.merge_joints,
        ..BuildParams::default()
    };
    build.validate().map_err(|e| usage(e.to_string()))?;
    if let Some(&bad) = a.remove.iter().find(|&&c| c >= curves.len()) {
        return Err(usage(format!(
            "--remove names curve {bad}, but the input has {} curves (ids 0..{})",
            curves.len(),
            curves.len().saturating_sub(1)
        )));
    }
    let out = pipeline::analyze(&curves, &build, &params, &a.remove, warnings)?;
    print_warnings(&out.report.warnings);
    if a.json {
        println!("{}", serde_json::to_string(&out.report)?);
    } else {
        print!("{}", out.report.to_text());
        println!("time: {:.3} s", start.elapsed().as_secs_f64());
    }
    Ok(())
}

//! `curvenet compare`: the paper's Fig. 10 experiment.

use super::surface::read_mesh_arg;
use crate::args::CompareArgs;
use crate::exit::usage;
use curvenet::experiments::compare::{CompareParams, Surface, compare};
use curvenet::io;
use curvenet::paper;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;

/// The reference's simple surfaces for random experiments.
const SIMPLE: [&str; 5] = ["1wave", "2waves", "half_sphere", "sine_disk", "leaf"];

pub fn run(a: CompareArgs) -> anyhow::Result<()> {
    let data = a.data.clone().or_else(paper::default_data_dir);
    let mut surfaces = Vec::new();
    for name in &a.surfaces {
        let path = match (&data, SIMPLE.contains(&name.as_str())) {
            (Some(d), true) => d.join("meshes").join(format!("{name}.obj")),
            (None, true) => {
                return Err(usage(format!(
                    "surface '{name}' is one of the reference's meshes, but the data folder was not \
                     found; pass --data DIR or use built-in surfaces (--surfaces dome,hill,saddle,wave)"
                )));
            }
            _ => PathBuf::from(name),
        };
        let m = read_mesh_arg(&path)?;
        surfaces.push(Surface {
            name: name.clone(),
            mesh: m.mesh,
        });
    }
    let params = CompareParams {
        sizes: a.sizes.clone(),
        instances: a.instances,
        budget: a.budget,
        seed: a.seed,
        exact_time_limit: a.exact_time_limit,
        ..CompareParams::default()
    };
    if params.sizes.iter().any(|n| !(2..=30).contains(n)) {
        return Err(usage(
            "--sizes must lie between 2 and 30 (exhaustive search is exponential)",
        ));
    }
    let bar = ProgressBar::new((params.sizes.len() * params.instances) as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} networks, ETA {eta}",
        )
        .expect("valid template"),
    );
    let report = compare(&params, &surfaces, &|done, _| bar.set_position(done as u64))?;
    bar.finish_and_clear();
    println!(
        "greedy, greedy + local search (and single moves), rounded relaxation, exact λ_fix, exhaustive and random \
         search, budget {}, {} networks per size, surfaces {}",
        params.budget,
        params.instances,
        report.surfaces.join(", ")
    );
    print!("{}", report.markdown());
    if let Some(p) = &a.json {
        let mut text = serde_json::to_vec_pretty(&report)?;
        text.push(b'\n');
        io::write_atomic(p, &text).map_err(|e| usage(format!("{}: {e}", p.display())))?;
    }
    if let Some(p) = &a.markdown {
        io::write_atomic(p, report.markdown().as_bytes())
            .map_err(|e| usage(format!("{}: {e}", p.display())))?;
    }
    Ok(())
}

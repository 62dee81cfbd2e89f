//! `curvenet compare`: the paper's Fig. 10 experiment, or (`--fresh N`) the searches that give
//! a run's answer on networks drawn afresh, or (`--constraints N`) what each design constraint
//! costs.

use crate::args::CompareArgs;
use crate::exit::usage;
use curvenet::experiments::compare::{
    Case, CompareParams, ConstrainedParams, FreshParams, RandomDraw, compare, constrained, fresh,
    surfaces,
};
use curvenet::io;
use curvenet::simplify::SimplifyError;
use curvenet::trace::SurfaceError;
use indicatif::{ProgressBar, ProgressStyle};

pub fn run(a: CompareArgs) -> anyhow::Result<()> {
    let data = curvenet::app::inputs::data_source(a.data.as_deref()).map_err(crate::front::fail)?;
    for (option, path) in [("--json", &a.json), ("--markdown", &a.markdown)] {
        if let Some(p) = path {
            super::writable_file(option, p)?;
        }
    }
    let (surfaces, warnings) = surfaces(&a.surfaces, &data).map_err(|e| match e {
        SurfaceError::Unknown(_) => usage(format!("--surfaces {e}")),
        e => usage(e.to_string()),
    })?;
    super::print_warnings(&warnings);
    let progress = |bar: &ProgressBar| {
        let bar = bar.clone();
        move |done: usize, _: usize| bar.set_position(done as u64)
    };
    if let Some(networks) = a.fresh {
        let d = FreshParams::default();
        let params = FreshParams {
            draw: RandomDraw {
                networks,
                seed: a.seed,
                ..d.draw
            },
            objective: a.objective,
            ..d
        };
        let bar = networks_bar(networks);
        let report = fresh(&params, &surfaces, &progress(&bar))?;
        bar.finish_and_clear();
        return print_and_write(&a, &report.markdown(), &report);
    }
    if let Some(networks) = a.constraints {
        let cases = (a.examples.iter().filter(|n| n.as_str() != "none"))
            .map(|name| {
                Case::example(name, &data).map_err(|e| usage(format!("--examples {name}: {e}")))
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        let d = ConstrainedParams::default();
        let params = ConstrainedParams {
            draw: RandomDraw {
                networks,
                seed: a.seed,
                ..d.draw
            },
            ..d
        };
        let bar = networks_bar(cases.len() + networks);
        let report = constrained(&params, cases, &surfaces, &progress(&bar))?;
        bar.finish_and_clear();
        return print_and_write(&a, &report.markdown(), &report);
    }
    if a.objective != curvenet::stability::Objective::Lambda {
        return Err(usage(format!(
            "--objective {} needs --fresh: the sizes' table also runs the rounded relaxation \
             and the exact λ_fix solver, which bound λ_fix, the paper's objective at the full \
             network's equilibrium, and do not model the mass metric",
            a.objective.name()
        )));
    }
    let params = CompareParams {
        sizes: a.sizes.clone(),
        instances: a.instances,
        budget: a.budget,
        seed: a.seed,
        exact_time_limit: a.exact_time_limit,
        ..CompareParams::default()
    };
    let bar = networks_bar(params.sizes.len() * params.instances);
    let report = compare(&params, &surfaces, &progress(&bar)).map_err(|e| match e {
        // The parameters do not fit the networks traced (a budget no subset meets).
        SimplifyError::Params(m) => usage(format!(
            "compare with --budget {} and --sizes {:?}: {m}; a larger --budget or more curves \
             leave the searches a subset to find",
            params.budget, params.sizes
        )),
        e => e.into(),
    })?;
    bar.finish_and_clear();
    println!(
        "greedy, greedy + local search (and single moves), rounded relaxation, exact λ_fix, exhaustive and random \
         search, budget {}, {} networks per size, surfaces {}",
        params.budget,
        params.instances,
        report.surfaces.join(", ")
    );
    print_and_write(&a, &report.markdown(), &report)
}

/// The progress bar over `networks` networks.
fn networks_bar(networks: usize) -> ProgressBar {
    let bar = ProgressBar::new(networks as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} networks, ETA {eta}",
        )
        .expect("valid template"),
    );
    bar
}

/// Prints the report's `markdown` table and writes the report as asked: `--json` (the
/// report) and `--markdown` (the table), each atomically.
fn print_and_write(
    a: &CompareArgs,
    markdown: &str,
    report: &impl serde::Serialize,
) -> anyhow::Result<()> {
    print!("{markdown}");
    if let Some(p) = &a.json {
        let mut text = serde_json::to_vec_pretty(report)?;
        text.push(b'\n');
        io::write_atomic(p, &text).map_err(|e| usage(format!("{}: {e}", p.display())))?;
    }
    if let Some(p) = &a.markdown {
        io::write_atomic(p, markdown.as_bytes())
            .map_err(|e| usage(format!("{}: {e}", p.display())))?;
    }
    Ok(())
}

//! `curvenet serve`: the network of the inputs (or of a paper's example, or of a run folder)
//! over a local JSON API (docs/serve.md), each edit warm-started from a nearby equilibrium and
//! giving the `λ` of `curvenet analyze --remove`; `--bench` measures edits against cold
//! analyses instead.

use super::{check_curve_ids, load_inputs, print_warnings, stability_params};
use crate::args::{InputArgs, ServeArgs};
use crate::exit::usage;
use curvenet::network::{BuildParams, build_network};
use curvenet::run_folder::RunFolder;
use curvenet::stability::Analyzer;
use curvenet_serve::bench::BenchParams;
use curvenet_serve::{AppState, Design, DesignError, Runner, Server};
use std::net::{SocketAddr, ToSocketAddrs};
use std::path::Path;
use std::sync::Arc;

pub fn run(a: ServeArgs) -> anyhow::Result<()> {
    // The benchmark listens on nothing.
    let server = if a.bench { None } else { Some(bind(&a)?) };
    let (analyzer, kept, runner) = match &a.run {
        Some(dir) => from_run(dir, &a.remove)?,
        None => {
            let (analyzer, kept) = from_inputs(&a)?;
            (analyzer, kept, Runner::default())
        }
    };
    let n = analyzer.curve_count();
    let design = Design::new(analyzer, &kept).map_err(|e| match e {
        DesignError::Empty => usage("--remove would remove every curve; nothing is left to serve"),
        e => anyhow::Error::new(e),
    })?;
    // What is served, in the page's title and the benchmark's report.
    let name = match (&a.example, &a.run) {
        (Some(name), _) => name.clone(),
        (None, Some(dir)) => dir.display().to_string(),
        (None, None) => a
            .curves
            .iter()
            .map(|c| c.display().to_string())
            .collect::<Vec<_>>()
            .join(", "),
    };
    let Some(server) = server else {
        let params = BenchParams {
            removals: a.bench_removals,
            ..BenchParams::default()
        };
        let report = curvenet_serve::bench::run(&design, params)?;
        print!("{}", report.text(&name));
        return Ok(());
    };
    let bound = server.local_addr()?;
    // The first line on stdout: scripts and tests read the URL from it.
    println!("{}", curvenet_serve::url(bound));
    let s = design.current().summary.clone();
    eprintln!(
        "serving {} of {n} curves: λ = {:.6e} ({}); Ctrl-C stops",
        s.curves.len(),
        s.lambda,
        s.status.word()
    );
    let app = AppState {
        design: Arc::new(design),
        greedy: Arc::new(runner),
        name: name.into(),
    };
    server.serve(app)?;
    Ok(())
}

/// The analyzer of the inputs (or of `--example`) and the curves kept at the start.
fn from_inputs(a: &ServeArgs) -> anyhow::Result<(Analyzer, Vec<usize>)> {
    let params = stability_params(&a.physics)?;
    let (curves, build, warnings) = match &a.example {
        Some(name) => {
            let data = super::data_source(a.data.as_deref())?;
            let supports = a.physics.supports.unwrap_or_default();
            let ex = curvenet::paper::load_from(name, &data, supports)?;
            let build = BuildParams {
                merge_joints_below: a.physics.merge_joints,
                ..ex.build.clone()
            };
            let warnings = ex.warnings.iter().map(|w| w.to_string()).collect();
            (ex.curves, build, warnings)
        }
        None => {
            let input = InputArgs {
                mesh: a.mesh.clone(),
                curves: a.curves.clone(),
                scale: a.scale,
                edge_length: a.edge_length,
            };
            let inputs = load_inputs(&input, &a.physics)?;
            (inputs.curves, inputs.build, inputs.warnings)
        }
    };
    print_warnings(&warnings);
    let n = curves.len();
    check_curve_ids("--remove", &a.remove, n)?;
    let (network, info) = build_network(&curves, &build)?;
    print_warnings(&info.warnings);
    let analyzer = Analyzer::new(network, params).map_err(usage)?;
    let kept = (0..n).filter(|c| !a.remove.contains(c)).collect();
    Ok((analyzer, kept))
}

/// The analyzer of a run folder's network and material, the curves of its answer (of its last
/// iteration when it has none) less `remove`, and its greedy iterations.
fn from_run(dir: &Path, remove: &[usize]) -> anyhow::Result<(Analyzer, Vec<usize>, Runner)> {
    let run = RunFolder::open(dir).map_err(usage)?;
    print_warnings(&run.warnings);
    let r = &run.result;
    check_curve_ids("--remove", remove, run.network.rods.len())?;
    let analyzer = Analyzer::new(run.network.clone(), r.setup.stability.clone())
        .map_err(|e| usage(format!("{}: {e}", dir.join("result.json").display())))?;
    let start = match &r.answer {
        Some(a) => &a.curves,
        None => &r.iterations[run.last_index()].curves,
    };
    let kept = start
        .iter()
        .copied()
        .filter(|c| !remove.contains(c))
        .collect();
    let fraction = r.budget / r.setup.total_length;
    let stop = r.stop.map(|s| s.to_string());
    let runner = Runner::finished(&r.iterations, (fraction, r.budget), stop);
    Ok((analyzer, kept, runner))
}

/// The server bound to `--host` and `--port` (a warning when it is not a loopback address).
fn bind(a: &ServeArgs) -> anyhow::Result<Server> {
    let addr = address(&a.host, a.port)?;
    if !addr.ip().is_loopback() {
        eprintln!(
            "warning: --host {} listens on {addr}, reachable from other machines: anyone who \
             reaches it can edit the design and keep the server computing",
            a.host
        );
    }
    Server::bind(addr).map_err(|e| {
        usage(format!(
            "cannot listen on {addr}: {e} (choose another --port, or --port 0 for any free one)"
        ))
    })
}

/// The socket address of `--host` and `--port`.
fn address(host: &str, port: u16) -> anyhow::Result<SocketAddr> {
    let mut addrs = (host, port).to_socket_addrs().map_err(|e| {
        usage(format!(
            "--host {host}: not an address this machine can listen on ({e})"
        ))
    })?;
    addrs
        .next()
        .ok_or_else(|| usage(format!("--host {host}: the name has no address")))
}

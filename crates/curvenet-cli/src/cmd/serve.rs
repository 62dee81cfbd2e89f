//! `curvenet serve`: the network of the inputs (or of a paper's example, or of a run folder)
//! over a local JSON API (docs/serve.md), each edit warm-started from a nearby equilibrium and
//! giving the `λ` of `curvenet analyze --remove` (and, in the physical mode, its physical
//! numbers); `--bench` measures edits against cold analyses instead.

use super::print_warnings;
use crate::args::ServeArgs;
use crate::exit::usage;
use crate::front::fail;
use curvenet::app::check_curve_ids;
use curvenet::io::TriMesh;
use curvenet::physics::PhysicalParams;
use curvenet::run_folder::{RunFiles, RunsRoot};
use curvenet::stability::{Analyzer, Objective};
use curvenet::words::Opt;
use curvenet_serve::bench::BenchParams;
use curvenet_serve::workspace::open_run;
use curvenet_serve::{AppState, Design, DesignError, Runner, ServeConfig, Server, Workspace};
use std::net::{SocketAddr, ToSocketAddrs};
use std::path::Path;

pub fn run(a: ServeArgs) -> anyhow::Result<()> {
    // The benchmark listens on nothing.
    let server = if a.bench { None } else { Some(bind(&a)?) };
    // A run folder (given or loaded from the page) gets the physical mode's options alone:
    // its curves' own materials and units are not recorded in it.
    // Options that need a curve file's units serve a run folder in the paper's mode.
    let model = super::model_options(&a.physics, &a.physical);
    let run_physical = match model.resolve(None, &[]) {
        Ok(m) => m.physical,
        Err(e) if a.run.is_some() => return Err(fail(e)),
        Err(_) => None,
    };
    let served = match &a.run {
        Some(dir) => from_run(dir, run_physical.as_ref())?,
        None => from_inputs(&a)?,
    };
    let Served {
        analyzer,
        kept,
        greedy,
        mesh,
    } = served;
    check_curve_ids(Opt::Remove, &a.remove, analyzer.curve_count()).map_err(fail)?;
    let n = analyzer.curve_count();
    let kept: Vec<usize> = kept.into_iter().filter(|c| !a.remove.contains(c)).collect();
    let design = Design::new(analyzer, &kept).map_err(|e| match e {
        DesignError::Empty => usage("--remove would remove every curve; nothing is left to serve"),
        e => anyhow::Error::new(e),
    })?;
    // What is served, in the page's title and the benchmark's report.
    let name = match (&a.example, &a.run) {
        (Some(name), _) => name.clone(),
        (None, Some(dir)) => dir.display().to_string(),
        (None, None) => a
            .input
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
    let url = curvenet_serve::url(server.local_addr()?);
    // The first line on stdout: scripts and tests read the URL from it.
    println!("{url}");
    let s = design.current().summary.clone();
    let objective = design.analyzer().objective();
    // Beside a physical analysis the paper's λ_eq is the paper's model's; the physical
    // figures follow with their units.
    let model = match (&s.physical, objective) {
        (Some(_), Objective::Lambda) => " (the paper's model)",
        _ => "",
    };
    let physical = s.physical.as_ref().map_or_else(String::new, |p| {
        let or_none = |v: Option<f64>, unit: &str| {
            v.map_or_else(|| "none (unstable)".into(), |v| format!("{v:.4} {unit}"))
        };
        format!(
            "; physical: first frequency {}, self-weight deflection {}",
            or_none(p.first_frequency_hz, "Hz"),
            or_none(p.self_weight_max_deflection, &p.units)
        )
    });
    eprintln!(
        "serving {} of {n} curves: {}{model} = {:.6e} ({}){physical}; Ctrl-C stops",
        s.curves.len(),
        objective.value_symbol(),
        s.lambda,
        s.status.word()
    );
    if let Some(p) = &s.physical {
        crate::front::print_messages(&p.warnings);
    }
    if a.open {
        super::open_in_browser(&url);
    }
    let ws = Workspace::new(design, &name)
        .with_greedy(greedy)
        .with_mesh(mesh);
    let config = ServeConfig {
        runs_root: Some(runs_root(a.runs.as_deref())?),
        physical: run_physical,
    };
    server.serve(AppState::new(ws, config))?;
    Ok(())
}

/// What `serve` starts on: the analyzer, the curves kept, the greedy's iterations (a run
/// folder's) and the surface.
struct Served {
    analyzer: Analyzer,
    kept: Vec<usize>,
    greedy: Runner,
    mesh: Option<TriMesh>,
}

/// The analyzer of the inputs (or of `--example`), in the physical mode when asked, every
/// curve kept.
fn from_inputs(a: &ServeArgs) -> anyhow::Result<Served> {
    let input = match &a.example {
        Some(name) => super::example_spec(name, a.data.as_deref(), &a.physics),
        None => super::input_spec(&a.input, &a.physics),
    };
    let mut setup = super::setup(&input, &super::model_options(&a.physics, &a.physical))?;
    let n = setup.curve_count();
    check_curve_ids(Opt::Remove, &a.remove, n).map_err(fail)?;
    let analyzer = setup.analyzer().map_err(fail)?;
    for w in setup.build_warnings() {
        print_warnings(&[crate::front::say(&w)]);
    }
    Ok(Served {
        analyzer,
        kept: (0..n).collect(),
        greedy: Runner::default(),
        mesh: setup.inputs.mesh,
    })
}

/// The run folder `dir` as `--run` serves it: its network and material, its answer to start
/// on, its greedy iterations, its surface.
fn from_run(dir: &Path, physical: Option<&PhysicalParams>) -> anyhow::Result<Served> {
    let run = open_run(RunFiles::unconfined(dir), physical).map_err(|e| usage(e.to_string()))?;
    print_warnings(&run.warnings);
    Ok(Served {
        analyzer: run.analyzer,
        kept: run.kept,
        greedy: run.greedy,
        mesh: run.mesh,
    })
}

/// The folder the page may load run folders from: `--runs` (which must be a folder), or the
/// current folder.
fn runs_root(runs: Option<&Path>) -> anyhow::Result<RunsRoot> {
    let dir = match runs {
        Some(dir) => dir.to_path_buf(),
        None => std::env::current_dir()?,
    };
    RunsRoot::new(&dir).map_err(|_| {
        usage(format!(
            "--runs {}: no such folder (the folder whose run folders the page may load)",
            dir.display()
        ))
    })
}

/// The server bound to `--host` and `--port` (a warning naming the address bound when it is
/// not a loopback address).
fn bind(a: &ServeArgs) -> anyhow::Result<Server> {
    if let Some(dir) = &a.runs {
        runs_root(Some(dir))?;
    }
    let addr = address(&a.host, a.port)?;
    let server = Server::bind(addr).map_err(|e| {
        usage(format!(
            "cannot listen on {addr}: {e} (choose another --port, or --port 0 for any free one)"
        ))
    })?;
    if !addr.ip().is_loopback() {
        let bound = server.local_addr().unwrap_or(addr);
        eprintln!(
            "warning: --host {} listens on {bound}, reachable from other machines: anyone who \
             reaches it can edit the design, load run folders under the served folder and \
             keep the server computing",
            a.host
        );
    }
    Ok(server)
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

//! `curvenet serve`: the network of the inputs (or of a paper's example) over a local JSON
//! API (docs/serve.md), each edit warm-started from the current equilibrium and giving the `λ`
//! of `curvenet analyze --remove`; `--bench` measures edits against cold analyses instead.

use super::{load_inputs, print_warnings, stability_params};
use crate::args::{InputArgs, ServeArgs};
use crate::exit::usage;
use curvenet::network::{BuildParams, build_network};
use curvenet::stability::Analyzer;
use curvenet_serve::bench::BenchParams;
use curvenet_serve::{Design, DesignError, Server};
use std::net::{SocketAddr, ToSocketAddrs};

pub fn run(a: ServeArgs) -> anyhow::Result<()> {
    // The benchmark listens on nothing.
    let server = if a.bench { None } else { Some(bind(&a)?) };
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
    if let Some(&bad) = a.remove.iter().find(|&&c| c >= n) {
        return Err(usage(format!(
            "--remove names curve {bad}, but the input has {n} curves (ids 0..{})",
            n.saturating_sub(1)
        )));
    }
    let (network, info) = build_network(&curves, &build)?;
    print_warnings(&info.warnings);
    let analyzer = Analyzer::new(network, params).map_err(usage)?;
    let kept: Vec<usize> = (0..n).filter(|c| !a.remove.contains(c)).collect();
    let design = Design::new(analyzer, &kept).map_err(|e| match e {
        DesignError::Empty => usage("--remove would remove every curve; nothing is left to serve"),
        e => anyhow::Error::new(e),
    })?;
    let Some(server) = server else {
        let name = match (&a.example, a.curves.first()) {
            (Some(name), _) => name.clone(),
            (None, Some(file)) => file.display().to_string(),
            (None, None) => String::from("network"),
        };
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
        "serving {} of {n} curves: λ = {:.6e} ({:?}); Ctrl-C stops",
        s.curves.len(),
        s.lambda,
        s.status
    );
    server.run(design)?;
    Ok(())
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

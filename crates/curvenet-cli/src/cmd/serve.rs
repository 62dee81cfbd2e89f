//! `curvenet serve`: the network of the inputs (or of a paper's example, or of a run folder)
//! over a local JSON API (docs/serve.md), each edit warm-started from a nearby equilibrium and
//! giving the `λ` of `curvenet analyze --remove` (and, in the physical mode, its physical
//! numbers); `--bench` measures edits against cold analyses instead. The server's start
//! (the socket, what is served) is `curvenet_serve::start`'s.

use crate::args::ServeArgs;
use crate::front::{Console, fail, print_messages};
use curvenet_serve::AppState;
use curvenet_serve::bench::BenchParams;
use curvenet_serve::start::{ServeSpec, Source, listen, open, runs_root};

pub fn run(a: ServeArgs) -> anyhow::Result<()> {
    let console = Console::new();
    // The page's run folders and the socket before any work; the benchmark listens on nothing.
    let listening = if a.bench {
        None
    } else {
        let runs = match &a.runs {
            Some(dir) => dir.clone(),
            None => std::env::current_dir()?,
        };
        let root = runs_root(&runs).map_err(fail)?;
        Some((listen(&a.host, a.port, &console).map_err(fail)?, root))
    };
    let source = match (&a.run, &a.example) {
        (Some(dir), _) => Source::Run(dir.clone()),
        (None, Some(name)) => Source::Inputs(Box::new(super::example_spec(
            name,
            a.data.as_deref(),
            &a.physics,
        ))),
        (None, None) => Source::Inputs(Box::new(super::input_spec(&a.input, &a.physics))),
    };
    let spec = ServeSpec {
        source,
        model: super::model_options(&a.physics, &a.physical),
        remove: a.remove.clone(),
    };
    let opened = open(&spec, &console).map_err(fail)?;
    let Some((server, root)) = listening else {
        let params = BenchParams {
            removals: a.bench_removals,
            ..BenchParams::default()
        };
        let report = curvenet_serve::bench::run(&opened.workspace.design, params)?;
        let draw = curvenet_serve::bench_draw::run(&opened.workspace, 8, params.seed);
        let draw = draw.map_or_else(String::new, |d| d.text());
        print!("{}{draw}", report.text(&opened.workspace.name));
        return Ok(());
    };
    let url = curvenet_serve::url(server.local_addr()?);
    // The first line on stdout: scripts and tests read the URL from it.
    println!("{url}");
    eprintln!("{}; Ctrl-C stops", opened.summary());
    if let Some(p) = &opened.workspace.design.current().summary.physical {
        print_messages(&p.warnings);
    }
    if a.open {
        super::open_in_browser(&url);
    }
    let config = opened.config(root);
    server.serve(AppState::new(opened.workspace, config))?;
    Ok(())
}

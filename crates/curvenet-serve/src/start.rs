//! Starting a server from the application layer's specifications: the socket it listens on
//! ([`listen`], bound before any network is built, so a busy port fails at once) and what it
//! serves ([`open`]: inputs read by [`curvenet::app`] as every front end reads them — the
//! default edge length, the input's warnings, a paper's example — or a run folder), with the
//! curves removed at the start. `curvenet serve` only translates its options into a
//! [`ServeSpec`] and prints what these return.

use crate::Server;
use crate::api::ServeConfig;
use crate::design::{Design, DesignError};
use crate::greedy::Runner;
use crate::workspace::{Workspace, open_run};
use curvenet::app::{
    AppError, CurveSource, Drawing, InputSpec, ModelOptions, Observer, Setup, check_curve_ids,
};
use curvenet::io::TriMesh;
use curvenet::physics::PhysicalParams;
use curvenet::run_folder::{RunFiles, RunsRoot};
use curvenet::stability::{Analyzer, Objective};
use curvenet::words::{Message, Opt, given, message};
use std::net::{SocketAddr, ToSocketAddrs};
use std::path::{Path, PathBuf};

/// What a server serves.
#[derive(Clone, Debug)]
pub enum Source {
    /// Inputs the application layer reads (curve files and a surface, a paper's example,
    /// curves given as arrays).
    Inputs(Box<InputSpec>),
    /// A run folder: its network and material, its answer to start on, its greedy's
    /// iterations to step through, its surface.
    Run(PathBuf),
}

/// A server's start, as a front end gives it.
#[derive(Clone, Debug)]
pub struct ServeSpec {
    /// What is served.
    pub source: Source,
    /// The model. A run folder keeps the material it recorded and takes only the physical
    /// mode's options (which also apply to run folders loaded later).
    pub model: ModelOptions,
    /// Curves removed at the start.
    pub remove: Vec<usize>,
}

/// A workspace ready to serve.
#[derive(Debug)]
pub struct Opened {
    /// The network served, its first structure analysed.
    pub workspace: Workspace,
    /// The physical mode's parameters for the run folders loaded later (`None`: the paper's
    /// mode).
    pub physical: Option<PhysicalParams>,
}

impl Opened {
    /// What is served, in one line: `serving 5 of 6 curves: λ_eq = 1.234560e-3 (stable)`,
    /// and in the physical mode its first frequency and self-weight deflection (beside which
    /// the paper's `λ_eq` is named the paper's model's).
    pub fn summary(&self) -> String {
        let design = &self.workspace.design;
        let s = design.current().summary.clone();
        let objective = design.analyzer().objective();
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
        format!(
            "serving {} of {} curves: {}{model} = {:.6e} ({}){physical}",
            s.curves.len(),
            design.analyzer().curve_count(),
            objective.value_symbol(),
            s.lambda,
            s.status.word()
        )
    }

    /// The server's configuration: run folders loaded from `runs`, in the physical mode of
    /// the start.
    pub fn config(&self, runs: RunsRoot) -> ServeConfig {
        ServeConfig {
            runs_root: Some(runs),
            physical: self.physical.clone(),
        }
    }
}

/// Reads what `spec` serves and analyses its first structure (every curve but the removed
/// ones; a run folder's answer less them), telling `observer` the input's and the build's
/// warnings.
///
/// # Errors
///
/// What reading the inputs or the run folder, building the network or the model found (a
/// usage error naming the option or the file), a removal naming an unknown curve or every
/// curve, or a failed analysis.
pub fn open(spec: &ServeSpec, observer: &dyn Observer) -> Result<Opened, AppError> {
    // A run folder (given or loaded from the page) gets the physical mode's options alone:
    // its curves' own materials and units are not recorded in it. Options that need a curve
    // file's units serve a run folder in the paper's mode.
    let physical = match spec.model.resolve(None, &[]) {
        Ok(m) => m.physical,
        Err(e) if matches!(spec.source, Source::Run(_)) => return Err(e),
        Err(_) => None,
    };
    let (analyzer, kept, greedy, mesh, drawing, slid) = match &spec.source {
        Source::Run(dir) => {
            let run = open_run(RunFiles::unconfined(dir), physical.as_ref())
                .map_err(|e| AppError::usage(e.to_string()))?;
            for w in run.warnings {
                observer.warning(&Message::from(w));
            }
            (run.analyzer, run.kept, run.greedy, run.mesh, None, run.slid)
        }
        Source::Inputs(input) => {
            let (analyzer, mesh, drawing) =
                from_inputs(input, &spec.model, &spec.remove, observer)?;
            let all = (0..analyzer.curve_count()).collect();
            (analyzer, all, Runner::default(), mesh, drawing, None)
        }
    };
    check_curve_ids(Opt::Remove, &spec.remove, analyzer.curve_count())?;
    let kept: Vec<usize> = kept
        .into_iter()
        .filter(|c| !spec.remove.contains(c))
        .collect();
    let design = Design::new(analyzer, &kept).map_err(|e| match e {
        DesignError::Empty => AppError::usage(message![
            Opt::Remove,
            " would remove every curve; nothing is left to serve"
        ]),
        e => AppError::Failed(e.to_string()),
    })?;
    let workspace = Workspace::new(design, &name_of(&spec.source))
        .with_greedy(greedy)
        .with_mesh(mesh)
        .with_drawing(drawing)
        .with_slid(slid);
    Ok(Opened {
        workspace,
        physical,
    })
}

/// The analyzer of `input` in `model`, the surface and the design's curves as drawn (when
/// there is a surface to draw on), read and built by the application layer (its warnings
/// told `observer`); `remove` is checked before the network is built.
fn from_inputs(
    input: &InputSpec,
    model: &ModelOptions,
    remove: &[usize],
    observer: &dyn Observer,
) -> Result<(Analyzer, Option<TriMesh>, Option<Drawing>), AppError> {
    let mut setup = Setup::new(input, model)?;
    for w in &setup.inputs.warnings {
        observer.warning(w);
    }
    check_curve_ids(Opt::Remove, remove, setup.curve_count())?;
    let analyzer = setup.analyzer()?;
    for w in setup.build_warnings() {
        observer.warning(&w);
    }
    let drawing = Drawing::new(&setup, model).ok();
    Ok((analyzer, setup.inputs.mesh, drawing))
}

/// What is served, for the page's title and the benchmark's report: an example's name, the
/// curve files, a run folder.
fn name_of(source: &Source) -> String {
    match source {
        Source::Run(dir) => dir.display().to_string(),
        Source::Inputs(input) => match &input.curves {
            CurveSource::Example { name, .. } => name.clone(),
            CurveSource::Files(files) => files
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(", "),
            CurveSource::Given(given) if !given.files.is_empty() => given.files.join(", "),
            CurveSource::Given(_) => "network".to_string(),
            CurveSource::Geodesics {
                surface,
                count,
                seed,
            } => format!("{count} geodesics (seed {seed}) on {surface}"),
        },
    }
}

/// The folder whose run folders the page may load (it must be a folder).
///
/// # Errors
///
/// `dir` is not a folder (a usage error naming the option).
pub fn runs_root(dir: &Path) -> Result<RunsRoot, AppError> {
    RunsRoot::new(dir).map_err(|_| {
        AppError::usage(message![
            given(Opt::Runs, dir.display()),
            ": no such folder (the folder whose run folders the page may load)"
        ])
    })
}

/// A server listening on `host` and `port` (0: any free port); a host that is not a loopback
/// address is a warning told `observer`, naming the address bound.
///
/// # Errors
///
/// The host has no address this machine can listen on, or the port cannot be bound (a usage
/// error naming the option).
pub fn listen(host: &str, port: u16, observer: &dyn Observer) -> Result<Server, AppError> {
    let addr = address(host, port)?;
    let server = Server::bind(addr).map_err(|e| {
        AppError::usage(message![
            format!("cannot listen on {addr}: {e} (choose another "),
            Opt::Port,
            ", or ",
            given(Opt::Port, 0),
            " for any free one)"
        ])
    })?;
    if !addr.ip().is_loopback() {
        let bound = server.local_addr().unwrap_or(addr);
        observer.warning(&message![
            given(Opt::Host, host),
            format!(
                " listens on {bound}, reachable from other machines: anyone who reaches it can \
                 edit the design, load run folders under the served folder and keep the \
                 server computing"
            )
        ]);
    }
    Ok(server)
}

/// The socket address of `host` and `port`.
fn address(host: &str, port: u16) -> Result<SocketAddr, AppError> {
    let mut addrs = (host, port).to_socket_addrs().map_err(|e| {
        AppError::usage(message![
            given(Opt::Host, host),
            format!(": not an address this machine can listen on ({e})")
        ])
    })?;
    addrs.next().ok_or_else(|| {
        AppError::usage(message![
            given(Opt::Host, host),
            ": the name has no address"
        ])
    })
}

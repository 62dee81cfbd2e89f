//! [`Workspace`]: one served network with everything a session does on it — its [`Design`]
//! (the current structure and the cache), its greedy and local search, its design
//! constraints, its surface — and [`open_run`], the workspace of a run folder (what
//! `serve --run DIR` starts on and `POST /api/run` loads; a run made with `--slide` is served
//! as its slid network, [`Slid`]).

use crate::constraints::SessionConstraints;
use crate::design::{Design, DesignError};
use crate::greedy::Runner;
use crate::local::LocalRunner;
use crate::slide::SlideRunner;
use curvenet::app::{DrawEdit, DrawError, Drawing};
use curvenet::io::{Polyline, TriMesh};
use curvenet::physics::PhysicalParams;
use curvenet::report::viewer::before_curves;
use curvenet::run_folder::schema::SlideRecord;
use curvenet::run_folder::{RunFiles, RunFolder, RunFolderError};
use curvenet::stability::Analyzer;
use std::sync::{Arc, Mutex, MutexGuard};

/// One served network and the session's work on it.
#[derive(Debug)]
pub struct Workspace {
    /// The network being designed and its current structure.
    pub design: Arc<Design>,
    /// The greedy runs on it.
    pub greedy: Arc<Runner>,
    /// The local searches on it.
    pub local: Arc<LocalRunner>,
    /// The slides of its structure.
    pub slide: Arc<SlideRunner>,
    /// What is served, for the page's title: an example's name, the curve files, a run folder.
    pub name: Arc<str>,
    /// The surface, when known (drawn by the page; `max_gap` needs it).
    pub mesh: Option<Arc<TriMesh>>,
    /// The design's curves as drawn, when they can be edited (served from curve files or an
    /// example with its surface; a run folder's network cannot).
    pub drawing: Option<Arc<Drawing>>,
    /// When the network served is a slid run's (a run made with `--slide`, or `curvenet
    /// slide`'s): how it slid and its curves before.
    pub slid: Option<Arc<Slid>>,
    constraints: Mutex<SessionConstraints>,
}

/// A slid run's network, served: the slide's record (`result.json`'s `slide`) and the curves
/// it started from.
#[derive(Clone, Debug)]
pub struct Slid {
    /// The slide's record.
    pub record: SlideRecord,
    /// The curves before they slid, in the slid run's curve order (empty when the run's
    /// `before.obj` cannot be read).
    pub before: Vec<Polyline>,
}

impl Workspace {
    /// The workspace of `design` named `name`: no greedy run, no surface, no constraint.
    pub fn new(design: Design, name: &str) -> Self {
        Workspace {
            design: Arc::new(design),
            greedy: Arc::new(Runner::default()),
            local: Arc::new(LocalRunner::default()),
            slide: Arc::new(SlideRunner::default()),
            name: name.into(),
            mesh: None,
            drawing: None,
            slid: None,
            constraints: Mutex::new(SessionConstraints::default()),
        }
        .in_its_units()
    }

    /// Its constraints measure the largest deviation as the design's analyzer does: in the
    /// physical mode on the structure's own model, in the scene's unit.
    fn in_its_units(self) -> Self {
        let unit = self
            .design
            .analyzer()
            .physical()
            .map(|p| p.physical.units.symbol().to_string());
        self.constraints().physical_unit = unit;
        self
    }

    /// With the greedy `runner` (a run folder's iterations).
    pub fn with_greedy(mut self, runner: Runner) -> Self {
        self.greedy = Arc::new(runner);
        self
    }

    /// With the surface `mesh`.
    pub fn with_mesh(mut self, mesh: Option<TriMesh>) -> Self {
        self.mesh = mesh.map(Arc::new);
        self
    }

    /// With the slide that gave its network (a slid run's).
    pub fn with_slid(mut self, slid: Option<Slid>) -> Self {
        self.slid = slid.map(Arc::new);
        self
    }

    /// With the design's curves as drawn.
    pub fn with_drawing(mut self, drawing: Option<Drawing>) -> Self {
        self.drawing = drawing.map(Arc::new);
        self
    }

    /// The workspace of `design`, the network of `drawing` (this one's curves edited): the
    /// same name and surface, the design constraints in force kept when they still apply to
    /// the new network, no greedy run.
    pub fn redrawn(&self, design: Design, drawing: Drawing) -> Workspace {
        let next = Workspace {
            mesh: self.mesh.clone(),
            ..Workspace::new(design, &self.name)
        };
        let params = self.constraints().params().clone();
        let net = next.design.analyzer().network();
        // Constraints that no longer apply (a group of deleted curves) are dropped.
        let _ = next.constraints().set(net, next.mesh.as_deref(), params);
        Workspace {
            drawing: Some(Arc::new(drawing)),
            ..next
        }
    }

    /// The workspace after the drawing edit `edit` of this one's curves (the network rebuilt
    /// and its structure analysed: the curves kept now, and a new curve) and the curve the
    /// edit drew or moved. This workspace is unchanged.
    ///
    /// # Errors
    ///
    /// Its curves cannot be drawn on (a run folder's network), the edit is refused, or the
    /// new network cannot be built or analysed.
    pub fn draw(&self, edit: &DrawEdit) -> Result<(Workspace, Option<usize>), Redraw> {
        let drawing = self.drawing.as_ref().ok_or(Redraw::NotEditable)?;
        let drawn = drawing.apply(edit)?;
        let (analyzer, _) = drawn.drawing.analyzer()?;
        let kept = edit.carry(
            &self.design.current().summary.curves,
            drawing.curves().len(),
        );
        let design = Design::new(analyzer, &kept)?;
        Ok((self.redrawn(design, drawn.drawing), drawn.curve))
    }

    /// The session's design constraints (a panic elsewhere leaves the last whole state).
    pub fn constraints(&self) -> MutexGuard<'_, SessionConstraints> {
        self.constraints.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Asks its running searches to stop (the workspace is being replaced).
    pub fn stop(&self) {
        self.greedy.stop();
        self.local.stop();
        self.slide.stop();
    }
}

/// Why a run folder's network cannot be drawn on or slid (`doing`), and what to do instead.
pub fn not_editable(doing: &str) -> String {
    format!(
        "{doing} edits the curves as drawn on their surface, which a run folder does not hold \
         (it holds the network's rods): export the run's curves (curvenet export RUNDIR \
         --format json --out curves.json) and serve them on the run's surface with the run's \
         edge length (curvenet serve --curves curves.json --mesh RUNDIR/mesh.obj --edge-length \
         H, H as result.json's setup.build.edge_length), or serve the curve files or the \
         paper's example the run was made from"
    )
}

/// Why a drawing edit was refused or failed.
#[derive(Debug, thiserror::Error)]
pub enum Redraw {
    /// The served network's curves cannot be drawn on.
    #[error("{}", not_editable("drawing"))]
    NotEditable,
    /// The edit itself was refused, or the network could not be built.
    #[error(transparent)]
    Draw(#[from] DrawError),
    /// The new structure could not be analysed.
    #[error(transparent)]
    Design(#[from] DesignError),
}

/// A run folder read for serving.
#[derive(Debug)]
pub struct ServedRun {
    /// The analyzer of the run's network and material (in the physical mode when asked).
    pub analyzer: Analyzer,
    /// The curves to start on: the run's answer (its last iteration when it has none).
    pub kept: Vec<usize>,
    /// The run's greedy iterations, as a finished run.
    pub greedy: Runner,
    /// The run's surface, when it has one.
    pub mesh: Option<TriMesh>,
    /// Problems reading it that did not stop the reading.
    pub warnings: Vec<String>,
    /// The slide, when the network is a slid run's.
    pub slid: Option<Slid>,
}

impl ServedRun {
    /// The workspace of the run (its first structure analysed) less `remove`, named `name`.
    ///
    /// # Errors
    ///
    /// `remove` leaves no curve, or the analysis failed.
    pub fn workspace(self, remove: &[usize], name: &str) -> Result<Workspace, DesignError> {
        let kept: Vec<usize> = self
            .kept
            .iter()
            .copied()
            .filter(|c| !remove.contains(c))
            .collect();
        let design = Design::new(self.analyzer, &kept)?;
        Ok(Workspace::new(design, name)
            .with_greedy(self.greedy)
            .with_mesh(self.mesh)
            .with_slid(self.slid))
    }
}

/// Why a run folder could not be served.
#[derive(Debug, thiserror::Error)]
pub enum OpenRunError {
    /// It could not be read (naming the file).
    #[error(transparent)]
    Folder(#[from] RunFolderError),
    /// Its recorded set-up cannot be analysed (or the physical mode's parameters applied to
    /// it).
    #[error("{file}: {message}")]
    Setup {
        /// `result.json`, as the reader names it.
        file: String,
        /// What is wrong.
        message: String,
    },
}

/// Reads the run folder of `files` for serving: its network and material as the run recorded
/// them (with `physical`, the physical mode's parameters, applied to it), its answer to start
/// on, its greedy iterations. Every file is read through `files`, so a confined reader reads
/// nothing outside its root.
///
/// # Errors
///
/// The folder is not a readable curvenet run folder (naming the file), or its set-up cannot be
/// analysed.
pub fn open_run(
    files: RunFiles,
    physical: Option<&PhysicalParams>,
) -> Result<ServedRun, OpenRunError> {
    // A run made with `--slide` holds its slid network in `slide/`: that is its answer.
    let files = match files.sub("slide") {
        Ok(slide) if slide.read("result.json").is_ok() => slide,
        _ => files,
    };
    let run = RunFolder::read(files)?;
    let r = &run.result;
    let in_result = |e: curvenet::stability::StabilityError| OpenRunError::Setup {
        file: run.files.name("result.json"),
        message: e.to_string(),
    };
    let mut analyzer =
        Analyzer::new(run.network.clone(), r.setup.stability.clone()).map_err(in_result)?;
    if let Some(p) = physical {
        analyzer = analyzer.with_physical(p.clone()).map_err(in_result)?;
    }
    let kept = match &r.answer {
        Some(a) => a.found.curves.clone(),
        None => r.iterations[run.last_index()].curves.clone(),
    };
    // A slid run's network is its answer alone, shorter than the budget it was chosen under:
    // the whole of it is within that budget.
    let fraction = (r.budget / r.setup.total_length).min(1.0);
    let stop = r.stop.map(|s| s.to_string());
    let greedy = Runner::finished(&r.iterations, (fraction, r.budget), stop);
    Ok(ServedRun {
        analyzer,
        kept,
        greedy,
        slid: r.slide.clone().map(|record| Slid {
            record,
            before: before_curves(&run).unwrap_or_default(),
        }),
        mesh: run.mesh,
        warnings: run.warnings,
    })
}

//! A simplification run, whole: [`RunSpec`] (budget, keep list, design constraints, the steps
//! after the greedy, the run folder) and [`execute`], which claims the folder, builds the
//! network, runs the greedy (or resumes it), the local search, the alternatives and the
//! certificate, chooses the answer, records everything and draws the pictures. Every front
//! end runs a simplification through here.

mod after;
mod folder;
mod notes;

use super::observer::{Observer, StageGuard};
use super::search::Search;
use super::setup::{Setup, check_curve_ids};
use super::{AppError, Stage};
use crate::cancel::Cancel;
use crate::constraints::{ConstraintParams, read_groups};
use crate::network::Network;
use crate::report::gravity_ahead::{Deflections, GravityAhead};
use crate::run_folder::schema::PhysicalModel;
use crate::run_folder::{OutputWriter, ResultFile, RunFolderError, RunSetup};
use crate::simplify::greedy::ResumePoint;
use crate::simplify::{Budget, SimplifyError, greedy};
use crate::stability::{Evaluation, Objective};
use crate::words::{Message, Opt, given, message};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub use after::AfterSeconds;

/// What a run does beyond its set-up.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// The run folder.
    pub out: PathBuf,
    /// The budget (`None`: a paper's example's own; else an error).
    pub budget: Option<Budget>,
    /// Curves never removed (`None`: a paper's example's own keep list; else none).
    pub keep: Option<Vec<usize>>,
    /// Design constraints (its groups after those of [`Self::groups_file`] and before the
    /// curve files' own).
    pub constraints: ConstraintParams,
    /// A groups file (one group per line).
    pub groups_file: Option<PathBuf>,
    /// The constraints are the front end's own defaults, not the user's (the demo): when
    /// nothing can meet them on this network, a note says so and the run goes on without.
    pub default_constraints: bool,
    /// Run the local search after the greedy.
    pub local_search: bool,
    /// Alternatives to record beside the answer (0 to 100; they need the local search, which
    /// then runs).
    pub alternatives: usize,
    /// Compute the certificate of the answer.
    pub certify: bool,
    /// Branch and bound nodes spent tightening the certificate (`None`: by network size).
    pub certificate_nodes: Option<usize>,
    /// Draw the pictures and the viewer.
    pub pictures: bool,
    /// Continue an interrupted run in the folder.
    pub resume: bool,
    /// Run into a non-empty folder that is not a curvenet run's.
    pub force: bool,
    /// Slide the answer on the surface afterwards, into the folder's `slide/` run
    /// ([`super::slide()`]; its `from` and `out` are set by the run).
    pub slide: Option<super::SlideSpec>,
}

impl RunSpec {
    /// A run into `out` with every option at its default (no budget given).
    pub fn new(out: impl Into<PathBuf>) -> Self {
        RunSpec {
            out: out.into(),
            budget: None,
            keep: None,
            constraints: ConstraintParams::default(),
            groups_file: None,
            default_constraints: false,
            local_search: false,
            alternatives: 0,
            certify: false,
            certificate_nodes: None,
            pictures: true,
            resume: false,
            force: false,
            slide: None,
        }
    }
}

/// The most alternatives a run records.
pub const MAX_ALTERNATIVES: usize = 100;

/// The most branch and bound nodes the certificate spends.
pub const MAX_CERTIFICATE_NODES: usize = 100_000;

/// What a run did.
#[derive(Clone, Debug)]
pub struct RunOutcome {
    /// The run folder.
    pub folder: PathBuf,
    /// Its record (`result.json`).
    pub result: ResultFile,
    /// The run was complete already (a resume found nothing to do).
    pub already_complete: bool,
    /// The seconds each step after the greedy took.
    pub seconds: AfterSeconds,
    /// The wall time, seconds.
    pub wall_seconds: f64,
    /// The slid run's record, when the run slid its answer (its folder: `slide/` in the run's).
    pub slide: Option<crate::run_folder::SlideRecord>,
}

/// Runs `spec` on `setup`: the whole simplification, recorded in `spec.out`. `observer`
/// hears warnings, notes and iterations as they come; `cancel` stops every long stage within
/// a second, keeping what is recorded ([`AppError::Cancelled`]).
pub fn execute(
    setup: &mut Setup,
    spec: &RunSpec,
    observer: &dyn Observer,
    cancel: &Cancel,
) -> Result<RunOutcome, AppError> {
    let start = Instant::now();
    let objective = setup.model.stability.objective;
    let budget = check_spec(setup, spec)?;
    let keep = spec
        .keep
        .clone()
        .or_else(|| setup.inputs.example.as_ref().map(|e| e.keep.clone()))
        .unwrap_or_default();
    check_curve_ids(Opt::Keep, &keep, setup.curve_count())?;
    if spec.certify && objective != Objective::Lambda {
        return Err(AppError::usage(message![
            Opt::Certify,
            " with ",
            given(Opt::Objective, objective.name()),
            ": the certificate bounds λ_fix, the paper's objective at the full network's \
             equilibrium, and its relaxation does not model the mass metric of the first \
             natural frequency (it changes with the set of curves); drop ",
            Opt::Certify,
            ", or use ",
            given(Opt::Objective, "lambda")
        ]));
    }
    let mut constraint_params = spec.constraints.clone();
    constraint_params.groups = match &spec.groups_file {
        Some(path) => read_groups(path)?,
        None => Vec::new(),
    };
    constraint_params
        .groups
        .extend(spec.constraints.groups.iter().cloned());
    constraint_params
        .groups
        .extend(setup.inputs.groups.iter().cloned());
    constraint_params.validate().map_err(AppError::Usage)?;
    // Held to the end of the run: another run into the folder is refused meanwhile.
    let (_lock, fresh) = folder::claim(&spec.out, spec.resume, spec.force, observer)?;
    let analyzer = setup.analyzer()?;
    for w in setup.build_warnings() {
        observer.warning(&w);
    }
    let network = analyzer.network();
    let n = network.rods.len();
    let total = network.total_length(&(0..n).collect::<Vec<_>>());
    let budget_length = budget.length(total);
    let info = setup.built().expect("built by the analyzer").1.clone();
    for w in notes::start_warnings(network, &info, &keep, budget_length, total) {
        observer.warning(&w);
    }
    let mesh = setup.inputs.mesh.as_ref();
    let unit = setup
        .model
        .physical
        .as_ref()
        .map(|p| p.physical.units.symbol());
    let search = Search::new(
        network,
        mesh,
        budget,
        keep,
        constraint_params,
        spec.default_constraints,
        unit,
        observer,
    )?;
    let params = &search.greedy;
    let run_setup = RunSetup {
        input: setup.inputs.description.clone(),
        build: setup.inputs.build.clone(),
        stability: setup.model.stability.clone(),
        greedy: params.clone(),
        network: info,
        total_length: total,
        constraints: search.settings.clone(),
        physical: setup.model.physical_options.clone(),
        physical_model: setup.model.physical.as_ref().map(PhysicalModel::of),
    };
    let opened = open_writer(
        spec,
        fresh.as_ref(),
        network,
        run_setup,
        mesh,
        budget_length,
        observer,
    )?;
    let Some((writer, resume_point)) = opened else {
        let result = ResultFile::read(&spec.out)?;
        // A run stopped while its pictures were drawn is complete without them.
        if spec.pictures && !spec.out.join("viewer.html").is_file() {
            write_pictures(&spec.out, observer, &Deflections::default());
        }
        let slide = slide_after(spec, observer, cancel)?;
        return Ok(RunOutcome {
            folder: spec.out.clone(),
            result,
            already_complete: true,
            seconds: AfterSeconds::default(),
            wall_seconds: start.elapsed().as_secs_f64(),
            slide,
        });
    };
    if let Some(mesh) = mesh {
        writer.write_mesh(mesh)?;
    }
    // The viewer's gravity deflections are solved on a thread of their own as the
    // iterations come.
    let ahead = (spec.pictures).then(|| {
        GravityAhead::start(
            network.clone(),
            setup.model.stability.clone(),
            analyzer.model().pattern().clone(),
        )
    });
    let progress = |k: usize, r: &crate::simplify::greedy::IterationRecord, e: &Evaluation| {
        observer.iteration(r, total, budget_length);
        if let Some(a) = &ahead {
            a.submit(k, &r.curves, &e.displacement, e.symbolic());
        }
    };
    let mut writer = writer.with_cancel(cancel.clone()).with_progress(&progress);
    let outcome = {
        let _stage = StageGuard::start(observer, Stage::Greedy);
        greedy(
            &analyzer,
            params,
            Some(&search.constraints),
            resume_point,
            &mut writer,
        )
    };
    let outcome = outcome.map_err(|e| match e {
        SimplifyError::Cancelled => AppError::Cancelled {
            stage: Stage::Greedy,
            kept: writer.result().iterations.len(),
            folder: spec.out.clone(),
        },
        SimplifyError::Params(m) => AppError::Usage(m),
        e => AppError::Failed(e.to_string()),
    })?;
    for w in crate::run_folder::unrelaxed(&outcome.iterations, analyzer.objective())
        .into_iter()
        .chain(crate::run_folder::unstable(
            &outcome.iterations,
            analyzer.objective(),
        ))
        .map(Message::from)
        .chain(notes::budget_unmet(&outcome, budget_length))
    {
        observer.warning(&w);
    }
    let after = after::After {
        local_search: spec.local_search || spec.alternatives > 0,
        alternatives: spec.alternatives,
        certificate: spec.certify,
        certificate_nodes: spec.certificate_nodes,
    };
    let seconds = after.run(
        &analyzer,
        &search,
        &outcome,
        &mut writer,
        &spec.out,
        observer,
        cancel,
    )?;
    let timings = serde_json::json!({
        "total_seconds": start.elapsed().as_secs_f64(),
        "greedy": outcome.timings,
        "certificate_seconds": spec.certify.then_some(seconds.certificate),
        "local_search_seconds": after.local_search.then_some(seconds.local_search),
        "alternatives_seconds": (spec.alternatives > 0).then_some(seconds.alternatives),
        "threads": rayon::current_num_threads(),
    });
    writer.finish(&outcome, &timings)?;
    let result = writer.result().clone();
    drop(writer);
    if let Some(a) = ahead {
        write_pictures(&spec.out, observer, &a.finish());
    }
    let slide = slide_after(spec, observer, cancel)?;
    Ok(RunOutcome {
        folder: spec.out.clone(),
        result,
        already_complete: false,
        seconds,
        wall_seconds: start.elapsed().as_secs_f64(),
        slide,
    })
}

/// Slides the finished run's answer into its `slide/` folder when `spec` asks for it.
fn slide_after(
    spec: &RunSpec,
    observer: &dyn Observer,
    cancel: &Cancel,
) -> Result<Option<crate::run_folder::SlideRecord>, AppError> {
    let Some(slide) = &spec.slide else {
        return Ok(None);
    };
    let slide = super::SlideSpec {
        from: spec.out.clone(),
        out: spec.out.join("slide"),
        pictures: spec.pictures,
        force: true,
        ..slide.clone()
    };
    Ok(Some(super::slide(&slide, observer, cancel)?.record))
}

/// The budget of `spec` (or the example's), checked with the steps asked for.
fn check_spec(setup: &Setup, spec: &RunSpec) -> Result<Budget, AppError> {
    let budget = match (spec.budget, &setup.inputs.example) {
        (Some(b), _) => b,
        (None, Some(e)) => Budget::Fraction(e.budget),
        (None, None) => {
            return Err(AppError::usage(message![
                "give a budget: ",
                Opt::Budget,
                " FRACTION or ",
                Opt::BudgetLength,
                " L"
            ]));
        }
    };
    let opt = match budget {
        Budget::Fraction(f) => given(Opt::Budget, f),
        Budget::Length(l) => given(Opt::BudgetLength, l),
    };
    budget
        .validate()
        .map_err(|e| AppError::Usage(e.prefixed([opt, ": ".into()])))?;
    if spec.alternatives > MAX_ALTERNATIVES {
        return Err(AppError::usage(message![
            given(Opt::Alternatives, spec.alternatives),
            format!(": at most {MAX_ALTERNATIVES}")
        ]));
    }
    if let Some(nodes) = spec.certificate_nodes
        && nodes > MAX_CERTIFICATE_NODES
    {
        return Err(AppError::usage(message![
            given(Opt::CertificateNodes, nodes),
            format!(": at most {MAX_CERTIFICATE_NODES}")
        ]));
    }
    Ok(budget)
}

/// The run folder's writer and the point to resume from: a new folder, or with `resume` the
/// recorded run in `out`. `None` when that run is already complete (and asked for no step it
/// lacks).
fn open_writer<'a>(
    spec: &RunSpec,
    fresh: Option<&crate::run_folder::folder::FreshStart>,
    network: &'a Network,
    setup: RunSetup,
    mesh: Option<&crate::io::TriMesh>,
    budget: f64,
    observer: &dyn Observer,
) -> Result<Option<(OutputWriter<'a>, Option<ResumePoint>)>, AppError> {
    let out = &spec.out;
    if !(spec.resume && out.join("result.json").is_file()) {
        if let Some(fresh) = fresh
            && let Some(note) = fresh.apply().map_err(|e| AppError::Usage(e.message()))?
        {
            observer.note(&Message::from(note));
        }
        let writer = OutputWriter::create(out, network, setup, budget)?;
        return Ok(Some((writer, None)));
    }
    // Whatever stops a resume is for the user to fix (another folder, the same options).
    let (writer, point) =
        OutputWriter::resume(out, network, &setup, mesh).map_err(|e| match e {
            RunFolderError::Resume(m) => AppError::Usage(m),
            e => AppError::usage(e.to_string()),
        })?;
    for w in writer.warnings() {
        observer.warning(&Message::from(w.clone()));
    }
    match &point {
        None if writer.result().complete => {
            notes::refuse_missing_steps(writer.result(), spec, out)?;
            observer.note(&Message::from(format!(
                "{}: the run is already complete",
                out.display()
            )));
            return Ok(None);
        }
        Some(p) => observer.note(&Message::from(format!(
            "resuming after iteration {} ({} curves)",
            p.iterations.len() - 1,
            p.iterations.last().map_or(0, |i| i.curves.len())
        ))),
        None => {}
    }
    Ok(Some((writer, point)))
}

/// Writes the pictures, viewer page (last) and fabrication table of the finished run in `out`,
/// with the gravity deflections solved `ahead`. A failure leaves the run's results intact, so
/// it is a warning.
pub(crate) fn write_pictures(out: &Path, observer: &dyn Observer, ahead: &Deflections) {
    match crate::report::viewer::write_run_outputs_with(out, ahead) {
        Ok(o) => {
            for w in o.warnings {
                observer.warning(&Message::from(w));
            }
        }
        Err(e) => observer.warning(&Message::from(format!(
            "pictures and viewer not written: {e}"
        ))),
    }
}

//! Sliding a run's answer on its surface ([`crate::slide`]): [`SlideSpec`] (the run folder it
//! starts from, the largest move, the ends, the pinned curves, the folder of the slid run) and
//! [`slide`], which reads the run, searches the moves, and records the slid network as a run
//! of its own: its curves are the moved curves, its answer (source `slide`) the whole slid
//! network, and its `result.json`'s `slide` object says how it got there; the network it
//! started from is kept beside it (`before.obj`) and in the run it came from.

use super::inputs::Inputs;
use super::model::Model;
use super::observer::{Observer, StageGuard};
use super::run::{RunOutcome, RunSpec, execute, write_pictures};
use super::setup::{Setup, check_curve_ids};
use super::{AppError, Stage};
use crate::cancel::Cancel;
use crate::constraints::{ConstraintParams, Constraints, SymmetryOption};
use crate::io::{Polyline, write_atomic};
use crate::material::RestShape;
use crate::network::BuildParams;
use crate::physics::PhysicalParams;
use crate::run_folder::schema::objective_name;
use crate::run_folder::{
    InputDescription, ResultFile, RunFolder, SlideCurve, SlideRecord, network_polylines,
};
use crate::simplify::Budget;
use crate::slide::{MaxMove, SlideError, SlideParams, SlideProblem, Slider};
use crate::words::{Message, Opt, message};
use std::path::PathBuf;
use std::time::Instant;

/// The most rounds of local search and sliding ([`SlideSpec::rounds`]).
pub const MAX_SLIDE_ROUNDS: usize = 100;

/// What sliding does.
#[derive(Clone, Debug, PartialEq)]
pub struct SlideSpec {
    /// The run folder whose answer slides.
    pub from: PathBuf,
    /// The folder of the slid run.
    pub out: PathBuf,
    /// How far a point may move.
    pub max_move: MaxMove,
    /// Every curve end stays where it is.
    pub fixed_ends: bool,
    /// Curves that do not move (ids of the run's network).
    pub pin: Vec<usize>,
    /// Draw the pictures and the viewer.
    pub pictures: bool,
    /// Run into a non-empty folder that is not a curvenet run's.
    pub force: bool,
    /// Rounds of topology and geometry after the slide (0: none): each a local search on the
    /// slid network's curves, then a slide of its network; the best slide of all is the
    /// answer ([`super::rounds`]).
    pub rounds: usize,
}

impl SlideSpec {
    /// Slides the answer of `from` into `out`, every option at its default.
    pub fn new(from: impl Into<PathBuf>, out: impl Into<PathBuf>) -> Self {
        SlideSpec {
            from: from.into(),
            out: out.into(),
            max_move: MaxMove::default(),
            fixed_ends: false,
            pin: Vec::new(),
            pictures: true,
            force: false,
            rounds: 0,
        }
    }
}

/// What sliding did.
#[derive(Clone, Debug)]
pub struct SlideOutcome {
    /// The slid run (its `result.json` holds the `slide` record).
    pub run: RunOutcome,
    /// The record.
    pub record: SlideRecord,
    /// The wall time, seconds.
    pub wall_seconds: f64,
}

/// Slides the answer of the run in `spec.from` on its surface and records the slid network
/// as the run in `spec.out`, then runs the rounds `spec.rounds` asks for. `observer` hears
/// each step; `cancel` stops the search within a second, the best network so far recorded
/// ([`AppError::Cancelled`] after it is).
pub fn slide(
    spec: &SlideSpec,
    observer: &dyn Observer,
    cancel: &Cancel,
) -> Result<SlideOutcome, AppError> {
    let start = Instant::now();
    if spec.rounds > MAX_SLIDE_ROUNDS {
        return Err(AppError::usage(message![
            Opt::SlideRounds,
            format!(" is {}: at most {MAX_SLIDE_ROUNDS} rounds", spec.rounds)
        ]));
    }
    let mut outcome = slide_once(spec, None, observer, cancel)?;
    if spec.rounds > 0 {
        super::rounds::run(spec, &mut outcome, observer, cancel)?;
    }
    outcome.wall_seconds = start.elapsed().as_secs_f64();
    Ok(outcome)
}

/// One slide: the answer of the run in `spec.from` slid and recorded in `spec.out`. `drawn`,
/// when given, holds each curve of that run as the designer drew it (by its id), which the
/// largest move is measured from (the round's network slid again: [`super::rounds`]); else the
/// run's own curves are.
pub(super) fn slide_once(
    spec: &SlideSpec,
    drawn: Option<&[Polyline]>,
    observer: &dyn Observer,
    cancel: &Cancel,
) -> Result<SlideOutcome, AppError> {
    let start = Instant::now();
    let run = RunFolder::open(&spec.from).map_err(|e| match e.is_input() {
        true => AppError::Usage(Message::from(e.to_string())),
        false => AppError::Failed(e.to_string()),
    })?;
    // A run without an answer (no stable network within the budget) slides its final
    // network: sliding may make it stable.
    let (curves, lambda_recorded) = match (&run.result.answer, &run.result.final_network) {
        (Some(a), _) => (a.found.curves.clone(), a.found.lambda),
        (None, Some(f)) => {
            observer.note(&Message::from(format!(
                "{}: the run has no answer; its final network slides",
                spec.from.display()
            )));
            (f.curves.clone(), f.lambda)
        }
        (None, None) => {
            return Err(AppError::usage(format!(
                "{}: the run recorded no network to slide (it is not complete)",
                spec.from.display()
            )));
        }
    };
    let n = run.network.rods.len();
    check_curve_ids(Opt::Pin, &spec.pin, n)?;
    // The slid run's folder is checked before the search, which takes a while.
    if spec.out == spec.from {
        return Err(AppError::usage(message![
            Opt::Out,
            " names the run folder that slides: give another folder for the slid run"
        ]));
    }
    if spec.out.is_dir() {
        crate::run_folder::folder::fresh_start(&spec.out, spec.force)
            .map_err(|e| AppError::Usage(e.message()))?;
    }
    let curves = &curves;
    let setup = &run.result.setup;
    let budget = run.result.budget;
    // Curves that stay: the keep list; groups and symmetry orbits move together (ties).
    let position = |ids: &[usize]| -> Vec<usize> {
        (curves.iter().enumerate())
            .filter(|(_, c)| ids.contains(c))
            .map(|(i, _)| i)
            .collect()
    };
    let drawn_before = drawn;
    let drawn = network_polylines(&run.network, curves, None);
    let mut fixed = position(&setup.greedy.keep);
    let mut ties = Vec::new();
    let c = &setup.constraints;
    if c.groups.iter().any(|g| g.curves.len() > 1) || c.symmetry != SymmetryOption::None {
        let keep = &setup.greedy.keep;
        let bound = Constraints::new(&run.network, run.mesh.as_ref(), c, budget, keep)
            .map_err(|e| AppError::Usage(e.message()))?;
        let (tied, stay) = crate::slide::ties::ties_of(&bound, curves, &drawn);
        ties = tied;
        fixed.extend(stay);
    }
    let physical = physical_of(&run, curves)?;
    let problem = SlideProblem {
        physical,
        drawn: drawn_before
            .map_or_else(Vec::new, |d| curves.iter().map(|&c| d[c].clone()).collect()),
        curves: drawn,
        ids: curves.clone(),
        build: build_for(&setup.build, curves),
        stability: setup.stability.clone(),
        budget,
        fixed,
        ties,
        constraints: ConstraintParams {
            groups: Vec::new(),
            symmetry: SymmetryOption::None,
            ..c.clone()
        },
    };
    let params = SlideParams {
        max_move: spec.max_move,
        fixed_ends: spec.fixed_ends,
        pinned: position(&spec.pin),
        ..SlideParams::default()
    };
    let slider = Slider::new(problem, run.mesh.as_ref(), params).map_err(slide_error)?;
    let outcome = {
        let _stage = StageGuard::start(observer, Stage::Slide);
        slider
            .run(cancel, &|s| observer.slide_step(s))
            .map_err(slide_error)?
    };
    let (before, after) = (&outcome.before, &outcome.after);
    let record = SlideRecord {
        from: spec.from.display().to_string(),
        objective: objective_name(setup.stability.objective).to_string(),
        lambda_before: before.lambda,
        lambda_after: after.lambda,
        lambda_recorded,
        max_move: outcome.max_move,
        largest_move: after.moves.iter().copied().fold(0.0, f64::max),
        joints_added: outcome.joints_added,
        joints_removed: outcome.joints_removed,
        length_before: before.length,
        length_after: after.length,
        budget,
        fixed_ends: spec.fixed_ends,
        curves: (curves.iter().enumerate())
            .map(|(i, &id)| SlideCurve {
                from: id,
                free: slider.moving(i),
                largest_move: after.moves[i],
                coefficients: outcome.coefficients[i].clone(),
            })
            .collect(),
        evaluations: outcome.search.evaluations,
        sweeps: outcome.search.sweeps,
        steps: outcome.search.steps.clone(),
        stopped: outcome.search.cancelled,
        rounds: Vec::new(),
        answer_round: None,
        deviation: after.deviation,
    };
    // Point loads go with the curves they act on.
    let loads = (run.result.setup.physical_model.as_ref())
        .and_then(|m| m.loads.as_ref())
        .map(|l| crate::slide::loads::follow(l, &before.curves, &after.curves));
    let mut recorded = record_network(
        after.curves.clone(),
        curves,
        &run,
        budget.max(after.length),
        loads,
        &spec.out,
        spec.force,
    )?;
    let result = &mut recorded.result;
    if let Some(a) = result.answer.as_mut() {
        a.found.source = "slide".into();
    }
    result.slide = Some(record.clone());
    write_result(&spec.out, result)?;
    let before_obj = crate::io::curves_to_obj(&before.curves);
    let path = spec.out.join("before.obj");
    write_atomic(&path, before_obj.as_bytes())
        .map_err(|e| AppError::Failed(format!("{}: {e}", path.display())))?;
    if spec.pictures {
        write_pictures(&spec.out, observer, &Default::default());
    }
    if record.stopped {
        return Err(AppError::Cancelled {
            stage: Stage::Slide,
            kept: 1,
            folder: spec.out.clone(),
        });
    }
    Ok(SlideOutcome {
        run: recorded,
        record,
        wall_seconds: start.elapsed().as_secs_f64(),
    })
}

/// The build parameters of the curves `ids` of a network built with `build`, as a network of
/// their own: each curve keeps its ends' supports and the surface's directions at its ends.
pub(super) fn build_for(build: &BuildParams, ids: &[usize]) -> BuildParams {
    fn pick<T: Clone>(all: &[[Option<T>; 2]], ids: &[usize]) -> Vec<[Option<T>; 2]> {
        match all.is_empty() {
            true => Vec::new(),
            false => (ids.iter())
                .map(|&c| all.get(c).cloned().unwrap_or([None, None]))
                .collect(),
        }
    }
    BuildParams {
        ends: pick(&build.ends, ids),
        end_frames: pick(&build.end_frames, ids),
        ..build.clone()
    }
}

/// `curves` (the curves `ids` of the run `run`, moved) recorded as a run of their own in
/// `out`, with the set-up of `run` (its mesh, build and objective; each curve's end supports,
/// material, section and rest shape its own; in the physical mode `loads` its load cases),
/// every curve kept, `budget` its budget.
pub(super) fn record_network(
    curves: Vec<Polyline>,
    ids: &[usize],
    run: &RunFolder,
    budget: f64,
    loads: Option<crate::physics::cases::Loads>,
    out: &std::path::Path,
    force: bool,
) -> Result<RunOutcome, AppError> {
    let setup = &run.result.setup;
    let from = &run.dir;
    let inputs = Inputs {
        curves,
        mesh: run.mesh.clone(),
        build: build_for(&setup.build, ids),
        description: InputDescription {
            example: setup.input.example.clone(),
            mesh: Some(from.join("mesh.obj").display().to_string()),
            curve_files: vec![from.join("network.json").display().to_string()],
            scale: 1.0,
        },
        groups: Vec::new(),
        specs: Vec::new(),
        file_units: None,
        warnings: Vec::new(),
        example: None,
    };
    let k = inputs.curves.len();
    let mut model = model_of(run, ids)?;
    if let Some(p) = model.physical.as_mut() {
        p.loads = loads;
    }
    let mut slid = Setup::from_parts(inputs, model);
    let run_spec = RunSpec {
        budget: Some(Budget::Length(budget)),
        keep: Some((0..k).collect()),
        pictures: false,
        force,
        ..RunSpec::new(out)
    };
    execute(&mut slid, &run_spec, &super::Silent, &Cancel::never())
}

/// Rewrites `dir/result.json` (and its summary) with `result`.
pub(super) fn write_result(dir: &std::path::Path, result: &ResultFile) -> Result<(), AppError> {
    let mut text =
        serde_json::to_vec_pretty(result).map_err(|e| AppError::Failed(e.to_string()))?;
    text.push(b'\n');
    for (name, bytes) in [
        ("result.json", text),
        (
            "summary.txt",
            crate::run_folder::summary(result).into_bytes(),
        ),
    ] {
        let path = dir.join(name);
        write_atomic(&path, &bytes)
            .map_err(|e| AppError::Failed(format!("{}: {e}", path.display())))?;
    }
    Ok(())
}

/// A slider's error as the application layer's.
fn slide_error(e: SlideError) -> AppError {
    match e {
        SlideError::Failed(m) => AppError::Failed(m),
        e => AppError::Usage(e.message()),
    }
}

/// The model of the run `run` (its objective; in the physical mode its physical model) for a
/// network of its curves `ids` (in that order), without load cases.
pub(super) fn model_of(run: &RunFolder, ids: &[usize]) -> Result<Model, AppError> {
    let setup = &run.result.setup;
    Ok(Model {
        stability: setup.stability.clone(),
        physical: physical_of(run, ids)?,
        physical_options: setup.physical.clone(),
    })
}

/// The physical mode's parameters of the run `run` for a network of its curves `ids`, in
/// that order (`None` in the paper's mode): a curve keeps its own material and section and
/// its rest shape (a pre-bent curve is pre-bent as it now lies), by its id. Without load
/// cases: the searches' analyses carry none, and a slid run's are placed by
/// [`crate::slide::loads::follow`].
fn physical_of(run: &RunFolder, ids: &[usize]) -> Result<Option<PhysicalParams>, AppError> {
    let setup = &run.result.setup;
    let (Some(options), Some(model)) = (&setup.physical, &setup.physical_model) else {
        return Ok(None);
    };
    // The load cases are the run's record's (its loads file is not read again).
    let options = crate::physics::PhysicalOptions {
        loads: None,
        ..options.clone()
    };
    let resolved = options.resolve(None, &[]).map_err(AppError::Usage)?;
    Ok(resolved.map(|mut p| {
        p.physical = model.physical.clone();
        p.physical.curves = model.physical.overrides_for(ids);
        p.rest = (ids.iter())
            .map(|id| match model.pre_bent.contains(id) {
                true => RestShape::PreBent,
                false => RestShape::Straight,
            })
            .collect();
        p.frequencies = setup.stability.eigen.count;
        p.loads = None;
        p
    }))
}

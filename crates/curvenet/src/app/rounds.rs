//! Topology and geometry together: the rounds after a slide ([`super::SlideSpec::rounds`]).
//!
//! One round takes the network the last slide made and runs the local search over the curves
//! of the run the first slide started from, the slid curves in place of their drawn shapes
//! (so it may add curves that were not chosen, drop or swap slid ones), from the slid network,
//! under the run's budget, keep list and design constraints; its best network is recorded as
//! a run (`rounds/K/local` in the slid run's folder) and slid again (`rounds/K/slid`), every
//! move still measured from the curve as drawn. Each round's objectives go into the record
//! ([`SlideRound`]). The answer is the best network of every slide, by the objective, the
//! earliest of equals: when a round's is better than the first slide's, the slid run's folder
//! takes that round's slid run (its record the round's slide's own, with every round and
//! `answer_round`) and the first slide is kept in `rounds/0/slid`; a cancelled round leaves the
//! best so far as the answer.

use super::inputs::Inputs;
use super::observer::{Observer, StageGuard};
use super::search::Search;
use super::setup::Setup;
use super::slide::{SlideOutcome, SlideSpec, model_of, record_network, slide_once, write_result};
use super::{AppError, Stage};
use crate::cancel::Cancel;
use crate::run_folder::{InputDescription, RunFolder, SlideRound, network_polylines};
use crate::simplify::Budget;
use crate::simplify::local::local_search;

/// Runs `spec.rounds` rounds after the slide `first` (recorded in `spec.out`), adding each
/// round to its record and to `spec.out`'s `result.json`, then makes the best slide's network
/// the answer (module docs); `first` then describes the folder's run.
pub(super) fn run(
    spec: &SlideSpec,
    first: &mut SlideOutcome,
    observer: &dyn Observer,
    cancel: &Cancel,
) -> Result<(), AppError> {
    let mut rounds = Vec::new();
    let done = run_rounds(spec, first, &mut rounds, observer, cancel);
    // The best of every slide (the first slide's is round 0): a later one only for a gain.
    let mut best = (0, first.record.lambda_after);
    for r in &rounds {
        if crate::slide::is_gain(r.slid, best.1) {
            best = (r.round, r.slid);
        }
    }
    // A signal that comes during the swap of folders and the record after it ends the process
    // once they are done, so that the folder is whole.
    let _whole = (best.0 > 0).then(crate::io::hold_exit);
    if best.0 > 0 {
        adopt_round(spec, best.0, first)?;
    }
    first.record.rounds = rounds;
    first.record.answer_round = Some(best.0);
    let result = &mut first.run.result;
    result.slide = Some(first.record.clone());
    write_result(&spec.out, result)?;
    done
}

/// The slid run of round `round` made the run in `spec.out`: the first slide's files moved to
/// `rounds/0/slid`, the round's copied in, and `first` read back from them.
///
/// Neither folder ever holds a mix of two runs under a `result.json`: the first slide's
/// `result.json` leaves first (to a temporary name beside its new place) and takes its place
/// last, the round's is put in place last, each atomically. A process killed in between leaves
/// folders that open as incomplete runs, and every file of both runs is still on disk. (A
/// signal waits for the whole swap: [`run`] holds the exit.)
fn adopt_round(spec: &SlideSpec, round: usize, first: &mut SlideOutcome) -> Result<(), AppError> {
    use crate::run_layout::{ROUNDS, round_folder};
    use std::path::Path;
    const RESULT_FILE: &str = "result.json";
    let kept = spec.out.join(round_folder(0)).join("slid");
    let from = spec.out.join(round_folder(round)).join("slid");
    let failed = |p: &Path, e: std::io::Error| AppError::Failed(format!("{}: {e}", p.display()));
    // Every file and folder of a run (its states, modes and iterations too), but the rounds,
    // the lock and `result.json`.
    let entries = |dir: &Path| -> Result<Vec<std::ffi::OsString>, AppError> {
        let mut names = Vec::new();
        for entry in std::fs::read_dir(dir).map_err(|e| failed(dir, e))? {
            let name = entry.map_err(|e| failed(dir, e))?.file_name();
            let skipped = [crate::run_folder::folder::LOCK_FILE, ROUNDS, RESULT_FILE];
            if !skipped.iter().any(|s| name == *s) {
                names.push(name);
            }
        }
        Ok(names)
    };
    // The first slide's own record (as `run_rounds` last wrote it), without the rounds that
    // came after it.
    let mut own = first.run.result.clone();
    if let Some(r) = own.slide.as_mut() {
        r.rounds.clear();
    }
    std::fs::create_dir_all(&kept).map_err(|e| failed(&kept, e))?;
    let parked = kept.join(format!(".{RESULT_FILE}.tmp.adopted"));
    std::fs::rename(spec.out.join(RESULT_FILE), &parked).map_err(|e| failed(&parked, e))?;
    for name in entries(&spec.out)? {
        let target = kept.join(&name);
        std::fs::rename(spec.out.join(&name), &target).map_err(|e| failed(&target, e))?;
    }
    write_result(&kept, &own)?;
    std::fs::remove_file(&parked).map_err(|e| failed(&parked, e))?;
    for name in entries(&from)? {
        let target = spec.out.join(&name);
        copy_tree(&from.join(&name), &target).map_err(|e| failed(&target, e))?;
    }
    let result = from.join(RESULT_FILE);
    let bytes = std::fs::read(&result).map_err(|e| failed(&result, e))?;
    let target = spec.out.join(RESULT_FILE);
    crate::io::write_atomic(&target, &bytes).map_err(|e| failed(&target, e))?;
    let open = open(&spec.out)?;
    let record = (open.result.slide.clone())
        .ok_or_else(|| AppError::Failed(format!("{}: no slide record", from.display())))?;
    first.record = record;
    first.run.result = open.result;
    Ok(())
}

/// The run in `dir`, which this slide wrote (so a failure to read it is no input's fault).
fn open(dir: &std::path::Path) -> Result<RunFolder, AppError> {
    RunFolder::open(dir).map_err(|e| AppError::Failed(e.to_string()))
}

/// Copies the file or folder `from` (with everything in it) to `to`.
fn copy_tree(from: &std::path::Path, to: &std::path::Path) -> std::io::Result<()> {
    if !from.is_dir() {
        return std::fs::copy(from, to).map(|_| ());
    }
    std::fs::create_dir_all(to)?;
    for entry in std::fs::read_dir(from)? {
        let entry = entry?;
        copy_tree(&entry.path(), &to.join(entry.file_name()))?;
    }
    Ok(())
}

/// The rounds themselves, each pushed to `rounds` as it ends (a cancelled round is not).
fn run_rounds(
    spec: &SlideSpec,
    first: &mut SlideOutcome,
    rounds: &mut Vec<SlideRound>,
    observer: &dyn Observer,
    cancel: &Cancel,
) -> Result<(), AppError> {
    let source = open(&spec.from)?;
    let setup = &source.result.setup;
    let n = source.network.rods.len();
    let drawn = network_polylines(&source.network, &(0..n).collect::<Vec<_>>(), None);
    // The network the last slide made: its curves' ids in the source run, and its polylines.
    let mut ids: Vec<usize> = first.record.curves.iter().map(|c| c.from).collect();
    let mut last = spec.out.clone();
    let mut value = first.record.lambda_after;
    for round in 1..=spec.rounds {
        let slid = open(&last)?;
        let k = slid.network.rods.len();
        let mut curves = drawn.clone();
        for (c, p) in network_polylines(&slid.network, &(0..k).collect::<Vec<_>>(), None)
            .into_iter()
            .enumerate()
        {
            curves[ids[c]] = p;
        }
        let inputs = Inputs {
            curves: curves.clone(),
            mesh: source.mesh.clone(),
            build: setup.build.clone(),
            description: InputDescription {
                example: setup.input.example.clone(),
                mesh: None,
                curve_files: Vec::new(),
                scale: 1.0,
            },
            groups: Vec::new(),
            specs: Vec::new(),
            file_units: None,
            warnings: Vec::new(),
            example: None,
        };
        let model = model_of(&source, &(0..n).collect::<Vec<_>>())?;
        let unit = (model.physical.as_ref()).map(|p| p.physical.units.symbol().to_string());
        let mut combined = Setup::from_parts(inputs, model);
        let analyzer = combined.analyzer()?;
        let search = Search::new(
            analyzer.network(),
            source.mesh.as_ref(),
            Budget::Length(source.result.budget),
            setup.greedy.keep.clone(),
            setup.constraints.clone(),
            false,
            unit.as_deref(),
            &super::Silent,
        )?;
        let mut start = ids.clone();
        start.sort_unstable();
        let found = {
            let _stage = StageGuard::start(observer, Stage::LocalSearch);
            local_search(
                &analyzer,
                &search.local(),
                Some(&search.constraints),
                &start,
                cancel,
            )
        };
        let stopped = || AppError::Cancelled {
            stage: Stage::LocalSearch,
            kept: rounds.len(),
            folder: spec.out.clone(),
        };
        if cancel.is_cancelled() {
            return Err(stopped());
        }
        let found = found.map_err(|e| AppError::Failed(e.to_string()))?.best;
        let folder = crate::run_layout::round_folder(round);
        let local_dir = spec.out.join(&folder).join("local");
        let chosen: Vec<_> = found.curves.iter().map(|&c| curves[c].clone()).collect();
        // The last slid run's load cases, placed on its curves, which the local search's
        // network holds as they are.
        let loads = (slid.result.setup.physical_model.as_ref()).and_then(|m| m.loads.clone());
        record_network(
            chosen,
            &found.curves,
            &source,
            source.result.budget.max(found.length),
            loads,
            &local_dir,
            true,
        )?;
        let again = SlideSpec {
            from: local_dir,
            out: spec.out.join(&folder).join("slid"),
            force: true,
            rounds: 0,
            ..spec.clone()
        };
        let origin: Vec<_> = found.curves.iter().map(|&c| drawn[c].clone()).collect();
        let done = slide_once(&again, Some(&origin), observer, cancel)?;
        rounds.push(SlideRound {
            round,
            start: value,
            local_search: found.lambda,
            slid: done.record.lambda_after,
            curves: found.curves.clone(),
            folder,
        });
        ids = (done.record.curves.iter())
            .map(|c| found.curves[c.from])
            .collect();
        value = done.record.lambda_after;
        last = again.out;
        first.record.rounds = rounds.clone();
        let result = &mut first.run.result;
        result.slide = Some(first.record.clone());
        write_result(&spec.out, result)?;
    }
    Ok(())
}

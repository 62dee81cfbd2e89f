//! Topology and geometry together: the rounds after a slide ([`super::SlideSpec::rounds`]).
//!
//! One round takes the network the last slide made and runs the local search over the curves
//! of the run the first slide started from, the slid curves in place of their drawn shapes
//! (so it may add curves that were not chosen, drop or swap slid ones), from the slid network,
//! under the run's budget, keep list and design constraints; its best network is recorded as
//! a run (`rounds/K/local` in the slid run's folder) and slid again (`rounds/K/slid`). Each
//! round's objectives go into the first slide's record ([`SlideRound`]); the last round's
//! `slid` folder holds the final network.

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
/// round to its record and to `spec.out`'s `result.json`.
pub(super) fn run(
    spec: &SlideSpec,
    first: &mut SlideOutcome,
    observer: &dyn Observer,
    cancel: &Cancel,
) -> Result<(), AppError> {
    let open =
        |dir: &std::path::Path| RunFolder::open(dir).map_err(|e| AppError::Failed(e.to_string()));
    let source = open(&spec.from)?;
    let setup = &source.result.setup;
    let n = source.network.rods.len();
    let drawn = network_polylines(&source.network, &(0..n).collect::<Vec<_>>(), None);
    // The network the last slide made: its curves' ids in the source run, and its polylines.
    let mut ids: Vec<usize> = first.record.curves.iter().map(|c| c.from).collect();
    let mut last = spec.out.clone();
    let mut value = first.record.lambda_after;
    let mut rounds = Vec::new();
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
        let model = model_of(&source, n)?;
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
        let folder = format!("rounds/{round}");
        let local_dir = spec.out.join(&folder).join("local");
        let chosen: Vec<_> = found.curves.iter().map(|&c| curves[c].clone()).collect();
        record_network(
            chosen,
            &found.curves,
            &source,
            source.result.budget.max(found.length),
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
        let done = slide_once(&again, observer, cancel)?;
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

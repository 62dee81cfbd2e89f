//! [`OutputWriter`]: the greedy's hooks that write the run folder as the run goes.

use super::answer::{NetworkState, greedy_offers};
use super::carried::{CARRIED_FILES, carried_bytes, carried_file, read_carried};
use super::schema::{FinalRecord, LocalSearchRecord, ResultFile, RunSetup, VERSION};
use super::summary::summary;
use super::{RunFolderError, f64_bytes, network_polylines, read_f64_file};
use crate::constraints::Constraints;
use crate::constraints::answer::{Answer, NoAnswer, choose};
use crate::io;
use crate::network::Network;
use crate::run_layout;
use crate::simplify::certificate::Certificate;
use crate::simplify::greedy::{GreedyHooks, GreedyOutcome, IterationRecord, ResumePoint};
use crate::stability::Evaluation;
use crate::stability::candidates::Carried;
use crate::words::{Opt, message};
use std::path::{Path, PathBuf};

/// The OBJ of a recorded network at displacements `u`, with a comment line first naming it
/// unstable when it is: what to format, and the formatting (left to the writer thread).
fn record_obj(
    network: &Network,
    record: &IterationRecord,
    u: &[f64],
) -> impl Fn() -> Result<Vec<u8>, String> + Send + Sync + 'static {
    let lines = network_polylines(network, &record.curves, Some(u));
    let warning = super::summary::record_instability(record);
    move || {
        let obj = io::curves_to_obj(&lines);
        Ok(match &warning {
            Some(w) => format!("# WARNING: this network is {w}; it cannot stand as built\n{obj}"),
            None => obj,
        }
        .into_bytes())
    }
}

fn io_err(path: &Path, e: std::io::Error) -> RunFolderError {
    RunFolderError::io(path, e)
}

/// An answer given to [`OutputWriter::set_answer`] and its equilibrium and mode (when it is
/// not one of the greedy's iterations).
type GivenAnswer = (Result<Answer, NoAnswer>, Option<NetworkState>);

/// What [`OutputWriter::with_progress`] calls after each iteration is recorded: the
/// iteration's index, its record and its evaluation (the equilibrium, the spectrum and the
/// structure's symbolic analysis).
pub type Progress<'a> = dyn Fn(usize, &IterationRecord, &Evaluation) + Sync + 'a;

/// Writes a run's folder as the greedy goes (a [`GreedyHooks`]).
///
/// The files are written on a background thread ([`io::BackgroundWriter`]), in the order the
/// run produces them, while the greedy computes the next iteration; [`Self::flush`] (called
/// by the greedy before it returns, [`GreedyHooks::flush`]) and [`Self::finish`] wait for
/// them, and dropping the writer writes whatever is still queued.
pub struct OutputWriter<'a> {
    dir: PathBuf,
    network: &'a Network,
    result: ResultFile,
    files: io::BackgroundWriter,
    /// What a resume found that the run can go on without ([`Self::warnings`]).
    warnings: Vec<String>,
    cancel: crate::cancel::Cancel,
    /// Called after each iteration is recorded (e.g. to move a progress bar).
    progress: Option<&'a Progress<'a>>,
    /// The answer given by [`Self::set_answer`], with its equilibrium when it is not one of
    /// the greedy's iterations.
    answer: Option<GivenAnswer>,
    /// The alternatives given by [`Self::set_alternatives`], each with its equilibrium and
    /// mode when it is not one of the greedy's iterations.
    alternatives: Vec<(Answer, Option<NetworkState>)>,
}

impl std::fmt::Debug for OutputWriter<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OutputWriter")
            .field("dir", &self.dir)
            .finish_non_exhaustive()
    }
}

impl<'a> OutputWriter<'a> {
    /// Creates the folder and writes `network.json` and an empty `result.json`.
    pub fn create(
        dir: &Path,
        network: &'a Network,
        setup: RunSetup,
        budget: f64,
    ) -> Result<Self, RunFolderError> {
        for sub in [
            "",
            run_layout::MODES,
            run_layout::STATES,
            run_layout::ITERATIONS,
        ] {
            let d = dir.join(sub);
            std::fs::create_dir_all(&d).map_err(|e| io_err(&d, e))?;
        }
        let net_path = dir.join("network.json");
        let net_json = serde_json::to_vec(network).map_err(|e| e.to_string())?;
        io::write_atomic(&net_path, &net_json).map_err(|e| io_err(&net_path, e))?;
        let result = ResultFile {
            version: VERSION,
            objective: super::schema::objective_name(setup.stability.objective).into(),
            setup,
            budget,
            complete: false,
            stop: None,
            iterations: Vec::new(),
            final_network: None,
            certificate: None,
            local_search: None,
            answer: None,
            no_answer: None,
            alternatives: Vec::new(),
            slide: None,
        };
        let w = Self::new(dir, network, result, Vec::new())?;
        w.write_result()?;
        Ok(w)
    }

    /// Continues an interrupted run in `dir`: checks that it was made with `setup` (and
    /// `mesh`, against the run's `mesh.obj`) and returns the writer and the point to resume
    /// from (`None` if the run already completed).
    pub fn resume(
        dir: &Path,
        network: &'a Network,
        setup: &RunSetup,
        mesh: Option<&crate::io::TriMesh>,
    ) -> Result<(Self, Option<ResumePoint>), RunFolderError> {
        let result = ResultFile::read(dir)?;
        let mut warnings = Vec::new();
        // Inputs compared by content: the same file by another path resumes the run, which
        // keeps its recorded description.
        if let Some(d) =
            super::setup_diff::resume_difference(dir, &result.setup, setup, mesh, network)?
        {
            return Err(RunFolderError::Resume(
                message![format!("{}: cannot resume: ", dir.display())]
                    .then(d)
                    .then(message![
                        "; use another ",
                        Opt::Out,
                        " or drop ",
                        Opt::Resume
                    ]),
            ));
        }
        let point = match result.iterations.last() {
            Some(last) if !result.complete && last.removed.is_some() => {
                let k = result.iterations.len() - 1;
                let n = network.dofs();
                let displacement = read_f64_file(&dir.join(crate::run_layout::state_file(k)))?;
                let modes = read_f64_file(&dir.join(crate::run_layout::state_modes_file(k)))?;
                if displacement.len() != n || modes.is_empty() || modes.len() % n != 0 {
                    return Err(RunFolderError::Invalid {
                        file: crate::run_layout::state_file(k),
                        problem: "does not match the network".into(),
                    });
                }
                let modes = faer::Mat::from_fn(n, modes.len() / n, |i, j| modes[j * n + i]);
                let carried = read_carried(dir, network.rods.len(), n, k, &mut warnings);
                Some(ResumePoint {
                    iterations: result.iterations.clone(),
                    displacement,
                    modes,
                    carried,
                })
            }
            _ => None,
        };
        let mut result = result;
        if point.is_none() && !result.complete {
            // Nothing usable was recorded: start over.
            result.iterations.clear();
        }
        Ok((Self::new(dir, network, result, warnings)?, point))
    }

    /// A writer of `result` into `dir`, with its thread started.
    fn new(
        dir: &Path,
        network: &'a Network,
        result: ResultFile,
        warnings: Vec<String>,
    ) -> Result<Self, RunFolderError> {
        let files = io::BackgroundWriter::new().map_err(|e| {
            RunFolderError::Failed(format!("cannot start the output writer thread: {e}"))
        })?;
        Ok(OutputWriter {
            dir: dir.to_path_buf(),
            network,
            result,
            files,
            warnings,
            cancel: crate::cancel::Cancel::never(),
            progress: None,
            answer: None,
            alternatives: Vec::new(),
        })
    }

    /// Writes the surface mesh (scene units) as `mesh.obj`, for viewers and pictures.
    pub fn write_mesh(&self, mesh: &crate::io::TriMesh) -> Result<(), RunFolderError> {
        self.write("mesh.obj", io::mesh_to_obj(mesh))
    }

    /// Polls `cancel` (the run's token) between candidates and iterations.
    pub fn with_cancel(mut self, cancel: crate::cancel::Cancel) -> Self {
        self.cancel = cancel;
        self
    }

    /// Calls `f` after each iteration is recorded.
    pub fn with_progress(mut self, f: &'a Progress<'a>) -> Self {
        self.progress = Some(f);
        self
    }

    /// What [`Self::resume`] found that the run can go on without (the carried test vectors
    /// of the last recorded iteration missing, damaged or stale); empty for a new run.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The result so far.
    pub fn result(&self) -> &ResultFile {
        &self.result
    }

    /// Queues `result.json` as the result stands now (serialized on the writer thread).
    fn write_result(&self) -> Result<(), RunFolderError> {
        let result = self.result.clone();
        self.write_with("result.json", move || {
            let mut text = serde_json::to_vec_pretty(&result).map_err(|e| e.to_string())?;
            text.push(b'\n');
            Ok(text)
        })
    }

    /// Queues `bytes` for the file `rel` of the folder (written atomically, in order).
    fn write(&self, rel: &str, bytes: impl Into<Vec<u8>>) -> Result<(), RunFolderError> {
        Ok(self.files.submit(self.dir.join(rel), bytes.into())?)
    }

    /// [`Self::write`] of the bytes `make` gives on a background thread (formatting kept off
    /// the computing thread; `make` a pure function of what it captured).
    fn write_with(
        &self,
        rel: &str,
        make: impl Fn() -> Result<Vec<u8>, String> + Send + Sync + 'static,
    ) -> Result<(), RunFolderError> {
        Ok(self.files.submit_with(self.dir.join(rel), make)?)
    }

    /// Waits until every file submitted so far is written; an error names the first file
    /// that could not be.
    pub fn flush(&self) -> Result<(), RunFolderError> {
        Ok(self.files.flush()?)
    }

    /// Sets the certificate of the final network (written by [`Self::finish`]).
    pub fn set_certificate(&mut self, certificate: Option<Certificate>) {
        self.result.certificate = certificate;
    }

    /// Sets the local search's record (written by [`Self::finish`]).
    pub fn set_local_search(&mut self, record: Option<LocalSearchRecord>) {
        self.result.local_search = record;
    }

    /// Sets the answer (written by [`Self::finish`], with `answer.obj`). `state` is the
    /// answer's equilibrium and mode, needed when it is not one of the greedy's iterations
    /// (whose states the folder holds; then `states/answer.bin` and `modes/answer.bin` hold
    /// them). Without it, [`Self::finish`] chooses among the greedy's iterations with no
    /// constraint but the budget and the keep list.
    pub fn set_answer(&mut self, answer: Result<Answer, NoAnswer>, state: Option<NetworkState>) {
        self.answer = Some((answer, state));
    }

    /// Sets the alternatives (written by [`Self::finish`]: `alternatives` in `result.json`,
    /// `alternative-N.obj` from 1, and for those that are not greedy iterations
    /// `states/alternative-N.bin` and `modes/alternative-N.bin`), each with its equilibrium and
    /// mode when it is not one of the greedy's iterations.
    pub fn set_alternatives(&mut self, alternatives: Vec<(Answer, Option<NetworkState>)>) {
        self.alternatives = alternatives;
    }

    /// The equilibrium of a network of the run: `state`'s, else its greedy iteration's.
    fn equilibrium_of(
        &self,
        a: &Answer,
        state: Option<&NetworkState>,
        what: &str,
    ) -> Result<Vec<f64>, RunFolderError> {
        match (a.found.iteration, state) {
            (_, Some(s)) => Ok(s.displacement.clone()),
            (Some(k), None) => read_f64_file(&self.dir.join(crate::run_layout::state_file(k))),
            (None, None) => Err(format!("the {what}'s equilibrium is not known").into()),
        }
    }

    /// Queues `answer.obj` or `alternative-N.obj` (`name`), and the state and mode files
    /// `states/STEM.bin`, `modes/STEM.bin` when `state` is given.
    fn write_network(
        &self,
        stem: &str,
        a: &Answer,
        state: Option<&NetworkState>,
    ) -> Result<(), RunFolderError> {
        let u = self.equilibrium_of(a, state, stem)?;
        let obj = io::curves_to_obj(&network_polylines(self.network, &a.found.curves, Some(&u)));
        self.write(&format!("{stem}.obj"), obj)?;
        if let Some(s) = state {
            self.write(
                &crate::run_layout::tagged_state_file(stem),
                f64_bytes(&s.displacement),
            )?;
            self.write(
                &crate::run_layout::tagged_mode_file(stem),
                f64_bytes(&s.mode),
            )?;
        }
        Ok(())
    }

    /// Removes the files of an earlier run in this folder that this run does not write again:
    /// the answer's own state when the answer is not `own_answer_state`, alternatives past
    /// `count`.
    fn remove_stale(&self, own_answer_state: bool, count: usize) -> Result<(), RunFolderError> {
        let mut stale: Vec<PathBuf> = Vec::new();
        if !own_answer_state {
            stale.push(
                self.dir
                    .join(crate::run_layout::tagged_state_file("answer")),
            );
            stale.push(self.dir.join(crate::run_layout::tagged_mode_file("answer")));
        }
        for sub in ["", run_layout::STATES, run_layout::MODES] {
            let Ok(entries) = std::fs::read_dir(self.dir.join(sub)) else {
                continue;
            };
            for e in entries.flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                let Some(n) = name
                    .strip_prefix("alternative-")
                    .and_then(|r| r.split('.').next())
                    .and_then(|n| n.parse::<usize>().ok())
                else {
                    continue;
                };
                // Top level: `alternative-N.obj` and `.csv`; states and modes only for the
                // alternatives that are not greedy iterations.
                let written = n >= 1
                    && n <= count
                    && (sub.is_empty() || self.alternatives[n - 1].1.is_some());
                if !written {
                    stale.push(e.path());
                }
            }
        }
        for p in stale {
            if p.is_file() {
                std::fs::remove_file(&p).map_err(|e| io_err(&p, e))?;
            }
        }
        Ok(())
    }

    /// Finishes the run: final record, `result.json` complete, `final.obj`, `timings.json`,
    /// `summary.txt`.
    pub fn finish(
        &mut self,
        outcome: &GreedyOutcome,
        timings: &serde_json::Value,
    ) -> Result<(), RunFolderError> {
        self.result.iterations = outcome.iterations.clone();
        let (answer, answer_state) = self.answer.take().unwrap_or_else(|| {
            let keep = &self.result.setup.greedy.keep;
            let c = Constraints::none(self.network, self.result.budget, keep);
            (
                choose(&c, &greedy_offers(&outcome.iterations), 0).answer,
                None,
            )
        });
        (self.result.answer, self.result.no_answer) = match answer {
            Ok(a) => (Some(a), None),
            Err(n) => (None, Some(n)),
        };
        let alternatives = std::mem::take(&mut self.alternatives);
        self.result.alternatives = alternatives.iter().map(|a| a.0.clone()).collect();
        self.alternatives = alternatives;
        self.result.complete = true;
        self.result.stop = Some(outcome.stop);
        let last = (outcome.iterations.last())
            .ok_or_else(|| RunFolderError::Failed("no iteration recorded".into()))?;
        self.result.final_network = Some(FinalRecord {
            curves: last.curves.clone(),
            length: last.length,
            lambda: last.lambda,
        });
        self.write_result()?;
        self.flush()?;
        let k = outcome.iterations.len() - 1;
        let u = read_f64_file(&self.dir.join(crate::run_layout::state_file(k)))?;
        self.write_with("final.obj", record_obj(self.network, last, &u))?;
        let answer_path = self.dir.join("answer.obj");
        self.remove_stale(answer_state.is_some(), self.alternatives.len())?;
        for (i, (a, state)) in self.alternatives.iter().enumerate() {
            self.write_network(&format!("alternative-{}", i + 1), a, state.as_ref())?;
        }
        match &self.result.answer {
            Some(a) => self.write_network("answer", a, answer_state.as_ref())?,
            // A folder run again (--force, --resume) keeps no answer of an earlier run.
            None if answer_path.exists() => {
                std::fs::remove_file(&answer_path).map_err(|e| io_err(&answer_path, e))?;
            }
            None => {}
        }
        let mut t = serde_json::to_vec_pretty(timings).map_err(|e| e.to_string())?;
        t.push(b'\n');
        self.write("timings.json", t)?;
        self.write("summary.txt", summary(&self.result))?;
        self.flush()?;
        // Only a resume needs them.
        for f in CARRIED_FILES {
            let carried = self.dir.join(f);
            if carried.exists() {
                std::fs::remove_file(&carried).map_err(|e| io_err(&carried, e))?;
            }
        }
        Ok(())
    }
}

impl GreedyHooks for OutputWriter<'_> {
    fn carried(&mut self, carried: &Carried) -> Result<(), String> {
        // Handed on by the iteration about to be recorded as number `len`: its own slot, so
        // the last recorded iteration's survives until this one is recorded.
        let k = self.result.iterations.len();
        self.write(carried_file(k), carried_bytes(k, carried))
            .map_err(|e| e.to_string())
    }

    fn iteration(&mut self, record: &IterationRecord, eval: &Evaluation) -> Result<(), String> {
        self.record(record, eval).map_err(|e| e.to_string())
    }

    fn flush(&mut self) -> Result<(), String> {
        OutputWriter::flush(self).map_err(|e| e.to_string())
    }

    fn cancelled(&self) -> bool {
        self.cancel.is_cancelled()
    }
}

impl OutputWriter<'_> {
    /// Queues an iteration's files and the record with it.
    fn record(
        &mut self,
        record: &IterationRecord,
        eval: &Evaluation,
    ) -> Result<(), RunFolderError> {
        let k = self.result.iterations.len();
        let v = &eval.spectrum.vectors;
        let mut all = Vec::with_capacity(v.nrows() * v.ncols());
        for j in 0..v.ncols() {
            all.extend(v.col(j).iter().copied());
        }
        // The worst-case mode is the first column.
        self.write(
            &crate::run_layout::mode_file(k),
            f64_bytes(&all[..v.nrows()]),
        )?;
        self.write(
            &crate::run_layout::state_file(k),
            f64_bytes(&eval.displacement),
        )?;
        self.write(&crate::run_layout::state_modes_file(k), f64_bytes(&all))?;
        self.write_with(
            &run_layout::iteration_obj_file(k),
            record_obj(self.network, record, &eval.displacement),
        )?;
        self.result.iterations.push(record.clone());
        self.write_result()?;
        if let Some(p) = self.progress {
            p(k, record, eval);
        }
        Ok(())
    }
}

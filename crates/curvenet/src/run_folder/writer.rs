//! [`OutputWriter`]: the greedy's hooks that write the run folder as the run goes.

use super::answer::greedy_offers;
use super::carried::{CARRIED_FILES, carried_bytes, carried_file, read_carried};
use super::schema::{FinalRecord, LocalSearchRecord, ResultFile, RunSetup, VERSION};
use super::summary::summary;
use super::{f64_bytes, network_polylines, read_f64_file};
use crate::constraints::Constraints;
use crate::constraints::answer::{Answer, NoAnswer, choose};
use crate::io;
use crate::network::Network;
use crate::simplify::certificate::Certificate;
use crate::simplify::greedy::{GreedyHooks, GreedyOutcome, IterationRecord, ResumePoint};
use crate::stability::Evaluation;
use crate::stability::candidates::Carried;
use std::path::{Path, PathBuf};

/// The output folder's writer thread.
fn background() -> Result<io::BackgroundWriter, String> {
    io::BackgroundWriter::new().map_err(|e| format!("cannot start the output writer thread: {e}"))
}

/// An OBJ of a recorded network, with a comment line first naming it unstable when it is.
fn with_instability(record: &IterationRecord, obj: String) -> String {
    match super::summary::record_instability(record) {
        Some(w) => format!("# WARNING: this network is {w}; it cannot stand as built\n{obj}"),
        None => obj,
    }
}

fn io_err(path: &Path, e: std::io::Error) -> String {
    format!("{}: {e}", path.display())
}

/// An answer given to [`OutputWriter::set_answer`] and its equilibrium (when it is not one of
/// the greedy's iterations).
type GivenAnswer = (Result<Answer, NoAnswer>, Option<Vec<f64>>);

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
    cancel: Option<&'a std::sync::atomic::AtomicBool>,
    /// Called after each iteration (e.g. to move a progress bar).
    progress: Option<&'a (dyn Fn(&IterationRecord) + Sync)>,
    /// The answer given by [`Self::set_answer`], with its equilibrium when it is not one of
    /// the greedy's iterations.
    answer: Option<GivenAnswer>,
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
    ) -> Result<Self, String> {
        for sub in ["", "modes", "states", "iterations"] {
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
        };
        let w = OutputWriter {
            dir: dir.to_path_buf(),
            network,
            result,
            files: background()?,
            warnings: Vec::new(),
            cancel: None,
            progress: None,
            answer: None,
        };
        w.write_result()?;
        Ok(w)
    }

    /// Continues an interrupted run in `dir`: checks that it was made with `setup` and returns
    /// the writer and the point to resume from (`None` if the run already completed).
    pub fn resume(
        dir: &Path,
        network: &'a Network,
        setup: &RunSetup,
    ) -> Result<(Self, Option<ResumePoint>), String> {
        let result = ResultFile::read(dir)?;
        let mut warnings = Vec::new();
        // Inputs compared by content: the same file by another path resumes the run, which
        // keeps its recorded description.
        if let Some(d) = super::setup_diff::resume_difference(dir, &result.setup, setup, network)? {
            return Err(format!(
                "{}: cannot resume: {d}; use another --out or drop --resume",
                dir.display()
            ));
        }
        let point = match result.iterations.last() {
            Some(last) if !result.complete && last.removed.is_some() => {
                let k = result.iterations.len() - 1;
                let n = network.dofs();
                let displacement = read_f64_file(&dir.join(format!("states/{k:04}.bin")))?;
                let modes = read_f64_file(&dir.join(format!("states/{k:04}.modes.bin")))?;
                if displacement.len() != n || modes.is_empty() || modes.len() % n != 0 {
                    return Err(format!("states/{k:04}.bin does not match the network"));
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
        Ok((
            OutputWriter {
                dir: dir.to_path_buf(),
                network,
                result,
                files: background()?,
                warnings,
                cancel: None,
                progress: None,
                answer: None,
            },
            point,
        ))
    }

    /// Writes the surface mesh (scene units) as `mesh.obj`, for viewers and pictures.
    pub fn write_mesh(&self, mesh: &crate::io::TriMesh) -> Result<(), String> {
        self.write("mesh.obj", io::mesh_to_obj(mesh))
    }

    /// Polls `flag` for cancellation.
    pub fn with_cancel(mut self, flag: &'a std::sync::atomic::AtomicBool) -> Self {
        self.cancel = Some(flag);
        self
    }

    /// Calls `f` after each iteration.
    pub fn with_progress(mut self, f: &'a (dyn Fn(&IterationRecord) + Sync)) -> Self {
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

    fn write_result(&self) -> Result<(), String> {
        let mut text = serde_json::to_vec_pretty(&self.result).map_err(|e| e.to_string())?;
        text.push(b'\n');
        self.write("result.json", text)
    }

    /// Queues `bytes` for the file `rel` of the folder (written atomically, in order).
    fn write(&self, rel: &str, bytes: impl Into<Vec<u8>>) -> Result<(), String> {
        self.files.submit(self.dir.join(rel), bytes.into())
    }

    /// Waits until every file submitted so far is written; an error names the first file
    /// that could not be.
    pub fn flush(&self) -> Result<(), String> {
        self.files.flush()
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
    /// answer's equilibrium displacements, needed when it is not one of the greedy's
    /// iterations (whose states the folder holds). Without it, [`Self::finish`] chooses among
    /// the greedy's iterations with no constraint but the budget and the keep list.
    pub fn set_answer(&mut self, answer: Result<Answer, NoAnswer>, state: Option<Vec<f64>>) {
        self.answer = Some((answer, state));
    }

    /// Finishes the run: final record, `result.json` complete, `final.obj`, `timings.json`,
    /// `summary.txt`.
    pub fn finish(
        &mut self,
        outcome: &GreedyOutcome,
        timings: &serde_json::Value,
    ) -> Result<(), String> {
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
        self.result.complete = true;
        self.result.stop = Some(outcome.stop);
        let last = outcome.iterations.last().ok_or("no iteration recorded")?;
        self.result.final_network = Some(FinalRecord {
            curves: last.curves.clone(),
            length: last.length,
            lambda: last.lambda,
        });
        self.write_result()?;
        self.flush()?;
        let k = outcome.iterations.len() - 1;
        let u = read_f64_file(&self.dir.join(format!("states/{k:04}.bin")))?;
        let obj = io::curves_to_obj(&network_polylines(self.network, &last.curves, Some(&u)));
        self.write("final.obj", with_instability(last, obj))?;
        let answer_path = self.dir.join("answer.obj");
        match &self.result.answer {
            Some(a) => {
                let u = match (a.iteration, answer_state) {
                    (_, Some(u)) => u,
                    (Some(k), None) => read_f64_file(&self.dir.join(format!("states/{k:04}.bin")))?,
                    (None, None) => return Err("the answer's equilibrium is not known".into()),
                };
                let obj = io::curves_to_obj(&network_polylines(self.network, &a.curves, Some(&u)));
                self.write("answer.obj", obj)?;
            }
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
    }

    fn iteration(&mut self, record: &IterationRecord, eval: &Evaluation) -> Result<(), String> {
        let k = self.result.iterations.len();
        self.write(
            &format!("modes/{k:04}.bin"),
            f64_bytes(
                &eval
                    .spectrum
                    .vectors
                    .col(0)
                    .iter()
                    .copied()
                    .collect::<Vec<_>>(),
            ),
        )?;
        self.write(&format!("states/{k:04}.bin"), f64_bytes(&eval.displacement))?;
        let v = &eval.spectrum.vectors;
        let all: Vec<f64> = (0..v.ncols())
            .flat_map(|j| v.col(j).iter().copied().collect::<Vec<_>>())
            .collect();
        self.write(&format!("states/{k:04}.modes.bin"), f64_bytes(&all))?;
        let obj = io::curves_to_obj(&network_polylines(
            self.network,
            &record.curves,
            Some(&eval.displacement),
        ));
        self.write(
            &format!("iterations/{k:04}.obj"),
            with_instability(record, obj),
        )?;
        self.result.iterations.push(record.clone());
        self.write_result()?;
        if let Some(p) = self.progress {
            p(record);
        }
        Ok(())
    }

    fn flush(&mut self) -> Result<(), String> {
        OutputWriter::flush(self)
    }

    fn cancelled(&self) -> bool {
        self.cancel
            .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
    }
}

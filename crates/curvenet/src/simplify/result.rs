//! The output folder of a simplification run (SPEC §10), written as the run goes.
//!
//! ```text
//! DIR/result.json         every iteration so far; "complete": true once the run finished
//! DIR/timings.json        wall times (kept apart so result.json is reproducible)
//! DIR/network.json        the locked network (rest positions, rods, rest lengths, anchors)
//! DIR/modes/KKKK.bin      worst-case mode of iteration K: 3·V little-endian f64
//! DIR/states/KKKK.bin     equilibrium displacements of iteration K: 3·V little-endian f64
//! DIR/states/KKKK.modes.bin all low modes of iteration K, column after column (resume state)
//! DIR/states/carried.bin  the candidates' test vectors the last iteration handed on (resume
//!                         state, see `carried_bytes`; removed when the run completes)
//! DIR/iterations/KKKK.obj the network of iteration K at equilibrium, one polyline per curve
//! DIR/final.obj           the greedy's final network at equilibrium
//! DIR/answer.obj          the answer (the network to build) at equilibrium; absent when
//!                         no stable network within the budget was found
//! DIR/mesh.obj            the surface the curves were drawn on, in scene units (if known)
//! DIR/summary.txt         a short text summary
//! ```
//!
//! Every file is written atomically (temporary file + rename), and `result.json` is rewritten
//! after each iteration, so an interrupted run keeps everything it finished and can resume.
//! `result.json` holds no timings and depends only on the inputs, so it is byte-identical from
//! run to run on one machine and build, whatever the thread count.

use super::GreedyParams;
use super::certificate::Certificate;
use super::greedy::{GreedyHooks, GreedyOutcome, IterationRecord, ResumePoint, StopReason};
use super::local::{LocalOutcome, LocalParams, Step, Strategy};
use crate::constraints::Constraints;
use crate::constraints::answer::{Answer, NoAnswer, Offer, choose};
use crate::geom::Vec3;
use crate::io::{self, Origin, Polyline};
use crate::network::{BuildInfo, BuildParams, Network};
use crate::stability::Evaluation;
use crate::stability::StabilityParams;
use crate::stability::candidates::{Carried, CarriedVector};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format version of `result.json`.
pub const VERSION: u32 = 1;

/// Where the curves came from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputDescription {
    /// Paper example name, if any.
    pub example: Option<String>,
    /// Mesh file, if any.
    pub mesh: Option<String>,
    /// Curve files in loading order.
    pub curve_files: Vec<String>,
    /// Scale applied.
    pub scale: f64,
}

/// The set-up of a run: everything needed to rebuild and rerun it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSetup {
    /// Inputs.
    pub input: InputDescription,
    /// Network construction.
    pub build: BuildParams,
    /// Material and solvers.
    pub stability: StabilityParams,
    /// Greedy parameters (budget, keep list).
    pub greedy: GreedyParams,
    /// Network counts.
    pub network: BuildInfo,
    /// Total rest length of all curves.
    pub total_length: f64,
}

/// The final network of a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FinalRecord {
    /// Curves kept.
    pub curves: Vec<usize>,
    /// Their total rest length.
    pub length: f64,
    /// `λ_eq` of the final network.
    pub lambda: f64,
}

/// The local search run after the greedy (`--local-search`), from the greedy's final network.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocalSearchRecord {
    /// The objective: always `lambda_eq`, every subset relaxed from the drawn state (the
    /// evaluation of exhaustive search and `curvenet compare`; the greedy's own `λ_eq` is
    /// relaxed along its path, so it can differ slightly).
    pub objective: String,
    /// How moves were chosen.
    pub strategy: Strategy,
    /// Whether moves were followed by part steps.
    pub parts: bool,
    /// The greedy's final curves (the start).
    pub start_curves: Vec<usize>,
    /// Their `λ_eq`, relaxed from the drawn state.
    pub start_lambda: f64,
    /// The curves the search ended with (the start when nothing improved it).
    pub curves: Vec<usize>,
    /// Their total rest length (within the budget; the keep list is held).
    pub length: f64,
    /// Their `λ_eq`, relaxed from the drawn state.
    pub lambda: f64,
    /// `lambda / start_lambda` (`null` unless both are positive).
    pub ratio: Option<f64>,
    /// The moves taken, in order, with the `λ_eq` after each.
    pub moves: Vec<Step>,
    /// Rounds run (scans of single moves, each followed by a chain when it found nothing).
    pub rounds: usize,
    /// Variable-depth chains built.
    pub chains: usize,
    /// Distinct subsets evaluated.
    pub evaluations: usize,
    /// Connected structures relaxed (the expensive evaluations).
    pub structures: usize,
}

impl LocalSearchRecord {
    /// The record of `outcome`, run with `params`; `None` when a `λ_eq` is not finite (a
    /// failed evaluation: nothing worth recording).
    pub fn new(params: &LocalParams, outcome: &LocalOutcome) -> Option<Self> {
        let (s, b) = (&outcome.start, &outcome.best);
        if !(s.lambda.is_finite() && b.lambda.is_finite()) {
            return None;
        }
        Some(LocalSearchRecord {
            objective: "lambda_eq".into(),
            strategy: params.strategy,
            parts: params.parts,
            start_curves: s.curves.clone(),
            start_lambda: s.lambda,
            curves: b.curves.clone(),
            length: b.length,
            lambda: b.lambda,
            ratio: (s.lambda > 0.0 && b.lambda > 0.0).then(|| b.lambda / s.lambda),
            moves: outcome.steps.clone(),
            rounds: outcome.rounds,
            chains: outcome.chains,
            evaluations: outcome.evaluations,
            structures: outcome.structures,
        })
    }

    /// One line for summaries.
    pub fn describe(&self) -> String {
        let gain = self
            .ratio
            .map_or_else(String::new, |r| format!(", {r:.3}× the greedy's"));
        format!(
            "local search from the greedy's final network: {} move(s); curves {:?}, length {:.6}, \
             λ_eq {:.6e} (greedy's set {:.6e} relaxed from the drawn state{gain}); {} subsets \
             evaluated, {} structures relaxed",
            self.moves.len(),
            self.curves,
            self.length,
            self.lambda,
            self.start_lambda,
            self.evaluations,
            self.structures
        )
    }
}

/// `result.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResultFile {
    /// Format version ([`VERSION`]).
    pub version: u32,
    /// The set-up.
    pub setup: RunSetup,
    /// The objective reported per iteration.
    pub objective: String,
    /// The budget `V` as a length.
    pub budget: f64,
    /// False while the run is in progress (or was interrupted).
    pub complete: bool,
    /// Why the run stopped (absent while in progress).
    pub stop: Option<StopReason>,
    /// Every recorded iteration.
    pub iterations: Vec<IterationRecord>,
    /// The last recorded network.
    #[serde(rename = "final")]
    pub final_network: Option<FinalRecord>,
    /// How far the final network can be from the best feasible subset on the fixed-geometry
    /// objective `λ_fix` (absent when skipped or not computable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub certificate: Option<Certificate>,
    /// The local search from the final network (absent unless asked for, or when it could
    /// not run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub local_search: Option<LocalSearchRecord>,
    /// The network to build: the best stable network meeting the budget and every constraint
    /// among those the run's searches evaluated; `null` when there is none (see
    /// [`Self::no_answer`]) or while the run is in progress.
    #[serde(default)]
    pub answer: Option<Answer>,
    /// Why there is no answer, and the run's smallest stable network (present only when the
    /// run completed without an answer).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub no_answer: Option<NoAnswer>,
}

impl ResultFile {
    /// Reads `DIR/result.json`.
    pub fn read(dir: &Path) -> Result<ResultFile, String> {
        let path = dir.join("result.json");
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let r: ResultFile = serde_json::from_str(&text)
            .map_err(|e| format!("{}:{}: {e}", path.display(), e.line()))?;
        if r.version != VERSION {
            return Err(format!(
                "{}: unsupported version {} (expected {VERSION})",
                path.display(),
                r.version
            ));
        }
        Ok(r)
    }
}

/// Writes a vector of f64 as little-endian bytes.
pub fn f64_bytes(v: &[f64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// Reads a file of little-endian f64.
pub fn read_f64_file(path: &Path) -> Result<Vec<f64>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if bytes.len() % 8 != 0 {
        return Err(format!(
            "{}: truncated file ({} bytes is not a whole number of f64)",
            path.display(),
            bytes.len()
        ));
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect())
}

/// The polylines of `curves` of `network` at displacements `u` (the rest state for `u = 0`).
pub fn network_polylines(network: &Network, curves: &[usize], u: Option<&[f64]>) -> Vec<Polyline> {
    let pos = |v: u32| {
        let p = network.positions[v as usize];
        match u {
            Some(u) => {
                p + Vec3::new(
                    u[3 * v as usize],
                    u[3 * v as usize + 1],
                    u[3 * v as usize + 2],
                )
            }
            None => p,
        }
    };
    curves
        .iter()
        .map(|&c| {
            let r = &network.rods[c];
            Polyline {
                points: r.vertices.iter().map(|&v| pos(v)).collect(),
                closed: r.closed,
                origin: Origin {
                    file: "network".into(),
                    line: 0,
                },
                label: Some(format!("curve {c}")),
            }
        })
        .collect()
}

/// The output folder's writer thread.
fn background() -> Result<io::BackgroundWriter, String> {
    io::BackgroundWriter::new().map_err(|e| format!("cannot start the output writer thread: {e}"))
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
            setup,
            objective: "lambda_eq".into(),
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
        if &result.setup != setup {
            return Err(format!(
                "{}: the recorded run was made with a different set-up; use another --out or drop --resume",
                dir.join("result.json").display()
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

    /// What [`Self::resume`] found that the run can go on without (a damaged or stale
    /// carried-vectors file); empty for a new run.
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
        self.write("final.obj", obj)?;
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
        // Only a resume needs it.
        let carried = self.dir.join(CARRIED_FILE);
        if carried.exists() {
            std::fs::remove_file(&carried).map_err(|e| io_err(&carried, e))?;
        }
        Ok(())
    }
}

/// The carried test vectors' file (see [`carried_bytes`]).
const CARRIED_FILE: &str = "states/carried.bin";

/// The carried test vectors to resume after iteration `k` with: those of `CARRIED_FILE` if
/// they belong to iteration `k`, else none. Absent (a run without them) or newer (a run
/// stopped between writing them and its record) is normal; unreadable, damaged or older is
/// a warning: the run goes on with the same removals, its bounds start afresh, so its
/// `result.json` will differ from an uninterrupted run's in the recorded bounds.
fn read_carried(
    dir: &Path,
    curves: usize,
    dofs: usize,
    k: usize,
    warnings: &mut Vec<String>,
) -> Carried {
    let path = dir.join(CARRIED_FILE);
    let consequence = "the run goes on without the carried test vectors (the same removals; \
                       the recorded bounds will differ from an uninterrupted run's)";
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Vec::new(),
        Err(e) => {
            warnings.push(format!("{}: {e}; {consequence}", path.display()));
            return Vec::new();
        }
    };
    match carried_from_bytes(&bytes, curves, dofs) {
        Some((iteration, carried)) if iteration == k => carried,
        Some((iteration, _)) if iteration > k => Vec::new(),
        Some((iteration, _)) => {
            warnings.push(format!(
                "{}: holds the vectors of iteration {iteration}, not of the last recorded one \
                 ({k}); {consequence}",
                path.display()
            ));
            Vec::new()
        }
        None => {
            warnings.push(format!(
                "{}: damaged ({} bytes, not the vectors of {curves} curves with {dofs} \
                 unknowns); {consequence}",
                path.display(),
                bytes.len()
            ));
            Vec::new()
        }
    }
}

/// `carried.bin`: the index of the iteration that handed the vectors on (u64), the curve count
/// (u64), then per curve a flag byte (1: a vector follows) and, with a vector, its value
/// (f64) and its coordinates (f32 each, the network's degrees of freedom); little-endian.
pub fn carried_bytes(iteration: usize, carried: &Carried) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(&(iteration as u64).to_le_bytes());
    out.extend_from_slice(&(carried.len() as u64).to_le_bytes());
    for c in carried {
        match c {
            Some(v) => {
                out.push(1);
                out.extend_from_slice(&v.value.to_le_bytes());
                for x in &v.vector {
                    out.extend_from_slice(&x.to_le_bytes());
                }
            }
            None => out.push(0),
        }
    }
    out
}

/// Reads [`carried_bytes`] for a network of `curves` curves and `dofs` degrees of freedom:
/// the iteration and the vectors, `None` if the bytes do not match.
pub fn carried_from_bytes(bytes: &[u8], curves: usize, dofs: usize) -> Option<(usize, Carried)> {
    fn take<'b>(b: &mut &'b [u8], n: usize) -> Option<&'b [u8]> {
        if b.len() < n {
            return None;
        }
        let (head, tail) = b.split_at(n);
        *b = tail;
        Some(head)
    }
    let mut b = bytes;
    let u64_of = |s: &[u8]| u64::from_le_bytes(s.try_into().unwrap_or([0; 8]));
    let iteration = u64_of(take(&mut b, 8)?) as usize;
    if u64_of(take(&mut b, 8)?) as usize != curves {
        return None;
    }
    let mut carried = Vec::with_capacity(curves);
    for _ in 0..curves {
        match take(&mut b, 1)?[0] {
            0 => carried.push(None),
            1 => {
                let value = f64::from_le_bytes(take(&mut b, 8)?.try_into().ok()?);
                let vector = take(&mut b, 4 * dofs)?
                    .chunks_exact(4)
                    .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                    .collect();
                carried.push(Some(CarriedVector { value, vector }));
            }
            _ => return None,
        }
    }
    b.is_empty().then_some((iteration, carried))
}

impl GreedyHooks for OutputWriter<'_> {
    fn carried(&mut self, carried: &Carried) -> Result<(), String> {
        // Handed on by the iteration about to be recorded as number `len`.
        let k = self.result.iterations.len();
        self.write(CARRIED_FILE, carried_bytes(k, carried))
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
        self.write(&format!("iterations/{k:04}.obj"), obj)?;
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

/// One line per iteration whose relaxation stopped short of equilibrium (iteration cap,
/// stall, failed line search): its `λ_eq` belongs to an unrelaxed state. Empty when every
/// relaxation converged (to the tolerance or the round-off floor).
pub fn unrelaxed(iterations: &[IterationRecord]) -> Vec<String> {
    iterations
        .iter()
        .enumerate()
        .filter(|(_, r)| !r.newton.converged)
        .map(|(k, r)| {
            format!(
                "iteration {k} ({} curves): the relaxation stopped short of equilibrium \
                 ({:?} after {} Newton steps, relative gradient {:.1e}); its λ_eq is that of \
                 an unrelaxed state",
                r.curves.len(),
                r.newton.stop,
                r.newton.iterations,
                r.newton.grad_rel
            )
        })
        .collect()
}

/// A short text summary of a result.
pub fn summary(r: &ResultFile) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let first = r.iterations.first();
    let last = r.iterations.last();
    let _ = writeln!(
        s,
        "curvenet greedy simplification (objective λ_eq, supports {})",
        r.setup.build.supports.name()
    );
    if let Some(ex) = &r.setup.input.example {
        let _ = writeln!(s, "example: {ex}");
    }
    let n = &r.setup.network;
    let _ = writeln!(
        s,
        "network: {} curves, {} vertices, {} joints",
        n.curves, n.vertices, n.joints
    );
    let _ = writeln!(
        s,
        "budget: {:.6} of {:.6} total rest length",
        r.budget, r.setup.total_length
    );
    if let (Some(f), Some(l)) = (first, last) {
        let _ = writeln!(
            s,
            "start: {} curves, length {:.6}, λ_eq {:.6e}",
            f.curves.len(),
            f.length,
            f.lambda
        );
        let _ = writeln!(
            s,
            "final: {} curves, length {:.6}, λ_eq {:.6e}",
            l.curves.len(),
            l.length,
            l.lambda
        );
        let _ = writeln!(s, "kept curves: {:?}", l.curves);
    }
    let removed: Vec<String> = r
        .iterations
        .iter()
        .filter_map(|i| i.removed.map(|c| c.to_string()))
        .collect();
    let _ = writeln!(s, "removed in order: {}", removed.join(", "));
    let _ = writeln!(s, "iterations: {}; stop: {:?}", r.iterations.len(), r.stop);
    for line in unrelaxed(&r.iterations) {
        let _ = writeln!(s, "warning: {line}");
    }
    if let Some(l) = &r.local_search {
        let _ = writeln!(s, "{}", l.describe());
    }
    if let Some(c) = &r.certificate {
        let _ = writeln!(s, "{}", c.describe());
    }
    if let Some(a) = &r.answer {
        let _ = writeln!(s, "answer (the network to build): {}", a.describe());
    } else if let Some(n) = &r.no_answer {
        let _ = writeln!(s, "{}", n.describe());
    }
    s
}

/// The networks of the greedy's path, offered as the run's answer in the order they were
/// recorded (`source` "greedy", with their iteration).
pub fn greedy_offers(iterations: &[IterationRecord]) -> Vec<Offer> {
    iterations
        .iter()
        .enumerate()
        .map(|(k, it)| Offer {
            source: "greedy".into(),
            iteration: Some(k),
            curves: it.curves.clone(),
            length: it.length,
            lambda: it.lambda,
            zero_modes: it.zero_modes,
            negative_modes: it.negative_modes,
            deviation: None,
        })
        .collect()
}

/// A network another search found, evaluated in full (`λ_eq`, its modes), offered as the
/// run's answer.
pub fn evaluated_offer(source: &str, eval: &Evaluation) -> Offer {
    Offer {
        source: source.into(),
        iteration: None,
        curves: eval.curves.clone(),
        length: eval.length,
        lambda: eval.lambda(),
        zero_modes: eval.spectrum.zero_modes,
        negative_modes: eval.spectrum.negative_modes,
        deviation: None,
    }
}

#[cfg(test)]
mod tests {
    use super::unrelaxed;
    use crate::simplify::greedy::IterationRecord;
    use crate::solve::NewtonStop;
    use crate::solve::NewtonSummary;

    fn record(curves: usize, converged: bool, stop: NewtonStop) -> IterationRecord {
        IterationRecord {
            curves: (0..curves).collect(),
            length: 1.0,
            lambda: 1e-9,
            eigenvalues: vec![1e-9],
            zero_modes: 0,
            negative_modes: 0,
            newton: NewtonSummary {
                iterations: if converged { 5 } else { 200 },
                converged,
                grad_rel: if converged { 1e-12 } else { 2.6e-8 },
                stop,
                factorizations: 5,
                chord_steps: 0,
            },
            removed: None,
            removed_group: Vec::new(),
            score: None,
            candidates: Vec::new(),
            mode_file: String::new(),
            physical: None,
        }
    }

    #[test]
    fn relaxations_short_of_equilibrium_are_reported() {
        let its = vec![
            record(5, true, NewtonStop::Converged),
            record(4, true, NewtonStop::RoundoffFloor),
            record(3, false, NewtonStop::MaxIterations),
        ];
        let lines = unrelaxed(&its);
        assert_eq!(lines.len(), 1, "{lines:?}");
        assert!(
            lines[0].starts_with("iteration 2 (3 curves)"),
            "{}",
            lines[0]
        );
        assert!(
            lines[0].contains("MaxIterations after 200 Newton steps"),
            "{}",
            lines[0]
        );
        assert!(unrelaxed(&its[..2]).is_empty());
    }

    #[test]
    fn carried_vectors_round_trip_and_bad_files_are_refused() {
        use super::{CarriedVector, carried_bytes, carried_from_bytes};
        let carried = vec![
            Some(CarriedVector {
                value: 2.5e-7,
                vector: vec![1.0, -2.0, 0.5, 3.25, 0.0, -1e-3],
            }),
            None,
            Some(CarriedVector {
                value: -1.0,
                vector: vec![0.0; 6],
            }),
        ];
        let bytes = carried_bytes(7, &carried);
        assert_eq!(carried_from_bytes(&bytes, 3, 6), Some((7, carried.clone())));
        // Another network (curve count, degrees of freedom) or a damaged file: nothing
        // (the resumed run then starts its bounds afresh, with the same removals).
        assert_eq!(carried_from_bytes(&bytes, 4, 6), None);
        assert_eq!(carried_from_bytes(&bytes, 3, 5), None);
        for cut in [0, 7, 15, 16, 17, bytes.len() - 1] {
            assert_eq!(
                carried_from_bytes(&bytes[..cut], 3, 6),
                None,
                "cut at {cut}"
            );
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert_eq!(carried_from_bytes(&longer, 3, 6), None);
        let mut bad_flag = bytes.clone();
        bad_flag[16] = 2;
        assert_eq!(carried_from_bytes(&bad_flag, 3, 6), None);
    }
}

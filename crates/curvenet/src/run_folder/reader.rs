//! [`RunFolder`]: a run folder read back and checked, for the exports, pictures and viewer.
//!
//! [`RunFolder::read`] reads `result.json`, `network.json` and the optional `mesh.obj` through
//! a [`RunFiles`] (confined to a folder of run folders or not: see [`super::files`]), and
//! checks every index, length and number, so a missing or corrupt folder gives a clear error
//! naming the file, never a panic. The iterations' side files (`states/KKKK.bin`, the mode
//! files) are read on demand, through the same reader.

use super::RunFolderError;
use super::files::{RunFileError, RunFiles};
use super::schema::ResultFile;
use crate::constraints::answer::Answer;
use crate::io::{self, InputError, TriMesh};
use crate::network::Network;
use crate::simplify::greedy::IterationRecord;
use crate::words::{Message, Opt, given, message};
use std::path::{Path, PathBuf};

/// A run's output folder, read and checked.
#[derive(Clone, Debug)]
pub struct RunFolder {
    /// The folder.
    pub dir: PathBuf,
    /// How its files are read (every later read goes through it too).
    pub files: RunFiles,
    /// `result.json`.
    pub result: ResultFile,
    /// `network.json`.
    pub network: Network,
    /// `mesh.obj`, when the folder has a readable one.
    pub mesh: Option<TriMesh>,
    /// Problems that did not stop the reading (an unreadable `mesh.obj`, …).
    pub warnings: Vec<String>,
}

impl RunFolder {
    /// Reads `dir/result.json`, `dir/network.json` and (if present) `dir/mesh.obj`, and checks
    /// that they agree. Side files of the iterations are read on demand.
    ///
    /// # Errors
    ///
    /// As [`Self::read`].
    pub fn open(dir: &Path) -> Result<RunFolder, RunFolderError> {
        Self::read(RunFiles::unconfined(dir))
    }

    /// Reads the run folder of `files` (`result.json`, `network.json` and, if present,
    /// `mesh.obj`, each through `files`) and checks that they agree; its side files are read
    /// on demand through `files` too.
    ///
    /// # Errors
    ///
    /// The folder is not there, a file cannot be read or parsed, or they do not agree (each
    /// error naming the file as `files` names it).
    pub fn read(files: RunFiles) -> Result<RunFolder, RunFolderError> {
        if !files.folder_exists() {
            return Err(RunFileError::NotAFolder {
                file: files.shown(),
            }
            .into());
        }
        let invalid = |rel: &str, problem: String| RunFolderError::Invalid {
            file: files.name(rel),
            problem,
        };
        let result = ResultFile::read_from(&files)?;
        let network: Network = files.read_json("network.json", "a curvenet network")?;
        check_network(&network).map_err(|e| invalid("network.json", e.0))?;
        check_result(&result, network.rods.len()).map_err(|e| invalid("result.json", e))?;
        let mut warnings = Vec::new();
        let mesh = read_mesh(&files, &mut warnings);
        if !result.complete {
            warnings.push(format!(
                "{}: the run is not complete; showing the {} iteration(s) recorded",
                files.shown(),
                result.iterations.len()
            ));
        }
        Ok(RunFolder {
            dir: files.dir().to_path_buf(),
            files,
            result,
            network,
            mesh,
            warnings,
        })
    }

    /// Number of recorded iterations.
    pub fn iteration_count(&self) -> usize {
        self.result.iterations.len()
    }

    /// Index of the last recorded iteration (the final network of a complete run).
    pub fn last_index(&self) -> usize {
        self.result.iterations.len() - 1
    }

    /// The iteration the run's pictures and viewer show first: the answer's when it is one of
    /// the greedy's iterations, else the last.
    pub fn shown_index(&self) -> usize {
        self.result
            .answer
            .as_ref()
            .and_then(|a| a.found.iteration)
            .filter(|&k| k < self.iteration_count())
            .unwrap_or_else(|| self.last_index())
    }

    /// The record of iteration `k`.
    pub fn record(&self, k: usize) -> Result<&IterationRecord, RunFolderError> {
        self.result.iterations.get(k).ok_or_else(|| {
            RunFolderError::Absent(Message::from(format!(
                "{}: no iteration {k} (the run recorded iterations 0 to {})",
                self.files.shown(),
                self.last_index()
            )))
        })
    }

    fn vector_file(&self, rel: &str) -> Result<Vec<f64>, RunFolderError> {
        let v = self.files.read_f64(rel)?;
        let invalid = |problem: String| RunFolderError::Invalid {
            file: self.files.name(rel),
            problem,
        };
        if v.len() != self.network.dofs() {
            return Err(invalid(format!(
                "{} values, expected 3·V = {} for network.json",
                v.len(),
                self.network.dofs()
            )));
        }
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(invalid(format!("value {i} is not finite")));
        }
        Ok(v)
    }

    /// Equilibrium displacements of iteration `k` (`states/KKKK.bin`, 3·V values).
    pub fn displacement(&self, k: usize) -> Result<Vec<f64>, RunFolderError> {
        self.record(k)?;
        self.vector_file(&crate::run_layout::state_file(k))
    }

    /// Worst-case mode of iteration `k` (its `mode_file`, 3·V values).
    pub fn mode(&self, k: usize) -> Result<Vec<f64>, RunFolderError> {
        let rec = self.record(k)?;
        self.vector_file(&rec.mode_file)
    }

    /// The answer or the `n`-th alternative (from 1) of the run.
    fn chosen(&self, which: Which) -> Result<&Answer, RunFolderError> {
        let none = |what: Message| {
            RunFolderError::Absent(what.prefixed([format!("{}: ", self.files.shown()).into()]))
        };
        match which {
            Which::Iteration(_) => unreachable!("an iteration is no chosen network"),
            Which::Answer => self.result.answer.as_ref().ok_or_else(|| {
                none(message![
                    "the run has no answer (no stable network met the budget and the constraints)"
                ])
            }),
            Which::Alternative(n) => n
                .checked_sub(1)
                .and_then(|i| self.result.alternatives.get(i))
                .ok_or_else(|| {
                    none(match self.result.alternatives.len() {
                        0 => message![
                            format!(
                                "no alternative {n}: the run recorded no alternatives (run it \
                                 with "
                            ),
                            given(Opt::Alternatives, "K"),
                            ")"
                        ],
                        m => message![format!(
                            "no alternative {n}: the run recorded alternatives 1 to {m}"
                        )],
                    })
                }),
        }
    }

    /// What `which` is: its curves, length, `λ_eq`, and how exports name it.
    pub fn network_of(&self, which: Which) -> Result<Chosen, RunFolderError> {
        if let Which::Iteration(k) = which {
            let rec = self.record(k)?;
            return Ok(Chosen {
                what: format!("iteration {k}"),
                tag: format!("{k:04}"),
                curves: rec.curves.clone(),
                length: rec.length,
                lambda: rec.lambda,
                iteration: Some(k),
                unstable: super::record_instability(rec),
            });
        }
        let a = self.chosen(which)?;
        let (what, tag) = match which {
            Which::Alternative(n) => (format!("alternative {n}"), format!("alternative-{n}")),
            _ => ("the answer".to_string(), "answer".to_string()),
        };
        let place = a.found.iteration.map_or_else(
            || format!(" (the {}'s network)", a.found.source.replace('_', " ")),
            |k| format!(" (iteration {k})"),
        );
        Ok(Chosen {
            what: format!("{what}{place}"),
            tag,
            curves: a.found.curves.clone(),
            length: a.found.length,
            lambda: a.found.lambda,
            iteration: a.found.iteration,
            unstable: super::instability(a.found.lambda, a.zero_modes, a.negative_modes),
        })
    }

    /// Equilibrium displacements of `which`: its iteration's, else `states/TAG.bin`.
    pub fn displacement_of(&self, which: Which) -> Result<Vec<f64>, RunFolderError> {
        let c = self.network_of(which)?;
        match c.iteration {
            Some(k) => self.displacement(k),
            None => self.vector_file(&crate::run_layout::tagged_state_file(&c.tag)),
        }
    }

    /// Worst-case mode of `which`: its iteration's, else `modes/TAG.bin`.
    pub fn mode_of(&self, which: Which) -> Result<Vec<f64>, RunFolderError> {
        let c = self.network_of(which)?;
        match c.iteration {
            Some(k) => self.mode(k),
            None => self.vector_file(&crate::run_layout::tagged_mode_file(&c.tag)),
        }
    }
}

/// A network of a run: a greedy iteration, the answer, or an alternative.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Which {
    /// Iteration `K` of the greedy.
    Iteration(usize),
    /// The answer.
    Answer,
    /// The `N`-th alternative, from 1.
    Alternative(usize),
}

impl From<usize> for Which {
    fn from(k: usize) -> Self {
        Which::Iteration(k)
    }
}

/// What [`RunFolder::network_of`] says of a network of the run.
#[derive(Clone, Debug, PartialEq)]
pub struct Chosen {
    /// How a header names it: `iteration 3`, `the answer (the local search's network)`,
    /// `alternative 2 (iteration 7)`.
    pub what: String,
    /// How file names name it: `0003`, `answer`, `alternative-2`.
    pub tag: String,
    /// Curves, ascending.
    pub curves: Vec<usize>,
    /// Total rest length.
    pub length: f64,
    /// `λ_eq`.
    pub lambda: f64,
    /// The greedy's iteration, when it is one.
    pub iteration: Option<usize>,
    /// What makes it unstable, when it is (a zero or negative mode: see
    /// [`super::instability`]); never for the answer or an alternative.
    pub unstable: Option<String>,
}

/// The folder's `mesh.obj`, when it has a readable one with faces; what else is found there
/// is a warning (the surface is optional).
fn read_mesh(files: &RunFiles, warnings: &mut Vec<String>) -> Option<TriMesh> {
    const MESH: &str = "mesh.obj";
    let name = files.name(MESH);
    let text = match files.read_text(MESH) {
        Ok(text) => text,
        Err(RunFileError::Missing { .. }) => return None,
        Err(e) => {
            warnings.push(format!("{e}; the surface is left out"));
            return None;
        }
    };
    match io::parse_obj_mesh(&text, &name) {
        Ok(m) if !m.mesh.faces.is_empty() => Some(m.mesh),
        Ok(_) => {
            warnings.push(format!("{name}: no faces; ignored"));
            None
        }
        Err(e) => {
            let e = mesh_error(files, &e);
            warnings.push(format!("{e}; the surface is left out"));
            None
        }
    }
}

/// The error of a `mesh.obj` its parser refused: where, and (unconfined only) the parser's
/// words, which may quote the line.
fn mesh_error(files: &RunFiles, e: &InputError) -> RunFileError {
    let problem = match e.line() {
        Some(line) => format!("not a surface mesh (line {line})"),
        None => "not a surface mesh".to_string(),
    };
    files.malformed("mesh.obj", problem, Some(e.message()))
}

/// Checks that a run's record names only curves of its network (`n` of them) and iterations
/// it recorded, and that every network it records has curves.
fn check_result(result: &ResultFile, n: usize) -> Result<(), String> {
    if result.iterations.is_empty() {
        return Err("no iteration recorded yet".into());
    }
    for (k, it) in result.iterations.iter().enumerate() {
        if it.curves.is_empty() {
            return Err(format!("iteration {k} has no curves"));
        }
        if let Some(&c) = it.curves.iter().chain(it.removed.iter()).find(|&&c| c >= n) {
            return Err(format!(
                "iteration {k} names curve {c}, but network.json has {n} curves"
            ));
        }
    }
    let chosen = result.answer.iter().chain(&result.alternatives);
    for (i, a) in chosen.enumerate() {
        let what = if i == 0 && result.answer.is_some() {
            "the answer".to_string()
        } else {
            format!("alternative {}", i + usize::from(result.answer.is_none()))
        };
        if a.found.curves.is_empty() {
            return Err(format!("{what} has no curves"));
        }
        if let Some(&c) = a.found.curves.iter().find(|&&c| c >= n) {
            return Err(format!(
                "{what} names curve {c}, but network.json has {n} curves"
            ));
        }
        if let Some(k) = a.found.iteration.filter(|&k| k >= result.iterations.len()) {
            return Err(format!(
                "{what} names iteration {k}, but the run recorded {}",
                result.iterations.len()
            ));
        }
    }
    Ok(())
}

/// What makes a network inconsistent ([`check_network`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct InvalidNetwork(pub String);

impl From<String> for InvalidNetwork {
    fn from(problem: String) -> Self {
        InvalidNetwork(problem)
    }
}

impl From<&str> for InvalidNetwork {
    fn from(problem: &str) -> Self {
        InvalidNetwork(problem.to_string())
    }
}

/// Checks that a network is consistent: finite positions, indices in range, one positive
/// rest length per edge, enough vertices per rod. Everything the energy model indexes.
///
/// # Errors
///
/// The first inconsistency found.
pub fn check_network(net: &Network) -> Result<(), InvalidNetwork> {
    let nv = net.positions.len();
    if nv == 0 || net.rods.is_empty() {
        return Err("the network has no vertices or no rods".into());
    }
    if let Some(i) = net.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("position of vertex {i} is not finite").into());
    }
    for (c, rod) in net.rods.iter().enumerate() {
        let m = rod.vertices.len();
        let min = if rod.closed { 3 } else { 2 };
        if m < min {
            return Err(format!("rod {c} has {m} vertices (at least {min} needed)").into());
        }
        let edges = if rod.closed { m } else { m - 1 };
        if rod.rest_lengths.len() != edges {
            return Err(format!(
                "rod {c} has {} rest lengths for {edges} edges",
                rod.rest_lengths.len()
            )
            .into());
        }
        if let Some(j) = rod
            .rest_lengths
            .iter()
            .position(|&l| !(l.is_finite() && l > 0.0))
        {
            return Err(format!(
                "rod {c}: rest length of edge {j} is {} (must be positive and finite)",
                rod.rest_lengths[j]
            )
            .into());
        }
        if let Some(&v) = rod
            .vertices
            .iter()
            .chain(&rod.anchors)
            .find(|&&v| v as usize >= nv)
        {
            return Err(
                format!("rod {c} names vertex {v}, but the network has {nv} vertices").into(),
            );
        }
        if let Some(&v) = rod.anchors.iter().find(|v| !rod.vertices.contains(v)) {
            return Err(format!("rod {c} anchors vertex {v}, which is not on it").into());
        }
        if let Some(j) = (0..edges).find(|&j| {
            let (a, b) = rod.edge(j);
            a == b
        }) {
            return Err(format!("rod {c}: edge {j} joins a vertex to itself").into());
        }
    }
    for (j, joint) in net.joints.iter().enumerate() {
        if joint.vertex as usize >= nv {
            return Err(format!("joint {j} names vertex {}", joint.vertex).into());
        }
        if let Some(&c) = joint.curves.iter().find(|&&c| c as usize >= net.rods.len()) {
            return Err(format!("joint {j} names curve {c}").into());
        }
    }
    Ok(())
}

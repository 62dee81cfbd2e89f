//! The run folder: what a simplification run writes as it goes, and how it is read back.
//!
//! ```text
//! DIR/result.json         every iteration so far; "complete": true once the run finished
//! DIR/timings.json        wall times (kept apart so result.json is reproducible)
//! DIR/network.json        the locked network (rest positions, rods, rest lengths, anchors)
//! DIR/modes/KKKK.bin      worst-case mode of iteration K: 3·V little-endian f64
//! DIR/states/KKKK.bin     equilibrium displacements of iteration K: 3·V little-endian f64
//! DIR/states/KKKK.modes.bin all low modes of iteration K, column after column (resume state)
//! DIR/states/carried.P.bin the candidates' test vectors an iteration of parity P handed on
//!                         (resume state, see [`carried`]; removed when the run completes)
//! DIR/iterations/KKKK.obj the network of iteration K at equilibrium, one polyline per curve
//! DIR/final.obj           the greedy's final network at equilibrium
//! DIR/answer.obj          the answer (the network to build) at equilibrium; absent when
//!                         no stable network within the budget was found
//! DIR/states/answer.bin, DIR/modes/answer.bin
//!                         the answer's equilibrium and worst-case mode, when it is not one
//!                         of the greedy's iterations
//! DIR/alternative-N.obj   with --alternatives: the N-th alternative (from 1) at equilibrium
//! DIR/states/alternative-N.bin, DIR/modes/alternative-N.bin
//!                         its equilibrium and mode, when it is not a greedy iteration
//! DIR/mesh.obj            the surface the curves were drawn on, in scene units (if known)
//! DIR/summary.txt         a short text summary
//! DIR/.curvenet.lock      locked by the run writing the folder (see [`folder`])
//! ```
//!
//! - [`schema`]: `result.json` and its parts ([`ResultFile`], [`RunSetup`], …);
//! - [`writer`]: [`OutputWriter`], the greedy's hooks that write the folder as the run goes, and
//!   continue an interrupted run ([`OutputWriter::resume`]);
//! - [`carried`]: the carried test vectors' file;
//! - [`folder`]: the folder's lock (one run at a time), a fresh run starting clean, stale
//!   temporary files;
//! - [`reader`]: [`RunFolder`], a finished or interrupted folder read back and checked, for the
//!   exports, pictures and viewer of [`crate::report`];
//! - [`files`]: [`RunFiles`], the reader every read of a run folder's files goes through,
//!   confined to a folder of run folders ([`RunsRoot`]: the design server's, which reads no file
//!   outside it, each file's path resolved link by link) or not (the command line's);
//! - [`summary`]: `summary.txt` and the warnings a run's record calls for;
//! - [`answer`]: the networks a run offers as its answer and its alternatives
//!   ([`greedy_offers`], [`evaluated_offer`], [`answer::alternative_offers`]).
//!
//! Every file is written atomically (temporary file + rename), and `result.json` is rewritten
//! after each iteration, so an interrupted run keeps everything it finished and can resume.
//! `result.json` holds no timings and depends only on the inputs, so it is byte-identical from
//! run to run on one machine and build, whatever the thread count.

pub mod answer;
pub mod carried;
pub mod files;
pub mod folder;
pub mod reader;
pub mod schema;
pub mod setup_diff;
pub mod summary;
pub mod writer;

pub use answer::{evaluated_offer, greedy_offers, measure_greedy_deviations};
pub use files::{Access, RunFileError, RunFiles, RunsRoot};
pub use reader::{Chosen, InvalidNetwork, RunFolder, Which, check_network};
pub use schema::{
    FinalRecord, InputDescription, LocalSearchRecord, ResultFile, RunSetup, SlideCurve,
    SlideRecord, SlideRound, VERSION,
};
pub use summary::{instability, record_instability, summary, unrelaxed, unstable};
pub use writer::OutputWriter;

use crate::geom::Vec3;
use crate::io::{Origin, Polyline, WriteError};
use crate::network::Network;
use crate::words::Message;
use std::path::{Path, PathBuf};

/// Why a run folder could not be read, written or continued.
#[derive(Debug, thiserror::Error)]
pub enum RunFolderError {
    /// One of its files could not be read or parsed (through its [`RunFiles`]).
    #[error(transparent)]
    File(#[from] RunFileError),
    /// A file was read but does not hold what a run folder holds (an index out of range, an
    /// unsupported version, a state that does not match the network, …).
    #[error("{file}: {problem}")]
    Invalid {
        /// The file, as its reader names it.
        file: String,
        /// What is wrong.
        problem: String,
    },
    /// A file could not be written, created or removed: its path and the system's reason.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        error: std::io::Error,
    },
    /// A file written as the run went could not be (it names the file).
    #[error(transparent)]
    Write(#[from] WriteError),
    /// The network asked for is not in the run (no answer, no such alternative or
    /// iteration): the message says what the run holds.
    #[error("{0}")]
    Absent(Message),
    /// The run asked for cannot continue the one recorded (a resume with other settings):
    /// the message names the option that differs, for the user to fix.
    #[error("{0}")]
    Resume(Message),
    /// The writer could not go on (its thread would not start, the run recorded nothing).
    #[error("{0}")]
    Failed(String),
}

impl RunFolderError {
    /// The message spelled by `words` (a front end's option names: a missing network names
    /// the option that asks for it, a refused resume the option that differs).
    pub fn render(&self, words: &dyn crate::words::Wording) -> String {
        match self {
            RunFolderError::Absent(m) | RunFolderError::Resume(m) => m.render(words),
            e => e.to_string(),
        }
    }

    /// Whether the error is the input's (a run folder missing, damaged or not a run's: files
    /// missing, truncated or malformed, a network the run lacks, a resume with other
    /// settings), which the user can fix, rather than the writing's or the tool's.
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            RunFolderError::File(_)
                | RunFolderError::Invalid { .. }
                | RunFolderError::Absent(_)
                | RunFolderError::Resume(_)
        )
    }

    /// `path` could not be written, created or removed.
    pub fn io(path: &Path, error: std::io::Error) -> Self {
        RunFolderError::Io {
            path: path.to_path_buf(),
            error,
        }
    }

    /// Whether it refused a path leading outside the folder runs are loaded from.
    pub fn is_outside(&self) -> bool {
        matches!(self, RunFolderError::File(RunFileError::Outside { .. }))
    }
}

impl From<String> for RunFolderError {
    fn from(message: String) -> Self {
        RunFolderError::Failed(message)
    }
}

/// Writes a vector of f64 as little-endian bytes.
pub fn f64_bytes(v: &[f64]) -> Vec<u8> {
    let mut out = Vec::with_capacity(8 * v.len());
    for x in v {
        out.extend_from_slice(&x.to_le_bytes());
    }
    out
}

/// Reads a file of little-endian f64.
///
/// # Errors
///
/// The file cannot be read, or is not a whole number of f64.
pub fn read_f64_file(path: &Path) -> Result<Vec<f64>, RunFolderError> {
    let bytes = std::fs::read(path).map_err(|e| RunFolderError::io(path, e))?;
    f64_values(&bytes).ok_or_else(|| RunFolderError::Invalid {
        file: path.display().to_string(),
        problem: format!(
            "truncated file ({} bytes is not a whole number of f64)",
            bytes.len()
        ),
    })
}

/// The little-endian f64 of `bytes` (`None` when they are not a whole number of them).
fn f64_values(bytes: &[u8]) -> Option<Vec<f64>> {
    let chunks = bytes.chunks_exact(8);
    if !chunks.remainder().is_empty() {
        return None;
    }
    Some(
        chunks
            .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect(),
    )
}

/// Positions of all vertices at displacements `u` (`None`: the rest state).
pub fn positions_at(net: &Network, u: Option<&[f64]>) -> Vec<Vec3> {
    net.positions
        .iter()
        .enumerate()
        .map(|(i, &p)| match u {
            Some(u) => p + Vec3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]),
            None => p,
        })
        .collect()
}

/// The polylines of `curves` of `network` with vertices at `positions` (see [`positions_at`]),
/// each labelled by `label(curve)`.
pub fn curve_polylines(
    network: &Network,
    curves: &[usize],
    positions: &[Vec3],
    label: impl Fn(usize) -> String,
) -> Vec<Polyline> {
    curves
        .iter()
        .map(|&c| {
            let r = &network.rods[c];
            Polyline {
                points: r.vertices.iter().map(|&v| positions[v as usize]).collect(),
                closed: r.closed,
                origin: Origin::new("network", 0),
                label: Some(label(c)),
            }
        })
        .collect()
}

/// The polylines of `curves` of `network` at displacements `u` (the rest state for `None`),
/// labelled `curve N`.
pub fn network_polylines(network: &Network, curves: &[usize], u: Option<&[f64]>) -> Vec<Polyline> {
    curve_polylines(network, curves, &positions_at(network, u), |c| {
        format!("curve {c}")
    })
}

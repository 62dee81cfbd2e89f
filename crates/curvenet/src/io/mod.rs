//! Reading and writing curve sketches and triangle meshes.
//!
//! Curves come in three formats, chosen by [`read_curves`] from the file extension:
//!
//! | extension | format | parser | writer |
//! |---|---|---|---|
//! | `.txt` | the reference text format (`CURVE` records followed by `x y z` lines) | [`parse_reference_curves`] | [`curves_to_reference_text`] |
//! | `.obj` | OBJ polylines (`v` and `l` records, as Rhino exports curves) | [`parse_obj_polylines`] | [`curves_to_obj`] |
//! | `.json` | curvenet's own JSON format (`"format": "curvenet-curves"`) | [`parse_json_curves`] | [`curves_to_json`] |
//!
//! Curves given as point lists (arrays from Python, objects of a Rhino document) go through
//! [`curves_from_points`], with the same normalisation and checks.
//!
//! Meshes are read from OBJ `v`/`f` records ([`read_mesh`], [`parse_obj_mesh`]) and written by
//! [`mesh_to_obj`].
//!
//! Every parser checks its input completely: a malformed or non-finite number, a truncated point,
//! a curve with too few distinct points, an index that points nowhere, a JSON key given twice
//! in one object ([`duplicate_key`], which every JSON text the tool reads is checked with)… each
//! is an [`InputError`]
//! naming the file and the line, displayed as `file:line: message`. No input makes a parser panic.
//! Suspicious but usable input (consecutive points closer than `1e-9 ×` the curve's bounding-box
//! diagonal, degenerate mesh faces, …) is reported as [`InputWarning`]s next to the result.
//!
//! All curve readers share one normalisation: exact consecutive duplicates are dropped (with a
//! warning), a curve whose last point equals its first (exactly, or within `1e-9 ×` its
//! bounding-box diagonal) is closed and loses the repeated point, and near-duplicate points that
//! are not exactly equal are kept untouched. Writers emit numbers in Rust's shortest round-trip
//! form, so writing and reading again gives bit-identical coordinates.

mod atomic;
mod background;
mod checks;
mod json;
mod json_keys;
mod obj_curves;
mod obj_lexer;
mod obj_mesh;
mod points;
mod reference;
mod supports_file;

pub use atomic::{
    ExitHold, Staged, Unwritable, check_writable, exit_removing_temp_files, hold_exit,
    stage_atomic, write_atomic,
};
pub use background::{BackgroundWriter, WriteError};
pub use json::{FileExtras, curves_to_json, curves_to_json_with, parse_json_curves};
pub use json_keys::{DuplicateKey, duplicate_key};
pub use obj_curves::{curves_to_obj, parse_obj_polylines};
pub use obj_mesh::{mesh_to_obj, parse_obj_mesh};
pub use points::{PointCurve, curves_from_points};
pub use reference::{curves_to_reference_text, parse_reference_curves};
pub use supports_file::{EndPlace, SUPPORTS_FORMAT, SupportEntry, parse_supports_file};

use crate::geom::Vec3;
use crate::material::CurveSpec;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::fs;
use std::path::Path;

/// Where a piece of input came from, for messages.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Origin {
    /// The file name as given by the caller (or a description such as `<memory>`).
    pub file: String,
    /// 1-based line number; 0 when the line is unknown.
    pub line: usize,
}

impl Origin {
    /// Builds an origin from a file name and a 1-based line (0 = unknown).
    pub fn new(file: impl Into<String>, line: usize) -> Self {
        Origin {
            file: file.into(),
            line,
        }
    }
}

/// `file:line`, or `file` alone when the line is unknown (0): a whole-file finding.
impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}", self.file)
        } else {
            write!(f, "{}:{}", self.file, self.line)
        }
    }
}

/// One input curve.
///
/// For a closed curve, `points` does not repeat the first point at the end: the repeated point
/// is dropped on load, and the writers add it back for the formats that repeat it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Polyline {
    /// The curve's vertices in order.
    pub points: Vec<Vec3>,
    /// True when the last point connects back to the first.
    pub closed: bool,
    /// Where the curve was defined (its `CURVE` record, `l` record or JSON object).
    pub origin: Origin,
    /// The curve's label from the file, if it had one.
    pub label: Option<String>,
}

#[cfg(test)]
impl Polyline {
    /// The open straight polyline from `a` to `b` in `segments` equal segments, made in a test.
    pub(crate) fn straight(a: Vec3, b: Vec3, segments: usize) -> Self {
        Polyline {
            points: (0..=segments)
                .map(|k| a.lerp(b, k as f64 / segments as f64))
                .collect(),
            closed: false,
            origin: Origin::new("<test>", 0),
            label: None,
        }
    }
}

impl Polyline {
    /// Total length of the polyline, including the closing segment when the curve is closed.
    pub fn length(&self) -> f64 {
        let open: f64 = self.points.windows(2).map(|w| w[0].dist(w[1])).sum();
        match (self.closed, self.points.first(), self.points.last()) {
            (true, Some(&first), Some(&last)) if self.points.len() >= 2 => open + last.dist(first),
            _ => open,
        }
    }

    /// Number of segments: `n - 1` for an open curve of `n` points, `n` for a closed one
    /// (0 for fewer than two points).
    pub fn segment_count(&self) -> usize {
        match self.points.len() {
            0 | 1 => 0,
            n if self.closed => n,
            n => n - 1,
        }
    }
}

/// A triangle mesh.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TriMesh {
    /// Vertex positions.
    pub vertices: Vec<Vec3>,
    /// Triangles as 0-based indices into `vertices`.
    pub faces: Vec<[u32; 3]>,
}

impl TriMesh {
    /// The corners of every face whose indices are in range and whose corners are finite,
    /// in face order (the faces a geometric query can use).
    pub fn finite_triangles(&self) -> Vec<[Vec3; 3]> {
        self.faces
            .iter()
            .filter_map(|f| {
                let get = |i: u32| self.vertices.get(i as usize).copied();
                let t = [get(f[0])?, get(f[1])?, get(f[2])?];
                t.iter().all(|p| p.is_finite()).then_some(t)
            })
            .collect()
    }
}

/// An input error. Every variant names the file and (where it has one) the line, and displays
/// as `file:line: message`, or `file: message` when no line applies.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The file could not be read.
    #[error("{file}: cannot read the file: {source}")]
    Io {
        /// The file name.
        file: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The file extension does not name a format this reader knows.
    #[error("{file}: {message}")]
    UnsupportedFormat {
        /// The file name.
        file: String,
        /// What was expected.
        message: String,
    },
    /// The content is malformed or invalid.
    #[error("{}: {message}", Origin::new(file.as_str(), *line))]
    Parse {
        /// The file name.
        file: String,
        /// 1-based line of the offending token (or of the record of a whole-curve problem);
        /// 0 when it could not be located.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

impl InputError {
    /// Builds a [`InputError::Parse`].
    pub fn parse(file: &str, line: usize, message: impl Into<String>) -> Self {
        InputError::Parse {
            file: file.to_owned(),
            line,
            message: message.into(),
        }
    }

    /// The file the error is about.
    pub fn file(&self) -> &str {
        match self {
            InputError::Io { file, .. }
            | InputError::UnsupportedFormat { file, .. }
            | InputError::Parse { file, .. } => file,
        }
    }

    /// The 1-based line the error is about, if known.
    pub fn line(&self) -> Option<usize> {
        match self {
            InputError::Parse { line, .. } if *line > 0 => Some(*line),
            _ => None,
        }
    }

    /// The message without the `file:line:` prefix.
    pub fn message(&self) -> String {
        match self {
            InputError::Io { source, .. } => format!("cannot read the file: {source}"),
            InputError::UnsupportedFormat { message, .. } | InputError::Parse { message, .. } => {
                message.clone()
            }
        }
    }
}

/// A non-fatal finding while reading, such as near-duplicate consecutive points or a degenerate
/// mesh face. Displays as `file:line: warning: message`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputWarning {
    /// Where the finding is.
    pub origin: Origin,
    /// What was found, and what was done about it.
    pub message: String,
}

impl InputWarning {
    /// Builds a warning at `file:line`.
    pub fn new(file: &str, line: usize, message: impl Into<String>) -> Self {
        InputWarning {
            origin: Origin::new(file, line),
            message: message.into(),
        }
    }
}

impl fmt::Display for InputWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: warning: {}", self.origin, self.message)
    }
}

/// The curves of one file, with the warnings found while reading it.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveFile {
    /// The curves, in file order.
    pub curves: Vec<Polyline>,
    /// Non-fatal findings, in file order.
    pub warnings: Vec<InputWarning>,
    /// What the file says about each curve's material, section and rest shape (curvenet's
    /// JSON format only): one per curve, or empty when the file says nothing.
    pub specs: Vec<CurveSpec>,
    /// The length unit the file declares (JSON `"units"`), as written.
    pub units: Option<String>,
    /// Each curve's group (the JSON format's `"group"`; `None` for every curve of the other
    /// formats): curves of one group are kept or removed together. Aligned with `curves`.
    pub groups: Vec<Option<String>>,
    /// The edge length the file declares (JSON `"edge_length"`, in the file's coordinates):
    /// what the network is built with when the command line gives none.
    pub edge_length: Option<f64>,
}

impl CurveFile {
    /// Curves of a format that says nothing about materials, units or groups.
    fn plain(curves: Vec<Polyline>, warnings: Vec<InputWarning>) -> Self {
        let groups = vec![None; curves.len()];
        CurveFile {
            curves,
            warnings,
            specs: Vec::new(),
            units: None,
            groups,
            edge_length: None,
        }
    }
}

/// The mesh of one file, with the warnings found while reading it.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshFile {
    /// The triangles (degenerate faces left out).
    pub mesh: TriMesh,
    /// Non-fatal findings, in file order.
    pub warnings: Vec<InputWarning>,
}

/// Reads a curve file, choosing the format from the extension (case-insensitive): `.txt` is the
/// reference text format, `.obj` OBJ polylines, `.json` curvenet's JSON format.
///
/// Messages name the file as `path` displays.
///
/// # Errors
///
/// [`InputError::UnsupportedFormat`] for any other extension, [`InputError::Io`] when the file
/// cannot be read, [`InputError::Parse`] for text that is not UTF-8 and for everything the
/// format's parser rejects.
pub fn read_curves(path: &Path) -> Result<CurveFile, InputError> {
    let parse: Option<Parser<CurveFile>> = match extension(path).as_deref() {
        Some("txt") => Some(parse_reference_curves),
        Some("obj") => Some(parse_obj_polylines),
        Some("json") => Some(parse_json_curves),
        _ => None,
    };
    let expected = "unsupported curve file extension: expected .txt (reference format), .obj \
                    (polylines) or .json (curvenet-curves)";
    read_with(path, parse, expected)
}

/// Reads an OBJ triangle mesh (`v` and `f` records) with [`parse_obj_mesh`].
///
/// # Errors
///
/// [`InputError::UnsupportedFormat`] for an extension other than `.obj` (case-insensitive),
/// [`InputError::Io`] when the file cannot be read, [`InputError::Parse`] for text that is not
/// UTF-8 and for everything [`parse_obj_mesh`] rejects.
pub fn read_mesh(path: &Path) -> Result<MeshFile, InputError> {
    let obj = extension(path).as_deref() == Some("obj");
    let parse: Option<Parser<MeshFile>> = obj.then_some(parse_obj_mesh);
    read_with(
        path,
        parse,
        "unsupported mesh file extension: expected .obj",
    )
}

/// A parser of one format: the text, and the file's name for messages.
type Parser<T> = fn(&str, &str) -> Result<T, InputError>;

/// Reads `path` with `parse`, the parser its extension names (`None`: an
/// [`InputError::UnsupportedFormat`] saying what was `expected`). A directory is an
/// [`InputError::Io`] that says so, before its extension (which a directory's name need not
/// have) is looked at.
fn read_with<T>(path: &Path, parse: Option<Parser<T>>, expected: &str) -> Result<T, InputError> {
    let file = path.display().to_string();
    if path.is_dir() {
        let source = std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "it is a directory, not a file",
        );
        return Err(InputError::Io { file, source });
    }
    let Some(parse) = parse else {
        let message = expected.to_owned();
        return Err(InputError::UnsupportedFormat { file, message });
    };
    let text = read_text(path, &file)?;
    parse(&text, &file)
}

/// The lower-cased extension of `path`, if it has one.
fn extension(path: &Path) -> Option<String> {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
}

/// Reads the supports file at `path` ([`parse_supports_file`]).
///
/// # Errors
///
/// The file cannot be read, or what [`parse_supports_file`] finds.
pub fn read_supports_file(path: &Path) -> Result<Vec<SupportEntry>, InputError> {
    let file = path.display().to_string();
    let text = read_text(path, &file)?;
    parse_supports_file(&text, &file)
}

/// Reads a whole file as UTF-8; invalid UTF-8 is a parse error at the line where it occurs.
fn read_text(path: &Path, file: &str) -> Result<String, InputError> {
    let bytes = fs::read(path).map_err(|source| InputError::Io {
        file: file.to_owned(),
        source,
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let line = 1 + bytes[..valid.min(bytes.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        InputError::parse(file, line, "the file is not valid UTF-8 text")
    })
}

#[cfg(test)]
mod tests;

//! Exports of a run's networks for other tools: one recorded iteration `K` of a
//! [`RunFolder`] (the final one by default), its answer or one of its alternatives
//! ([`Which`]; files then named `…_answer.…`, `…_alternative-N.…` instead of `…_KKKK.…`) in
//! the formats of `curvenet export`.
//!
//! - [`curves`]: OBJ polylines and curvenet-curves JSON;
//! - [`tables`]: the points table and the fabrication table (CSV);
//! - [`network_file`]: the reloadable network file;
//! - [`rods`]: what the tables and the viewer say about a rod (arc lengths, supports, joints).
//!
//!
//! | function | file | content |
//! |---|---|---|
//! | [`curves_obj`] | `curves_KKKK.obj`, `curves_KKKK_rest.obj` | OBJ polylines (`v` + `l`, closed curves repeat their first index; `o curve N` names), at equilibrium or at rest |
//! | [`curves_json`] | `curves_KKKK.json`, `curves_KKKK_equilibrium.json` | curvenet-curves JSON ([`crate::io::read_curves`] reads it back) at rest or at equilibrium; each curve's label is `id=N; rest_length=L; closed=B; supports=S` |
//! | [`points_csv`] | `points_KKKK.csv` | one row per network vertex of every kept curve: arc length, rest and equilibrium positions |
//! | [`fabrication_csv`] | `fabrication_KKKK.csv` | one row per kept rod: rest (= cut) length, the joints along it (arc length and the rods met there), end supports |
//! | [`network_json`] | `network_KKKK.json` | the kept structure at network resolution (`"format": "curvenet-network"`): rest positions, rods with vertex lists, rest lengths and anchors, supports, material, equilibrium displacements; [`load_network`] reads it back |
//!
//! The OBJ, JSON and fabrication writers also take any structure of a network with its
//! displacements ([`structure_obj`], [`structure_json`], [`fabrication_table`]): `curvenet
//! serve` exports the structure being designed with them.
//!
//! The network file holds everything the energy depends on, bit for bit (numbers in Rust's
//! shortest round-trip form), so analysing the loaded network gives the `λ` of the exported
//! structure again with no resampling. Its vertices are the kept rods' vertices in their
//! original order, renumbered from 0; its rods are the kept curves in ascending id order,
//! renumbered from 0, each with its original `id`.

pub mod curves;
pub mod network_file;
pub mod opensees;
pub mod rods;
pub mod structural;
pub mod tables;

pub use curves::{curves_json, curves_obj, parse_curve_label, structure_json, structure_obj};
pub use network_file::{
    NETWORK_FORMAT, NETWORK_VERSION, NetworkFile, NetworkFileRod, joints_of, load_network,
    network_file, network_json, parse_network_file, read_network_file,
};
pub use opensees::opensees_script;
pub use rods::{RodJoint, arc_lengths, end_support, rod_joints, rod_supports};
pub use structural::{STRUCTURE_FORMAT, StructuralModel};
pub use tables::{fabrication_csv, fabrication_table, points_csv};

use crate::io;
use crate::report::ReportError;
use crate::run_folder::{RunFolder, Which};
use std::path::{Path, PathBuf};

/// Formats of `curvenet export`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// OBJ polylines at equilibrium and at rest.
    Obj,
    /// curvenet-curves JSON at rest and at equilibrium.
    Json,
    /// The points table and the fabrication table.
    Csv,
    /// The network file.
    Network,
    /// The neutral structural JSON (a physical run's).
    Structural,
    /// The OpenSeesPy script (a physical run's).
    Opensees,
    /// All of the above (the last two for a physical run).
    All,
}

impl std::str::FromStr for ExportFormat {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        use ExportFormat::*;
        let names = [
            ("obj", Obj),
            ("json", Json),
            ("csv", Csv),
            ("network", Network),
            ("structural", Structural),
            ("opensees", Opensees),
            ("all", All),
        ];
        let found = names.into_iter().find(|n| n.0 == s);
        found.map(|n| n.1).ok_or_else(|| {
            format!(
                "unknown export format '{s}' (expected obj, json, csv, network, structural, \
                 opensees or all)"
            )
        })
    }
}

/// The files of `format` for iteration `k` (or the answer, or an alternative: any
/// [`Which`]; files named by [`crate::run_folder::Chosen::tag`]: `curves_0003.obj`,
/// `curves_answer.obj`, `curves_alternative-2.obj`): `(file name, content)` pairs, each
/// format's main file first (OBJ at equilibrium, JSON at rest, the fabrication table, the
/// network file).
pub fn export_files(
    run: &RunFolder,
    which: impl Into<Which>,
    format: ExportFormat,
) -> Result<Vec<(String, String)>, ReportError> {
    use ExportFormat::*;
    type Make = fn(&RunFolder, Which) -> Result<String, ReportError>;
    // Each file: its format, its name around the tag, what writes it.
    let files: [(ExportFormat, &str, &str, Make); 9] = [
        (Obj, "curves_", ".obj", |r, w| curves_obj(r, w, false)),
        (Obj, "curves_", "_rest.obj", |r, w| curves_obj(r, w, true)),
        (Json, "curves_", ".json", |r, w| curves_json(r, w, true)),
        (Json, "curves_", "_equilibrium.json", |r, w| {
            curves_json(r, w, false)
        }),
        (Csv, "fabrication_", ".csv", |r, w| fabrication_csv(r, w)),
        (Csv, "points_", ".csv", |r, w| points_csv(r, w)),
        (Network, "network_", ".json", |r, w| network_json(r, w)),
        (Structural, "structure_", ".json", |r, w| {
            Ok(structural_model(r, w)?.to_json())
        }),
        (Opensees, "opensees_", ".py", |r, w| {
            Ok(opensees_script(&structural_model(r, w)?))
        }),
    ];
    let which = which.into();
    let k = run.network_of(which)?.tag;
    let physical = run.result.setup.physical_model.is_some();
    if matches!(format, Structural | Opensees) && !physical {
        return Err(ReportError::NotPhysical);
    }
    let wanted = files.iter().filter(|f| {
        (format == All && (physical || !matches!(f.0, Structural | Opensees))) || format == f.0
    });
    wanted
        .map(|(_, stem, end, make)| Ok((format!("{stem}{k}{end}"), make(run, which)?)))
        .collect()
}

/// The structural model of iteration `k` (any [`Which`]) of a physical run, at its drawn
/// positions ([`structural`] says what it carries).
///
/// # Errors
///
/// [`ReportError::NotPhysical`] for a run in the paper's mode; the run folder's errors.
pub fn structural_model(
    run: &RunFolder,
    which: impl Into<Which>,
) -> Result<StructuralModel, ReportError> {
    let which = which.into();
    let model = (run.result.setup.physical_model.as_ref()).ok_or(ReportError::NotPhysical)?;
    let rec = run.network_of(which)?;
    let source = format!("{} {}", run.dir.display(), rec.what);
    StructuralModel::new(&run.network, &rec.curves, model, source, rec.unstable)
        .map_err(|e| ReportError::Invalid(e.to_string()))
}

/// Writes the files of `format` for iteration `k` (any [`Which`]) into the folder `out`
/// (created if needed); returns their paths.
pub fn write_exports(
    run: &RunFolder,
    which: impl Into<Which>,
    format: ExportFormat,
    out: &Path,
) -> Result<Vec<PathBuf>, ReportError> {
    let files = export_files(run, which, format)?;
    std::fs::create_dir_all(out).map_err(|e| ReportError::io(out, e))?;
    let mut paths = Vec::new();
    for (name, text) in files {
        let p = out.join(name);
        io::write_atomic(&p, text.as_bytes()).map_err(|e| ReportError::io(&p, e))?;
        paths.push(p);
    }
    Ok(paths)
}

/// The header line of an export of an unstable network (`why` from
/// [`crate::run_folder::instability`]): the files say it cannot be built as it is.
pub fn unstable_header(why: &str) -> String {
    format!("WARNING: this network is {why}; it cannot stand as built (not a network to fabricate)")
}

/// `text` with the [`unstable_header`] of a network that is unstable (`why`) as a `#` comment
/// after its first line.
fn with_unstable_header(mut text: String, why: Option<&str>) -> String {
    if let Some(w) = why {
        let first = text.find('\n').map_or(text.len(), |i| i + 1);
        text.insert_str(first, &format!("# {}\n", unstable_header(w)));
    }
    text
}

/// A number in Rust's shortest round-trip form.
fn num(v: f64) -> String {
    format!("{v:?}")
}

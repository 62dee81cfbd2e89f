//! `GET /api/export`: the current structure as a file to save, in the formats of
//! `curvenet export` (its writers, [`curvenet::report::export`]).

use crate::design::Design;

/// A format of `GET /api/export?format=…`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// OBJ polylines at equilibrium.
    Obj,
    /// The fabrication table (CSV): one row per kept rod, its cut length and joints.
    Csv,
    /// curvenet-curves JSON at rest (reloadable as `--curves`).
    Json,
}

impl Format {
    /// The format named `name`.
    ///
    /// # Errors
    ///
    /// A message naming the formats when `name` is none of them.
    pub fn parse(name: &str) -> Result<Self, String> {
        match name {
            "obj" => Ok(Format::Obj),
            "csv" => Ok(Format::Csv),
            "json" => Ok(Format::Json),
            _ => Err(format!(
                "unknown export format '{name}' (expected obj, csv or json)"
            )),
        }
    }

    /// The MIME type of the file.
    pub fn content_type(self) -> &'static str {
        match self {
            Format::Obj => "text/plain; charset=utf-8",
            Format::Csv => "text/csv; charset=utf-8",
            Format::Json => "application/json",
        }
    }
}

/// The file of the current structure of `design` in `format`: its name and its content.
pub fn export(design: &Design, format: Format) -> (String, String) {
    let current = design.current();
    let net = design.analyzer().network();
    let curves = &current.summary.curves;
    let n = net.rods.len();
    let what = format!("the served structure ({} of {n} curves)", curves.len());
    let stem = format!("curvenet_{}_of_{n}", curves.len());
    use curvenet::report::export::{fabrication_table, structure_json, structure_obj};
    match format {
        Format::Obj => (
            format!("{stem}.obj"),
            structure_obj(net, curves, Some(&current.displacement), &what),
        ),
        Format::Csv => (
            format!("{stem}_fabrication.csv"),
            fabrication_table(net, &what, curves, current.summary.length),
        ),
        Format::Json => (format!("{stem}.json"), structure_json(net, curves, None)),
    }
}

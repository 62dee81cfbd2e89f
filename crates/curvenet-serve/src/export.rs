//! `GET /api/export`: the current structure as a file to save, in the formats of
//! `curvenet export` (its writers, [`curvenet::report::export`]).

use crate::workspace::Workspace;
use curvenet::run_folder::instability;

/// A format of `GET /api/export?format=…`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// OBJ polylines at equilibrium.
    Obj,
    /// The fabrication table (CSV): one row per kept rod, its cut length and joints.
    Csv,
    /// curvenet-curves JSON at rest (reloadable as `--curves`): the curves as drawn when the
    /// design's curves can be edited, else the network's rods.
    Json,
    /// The surface as an OBJ mesh (reloadable as `--mesh`), in the scene's units.
    Surface,
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
            "surface" => Ok(Format::Surface),
            _ => Err(format!(
                "unknown export format '{name}' (expected obj, csv, json or surface)"
            )),
        }
    }

    /// The MIME type of the file.
    pub fn content_type(self) -> &'static str {
        match self {
            Format::Obj | Format::Surface => "text/plain; charset=utf-8",
            Format::Csv => "text/csv; charset=utf-8",
            Format::Json => "application/json",
        }
    }
}

/// The file of the current structure of `ws` in `format`: its name and its content. The
/// OBJ and the fabrication table of an unstable structure carry the warning of
/// `curvenet export` on their second line. The JSON of a design whose curves can be edited
/// holds the kept curves as drawn (what `--curves` reads back into the same network, at the
/// same edge length); `surface` is the surface (`None` when the server has none).
pub fn export(ws: &Workspace, format: Format) -> Option<(String, String)> {
    let design = &ws.design;
    let current = design.current();
    let net = design.analyzer().network();
    let curves = &current.summary.curves;
    let n = net.rods.len();
    let what = format!("the served structure ({} of {n} curves)", curves.len());
    let stem = format!("curvenet_{}_of_{n}", curves.len());
    use curvenet::report::export::{
        fabrication_table, structure_json, structure_obj, unstable_header,
    };
    let s = &current.summary;
    // An unstable structure's files say so on their second line (as `curvenet export`'s).
    let warn = |text: String| match instability(s.lambda, s.zero_modes, s.negative_modes) {
        Some(why) => {
            let first = text.find('\n').map_or(text.len(), |i| i + 1);
            let mut text = text;
            text.insert_str(first, &format!("# {}\n", unstable_header(&why)));
            text
        }
        None => text,
    };
    Some(match format {
        Format::Obj => (
            format!("{stem}.obj"),
            warn(structure_obj(
                net,
                curves,
                Some(&current.displacement),
                &what,
            )),
        ),
        Format::Csv => (
            format!("{stem}_fabrication.csv"),
            warn(fabrication_table(net, &what, curves, s.length)),
        ),
        Format::Json => match &ws.drawing {
            Some(d) => (format!("{stem}.json"), d.curves_json(Some(curves))),
            None => (format!("{stem}.json"), structure_json(net, curves, None)),
        },
        Format::Surface => {
            let mesh = ws.mesh.as_deref()?;
            ("surface.obj".to_string(), curvenet::io::mesh_to_obj(mesh))
        }
    })
}

//! OBJ polylines and curvenet-curves JSON of an iteration's curves.

use super::num;
use super::rods::rod_supports;
use crate::io;
use crate::network::Network;
use crate::report::ReportError;
use crate::run_folder::{RunFolder, Which, curve_polylines, positions_at};

fn label(net: &Network, c: usize) -> String {
    let rod = &net.rods[c];
    format!(
        "id={c}; rest_length={}; closed={}; supports={}",
        num(rod.rest_length()),
        rod.closed,
        rod_supports(rod)
    )
}

/// OBJ polylines of the curves of iteration `k` (or of the answer or an alternative: any
/// [`Which`]): at equilibrium (`rest = false`) or in the designed rest state. One
/// `o curve N` object and one `l` record per curve.
pub fn curves_obj(
    run: &RunFolder,
    which: impl Into<Which>,
    rest: bool,
) -> Result<String, ReportError> {
    let which = which.into();
    let rec = run.network_of(which)?;
    let u = displacement(run, which, rest)?;
    let obj = structure_obj(&run.network, &rec.curves, u.as_deref(), &rec.what);
    Ok(super::with_unstable_header(obj, rec.unstable.as_deref()))
}

/// OBJ polylines of `curves` of `net` at displacements `u` (`None`: the designed rest state);
/// `what` names the structure in the header line. One `o curve N` object and one `l` record
/// per curve.
pub fn structure_obj(net: &Network, curves: &[usize], u: Option<&[f64]>, what: &str) -> String {
    let pos = positions_at(net, u);
    let mut out = format!(
        "# curvenet export: {what}, {} curves, {} state, scene units\n",
        curves.len(),
        if u.is_none() {
            "rest (designed)"
        } else {
            "equilibrium"
        }
    );
    out.push_str(&io::curves_to_obj(&curve_polylines(
        net,
        curves,
        &pos,
        |c| format!("curve {c}"),
    )));
    out
}

/// The displacements of `which` (`None` for the designed rest state).
fn displacement(
    run: &RunFolder,
    which: Which,
    rest: bool,
) -> Result<Option<Vec<f64>>, ReportError> {
    Ok((!rest).then(|| run.displacement_of(which)).transpose()?)
}

/// curvenet-curves JSON of the curves of iteration `k` (any [`Which`]), at rest or at
/// equilibrium; labels carry `id`, `rest_length`, `closed` and `supports`.
pub fn curves_json(
    run: &RunFolder,
    which: impl Into<Which>,
    rest: bool,
) -> Result<String, ReportError> {
    let which = which.into();
    let rec = run.network_of(which)?;
    let u = displacement(run, which, rest)?;
    Ok(structure_json(&run.network, &rec.curves, u.as_deref()))
}

/// curvenet-curves JSON of `curves` of `net` at displacements `u` (`None`: at rest); labels
/// carry `id`, `rest_length`, `closed` and `supports`.
pub fn structure_json(net: &Network, curves: &[usize], u: Option<&[f64]>) -> String {
    let pos = positions_at(net, u);
    io::curves_to_json(&curve_polylines(net, curves, &pos, |c| label(net, c)))
}

/// Parses a label written by [`curves_json`] into `(id, rest_length, closed, supports)`.
pub fn parse_curve_label(label: &str) -> Option<(usize, f64, bool, String)> {
    let mut id = None;
    let mut len = None;
    let mut closed = None;
    let mut supports = None;
    for part in label.split(';') {
        let (k, v) = part.trim().split_once('=')?;
        match k {
            "id" => id = v.parse().ok(),
            "rest_length" => len = v.parse().ok(),
            "closed" => closed = v.parse().ok(),
            "supports" => supports = Some(v.to_string()),
            _ => {}
        }
    }
    Some((id?, len?, closed?, supports?))
}

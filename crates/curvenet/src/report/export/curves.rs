//! OBJ polylines and curvenet-curves JSON of a recorded network's curves.

use super::num;
use super::rods::rod_supports;
use crate::io;
use crate::network::Network;
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
pub fn curves_obj(run: &RunFolder, which: impl Into<Which>, rest: bool) -> Result<String, String> {
    let which = which.into();
    let net = run.network_of(which)?;
    let pos = if rest {
        positions_at(&run.network, None)
    } else {
        positions_at(&run.network, Some(&run.displacement_of(which)?))
    };
    let mut out = format!(
        "# curvenet export: {}, {} curves, {} state, scene units\n",
        net.what,
        net.curves.len(),
        if rest {
            "rest (designed)"
        } else {
            "equilibrium"
        }
    );
    out.push_str(&io::curves_to_obj(&curve_polylines(
        &run.network,
        &net.curves,
        &pos,
        |c| format!("curve {c}"),
    )));
    Ok(out)
}

/// curvenet-curves JSON of the curves of iteration `k` (any [`Which`]), at rest or at
/// equilibrium; labels carry `id`, `rest_length`, `closed` and `supports`.
pub fn curves_json(run: &RunFolder, which: impl Into<Which>, rest: bool) -> Result<String, String> {
    let which = which.into();
    let net = run.network_of(which)?;
    let pos = if rest {
        positions_at(&run.network, None)
    } else {
        positions_at(&run.network, Some(&run.displacement_of(which)?))
    };
    Ok(io::curves_to_json(&curve_polylines(
        &run.network,
        &net.curves,
        &pos,
        |c| label(&run.network, c),
    )))
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

//! Sanity checks on a network's input: findings that do not stop a network from being built but
//! that a user should hear about (they go to stderr and into the output, and the run goes on).
//!
//! - [`surface`]: the distance from a point to a triangle mesh ([`MeshDistance`]) and the curves
//!   that do not lie on their surface ([`curves_far_from_mesh`]: wrong scale or units, the mesh
//!   of another scene);
//! - [`mesh`]: faces that point to no vertex, degenerate and duplicate faces, edges shared by
//!   more than two faces (non-manifold) and edges that two faces run the same way (inconsistent
//!   orientation): [`mesh_warnings`];
//! - [`overlaps`]: pairs of curves that run together ([`overlapping_curves`]);
//! - [`network_warnings`]: what construction found: curves that cross nothing (and closed curves
//!   that float free), curves that run together, and edges far shorter than `h`
//!   (`docs/model.md`, *Numerical hazards*).
//!
//! Every function here is total: any input, however degenerate or non-finite, gives an answer
//! and never a panic.

pub mod mesh;
pub mod overlaps;
pub mod surface;

pub use mesh::mesh_warnings;
pub use overlaps::{Overlap, overlapping_curves};
pub use surface::{
    FAR_FROM_MESH, FarCurve, FarFromMesh, MeshDistance, curves_far_from_mesh, far_from_mesh_warning,
};

use super::crossings::CurveGeometry;
use super::{BuildInfo, Network};
use crate::io::Polyline;
use crate::words::{Message, Opt, message};

/// A rest edge shorter than this fraction of the target edge length `h` earns a warning: the
/// bending stiffness grows like `1/ē³`, so such an edge ill-conditions the Hessian.
pub const SHORT_EDGE: f64 = 1e-2;

/// At most this many items are listed in one warning; the rest are counted or marked.
const LIST_LIMIT: usize = 8;

/// The first [`LIST_LIMIT`] of `items` shown by `show` and joined by `sep`, then `" …"` when
/// some are left out.
fn listed<T>(items: &[T], sep: &str, show: impl Fn(&T) -> String) -> String {
    let shown: Vec<String> = items.iter().take(LIST_LIMIT).map(show).collect();
    let more = if items.len() > LIST_LIMIT { " …" } else { "" };
    format!("{}{more}", shown.join(sep))
}

/// `" and N more"` after a list of `len` items cut at [`LIST_LIMIT`], else nothing.
fn and_more(len: usize) -> String {
    match len.checked_sub(LIST_LIMIT) {
        Some(more) if more > 0 => format!(" and {more} more"),
        _ => String::new(),
    }
}

/// The warnings of a freshly built network: curves that cross nothing (closed ones float
/// free), curves that run together, and rest edges shorter than [`SHORT_EDGE`]` × h`.
/// `curves` are the input curves (for their origins), `geo` the same curves prepared for crossing
/// detection, `h` the target edge length and `factor` the relative crossing tolerance.
pub fn network_warnings(
    network: &Network,
    info: &BuildInfo,
    curves: &[Polyline],
    geo: &[CurveGeometry],
    h: f64,
    factor: f64,
) -> Vec<Message> {
    let at = |c: usize| {
        curves
            .get(c)
            .map_or_else(String::new, |p| format!(" ({})", p.origin))
    };
    let mut warnings: Vec<Message> = isolated_warnings(network, info, &at)
        .into_iter()
        .map(Message::from)
        .collect();
    warnings.extend(overlap_warning(&overlaps::overlaps_of(geo, factor)).map(Message::from));
    warnings.extend(short_edge_warning(network, h, &at));
    warnings
}

/// Curves that cross nothing, and the closed ones among them that nothing holds.
fn isolated_warnings(
    network: &Network,
    info: &BuildInfo,
    at: &dyn Fn(usize) -> String,
) -> Vec<String> {
    let mut warnings = Vec::new();
    let isolated = &info.isolated_curves;
    if !isolated.is_empty() && network.rods.len() > 1 {
        let list: Vec<String> = isolated
            .iter()
            .take(LIST_LIMIT)
            .map(|&c| format!("{c}{}", at(c)))
            .collect();
        warnings.push(format!(
            "{} curve(s) cross no other curve and stand on their supports alone: {}{}",
            isolated.len(),
            list.join(", "),
            and_more(isolated.len())
        ));
    }
    let floating: Vec<String> = isolated
        .iter()
        .filter(|&&c| network.rods.get(c).is_some_and(|r| r.closed))
        .filter(|&&c| {
            !network
                .joints
                .iter()
                .any(|j| j.curves.contains(&(c as u32)))
        })
        .take(LIST_LIMIT)
        .map(|&c| format!("{c}{}", at(c)))
        .collect();
    if !floating.is_empty() {
        warnings.push(format!(
            "closed curve(s) without supports or crossings float free: nothing holds them \
             (six rigid-body zero modes each): {}",
            floating.join(", ")
        ));
    }
    warnings
}

/// One warning for all the pairs of curves that run together.
fn overlap_warning(overlaps: &[Overlap]) -> Option<String> {
    if overlaps.is_empty() {
        return None;
    }
    let list = listed(overlaps, "; ", |o| {
        format!(
            "{} and {} over {:.4e} from ({:.4e}, {:.4e}, {:.4e})",
            o.a, o.b, o.length, o.start.x, o.start.y, o.start.z
        )
    });
    Some(format!(
        "{} pair(s) of curves run together (within the crossing tolerance of each other, \
         not crossing): curves {list}; construction joins each such pair at one point, not \
         along its length",
        overlaps.len(),
    ))
}

/// The shortest rest edge, when it is shorter than [`SHORT_EDGE`]` × h`.
fn short_edge_warning(network: &Network, h: f64, at: &dyn Fn(usize) -> String) -> Option<Message> {
    let mut shortest: Option<(f64, usize)> = None;
    for (c, rod) in network.rods.iter().enumerate() {
        for &l in &rod.rest_lengths {
            if shortest.is_none_or(|(s, _)| l < s) {
                shortest = Some((l, c));
            }
        }
    }
    let (l, c) = shortest.filter(|&(l, _)| l < SHORT_EDGE * h)?;
    Some(message![
        format!(
            "the shortest rest edge, on curve {c}{}, is {l:.4e}: {:.2e} × the edge length \
             h = {h:.4e}; two joints nearly coincide along it (or a joint and the curve's \
             end), and the Hessian's condition grows like (h/ē)³ (consider ",
            at(c),
            l / h
        ),
        Opt::MergeJoints,
        ")"
    ])
}

#[cfg(test)]
pub(crate) mod tests {
    use crate::geom::Vec3;
    use crate::io::{Origin, Polyline, TriMesh};

    pub(crate) fn square_mesh() -> TriMesh {
        TriMesh {
            vertices: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            faces: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    pub(crate) fn polyline(points: &[[f64; 3]]) -> Polyline {
        Polyline {
            points: points.iter().map(|&p| Vec3::from(p)).collect(),
            closed: false,
            origin: Origin::new("c.txt", 3),
            label: None,
        }
    }
}

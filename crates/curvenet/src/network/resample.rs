//! Resampling and locking: every curve is split at its joints, each piece between consecutive
//! break points gets `k = max(2, round(length / h))` edges at equal arc-length steps along the
//! input polyline (a closed curve with no joint gets `max(3, round(L / h))`), rest lengths are
//! the resampled edge lengths and anchors hold the supported vertices where they are.

use super::build::BuildError;
use super::crossings::CurveGeometry;
use super::joints::{JointSeed, Pass};
use super::{BuildInfo, BuildParams, Joint, Network, Rod};
use crate::geom::Vec3;
use crate::io::Polyline;
use crate::material::EndSupport;
use crate::rod::Supports;

/// Turns closer to 180° than this (`1 + cos φ` below it) make a rod's bending term blow up: the
/// discrete curvature `2 tan(φ/2)` passes `1e5`, and at exactly 180° it is undefined.
const FOLD_BACK: f64 = 1e-10;

/// Fewest edges of a piece between two break points: 2, or 3 for a loop from a joint back to
/// the same joint (with 2 edges its two edges would be one segment traversed both ways).
fn min_edges(a: Option<usize>, b: Option<usize>) -> usize {
    if a.is_some() && a == b { 3 } else { 2 }
}

/// Number of edges of a piece of arc length `len`.
fn edges_for(len: f64, h: f64, min: usize) -> usize {
    ((len / h).round() as usize).max(min)
}

/// Splits the curves at their passes, resamples and locks the network.
pub(super) fn resample(
    geo: &[CurveGeometry],
    seeds: &[JointSeed],
    passes: &[Vec<Pass>],
    params: &BuildParams,
    curves: &[Polyline],
) -> Result<(Network, BuildInfo), BuildError> {
    let mut positions: Vec<Vec3> = Vec::new();
    let mut joint_vertex: Vec<Option<u32>> = vec![None; seeds.len()];
    let mut rods = Vec::with_capacity(geo.len());
    for (ci, g) in geo.iter().enumerate() {
        let stations = stations(g, &passes[ci], params.edge_length);
        let add = |p: Vec3, positions: &mut Vec<Vec3>| {
            positions.push(p);
            (positions.len() - 1) as u32
        };
        let verts: Vec<u32> = (stations.iter())
            .map(|&(s, joint)| match joint {
                Some(j) => {
                    *joint_vertex[j].get_or_insert_with(|| add(seeds[j].position, &mut positions))
                }
                None => add(g.point_at(s), &mut positions),
            })
            .collect();
        let ends = params.ends.get(ci).copied().unwrap_or([None; 2]);
        let mut rod = lock(&positions, verts, g, params, ends)
            .map_err(|message| BuildError::degenerate(curves, ci, message.into()))?;
        if let Some(frames) = params
            .end_frames
            .get(ci)
            .filter(|f| f.iter().any(Option::is_some))
        {
            rod.frames = rod
                .ends
                .is_some()
                .then(|| frames.map(Option::unwrap_or_default));
        }
        rods.push(rod);
    }
    let mut network = Network {
        positions,
        rods,
        joints: Vec::new(),
        supports: params.supports,
    };
    network.joints = joints_at(&joint_vertex, &network);
    let info = BuildInfo {
        curves: geo.len(),
        vertices: network.vertex_count(),
        joints: network.joints.len(),
        crossings: 0,
        self_crossings: 0,
        max_curves_at_joint: network
            .joints
            .iter()
            .map(|j| j.curves.len())
            .max()
            .unwrap_or(0),
        isolated_curves: Vec::new(),
        edge_length: network.edge_length_stats(),
        min_tolerance: 0.0,
        max_tolerance: 0.0,
        warnings: Vec::new(),
    };
    Ok((network, info))
}

/// The resampled vertices of curve `g` with `passes` at edge length `h`: their arc lengths,
/// with the joint of those that are joints.
fn stations(g: &CurveGeometry, passes: &[Pass], h: f64) -> Vec<(f64, Option<usize>)> {
    let len = g.length();
    // Break points: (arc length, joint or None for a free curve end).
    let mut breaks: Vec<(f64, Option<usize>)> =
        passes.iter().map(|p| (p.s, Some(p.joint))).collect();
    let mut vertex_s: Vec<(f64, Option<usize>)> = Vec::new();
    if g.closed {
        if breaks.is_empty() {
            let k = edges_for(len, h, 3);
            vertex_s.extend((0..k).map(|i| (len * i as f64 / k as f64, None)));
        } else {
            let first = breaks[0].0;
            breaks.push((first + len, breaks[0].1));
            pieces(&breaks, h, &mut vertex_s);
        }
    } else {
        if breaks.first().is_none_or(|b| b.0 > 0.0) {
            breaks.insert(0, (0.0, None));
        }
        if breaks.last().is_none_or(|b| b.0 < len) {
            breaks.push((len, None));
        }
        pieces(&breaks, h, &mut vertex_s);
        vertex_s.push(*breaks.last().expect("an open curve has two ends"));
    }
    vertex_s
}

/// The stations of the pieces between consecutive `breaks`: each piece's first break and its
/// interior vertices at equal arc-length steps.
fn pieces(breaks: &[(f64, Option<usize>)], h: f64, vertex_s: &mut Vec<(f64, Option<usize>)>) {
    for w in breaks.windows(2) {
        let (a, b) = (w[0].0, w[1].0);
        let k = edges_for(b - a, h, min_edges(w[0].1, w[1].1));
        vertex_s.push(w[0]);
        vertex_s.extend((1..k).map(|i| (a + (b - a) * i as f64 / k as f64, None)));
    }
}

/// The rod of curve `g` through vertices `verts`, locked: rest lengths measured, the
/// supported vertices anchored. An error (for the curve) when an edge is far shorter than the
/// curve's length or the rod folds back on itself.
fn lock(
    positions: &[Vec3],
    verts: Vec<u32>,
    g: &CurveGeometry,
    params: &BuildParams,
    ends: [Option<EndSupport>; 2],
) -> Result<Rod, String> {
    let m = verts.len();
    let ne = if g.closed { m } else { m - 1 };
    let rest_lengths: Vec<f64> = (0..ne)
        .map(|j| positions[verts[j] as usize].dist(positions[verts[(j + 1) % m] as usize]))
        .collect();
    // The shortest edge and where it starts (NaN lengths count as shortest).
    let mut shortest = f64::INFINITY;
    let mut at = 0;
    for (j, &l) in rest_lengths.iter().enumerate() {
        if !(l >= shortest) {
            shortest = l;
            at = j;
        }
    }
    if !(shortest > 1e-12 * g.length()) {
        let p = positions[verts[at] as usize];
        return Err(format!(
            "resampling gives an edge of length {shortest:e} at ({:e}, {:e}, {:e}): two \
             of its vertices coincide in space but not along the curve (two joints meet, or \
             the curve folds back on itself)",
            p.x, p.y, p.z
        ));
    }
    if let Some((p, cos)) = fold_back(positions, &verts, g.closed) {
        return Err(format!(
            "the curve folds back on itself at ({:e}, {:e}, {:e}): consecutive edges turn \
             by 180° (cosine {cos:.12}), where bending is undefined",
            p.x, p.y, p.z
        ));
    }
    // Each end's support: the curve's own where it has one, else the run's.
    let default = match params.supports {
        Supports::Clamped => EndSupport::CLAMPED,
        Supports::Pinned => EndSupport::PINNED,
    };
    let own = ends.iter().any(Option::is_some) && !g.closed;
    let end_supports = [ends[0].unwrap_or(default), ends[1].unwrap_or(default)];
    let anchors = if g.closed {
        Vec::new()
    } else {
        // An end is anchored when it is held at all; a held rotation anchors its neighbour
        // too (the paper's clamp, as the network records it).
        let mut idx = Vec::new();
        for (s, (end, next)) in end_supports
            .iter()
            .zip([(0, 1.min(m - 1)), (m - 1, m.saturating_sub(2))])
        {
            if s.is_support() {
                idx.push(end);
            }
            if s.rotation_held {
                idx.push(next);
            }
        }
        let mut a: Vec<u32> = idx.into_iter().map(|i| verts[i]).collect();
        a.sort_unstable();
        a.dedup();
        a
    };
    Ok(Rod {
        vertices: verts,
        closed: g.closed,
        rest_lengths,
        anchors,
        ends: own.then_some(end_supports),
        frames: None,
    })
}

/// The first vertex of a rod where consecutive edges turn back on themselves (`1 + cos φ ≤`
/// [`FOLD_BACK`]), with the cosine of the turn.
fn fold_back(positions: &[Vec3], verts: &[u32], closed: bool) -> Option<(Vec3, f64)> {
    let m = verts.len();
    let inner = if closed { 0..m } else { 1..m.saturating_sub(1) };
    for j in inner {
        let prev = positions[verts[(j + m - 1) % m] as usize];
        let here = positions[verts[j] as usize];
        let next = positions[verts[(j + 1) % m] as usize];
        let (e0, e1) = (here - prev, next - here);
        let cos = e0.dot(e1) / (e0.norm() * e1.norm());
        if !(1.0 + cos > FOLD_BACK) {
            return Some((here, cos));
        }
    }
    None
}

/// The joints at the joints' vertices, with the curves through each, by vertex.
fn joints_at(joint_vertex: &[Option<u32>], network: &Network) -> Vec<Joint> {
    let vertex_curves = network.vertex_curves();
    let mut joints: Vec<Joint> = joint_vertex
        .iter()
        .flatten()
        .map(|&jv| Joint {
            vertex: jv,
            curves: vertex_curves[jv as usize].clone(),
        })
        .collect();
    joints.sort_by_key(|j| j.vertex);
    joints
}

impl Network {
    /// The rods' rest polylines, one per curve, for export or for a second build at another
    /// resolution (the paper's examples resample at 2, then scale).
    pub fn to_polylines(&self, template: &[Polyline]) -> Vec<Polyline> {
        self.rods
            .iter()
            .zip(template)
            .map(|(r, t)| Polyline {
                points: r
                    .vertices
                    .iter()
                    .map(|&v| self.positions[v as usize])
                    .collect(),
                closed: r.closed,
                origin: t.origin.clone(),
                label: t.label.clone(),
            })
            .collect()
    }
}

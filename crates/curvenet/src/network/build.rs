//! From input polylines to a locked rod network (SPEC §2).
//!
//! 1. crossings by closest approach ([`super::crossings`]);
//! 2. joints: crossings whose points lie within the tolerance of each other (in space, or in
//!    arc length along a common curve) form one joint shared by all their curves; a joint
//!    within the tolerance of an open curve's end becomes that end;
//! 3. resampling: every curve is split at its joints and each piece between consecutive break
//!    points gets `k = max(2, round(length / h))` edges at equal arc-length steps along the
//!    input polyline (a closed curve with no joint gets `max(3, round(L / h))` edges);
//! 4. locking: rest lengths are the resampled edge lengths and anchors hold the supported
//!    vertices where they are.

use super::crossings::{Crossing, CurveGeometry, UnionFind, find_crossings};
use super::{EdgeLengthStats, Joint, Network, Rod};
use crate::geom::Vec3;
use crate::io::Polyline;
use crate::rod::Supports;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Parameters of network construction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BuildParams {
    /// Target edge length `h` in scene units.
    pub edge_length: f64,
    /// Supports of open curves.
    pub supports: Supports,
    /// Relative crossing tolerance: two curves cross where they come closer than
    /// `tolerance · ℓ`, `ℓ` the larger of their median segment lengths (SPEC: `1e-3`).
    pub tolerance: f64,
    /// Optional: also merge joints closer than this fraction of `h` (in space or along a
    /// curve). Off by default so counts match the paper; see SPEC §11 on tiny edges.
    pub merge_joints_below: Option<f64>,
}

impl Default for BuildParams {
    fn default() -> Self {
        BuildParams {
            edge_length: 1.0,
            supports: Supports::Clamped,
            tolerance: 1e-3,
            merge_joints_below: None,
        }
    }
}

impl BuildParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), BuildError> {
        if !(self.edge_length.is_finite() && self.edge_length > 0.0) {
            return Err(BuildError::InvalidParams(format!(
                "edge length h must be a positive finite number, got {}",
                self.edge_length
            )));
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0 && self.tolerance < 0.5) {
            return Err(BuildError::InvalidParams(format!(
                "crossing tolerance must lie in (0, 0.5), got {}",
                self.tolerance
            )));
        }
        if let Some(f) = self.merge_joints_below {
            if !(f.is_finite() && f > 0.0 && f < 1.0) {
                return Err(BuildError::InvalidParams(format!(
                    "joint merging fraction must lie in (0, 1), got {f}"
                )));
            }
        }
        Ok(())
    }
}

/// Why no network could be built.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// Parameters out of range.
    #[error("invalid network parameters: {0}")]
    InvalidParams(String),
    /// No curves at all.
    #[error("no curves to build a network from")]
    NoCurves,
    /// The edge length would cut the curves into more than [`MAX_VERTICES`] vertices.
    #[error(
        "the edge length h = {edge_length:e} would cut the curves (total length \
         {total_length:e}) into about {vertices:.3e} vertices, more than the {MAX_VERTICES} a \
         network may have; give a larger --edge-length"
    )]
    TooManyVertices {
        /// The target edge length.
        edge_length: f64,
        /// Total input length of the curves.
        total_length: f64,
        /// Estimated vertex count.
        vertices: f64,
    },
    /// A curve that cannot become a rod.
    #[error("{file}:{line}: curve {curve}: {message}")]
    DegenerateCurve {
        /// Source file of the curve.
        file: String,
        /// Line of the curve in its file.
        line: usize,
        /// Curve id.
        curve: usize,
        /// What is wrong.
        message: String,
    },
}

/// What construction found, for reports.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BuildInfo {
    /// Number of curves (= rods).
    pub curves: usize,
    /// Number of vertices.
    pub vertices: usize,
    /// Number of joints.
    pub joints: usize,
    /// Crossings of two different curves (after merging hits of the same pair).
    pub crossings: usize,
    /// Crossings of a curve with itself.
    pub self_crossings: usize,
    /// Largest number of curves meeting at one joint.
    pub max_curves_at_joint: usize,
    /// Curves that cross no other curve (they stand alone, held by their supports only).
    pub isolated_curves: Vec<usize>,
    /// Rest edge lengths.
    pub edge_length: EdgeLengthStats,
    /// Smallest crossing tolerance used (scene units).
    pub min_tolerance: f64,
    /// Largest crossing tolerance used (scene units).
    pub max_tolerance: f64,
    /// Findings that do not stop the build ([`super::checks::network_warnings`]): curves that
    /// cross nothing, curves that run together, edges far shorter than `h`.
    #[serde(default)]
    pub warnings: Vec<String>,
}

/// The most vertices a network may have. The paper's largest has 25,442; far more than this
/// limit only comes from an edge length that is tiny against the curves, which would otherwise
/// exhaust memory before anything is reported.
pub const MAX_VERTICES: usize = 5_000_000;

/// The range of curve lengths and coordinate magnitudes (scene units) a network may have. The
/// bending terms scale like `1/ē³` and their Hessians faster, so far smaller scenes overflow
/// them; far larger ones lose the anchors' and the stretching terms' precision. Any physical
/// scene, in any unit, lies well inside.
pub const LENGTH_RANGE: (f64, f64) = (1e-30, 1e30);

/// One passage of a curve through a joint.
#[derive(Clone, Copy, Debug)]
struct Pass {
    s: f64,
    joint: usize,
}

/// Builds the rod network of `curves` (SPEC §2).
pub fn build_network(
    curves: &[Polyline],
    params: &BuildParams,
) -> Result<(Network, BuildInfo), BuildError> {
    params.validate()?;
    if curves.is_empty() {
        return Err(BuildError::NoCurves);
    }
    let geo: Vec<CurveGeometry> = curves
        .iter()
        .map(|c| CurveGeometry::new(c.points.clone(), c.closed))
        .collect();
    for (i, (g, c)) in geo.iter().zip(curves).enumerate() {
        let bad = |message: String| BuildError::DegenerateCurve {
            file: c.origin.file.clone(),
            line: c.origin.line,
            curve: i,
            message,
        };
        if g.points.len() < 2 || (g.closed && g.points.len() < 3) {
            return Err(bad(format!(
                "{} points are too few for a rod",
                g.points.len()
            )));
        }
        if let Some(p) = g.points.iter().find(|p| !p.is_finite()) {
            return Err(bad(format!("non-finite point {p:?}")));
        }
        if !(g.length() > 0.0) || !(g.median_segment > 0.0) {
            return Err(bad(format!(
                "the curve has zero length{}",
                if g.points.iter().any(|p| *p != g.points[0]) {
                    " (its points differ, but by so little that lengths underflow)"
                } else {
                    ""
                }
            )));
        }
        let largest = g
            .points
            .iter()
            .flat_map(|p| p.to_array())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let (lo, hi) = LENGTH_RANGE;
        if !(g.length() >= lo && g.length() <= hi && largest <= hi) {
            return Err(bad(format!(
                "the curve's length {:e} (coordinates up to {largest:e}) is outside \
                 {lo:e}..{hi:e}, the range of scene sizes the rod model computes with; \
                 rescale the scene (--scale)",
                g.length(),
            )));
        }
    }
    // Each open curve gets at least 2 edges per piece, a closed one at least 3; the estimate
    // is made in floating point so that a tiny h cannot overflow it.
    let total_length: f64 = geo.iter().map(CurveGeometry::length).sum();
    let estimate: f64 = geo
        .iter()
        .map(|g| (g.length() / params.edge_length).max(3.0) + 1.0)
        .sum();
    if !(estimate <= MAX_VERTICES as f64) {
        return Err(BuildError::TooManyVertices {
            edge_length: params.edge_length,
            total_length,
            vertices: estimate,
        });
    }
    let crossings = find_crossings(&geo, params.tolerance);
    let (joints, passes) = cluster_joints(&geo, &crossings, params);
    // Every pass through a joint splits a piece, which adds at least two edges.
    let with_joints = estimate + 2.0 * passes.iter().map(Vec::len).sum::<usize>() as f64;
    if !(with_joints <= MAX_VERTICES as f64) {
        return Err(BuildError::TooManyVertices {
            edge_length: params.edge_length,
            total_length,
            vertices: with_joints,
        });
    }
    let (network, mut info) = resample(&geo, &joints, &passes, params, curves)?;

    info.crossings = crossings.iter().filter(|c| c.a.curve != c.b.curve).count();
    info.self_crossings = crossings.len() - info.crossings;
    let mut touched = vec![false; curves.len()];
    for c in crossings.iter().filter(|c| c.a.curve != c.b.curve) {
        touched[c.a.curve as usize] = true;
        touched[c.b.curve as usize] = true;
    }
    info.isolated_curves = (0..curves.len()).filter(|&c| !touched[c]).collect();
    let tols: Vec<f64> = geo.iter().map(|g| g.tolerance(params.tolerance)).collect();
    info.min_tolerance = tols.iter().copied().fold(f64::INFINITY, f64::min);
    info.max_tolerance = tols.iter().copied().fold(0.0, f64::max);
    info.warnings = super::checks::network_warnings(
        &network,
        &info,
        curves,
        &geo,
        params.edge_length,
        params.tolerance,
    );
    Ok((network, info))
}

/// A joint before resampling: position and tolerance.
#[derive(Clone, Debug)]
struct JointSeed {
    position: Vec3,
    tolerance: f64,
}

/// Groups crossings into joints; returns the joints and, per curve, its passes sorted by arc
/// length.
fn cluster_joints(
    geo: &[CurveGeometry],
    crossings: &[Crossing],
    params: &BuildParams,
) -> (Vec<JointSeed>, Vec<Vec<Pass>>) {
    let extra = params
        .merge_joints_below
        .map_or(0.0, |f| f * params.edge_length);
    let n = crossings.len();
    let mut uf = UnionFind::new(n);

    // (a) Points of two crossings on a common curve within its tolerance in arc length.
    let mut on_curve: Vec<Vec<(f64, usize)>> = vec![Vec::new(); geo.len()];
    for (k, c) in crossings.iter().enumerate() {
        on_curve[c.a.curve as usize].push((c.a.s, k));
        on_curve[c.b.curve as usize].push((c.b.s, k));
    }
    for (ci, pts) in on_curve.iter_mut().enumerate() {
        pts.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let g = &geo[ci];
        let tol = g.tolerance(params.tolerance).max(extra);
        for w in pts.windows(2) {
            if w[1].0 - w[0].0 <= tol {
                uf.union(w[0].1, w[1].1);
            }
        }
        if g.closed && pts.len() > 1 {
            let (first, last) = (pts[0], pts[pts.len() - 1]);
            if g.arc_distance(first.0, last.0) <= tol {
                uf.union(first.1, last.1);
            }
        }
    }

    // (b) Crossing points within the tolerance of each other in space (grid hashing).
    let tol_of = |k: usize| crossings[k].tolerance.max(extra);
    let cell = (0..n).map(tol_of).fold(0.0, f64::max);
    if cell > 0.0 {
        let key = |p: Vec3| {
            (
                (p.x / cell).floor() as i64,
                (p.y / cell).floor() as i64,
                (p.z / cell).floor() as i64,
            )
        };
        let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
        for (k, c) in crossings.iter().enumerate() {
            grid.entry(key(c.midpoint())).or_default().push(k);
        }
        for (k, c) in crossings.iter().enumerate() {
            let m = c.midpoint();
            let (x, y, z) = key(m);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        if let Some(list) = grid.get(&(x + dx, y + dy, z + dz)) {
                            for &j in list {
                                if j > k
                                    && m.dist(crossings[j].midpoint()) < tol_of(k).max(tol_of(j))
                                {
                                    uf.union(k, j);
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    // Components in order of their smallest crossing: joint ids are deterministic.
    let mut joint_of = vec![usize::MAX; n];
    let mut seeds: Vec<JointSeed> = Vec::new();
    let mut sums: Vec<(Vec3, usize)> = Vec::new();
    for k in 0..n {
        let r = uf.find(k);
        if joint_of[r] == usize::MAX {
            joint_of[r] = seeds.len();
            seeds.push(JointSeed {
                position: Vec3::ZERO,
                tolerance: 0.0,
            });
            sums.push((Vec3::ZERO, 0));
        }
        let j = joint_of[r];
        joint_of[k] = j;
        sums[j].0 += crossings[k].midpoint();
        sums[j].1 += 1;
        seeds[j].tolerance = seeds[j].tolerance.max(tol_of(k));
    }
    for (seed, (sum, count)) in seeds.iter_mut().zip(&sums) {
        seed.position = *sum / *count as f64;
    }

    // Passes: per curve and joint, the curve's points clustered by arc length.
    let mut passes: Vec<Vec<Pass>> = vec![Vec::new(); geo.len()];
    for (ci, pts) in on_curve.iter().enumerate() {
        let g = &geo[ci];
        let len = g.length();
        let mut by_joint: Vec<(usize, f64)> = pts.iter().map(|&(s, k)| (joint_of[k], s)).collect();
        by_joint.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
        let mut i = 0;
        while i < by_joint.len() {
            let j = by_joint[i].0;
            let mut end = i;
            while end < by_joint.len() && by_joint[end].0 == j {
                end += 1;
            }
            let tol = seeds[j].tolerance.max(g.tolerance(params.tolerance));
            let mut group: Vec<f64> = by_joint[i..end].iter().map(|x| x.1).collect();
            // A closed curve's cluster may straddle s = 0: move the low side past L.
            if g.closed && group.len() > 1 && group[0] + len - group[group.len() - 1] <= tol {
                let wrap_from = group
                    .windows(2)
                    .position(|w| w[1] - w[0] > tol)
                    .map_or(0, |p| p + 1);
                for v in &mut group[..wrap_from] {
                    *v += len;
                }
                group.sort_by(f64::total_cmp);
            }
            let mut start = 0;
            for q in 1..=group.len() {
                if q == group.len() || group[q] - group[q - 1] > tol {
                    let mean = group[start..q].iter().sum::<f64>() / (q - start) as f64;
                    let mut s = if g.closed { mean.rem_euclid(len) } else { mean };
                    if !g.closed {
                        if s <= tol {
                            s = 0.0;
                        } else if s >= len - tol {
                            s = len;
                        }
                    }
                    passes[ci].push(Pass { s, joint: j });
                    start = q;
                }
            }
            i = end;
        }
        passes[ci].sort_by(|x, y| x.s.total_cmp(&y.s).then(x.joint.cmp(&y.joint)));
    }
    // A joint needs two passes. Merging (`merge_joints_below` wider than a small loop) can fold
    // the two passes of a self-crossing into one; that joint is then no joint at all.
    let mut count = vec![0usize; seeds.len()];
    for p in passes.iter().flatten() {
        count[p.joint] += 1;
    }
    for list in &mut passes {
        list.retain(|p| count[p.joint] >= 2);
    }
    (seeds, passes)
}

/// Fewest edges of a piece between two break points: 2, or 3 for a loop from a joint back to
/// the same joint (with 2 edges its two edges would be one segment traversed both ways).
fn min_edges(a: Option<usize>, b: Option<usize>) -> usize {
    if a.is_some() && a == b { 3 } else { 2 }
}

/// Number of edges of a piece of arc length `len`.
fn edges_for(len: f64, h: f64, min: usize) -> usize {
    ((len / h).round() as usize).max(min)
}

/// Turns closer to 180° than this (`1 + cos φ` below it) make a rod's bending term blow up: the
/// discrete curvature `2 tan(φ/2)` passes `1e5`, and at exactly 180° it is undefined.
const FOLD_BACK: f64 = 1e-10;

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

/// Splits the curves at their passes, resamples and locks the network.
fn resample(
    geo: &[CurveGeometry],
    seeds: &[JointSeed],
    passes: &[Vec<Pass>],
    params: &BuildParams,
    curves: &[Polyline],
) -> Result<(Network, BuildInfo), BuildError> {
    let h = params.edge_length;
    let mut positions: Vec<Vec3> = Vec::new();
    let mut joint_vertex: Vec<Option<u32>> = vec![None; seeds.len()];
    let mut rods = Vec::with_capacity(geo.len());

    for (ci, g) in geo.iter().enumerate() {
        let len = g.length();
        // Break points: (arc length, joint or None for a free curve end).
        let mut breaks: Vec<(f64, Option<usize>)> =
            passes[ci].iter().map(|p| (p.s, Some(p.joint))).collect();
        let mut vertex_s: Vec<(f64, Option<usize>)> = Vec::new();
        if g.closed {
            if breaks.is_empty() {
                let k = edges_for(len, h, 3);
                vertex_s.extend((0..k).map(|i| (len * i as f64 / k as f64, None)));
            } else {
                let first = breaks[0].0;
                breaks.push((first + len, breaks[0].1));
                for w in breaks.windows(2) {
                    let (a, b) = (w[0].0, w[1].0);
                    let k = edges_for(b - a, h, min_edges(w[0].1, w[1].1));
                    vertex_s.push(w[0]);
                    vertex_s.extend((1..k).map(|i| (a + (b - a) * i as f64 / k as f64, None)));
                }
            }
        } else {
            if breaks.first().is_none_or(|b| b.0 > 0.0) {
                breaks.insert(0, (0.0, None));
            }
            if breaks.last().is_none_or(|b| b.0 < len) {
                breaks.push((len, None));
            }
            for w in breaks.windows(2) {
                let (a, b) = (w[0].0, w[1].0);
                let k = edges_for(b - a, h, min_edges(w[0].1, w[1].1));
                vertex_s.push(w[0]);
                vertex_s.extend((1..k).map(|i| (a + (b - a) * i as f64 / k as f64, None)));
            }
            vertex_s.push(*breaks.last().expect("an open curve has two ends"));
        }

        let mut verts = Vec::with_capacity(vertex_s.len());
        for &(s, joint) in &vertex_s {
            let v = match joint {
                Some(j) => *joint_vertex[j].get_or_insert_with(|| {
                    positions.push(seeds[j].position);
                    (positions.len() - 1) as u32
                }),
                None => {
                    positions.push(g.point_at(s));
                    (positions.len() - 1) as u32
                }
            };
            verts.push(v);
        }
        let m = verts.len();
        let ne = if g.closed { m } else { m - 1 };
        let rest_lengths: Vec<f64> = (0..ne)
            .map(|j| positions[verts[j] as usize].dist(positions[verts[(j + 1) % m] as usize]))
            .collect();
        let degenerate = |message: String| {
            let c = &curves[ci];
            BuildError::DegenerateCurve {
                file: c.origin.file.clone(),
                line: c.origin.line,
                curve: ci,
                message,
            }
        };
        // The shortest edge and where it starts (NaN lengths count as shortest).
        let mut shortest = f64::INFINITY;
        let mut at = 0;
        for (j, &l) in rest_lengths.iter().enumerate() {
            if !(l >= shortest) {
                shortest = l;
                at = j;
            }
        }
        if !(shortest > 1e-12 * len) {
            let p = positions[verts[at] as usize];
            return Err(degenerate(format!(
                "resampling gives an edge of length {shortest:e} at ({:e}, {:e}, {:e}): two \
                 of its vertices coincide in space but not along the curve (two joints meet, or \
                 the curve folds back on itself)",
                p.x, p.y, p.z
            )));
        }
        if let Some((p, cos)) = fold_back(&positions, &verts, g.closed) {
            return Err(degenerate(format!(
                "the curve folds back on itself at ({:e}, {:e}, {:e}): consecutive edges turn \
                 by 180° (cosine {cos:.12}), where bending is undefined",
                p.x, p.y, p.z
            )));
        }
        let anchors = if g.closed {
            Vec::new()
        } else {
            let mut a: Vec<u32> = params
                .supports
                .anchored_indices(m)
                .into_iter()
                .map(|i| verts[i])
                .collect();
            a.sort_unstable();
            a.dedup();
            a
        };
        rods.push(Rod {
            vertices: verts,
            closed: g.closed,
            rest_lengths,
            anchors,
        });
    }

    let mut joints: Vec<Joint> = Vec::new();
    let vertex_curves = {
        let mut vc: Vec<Vec<u32>> = vec![Vec::new(); positions.len()];
        for (c, r) in rods.iter().enumerate() {
            for &v in &r.vertices {
                vc[v as usize].push(c as u32);
            }
        }
        vc
    };
    for jv in joint_vertex.iter().flatten() {
        let mut cs = vertex_curves[*jv as usize].clone();
        cs.sort_unstable();
        cs.dedup();
        joints.push(Joint {
            vertex: *jv,
            curves: cs,
        });
    }
    joints.sort_by_key(|j| j.vertex);
    let network = Network {
        positions,
        rods,
        joints,
        supports: params.supports,
    };
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

impl Network {
    /// The rods' rest polylines, one per curve, for export or for a second build at another
    /// resolution ("resampled at 2, then scaled", SPEC §9).
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

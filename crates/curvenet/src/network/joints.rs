//! Joints from crossings: crossings whose points lie within the tolerance of each other (in
//! space, or in arc length along a common curve) form one joint shared by all their curves,
//! and each curve passes through it where its points cluster.

use super::BuildParams;
use super::crossings::{Crossing, CurveGeometry, UnionFind};
use crate::geom::Vec3;
use std::collections::HashMap;

/// A joint before resampling: position and tolerance.
#[derive(Clone, Debug)]
pub(super) struct JointSeed {
    pub(super) position: Vec3,
    pub(super) tolerance: f64,
}

/// One passage of a curve through a joint, at arc length `s`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pass {
    pub(super) s: f64,
    pub(super) joint: usize,
}

/// Groups crossings into joints; returns the joints and, per curve, its passes sorted by arc
/// length.
pub(super) fn cluster_joints(
    geo: &[CurveGeometry],
    crossings: &[Crossing],
    params: &BuildParams,
) -> (Vec<JointSeed>, Vec<Vec<Pass>>) {
    let extra = params
        .merge_joints_below
        .map_or(0.0, |f| f * params.edge_length);
    let mut uf = UnionFind::new(crossings.len());
    let on_curve = union_along_curves(geo, crossings, params.tolerance, extra, &mut uf);
    let tol_of = |k: usize| crossings[k].tolerance.max(extra);
    union_in_space(crossings, &tol_of, &mut uf);
    let (seeds, joint_of) = joint_seeds(crossings, &tol_of, &mut uf);
    // Merging joins crossings near each other in space, so one curve can pass through a
    // merged joint twice a short way apart: the piece between would be a loop of two edges,
    // out and back (a fold). Such passes are one.
    let fold = if extra > 0.0 {
        FOLD_LOOP * params.edge_length
    } else {
        0.0
    };
    let mut passes: Vec<Vec<Pass>> = geo
        .iter()
        .zip(&on_curve)
        .map(|(g, pts)| passes_of(g, pts, &joint_of, &seeds, params.tolerance, fold))
        .collect();
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

/// A loop shorter than this many edge lengths is resampled into two edges (a fold).
const FOLD_LOOP: f64 = 2.5;

/// Joins the crossings whose points on a common curve lie within its tolerance (or `extra`)
/// in arc length; returns each curve's crossing points `(s, crossing)` sorted by arc length.
fn union_along_curves(
    geo: &[CurveGeometry],
    crossings: &[Crossing],
    tolerance: f64,
    extra: f64,
    uf: &mut UnionFind,
) -> Vec<Vec<(f64, usize)>> {
    let mut on_curve: Vec<Vec<(f64, usize)>> = vec![Vec::new(); geo.len()];
    for (k, c) in crossings.iter().enumerate() {
        on_curve[c.a.curve as usize].push((c.a.s, k));
        on_curve[c.b.curve as usize].push((c.b.s, k));
    }
    for (ci, pts) in on_curve.iter_mut().enumerate() {
        pts.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let g = &geo[ci];
        let tol = g.tolerance(tolerance).max(extra);
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
    on_curve
}

/// Joins the crossings whose points lie within the larger of their tolerances (`tol_of`) of
/// each other in space (grid hashing).
fn union_in_space(crossings: &[Crossing], tol_of: &impl Fn(usize) -> f64, uf: &mut UnionFind) {
    let cell = (0..crossings.len()).map(tol_of).fold(0.0, f64::max);
    if !(cell > 0.0) {
        return;
    }
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
                    // Cells saturate at the ends of i64 (a tolerance far below the scene's
                    // coordinates); a saturated neighbour is the cell itself.
                    let cell = (
                        x.saturating_add(dx),
                        y.saturating_add(dy),
                        z.saturating_add(dz),
                    );
                    let Some(list) = grid.get(&cell) else {
                        continue;
                    };
                    for &j in list {
                        if j > k && m.dist(crossings[j].midpoint()) < tol_of(k).max(tol_of(j)) {
                            uf.union(k, j);
                        }
                    }
                }
            }
        }
    }
}

/// The joints (one per component, in order of its smallest crossing, so joint ids are
/// deterministic) at the mean of their crossings' points, and the joint of each crossing.
fn joint_seeds(
    crossings: &[Crossing],
    tol_of: &impl Fn(usize) -> f64,
    uf: &mut UnionFind,
) -> (Vec<JointSeed>, Vec<usize>) {
    let n = crossings.len();
    let mut joint_of = vec![usize::MAX; n];
    // Per joint: the sum of its crossings' midpoints, their number, the largest tolerance.
    let mut sums: Vec<(Vec3, usize, f64)> = Vec::new();
    for k in 0..n {
        let r = uf.find(k);
        if joint_of[r] == usize::MAX {
            joint_of[r] = sums.len();
            sums.push((Vec3::ZERO, 0, 0.0));
        }
        let j = joint_of[r];
        joint_of[k] = j;
        sums[j].0 += crossings[k].midpoint();
        sums[j].1 += 1;
        sums[j].2 = sums[j].2.max(tol_of(k));
    }
    let seeds = (sums.into_iter())
        .map(|(sum, count, tolerance)| JointSeed {
            position: sum / count as f64,
            tolerance,
        })
        .collect();
    (seeds, joint_of)
}

/// A curve's passes through joints, sorted by arc length: per joint, its points `pts`
/// clustered by arc length (within the tolerance, or `fold`; a closed curve's cluster may
/// straddle `s = 0`), each cluster at its mean; an open curve's pass within the tolerance of
/// an end becomes that end.
fn passes_of(
    g: &CurveGeometry,
    pts: &[(f64, usize)],
    joint_of: &[usize],
    seeds: &[JointSeed],
    tolerance: f64,
    fold: f64,
) -> Vec<Pass> {
    let len = g.length();
    let mut passes = Vec::new();
    let mut by_joint: Vec<(usize, f64)> = pts.iter().map(|&(s, k)| (joint_of[k], s)).collect();
    by_joint.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    for run in by_joint.chunk_by(|a, b| a.0 == b.0) {
        let j = run[0].0;
        let tol = seeds[j].tolerance.max(g.tolerance(tolerance));
        let apart = tol.max(fold);
        let mut group: Vec<f64> = run.iter().map(|x| x.1).collect();
        // A closed curve's cluster may straddle s = 0: move the low side past L.
        if g.closed && group.len() > 1 && group[0] + len - group[group.len() - 1] <= apart {
            let wrap_from = group
                .windows(2)
                .position(|w| w[1] - w[0] > apart)
                .map_or(0, |p| p + 1);
            for v in &mut group[..wrap_from] {
                *v += len;
            }
            group.sort_by(f64::total_cmp);
        }
        for cluster in group.chunk_by(|a, b| !(b - a > apart)) {
            let mean = cluster.iter().sum::<f64>() / cluster.len() as f64;
            let mut s = if g.closed { mean.rem_euclid(len) } else { mean };
            if !g.closed {
                if s <= tol {
                    s = 0.0;
                } else if s >= len - tol {
                    s = len;
                }
            }
            passes.push(Pass { s, joint: j });
        }
    }
    passes.sort_by(|x, y| x.s.total_cmp(&y.s).then(x.joint.cmp(&y.joint)));
    passes
}

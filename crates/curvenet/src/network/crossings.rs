//! Crossing detection between input polylines (`docs/model.md`, *Network construction*).
//!
//! Two curves cross where two of their segments come closer than `tol = 1e-3 · ℓ`, `ℓ` the
//! larger of the two curves' median input segment lengths; a curve crosses itself where two of
//! its segments more than two segment lengths apart along it come that close. Candidate segment
//! pairs come from a bounding-volume hierarchy over the segments' boxes inflated by their
//! curve's tolerance; the test itself is the exact closest approach of two segments.
//! Hits that join the same two curves within one local segment length along both are one
//! crossing (a crossing at a polyline vertex is seen by up to four segment pairs).

use crate::geom::{Aabb, Bvh, Vec3, segment_closest_points};

/// A curve prepared for crossing detection: its points, arc lengths and tolerance.
#[derive(Clone, Debug)]
pub struct CurveGeometry {
    /// Points; a closed curve does not repeat its first point.
    pub points: Vec<Vec3>,
    /// True when an extra segment joins the last point to the first.
    pub closed: bool,
    /// Arc length at each point, and at the end (`segments + 1` entries).
    pub arc: Vec<f64>,
    /// Median input segment length `ℓ`.
    pub median_segment: f64,
}

impl CurveGeometry {
    /// Prepares a polyline.
    pub fn new(points: Vec<Vec3>, closed: bool) -> Self {
        let m = points.len();
        let segs = if closed { m } else { m.saturating_sub(1) };
        let mut arc = Vec::with_capacity(segs + 1);
        arc.push(0.0);
        let mut lens = Vec::with_capacity(segs);
        for k in 0..segs {
            let l = points[k].dist(points[(k + 1) % m]);
            lens.push(l);
            arc.push(arc[k] + l);
        }
        lens.sort_by(f64::total_cmp);
        let median_segment = if lens.is_empty() {
            0.0
        } else if lens.len() % 2 == 1 {
            lens[lens.len() / 2]
        } else {
            0.5 * (lens[lens.len() / 2 - 1] + lens[lens.len() / 2])
        };
        CurveGeometry {
            points,
            closed,
            arc,
            median_segment,
        }
    }

    /// Number of segments.
    pub fn segment_count(&self) -> usize {
        self.arc.len() - 1
    }

    /// Total arc length (including the closing segment of a closed curve).
    pub fn length(&self) -> f64 {
        *self.arc.last().expect("arc has at least one entry")
    }

    /// End points of segment `k`.
    pub fn segment(&self, k: usize) -> (Vec3, Vec3) {
        let m = self.points.len();
        (self.points[k], self.points[(k + 1) % m])
    }

    /// Length of segment `k`.
    pub fn segment_length(&self, k: usize) -> f64 {
        self.arc[k + 1] - self.arc[k]
    }

    /// The point at arc length `s` (clamped to the curve; wrapped for closed curves).
    pub fn point_at(&self, s: f64) -> Vec3 {
        let len = self.length();
        let s = if self.closed && len > 0.0 {
            s.rem_euclid(len)
        } else {
            s.clamp(0.0, len)
        };
        // Last segment whose start is <= s.
        let k = match self.arc.partition_point(|&a| a <= s) {
            0 => 0,
            i => (i - 1).min(self.segment_count() - 1),
        };
        let (a, b) = self.segment(k);
        let l = self.segment_length(k);
        if l <= 0.0 {
            a
        } else {
            a.lerp(b, ((s - self.arc[k]) / l).clamp(0.0, 1.0))
        }
    }

    /// Distance along the curve between arc lengths `a` and `b` (the shorter way round for
    /// closed curves).
    pub fn arc_distance(&self, a: f64, b: f64) -> f64 {
        let d = (a - b).abs();
        if self.closed {
            d.min(self.length() - d)
        } else {
            d
        }
    }

    /// Detection tolerance of this curve alone, `1e-3 · ℓ` (scaled by `factor / 1e-3`).
    pub fn tolerance(&self, factor: f64) -> f64 {
        factor * self.median_segment
    }
}

/// One point of a crossing on one curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// Curve id.
    pub curve: u32,
    /// Arc length along the curve.
    pub s: f64,
    /// Position on the curve.
    pub point: Vec3,
    /// Length of the input segment holding the point.
    pub segment_length: f64,
}

/// A crossing of two curves (or of one curve with itself).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The point on the first curve (the lower id; the smaller arc length on a self-crossing).
    pub a: CurvePoint,
    /// The point on the second curve.
    pub b: CurvePoint,
    /// Closest-approach distance.
    pub distance: f64,
    /// Detection tolerance of this pair.
    pub tolerance: f64,
}

impl Crossing {
    /// Midpoint of the two curve points.
    pub fn midpoint(&self) -> Vec3 {
        self.a.point.lerp(self.b.point, 0.5)
    }
}

/// A segment's identity in the flat list: curve and index along it.
#[derive(Clone, Copy, Debug)]
struct SegRef {
    curve: u32,
    seg: u32,
}

/// All crossings between the curves (and of curves with themselves), merged per curve pair,
/// in a deterministic order (by curve pair, then along the first curve).
///
/// `factor` is the relative tolerance (`1e-3` by default, [`super::BuildParams`]).
pub fn find_crossings(curves: &[CurveGeometry], factor: f64) -> Vec<Crossing> {
    // Flat list of segments with boxes inflated by their own curve's tolerance: two segments
    // closer than max(tol_a, tol_b) then always have overlapping boxes.
    let mut segs = Vec::new();
    let mut boxes = Vec::new();
    for (c, g) in curves.iter().enumerate() {
        let tol = g.tolerance(factor);
        for k in 0..g.segment_count() {
            let (p, q) = g.segment(k);
            segs.push(SegRef {
                curve: c as u32,
                seg: k as u32,
            });
            boxes.push(Aabb::of_points([&p, &q]).inflated(tol));
        }
    }
    let bvh = Bvh::new(boxes);

    let mut hits = Vec::new();
    for (i, si) in segs.iter().enumerate() {
        bvh.overlapping(bvh.item_box(i as u32), |j| {
            let j = j as usize;
            if j <= i {
                return;
            }
            if let Some(h) = test_pair(curves, si, &segs[j], factor) {
                hits.push(h);
            }
        });
    }
    merge_hits(curves, hits)
}

/// Closest approach of two segments; a hit when closer than the pair's tolerance.
fn test_pair(curves: &[CurveGeometry], a: &SegRef, b: &SegRef, factor: f64) -> Option<Crossing> {
    let (ga, gb) = (&curves[a.curve as usize], &curves[b.curve as usize]);
    let tol = ga.tolerance(factor).max(gb.tolerance(factor));
    let (p0, p1) = ga.segment(a.seg as usize);
    let (q0, q1) = gb.segment(b.seg as usize);
    let (s, t, d) = segment_closest_points(p0, p1, q0, q1);
    if d >= tol {
        return None;
    }
    let (la, lb) = (
        ga.segment_length(a.seg as usize),
        gb.segment_length(b.seg as usize),
    );
    let pa = CurvePoint {
        curve: a.curve,
        s: ga.arc[a.seg as usize] + s * la,
        point: p0.lerp(p1, s),
        segment_length: la,
    };
    let pb = CurvePoint {
        curve: b.curve,
        s: gb.arc[b.seg as usize] + t * lb,
        point: q0.lerp(q1, t),
        segment_length: lb,
    };
    if a.curve == b.curve {
        // A self-crossing needs two passes more than ~2 segment lengths apart along the curve.
        let gap = 2.0 * ga.median_segment.max(la).max(lb);
        if ga.arc_distance(pa.s, pb.s) <= gap {
            return None;
        }
    }
    let (pa, pb) = if (pa.curve, pa.s) <= (pb.curve, pb.s) {
        (pa, pb)
    } else {
        (pb, pa)
    };
    Some(Crossing {
        a: pa,
        b: pb,
        distance: d,
        tolerance: tol,
    })
}

/// Merges hits of the same curve pair that lie within one local segment length of each other
/// along both curves; keeps the closest hit of each group.
fn merge_hits(curves: &[CurveGeometry], mut hits: Vec<Crossing>) -> Vec<Crossing> {
    hits.sort_by(|x, y| {
        (x.a.curve, x.b.curve)
            .cmp(&(y.a.curve, y.b.curve))
            .then(x.a.s.total_cmp(&y.a.s))
            .then(x.b.s.total_cmp(&y.b.s))
    });
    let mut out = Vec::new();
    for group in hits.chunk_by(|x, y| (x.a.curve, x.b.curve) == (y.a.curve, y.b.curve)) {
        let (ga, gb) = (
            &curves[group[0].a.curve as usize],
            &curves[group[0].b.curve as usize],
        );
        let mut uf = UnionFind::new(group.len());
        let reach = group.iter().map(|h| h.a.segment_length).fold(0.0, f64::max);
        for i in 0..group.len() {
            for j in i + 1..group.len() {
                let (x, y) = (&group[i], &group[j]);
                if y.a.s - x.a.s > reach && !ga.closed {
                    break; // sorted by a.s: nothing further along can be within reach
                }
                let la = x.a.segment_length.max(y.a.segment_length);
                let lb = x.b.segment_length.max(y.b.segment_length);
                if ga.arc_distance(x.a.s, y.a.s) <= la && gb.arc_distance(x.b.s, y.b.s) <= lb {
                    uf.union(i, j);
                }
            }
        }
        let mut best: Vec<Option<usize>> = vec![None; group.len()];
        for i in 0..group.len() {
            let r = uf.find(i);
            match best[r] {
                Some(k) if group[k].distance <= group[i].distance => {}
                _ => best[r] = Some(i),
            }
        }
        let mut reps: Vec<usize> = best.into_iter().flatten().collect();
        reps.sort_unstable();
        out.extend(reps.into_iter().map(|k| group[k]));
    }
    out
}

/// Disjoint-set forest with path halving and union by index (deterministic roots: the
/// smallest index of a set is its root).
#[derive(Clone, Debug)]
pub struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    /// `n` singletons.
    pub fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n).collect(),
        }
    }

    /// Root of `i`'s set (its smallest member).
    pub fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// Joins the sets of `a` and `b`.
    pub fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi] = lo;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(a: Vec3, b: Vec3, n: usize) -> CurveGeometry {
        CurveGeometry::new(
            (0..=n).map(|i| a.lerp(b, i as f64 / n as f64)).collect(),
            false,
        )
    }

    #[test]
    fn two_lines_cross_once_even_at_polyline_vertices() {
        // Both lines have a vertex exactly at the crossing: four segment pairs see it.
        let a = line(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 10);
        let b = line(Vec3::new(0.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0), 10);
        let c = find_crossings(&[a, b], 1e-3);
        assert_eq!(c.len(), 1);
        assert!((c[0].a.s - 1.0).abs() < 1e-12 && (c[0].b.s - 1.0).abs() < 1e-12);
    }

    #[test]
    fn near_miss_within_tolerance_is_a_crossing_and_beyond_is_not() {
        let a = line(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 10);
        // median segment 0.2 → tolerance 2e-4
        let near = line(
            Vec3::new(0.03, -1.0, 1.5e-4),
            Vec3::new(0.03, 1.0, 1.5e-4),
            10,
        );
        let far = line(
            Vec3::new(0.03, -1.0, 2.5e-4),
            Vec3::new(0.03, 1.0, 2.5e-4),
            10,
        );
        assert_eq!(find_crossings(&[a.clone(), near], 1e-3).len(), 1);
        assert_eq!(find_crossings(&[a, far], 1e-3).len(), 0);
    }

    #[test]
    fn self_crossing_loop_is_found_but_neighbours_are_not() {
        // A curve that loops over itself: a circle-like path passing its start again.
        let n = 40;
        let pts: Vec<Vec3> = (0..=n)
            .map(|i| {
                let t = -0.3 + (2.0 * std::f64::consts::PI + 0.6) * i as f64 / n as f64;
                Vec3::new(t.sin() + 0.2 * t, 1.0 - t.cos(), 0.0)
            })
            .collect();
        let g = CurveGeometry::new(pts, false);
        let c = find_crossings(&[g], 1e-3);
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!(c[0].a.curve, 0);
        assert!(c[0].b.s - c[0].a.s > 1.0);
    }

    #[test]
    fn point_at_follows_the_polyline() {
        let g = CurveGeometry::new(
            vec![
                Vec3::ZERO,
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 2.0, 0.0),
            ],
            false,
        );
        assert_eq!(g.length(), 3.0);
        assert_eq!(g.point_at(0.5), Vec3::new(0.5, 0.0, 0.0));
        assert_eq!(g.point_at(2.0), Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(g.point_at(9.0), Vec3::new(1.0, 2.0, 0.0));
        let closed = CurveGeometry::new(
            vec![
                Vec3::ZERO,
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            true,
        );
        assert_eq!(closed.length(), 4.0);
        assert_eq!(closed.point_at(3.5), Vec3::new(0.0, 0.5, 0.0));
        assert_eq!(closed.arc_distance(0.5, 3.5), 1.0);
    }
}

//! Curves that run together: within the crossing tolerance of each other over a length where
//! a crossing would have left them. Construction then sees one crossing (one joint) where the
//! designer drew two rods lying on each other.

use crate::geom::{Aabb, Bvh, Vec3, point_segment_distance};
use crate::io::Polyline;
use crate::network::crossings::CurveGeometry;
use std::collections::HashMap;

/// Two curves that run together.
#[derive(Clone, Debug, PartialEq)]
pub struct Overlap {
    /// The lower curve id.
    pub a: usize,
    /// The higher curve id.
    pub b: usize,
    /// Length along `a` over which `b` stays within the crossing tolerance.
    pub length: f64,
    /// Where the overlap starts on `a`.
    pub start: Vec3,
}

/// Pairs of distinct curves that stay within the crossing tolerance of each other
/// (`factor ×` the larger median segment, as in crossing detection) over at least a quarter of
/// the larger of their median segment lengths (sampled every quarter of a median segment). A
/// crossing at an angle `θ` keeps the curves that close only over about `2 · tol / θ`, so with
/// the default `factor = 1e-3` this flags curves that are tangent within about 0.5° or lie on
/// each other. Sorted by curve pair; one entry (the longest run) per pair.
pub fn overlapping_curves(curves: &[Polyline], factor: f64) -> Vec<Overlap> {
    let geo: Vec<CurveGeometry> = curves
        .iter()
        .map(|c| CurveGeometry::new(c.points.clone(), c.closed))
        .collect();
    overlaps_of(&geo, factor)
}

/// Whether a curve takes part in the overlap check: two finite points at least, a finite
/// length and a positive median segment.
fn usable(g: &CurveGeometry) -> bool {
    g.points.len() >= 2
        && g.points.iter().all(|p| p.is_finite())
        && g.length().is_finite()
        && g.median_segment > 0.0
}

/// The segments of the usable curves, `(curve, segment)`, in a [`Bvh`] over their boxes
/// inflated by the largest tolerance any pair can use with them.
struct SegmentIndex {
    segments: Vec<(u32, u32)>,
    bvh: Bvh,
}

impl SegmentIndex {
    /// `None` when fewer than two curves or no usable tolerance: nothing can overlap.
    fn new(geo: &[CurveGeometry], factor: f64) -> Option<SegmentIndex> {
        let tol_max = geo
            .iter()
            .filter(|g| usable(g))
            .map(|g| g.tolerance(factor))
            .fold(0.0, f64::max);
        if !(tol_max.is_finite() && tol_max > 0.0) || geo.len() < 2 {
            return None;
        }
        let mut segments = Vec::new();
        let mut boxes = Vec::new();
        for (c, g) in geo.iter().enumerate().filter(|(_, g)| usable(g)) {
            for k in 0..g.segment_count() {
                let (p, q) = g.segment(k);
                segments.push((c as u32, k as u32));
                boxes.push(Aabb::of_points([&p, &q]).inflated(tol_max));
            }
        }
        Some(SegmentIndex {
            segments,
            bvh: Bvh::new(boxes),
        })
    }

    /// The curves other than `a` with a segment within the pair's tolerance of `p`, each once,
    /// into `near`.
    fn near(&self, geo: &[CurveGeometry], a: usize, p: Vec3, factor: f64, near: &mut Vec<usize>) {
        near.clear();
        let tol_a = geo[a].tolerance(factor);
        self.bvh.containing(p, |i| {
            let (b, kb) = self.segments[i as usize];
            let b = b as usize;
            if b == a || near.contains(&b) {
                return;
            }
            let gb = &geo[b];
            let (q0, q1) = gb.segment(kb as usize);
            if point_segment_distance(p, q0, q1) < tol_a.max(gb.tolerance(factor)) {
                near.push(b);
            }
        });
    }
}

/// A run of curve `a` near another curve: arc length along `a` where it started, its position,
/// and the arc length of the latest sample near it.
type Run = (f64, Vec3, f64);

/// The longest run per curve pair.
type Longest = HashMap<(usize, usize), Overlap>;

/// [`overlapping_curves`] on prepared geometry.
pub(super) fn overlaps_of(geo: &[CurveGeometry], factor: f64) -> Vec<Overlap> {
    let Some(index) = SegmentIndex::new(geo, factor) else {
        return Vec::new();
    };
    let mut best = Longest::new();
    for a in (0..geo.len()).filter(|&a| usable(&geo[a])) {
        runs_along(geo, a, &index, factor, &mut best);
    }
    let mut out: Vec<Overlap> = best.into_values().collect();
    out.sort_by_key(|o| (o.a, o.b));
    out
}

/// Samples curve `a` every quarter of its median segment and records, per other curve, the
/// runs of samples near it.
fn runs_along(
    geo: &[CurveGeometry],
    a: usize,
    index: &SegmentIndex,
    factor: f64,
    best: &mut Longest,
) {
    let ga = &geo[a];
    let mut runs: HashMap<usize, Run> = HashMap::new();
    let step = ga.median_segment / 4.0;
    let mut near: Vec<usize> = Vec::new();
    for k in 0..ga.segment_count() {
        let len = ga.segment_length(k);
        let samples = ((len / step).ceil() as usize).clamp(1, 16);
        let last = k + 1 == ga.segment_count();
        let (p0, p1) = ga.segment(k);
        for j in 0..samples + usize::from(last) {
            let t = j as f64 / samples as f64;
            let p = p0.lerp(p1, t);
            let s = ga.arc[k] + t * len;
            index.near(geo, a, p, factor, &mut near);
            for &b in &near {
                runs.entry(b).and_modify(|r| r.2 = s).or_insert((s, p, s));
            }
            let ended: Vec<usize> = runs.keys().copied().filter(|b| !near.contains(b)).collect();
            for b in ended {
                if let Some(run) = runs.remove(&b) {
                    close_run(geo, a, b, run, best);
                }
            }
        }
    }
    let mut open: Vec<(usize, Run)> = runs.into_iter().collect();
    open.sort_by_key(|(b, _)| *b);
    for (b, run) in open {
        close_run(geo, a, b, run, best);
    }
}

/// Keeps `run` of `a` near `b` when it is long enough (a quarter of the larger median
/// segment) and the longest of its pair so far.
fn close_run(geo: &[CurveGeometry], a: usize, b: usize, run: Run, best: &mut Longest) {
    let length = run.2 - run.0;
    let needed = 0.25 * geo[a].median_segment.max(geo[b].median_segment);
    if length < needed {
        return;
    }
    let key = (a.min(b), a.max(b));
    if best.get(&key).is_some_and(|o| o.length >= length) {
        return;
    }
    best.insert(
        key,
        Overlap {
            a: key.0,
            b: key.1,
            length,
            start: run.1,
        },
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::checks::tests::polyline;

    #[test]
    fn overlapping_curves_are_found_but_crossings_are_not() {
        let curves = vec![
            polyline(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]),
            polyline(&[[1.0, -1.0, 0.0], [1.0, 1.0, 0.0]]),
            polyline(&[[0.5, 0.0, 0.0], [1.5, 0.0, 0.0], [2.5, 0.0, 0.0]]),
            polyline(&[[0.0, 1.0, 0.0], [2.0, 1.0001, 0.0]]),
        ];
        let o = overlapping_curves(&curves, 1e-3);
        assert_eq!(o.len(), 1, "{o:?}");
        assert_eq!((o[0].a, o[0].b), (0, 2));
        assert!((o[0].length - 1.5).abs() < 1e-9, "{o:?}");
        // Nearly tangent lines at a 1e-5 angle overlap too; at 5° they cross.
        let tangent = vec![
            polyline(&[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]),
            polyline(&[[0.0, 0.0, 0.0], [10.0, 1e-4, 0.0]]),
        ];
        assert_eq!(overlapping_curves(&tangent, 1e-3).len(), 1);
        let crossing = vec![
            polyline(&[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]),
            polyline(&[[0.0, -0.4, 0.0], [10.0, 0.47, 0.0]]),
        ];
        assert!(overlapping_curves(&crossing, 1e-3).is_empty());
    }
}

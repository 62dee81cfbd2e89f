//! Crossings kept exact: a moved curve is made to pass *through* the curves it crosses.
//!
//! Moved points are projected onto the surface's flat triangles while the drawn curves lie on
//! the surface they were drawn on (a smooth one, of which the mesh is an approximation), so
//! two curves that cross on the surface can pass each other a hair apart, farther than the
//! network builder's crossing tolerance: the joint would be lost, and a curve left floating.
//! Where a segment of a moved curve passes within [`SNAP`] edge lengths of a segment of
//! another curve (the closest points inside both segments), the point of the other curve is
//! inserted into the moved one, so the builder finds the crossing exactly. The other curve is
//! not changed.

use crate::geom::{Vec3, segment_closest_points};
use crate::io::Polyline;

/// A moved curve passing closer than this many edge lengths to another curve crosses it.
pub const SNAP: f64 = 0.1;

/// Inserts into each curve of `curves` marked in `moved` the points of the other curves it
/// passes within `SNAP · edge_length` of (in curve order, so the result does not depend on
/// anything else).
pub fn snap_crossings(curves: &mut [Polyline], moved: &[bool], edge_length: f64) {
    let limit = SNAP * edge_length;
    for c in 0..curves.len() {
        if !moved[c] {
            continue;
        }
        let mut inserts: Vec<(usize, f64, Vec3)> = Vec::new();
        for (d, other) in curves.iter().enumerate() {
            if d == c {
                continue;
            }
            let segs = segments(other);
            for (i, (a, b)) in segments(&curves[c]).into_iter().enumerate() {
                let reach = limit + a.dist(b);
                for &(p, q) in &segs {
                    // Cheap rejection before the closest points.
                    if p.dist(a) > reach + p.dist(q) {
                        continue;
                    }
                    let (s, t, dist) = segment_closest_points(a, b, p, q);
                    let inside = |x: f64| x > 1e-9 && x < 1.0 - 1e-9;
                    if dist > 0.0 && dist <= limit && inside(s) && inside(t) {
                        inserts.push((i, s, p.lerp(q, t)));
                    }
                }
            }
        }
        if inserts.is_empty() {
            continue;
        }
        inserts.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
        let curve = &mut curves[c];
        let old = std::mem::take(&mut curve.points);
        let m = old.len();
        let mut k = 0;
        for i in 0..m {
            curve.points.push(old[i]);
            while k < inserts.len() && inserts[k].0 == i {
                curve.points.push(inserts[k].2);
                k += 1;
            }
        }
        // A closed curve's last segment (back to the first point) is the last index.
        debug_assert!(k == inserts.len() || curve.closed);
    }
}

/// The segments of a polyline, the closing one last.
fn segments(curve: &Polyline) -> Vec<(Vec3, Vec3)> {
    let p = &curve.points;
    let mut s: Vec<(Vec3, Vec3)> = p.windows(2).map(|w| (w[0], w[1])).collect();
    if curve.closed && p.len() > 2 {
        s.push((p[p.len() - 1], p[0]));
    }
    s
}

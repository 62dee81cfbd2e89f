//! Closest points: segment to segment, point to segment, point to triangle.

use super::Vec3;

/// Closest points of segments `[p0, p1]` and `[q0, q1]`.
///
/// Returns `(s, t, distance)` with the closest points `p0 + s (p1 - p0)` and `q0 + t (q1 - q0)`,
/// `s, t ∈ [0, 1]`. Degenerate (zero-length) segments are handled as points; parallel segments
/// give one of the closest pairs. This is the classic clamped two-parameter minimisation
/// (Ericson, *Real-Time Collision Detection*, §5.1.9), written here for this crate.
pub fn segment_closest_points(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> (f64, f64, f64) {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let a = d1.norm2();
    let e = d2.norm2();
    let f = d2.dot(r);
    let tiny = f64::MIN_POSITIVE.sqrt();
    let (s, t);
    if a <= tiny && e <= tiny {
        s = 0.0;
        t = 0.0;
    } else if a <= tiny {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(r);
        if e <= tiny {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > 1e-14 * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    let cp = p0 + d1 * s;
    let cq = q0 + d2 * t;
    (s, t, cp.dist(cq))
}

/// Distance from `p` to the segment `[a, b]` (a point when `a = b`).
pub fn point_segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    p.dist(closest_point_on_segment(p, a, b))
}

/// The point of the segment `[a, b]` closest to `p` (`a` when `a = b`).
pub fn closest_point_on_segment(p: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let d = b - a;
    let len2 = d.norm2();
    let t = if len2 > 0.0 {
        ((p - a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    a + d * t
}

/// The point of triangle `abc` closest to `p` (Ericson, *Real-Time Collision Detection*, §5.1.5,
/// by Voronoi regions). A degenerate triangle (collinear or repeated vertices) is handled as its
/// three edges.
pub fn closest_point_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let on_triangle = closest_point_regions(p, a, b, c);
    if on_triangle.is_finite() {
        return on_triangle;
    }
    // Degenerate: the nearest of the edges' nearest points.
    let mut best = a;
    let mut best_d = f64::INFINITY;
    for (u, v) in [(a, b), (b, c), (c, a)] {
        let q = closest_point_on_segment(p, u, v);
        let dq = p.dist(q);
        if dq < best_d {
            best_d = dq;
            best = q;
        }
    }
    best
}

/// Ericson's Voronoi-region walk; non-finite for degenerate triangles.
fn closest_point_regions(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_segments_meet() {
        let (s, t, d) = segment_closest_points(
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.5, -1.0, 0.1),
            Vec3::new(0.5, 1.0, 0.1),
        );
        assert!((s - 0.75).abs() < 1e-12);
        assert!((t - 0.5).abs() < 1e-12);
        assert!((d - 0.1).abs() < 1e-12);
    }

    #[test]
    fn closest_points_match_brute_force() {
        // Deterministic pseudo-random segments against a dense parameter sampling.
        let mut rng = crate::rng::SplitMix64::new(12345);
        let mut rnd = || rng.signed();
        for _ in 0..200 {
            let p0 = Vec3::new(rnd(), rnd(), rnd());
            let p1 = Vec3::new(rnd(), rnd(), rnd());
            let q0 = Vec3::new(rnd(), rnd(), rnd());
            let q1 = Vec3::new(rnd(), rnd(), rnd());
            let (_, _, d) = segment_closest_points(p0, p1, q0, q1);
            let mut best = f64::INFINITY;
            let n = 200;
            for i in 0..=n {
                for j in 0..=n {
                    let a = p0.lerp(p1, i as f64 / n as f64);
                    let b = q0.lerp(q1, j as f64 / n as f64);
                    best = best.min(a.dist(b));
                }
            }
            assert!(
                d <= best + 1e-12,
                "closest distance {d} above sampled {best}"
            );
            assert!(
                d >= best - 2e-2,
                "closest distance {d} far below sampled {best}"
            );
        }
    }

    #[test]
    fn parallel_and_degenerate_segments() {
        let (_, _, d) = segment_closest_points(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.5, 1.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
        );
        assert!((d - 1.0).abs() < 1e-12);
        let p = Vec3::new(0.2, 0.3, 0.4);
        let (_, t, d) =
            segment_closest_points(p, p, Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        assert!((t - 0.2).abs() < 1e-12);
        assert!((d - 0.5).abs() < 1e-12);
    }

    #[test]
    fn closest_points_on_a_triangle_by_region() {
        let (a, b, c) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        );
        let cases = [
            (Vec3::new(0.5, 0.5, 3.0), Vec3::new(0.5, 0.5, 0.0)),
            (Vec3::new(-1.0, -1.0, 0.0), a),
            (Vec3::new(3.0, -1.0, 0.0), b),
            (Vec3::new(-1.0, 3.0, 1.0), c),
            (Vec3::new(1.0, -2.0, 0.0), Vec3::new(1.0, 0.0, 0.0)),
            (Vec3::new(2.0, 2.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
        ];
        for (p, want) in cases {
            let got = closest_point_on_triangle(p, a, b, c);
            assert!(got.dist(want) < 1e-12, "{p:?}: {got:?} != {want:?}");
        }
        // Degenerate triangles: collinear and a single point.
        let got =
            closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), a, b, Vec3::new(1.0, 0.0, 0.0));
        assert!(got.dist(Vec3::new(1.0, 0.0, 0.0)) < 1e-12, "{got:?}");
        let got = closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), a, a, a);
        assert_eq!(got, a);
    }
}

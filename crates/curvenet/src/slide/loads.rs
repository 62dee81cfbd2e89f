//! Load cases that follow a slid structure: a point load is given by a position on the
//! network as drawn; once the curves move, it goes with the curve it acted on, to the moved
//! curve's point at the same fraction of its arc length. Self-weight, line loads and
//! pressures are defined on whatever the structure's geometry is, so they follow it as they
//! are.

use crate::geom::{Vec3, closest_point_on_segment};
use crate::io::Polyline;
use crate::physics::cases::Loads;

/// `loads` with every point load moved from the curves `before` to the same curves `after`
/// (the same order): each goes to the curve of `before` nearest to it, at the fraction of
/// that curve's arc length where its closest point lies, then to the point of `after`'s
/// curve at that fraction. Loads without point loads come back unchanged.
pub fn follow(loads: &Loads, before: &[Polyline], after: &[Polyline]) -> Loads {
    let mut moved = loads.clone();
    for case in &mut moved.cases {
        for p in &mut case.points {
            let at = Vec3::from(p.at);
            let nearest = (before.iter().enumerate())
                .map(|(c, curve)| (c, closest_fraction(curve, at)))
                .min_by(|a, b| a.1.1.total_cmp(&b.1.1));
            if let Some((c, (fraction, _))) = nearest
                && let Some(curve) = after.get(c)
            {
                let q = at_fraction(curve, fraction);
                p.at = [q.x, q.y, q.z];
            }
        }
    }
    moved
}

/// The segments of `curve` (its closing one too when closed).
fn segments(curve: &Polyline) -> Vec<(Vec3, Vec3)> {
    let p = &curve.points;
    let mut s: Vec<(Vec3, Vec3)> = p.windows(2).map(|w| (w[0], w[1])).collect();
    if curve.closed && p.len() > 2 {
        s.push((p[p.len() - 1], p[0]));
    }
    s
}

/// The fraction of `curve`'s arc length at its point closest to `at`, and that distance.
pub fn closest_fraction(curve: &Polyline, at: Vec3) -> (f64, f64) {
    let segs = segments(curve);
    let total: f64 = segs.iter().map(|(a, b)| a.dist(*b)).sum();
    let Some(&first) = curve.points.first() else {
        return (0.0, f64::INFINITY);
    };
    let (mut best, mut best_d, mut walked) = (0.0, at.dist(first), 0.0);
    for (a, b) in segs {
        let q = closest_point_on_segment(at, a, b);
        let d = at.dist(q);
        if d < best_d {
            (best, best_d) = (walked + a.dist(q), d);
        }
        walked += a.dist(b);
    }
    let fraction = if total > 0.0 { best / total } else { 0.0 };
    (fraction.clamp(0.0, 1.0), best_d)
}

/// The point of `curve` at `fraction` of its arc length.
pub fn at_fraction(curve: &Polyline, fraction: f64) -> Vec3 {
    let segs = segments(curve);
    let total: f64 = segs.iter().map(|(a, b)| a.dist(*b)).sum();
    let mut left = fraction.clamp(0.0, 1.0) * total;
    for &(a, b) in &segs {
        let l = a.dist(b);
        if left <= l && l > 0.0 {
            return a.lerp(b, left / l);
        }
        left -= l;
    }
    (segs.last().map(|s| s.1))
        .or_else(|| curve.points.first().copied())
        .unwrap_or(Vec3::new(0.0, 0.0, 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(a: Vec3, b: Vec3) -> Polyline {
        Polyline::straight(a, b, 10)
    }

    #[test]
    fn a_point_load_keeps_its_fraction_of_the_curve_it_acts_on() {
        let before = vec![
            line(Vec3::new(0.0, 0.0, 0.0), Vec3::new(10.0, 0.0, 0.0)),
            line(Vec3::new(0.0, 5.0, 0.0), Vec3::new(10.0, 5.0, 0.0)),
        ];
        let after = vec![
            line(Vec3::new(0.0, 1.0, 0.0), Vec3::new(10.0, 1.0, 0.0)),
            line(Vec3::new(0.0, 5.0, 0.0), Vec3::new(20.0, 5.0, 0.0)),
        ];
        let loads: Loads = serde_json::from_str(
            r#"{"cases": [{"name": "P", "points": [
                {"at": [3.0, 0.1, 0.0], "force": [0, 0, -1]},
                {"at": [2.5, 4.9, 0.0], "force": [0, 0, -1]}]}]}"#,
        )
        .expect("loads");
        let moved = follow(&loads, &before, &after);
        let at: Vec<[f64; 3]> = moved.cases[0].points.iter().map(|p| p.at).collect();
        let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12);
        assert!(near(at[0], [3.0, 1.0, 0.0]), "{at:?}");
        assert!(near(at[1], [5.0, 5.0, 0.0]), "{at:?}");
        assert_eq!(moved.cases[0].points[0].force, [0.0, 0.0, -1.0]);
    }
}

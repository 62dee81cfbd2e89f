//! Curves drawn through points and dragged: the smooth curve on the surface through given
//! points ([`smooth_through`]) and the move coefficients of a drag ([`drag_params`]).

use super::DrawError;
use crate::geom::Vec3;
use crate::io::{Origin, Polyline};
use crate::slide::moves::largest_distance;
use crate::slide::{CurveMove, ON_BOUNDARY, Surface};

/// The most points a curve through points takes.
pub const MAX_POINTS: usize = 1000;

/// How many times a drag's move is halved to come within the limits.
const HALVINGS: usize = 24;

/// The smooth curve through `points` (on `surface`, in order): a Catmull–Rom spline through
/// them sampled about every `spacing`, every sample projected onto the surface; an end within
/// the slide feature's distance of the boundary ([`ON_BOUNDARY`] of the diagonal) is put on
/// it, so that it slides along it when the curve is moved.
///
/// # Errors
///
/// [`DrawError::TooFewPoints`] for fewer than two distinct points.
pub fn smooth_through(
    points: &[Vec3],
    surface: &Surface,
    spacing: f64,
) -> Result<Polyline, DrawError> {
    let diagonal = surface.diagonal();
    let mut p: Vec<Vec3> = Vec::with_capacity(points.len());
    for &q in points {
        if p.last().is_none_or(|l: &Vec3| l.dist(q) > 1e-9 * diagonal) {
            p.push(q);
        }
    }
    let n = p.len();
    if n < 2 {
        return Err(DrawError::TooFewPoints { count: n });
    }
    let at = |i: isize| -> Vec3 {
        match i {
            -1 => p[0] * 2.0 - p[1],
            i if i as usize >= n => p[n - 1] * 2.0 - p[n - 2],
            i => p[i as usize],
        }
    };
    let spacing = if spacing.is_finite() && spacing > 0.0 {
        spacing
    } else {
        diagonal / 100.0
    };
    let mut out: Vec<Vec3> = Vec::new();
    for i in 0..n - 1 {
        let i = i as isize;
        let (p0, p1, p2, p3) = (at(i - 1), at(i), at(i + 1), at(i + 2));
        let steps = ((p1.dist(p2) / spacing).ceil() as usize).clamp(1, 10_000);
        for s in 0..steps {
            let t = s as f64 / steps as f64;
            let q = catmull_rom(p0, p1, p2, p3, t);
            out.push(surface.closest(q).map_or(q, |c| c.point));
        }
    }
    out.push(p[n - 1]);
    for k in [0, out.len() - 1] {
        if let Some((b, d)) = surface.closest_on_boundary(out[k])
            && d <= ON_BOUNDARY * diagonal
        {
            out[k] = b;
        }
    }
    out.dedup_by(|a, b| a.dist(*b) <= 1e-9 * diagonal);
    if out.len() < 2 {
        return Err(DrawError::TooFewPoints { count: 1 });
    }
    Ok(Polyline {
        points: out,
        closed: false,
        origin: Origin::new("<drawn through points>", 0),
        label: None,
    })
}

/// The uniform Catmull–Rom spline of `p0 … p3` between `p1` (`t = 0`) and `p2` (`t = 1`).
fn catmull_rom(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3, t: f64) -> Vec3 {
    let (t2, t3) = (t * t, t * t * t);
    (p1 * 2.0
        + (p2 - p0) * t
        + (p0 * 2.0 - p1 * 5.0 + p2 * 4.0 - p3) * t2
        + (p1 * 3.0 - p0 - p2 * 3.0 + p3) * t3)
        * 0.5
}

/// The coefficients of `family`'s move that carries the drawn curve's point nearest `from`
/// towards `to`: the function largest at that point, scaled so the point moves by the drag's
/// component across the curve, in the sense that brings the curve nearer `to`, halved until
/// the move is within the limits (all zero when none is).
///
/// # Errors
///
/// None today; a `Result` for the front ends' one error path.
pub fn drag_params(
    family: &CurveMove,
    surface: &Surface,
    from: Vec3,
    to: Vec3,
    max_move: f64,
) -> Result<Vec<f64>, DrawError> {
    let dim = family.dimension();
    let zero = vec![0.0; dim];
    let drawn = family.drawn();
    let Some((u, tangent)) = nearest_on(drawn, from) else {
        return Ok(zero);
    };
    let d = to - from;
    let across = (d - tangent * d.dot(tangent)).norm();
    let basis = family.basis();
    let Some((k, b)) = basis
        .iter()
        .map(|f| f.at(u))
        .enumerate()
        .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
    else {
        return Ok(zero);
    };
    if !(b.abs() > 1e-6 && across > 0.0) {
        return Ok(zero);
    }
    let mut best: Option<(f64, Vec<f64>)> = None;
    for sign in [1.0, -1.0] {
        let mut a = sign * across / b;
        for _ in 0..HALVINGS {
            let mut x = zero.clone();
            x[k] = a;
            if let Some(moved) = family.apply(&x, surface, max_move) {
                let gap = largest_distance(&[to], &moved);
                if best.as_ref().is_none_or(|(g, _)| gap < *g) {
                    best = Some((gap, x));
                }
                break;
            }
            a *= 0.5;
        }
    }
    Ok(best.map_or(zero, |(_, x)| x))
}

/// The arc-length fraction of the point of `curve` nearest `p`, and the unit tangent there.
fn nearest_on(curve: &Polyline, p: Vec3) -> Option<(f64, Vec3)> {
    let pts = &curve.points;
    let m = pts.len();
    let segments = if curve.closed { m } else { m.checked_sub(1)? };
    let total = curve.length();
    if segments == 0 || !(total > 0.0) {
        return None;
    }
    let mut run = 0.0;
    let mut best: Option<(f64, f64, Vec3)> = None;
    for s in 0..segments {
        let (a, b) = (pts[s], pts[(s + 1) % m]);
        let ab = b - a;
        let len = ab.norm();
        let t = ((p - a).dot(ab) / (len * len).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        let d = p.dist(a.lerp(b, t));
        if best.as_ref().is_none_or(|(bd, _, _)| d < *bd) && len > 0.0 {
            best = Some((d, (run + t * len) / total, ab * (1.0 / len)));
        }
        run += len;
    }
    best.map(|(_, u, t)| (u, t))
}

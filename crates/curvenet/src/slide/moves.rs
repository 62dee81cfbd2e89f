//! The family of moves of one curve: a smooth offset `o(u) = Σ a_k φ_k(u)` along the curve
//! (`u` its arc length over its length), applied within the surface along the direction
//! `d = n × t` (the surface's normal across the curve's tangent), every point then projected
//! back onto the surface; an end on the surface's boundary projected onto the boundary.
//!
//! The basis functions, in order (a family uses the first [`super::SlideParams::functions`]):
//!
//! | the curve | functions |
//! |---|---|
//! | open, both ends slide along the boundary | `1`, `2u − 1`, `sin πu`, `sin 2πu` |
//! | open, one end slides | `1 − u` (or `u`), `sin πu`, `sin 2πu` |
//! | open, both ends stay | `sin πu`, `sin 2πu`, `sin 3πu` |
//! | closed | `1`, `cos 2πu`, `sin 2πu` |
//!
//! Every function vanishes at an end that stays, so that end stays exactly where it is.

use super::surface::Surface;
use crate::geom::Vec3;
use crate::io::Polyline;
use std::f64::consts::PI;

/// The most a segment of a moved curve may turn beyond the drawn curve's turn at that point
/// (radians): larger turns are kinks.
pub const MAX_EXTRA_TURN: f64 = 0.5;

/// The shortest a moved segment may become, relative to the drawn one: shorter segments are
/// folds.
pub const MIN_SEGMENT_RATIO: f64 = 0.25;

/// One basis function of a curve's offset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Basis {
    /// `1`.
    Constant,
    /// `2u − 1`.
    Tilt,
    /// `1 − u`: the start end moves alone.
    Start,
    /// `u`: the far end moves alone.
    End,
    /// `sin kπu`.
    Sine(u32),
    /// `cos 2kπu` (closed curves).
    CosLoop(u32),
    /// `sin 2kπu` (closed curves).
    SinLoop(u32),
}

impl Basis {
    /// The function's value at `u ∈ [0, 1]`.
    pub fn at(self, u: f64) -> f64 {
        match self {
            Basis::Constant => 1.0,
            Basis::Tilt => 2.0 * u - 1.0,
            Basis::Start => 1.0 - u,
            Basis::End => u,
            Basis::Sine(k) => (k as f64 * PI * u).sin(),
            Basis::CosLoop(k) => (2.0 * k as f64 * PI * u).cos(),
            Basis::SinLoop(k) => (2.0 * k as f64 * PI * u).sin(),
        }
    }

    /// The basis of a curve: closed, or open with each end sliding or not; the first
    /// `functions` of its list (module docs).
    pub fn of(closed: bool, slides: [bool; 2], functions: usize) -> Vec<Basis> {
        let all = match (closed, slides) {
            (true, _) => vec![Basis::Constant, Basis::CosLoop(1), Basis::SinLoop(1)],
            (false, [true, true]) => {
                vec![Basis::Constant, Basis::Tilt, Basis::Sine(1), Basis::Sine(2)]
            }
            (false, [true, false]) => vec![Basis::Start, Basis::Sine(1), Basis::Sine(2)],
            (false, [false, true]) => vec![Basis::End, Basis::Sine(1), Basis::Sine(2)],
            (false, [false, false]) => vec![Basis::Sine(1), Basis::Sine(2), Basis::Sine(3)],
        };
        all.into_iter().take(functions).collect()
    }
}

/// One curve made ready to move: the drawn curve resampled, each sample's arc-length
/// parameter and in-surface direction across the curve, and its basis.
#[derive(Clone, Debug)]
pub struct CurveMove {
    drawn: Polyline,
    samples: Vec<Vec3>,
    u: Vec<f64>,
    across: Vec<Vec3>,
    turns: Vec<f64>,
    spacing: f64,
    slides: [bool; 2],
    basis: Vec<Basis>,
}

impl CurveMove {
    /// Prepares `drawn` (a curve on `surface`) to move: resampled at about `spacing`, its
    /// ends sliding where `slides` says (open curves), with the first `functions` of its
    /// basis.
    pub fn new(
        drawn: &Polyline,
        surface: &Surface,
        spacing: f64,
        slides: [bool; 2],
        functions: usize,
    ) -> CurveMove {
        let closed = drawn.closed;
        let samples = resample(drawn, spacing);
        let m = samples.len();
        let count = if closed { m } else { m - 1 };
        let u: Vec<f64> = (0..m).map(|i| i as f64 / count as f64).collect();
        let mut across: Vec<Vec3> = Vec::with_capacity(m);
        for i in 0..m {
            let (prev, next) = neighbours(&samples, i, closed);
            let t = (next - prev).normalized();
            let n = surface
                .closest(samples[i])
                .map_or(Vec3::new(0.0, 0.0, 1.0), |s| s.normal);
            let mut d = n.cross(t).normalized();
            if let Some(&last) = across.last()
                && d.dot(last) < 0.0
            {
                d = -d;
            }
            across.push(d);
        }
        // Two passes of neighbour averaging: the triangles' normals are piecewise constant.
        for _ in 0..2 {
            let smooth: Vec<Vec3> = (0..m)
                .map(|i| {
                    let (a, b) = neighbour_indices(m, i, closed);
                    (across[a] + across[i] * 2.0 + across[b]).normalized()
                })
                .collect();
            across = smooth;
        }
        let turns = turn_angles(&samples, closed);
        let basis = Basis::of(closed, if closed { [false; 2] } else { slides }, functions);
        CurveMove {
            drawn: drawn.clone(),
            spacing: (drawn.length() / count as f64).max(f64::MIN_POSITIVE),
            samples,
            u,
            across,
            turns,
            slides,
            basis,
        }
    }

    /// How many parameters the curve's moves have.
    pub fn dimension(&self) -> usize {
        self.basis.len()
    }

    /// The basis.
    pub fn basis(&self) -> &[Basis] {
        &self.basis
    }

    /// The drawn curve.
    pub fn drawn(&self) -> &Polyline {
        &self.drawn
    }

    /// The curve moved by coefficients `a` (one per basis function), or `None` when the move
    /// is not allowed: a point farther than `max_move` from where it was drawn, a kink (a
    /// turn more than [`MAX_EXTRA_TURN`] beyond the drawn curve's), a fold (a segment shorter
    /// than [`MIN_SEGMENT_RATIO`] of the drawn one), or a point the surface cannot take.
    /// All-zero coefficients give the drawn curve itself.
    pub fn apply(&self, a: &[f64], surface: &Surface, max_move: f64) -> Option<Polyline> {
        if a.iter().all(|&x| x == 0.0) {
            return Some(self.drawn.clone());
        }
        let m = self.samples.len();
        let closed = self.drawn.closed;
        let mut points = Vec::with_capacity(m);
        for i in 0..m {
            let o: f64 = self
                .basis
                .iter()
                .zip(a)
                .map(|(b, &x)| x * b.at(self.u[i]))
                .sum();
            let p = self.samples[i];
            let end = !closed && (i == 0 || i + 1 == m);
            let q = if end {
                let k = usize::from(i != 0);
                if !self.slides[k] {
                    p
                } else {
                    surface.closest_on_boundary(p + self.across[i] * o)?.0
                }
            } else {
                surface.closest(p + self.across[i] * o)?.point
            };
            if q.dist(p) > max_move {
                return None;
            }
            points.push(q);
        }
        let moved = Polyline {
            points,
            closed,
            origin: self.drawn.origin.clone(),
            label: self.drawn.label.clone(),
        };
        let count = if closed { m } else { m - 1 };
        for s in 0..count {
            let (a, b) = (moved.points[s], moved.points[(s + 1) % m]);
            if a.dist(b) < MIN_SEGMENT_RATIO * self.spacing {
                return None;
            }
        }
        let turns = turn_angles(&moved.points, closed);
        if turns
            .iter()
            .zip(&self.turns)
            .any(|(t, t0)| *t > t0 + MAX_EXTRA_TURN)
        {
            return None;
        }
        Some(moved)
    }
}

/// The largest distance from a point of `points` to the polyline `drawn`.
pub fn largest_distance(points: &[Vec3], drawn: &Polyline) -> f64 {
    let p = &drawn.points;
    let mut segments: Vec<(Vec3, Vec3)> = p.windows(2).map(|w| (w[0], w[1])).collect();
    if drawn.closed && p.len() > 2 {
        segments.push((p[p.len() - 1], p[0]));
    }
    if segments.is_empty() {
        return points
            .iter()
            .map(|q| p.first().map_or(0.0, |a| q.dist(*a)))
            .fold(0.0, f64::max);
    }
    points
        .iter()
        .map(|&q| {
            segments
                .iter()
                .map(|&(a, b)| crate::geom::point_segment_distance(q, a, b))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// `curve` resampled at equal arc length, about `spacing` apart (at least 8 segments); the
/// points lie on the polyline, the first and last (open) where its ends are.
fn resample(curve: &Polyline, spacing: f64) -> Vec<Vec3> {
    let mut pts = curve.points.clone();
    if curve.closed
        && let Some(&first) = pts.first()
    {
        pts.push(first);
    }
    let mut cumulative = vec![0.0];
    for w in pts.windows(2) {
        cumulative.push(cumulative.last().copied().unwrap_or(0.0) + w[0].dist(w[1]));
    }
    let total = cumulative.last().copied().unwrap_or(0.0);
    if pts.len() < 2 || total <= 0.0 {
        return curve.points.clone();
    }
    let segments = ((total / spacing).ceil() as usize).max(8);
    let count = if curve.closed { segments } else { segments + 1 };
    let mut out = Vec::with_capacity(count);
    let mut j = 0;
    for i in 0..count {
        let s = total * i as f64 / segments as f64;
        while j + 2 < cumulative.len() && cumulative[j + 1] < s {
            j += 1;
        }
        let len = cumulative[j + 1] - cumulative[j];
        let t = if len > 0.0 {
            ((s - cumulative[j]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(pts[j].lerp(pts[j + 1], t));
    }
    if !curve.closed
        && let (Some(last), Some(&end)) = (out.last_mut(), curve.points.last())
    {
        *last = end;
    }
    out
}

fn neighbour_indices(m: usize, i: usize, closed: bool) -> (usize, usize) {
    if closed {
        ((i + m - 1) % m, (i + 1) % m)
    } else {
        (i.saturating_sub(1), (i + 1).min(m - 1))
    }
}

fn neighbours(points: &[Vec3], i: usize, closed: bool) -> (Vec3, Vec3) {
    let (a, b) = neighbour_indices(points.len(), i, closed);
    (points[a], points[b])
}

/// The turning angle at every point (0 at an open curve's ends).
fn turn_angles(points: &[Vec3], closed: bool) -> Vec<f64> {
    let m = points.len();
    (0..m)
        .map(|i| {
            if !closed && (i == 0 || i + 1 == m) {
                return 0.0;
            }
            let (a, b) = neighbour_indices(m, i, closed);
            let e0 = (points[i] - points[a]).normalized();
            let e1 = (points[b] - points[i]).normalized();
            e0.dot(e1).clamp(-1.0, 1.0).acos()
        })
        .collect()
}

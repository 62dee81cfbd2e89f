//! Small fixed-size geometry: 3-vectors and axis-aligned boxes.
//!
//! Everything else in the crate builds on these few types; they are plain `Copy` values with the
//! arithmetic operators a reader expects, so the energy and construction code reads like the
//! formulas in `SPEC.md`.

use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, Neg, Sub, SubAssign};

/// A point or direction in 3D.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(from = "[f64; 3]", into = "[f64; 3]")]
pub struct Vec3 {
    /// x coordinate.
    pub x: f64,
    /// y coordinate.
    pub y: f64,
    /// z coordinate.
    pub z: f64,
}

impl From<[f64; 3]> for Vec3 {
    fn from(a: [f64; 3]) -> Self {
        Vec3::new(a[0], a[1], a[2])
    }
}

impl From<Vec3> for [f64; 3] {
    fn from(v: Vec3) -> Self {
        [v.x, v.y, v.z]
    }
}

impl Vec3 {
    /// The zero vector.
    pub const ZERO: Vec3 = Vec3 {
        x: 0.0,
        y: 0.0,
        z: 0.0,
    };

    /// Builds a vector from its coordinates.
    #[inline]
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Vec3 { x, y, z }
    }

    /// Dot product.
    #[inline]
    pub fn dot(self, o: Vec3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product.
    #[inline]
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// Squared Euclidean norm.
    #[inline]
    pub fn norm2(self) -> f64 {
        self.dot(self)
    }

    /// Euclidean norm.
    #[inline]
    pub fn norm(self) -> f64 {
        self.norm2().sqrt()
    }

    /// Distance to another point.
    #[inline]
    pub fn dist(self, o: Vec3) -> f64 {
        (self - o).norm()
    }

    /// Unit vector in the same direction (the zero vector stays zero).
    #[inline]
    pub fn normalized(self) -> Vec3 {
        let n = self.norm();
        if n > 0.0 { self / n } else { self }
    }

    /// Linear interpolation `self + t (o - self)`.
    #[inline]
    pub fn lerp(self, o: Vec3, t: f64) -> Vec3 {
        self + (o - self) * t
    }

    /// Component-wise minimum.
    #[inline]
    pub fn min(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x.min(o.x), self.y.min(o.y), self.z.min(o.z))
    }

    /// Component-wise maximum.
    #[inline]
    pub fn max(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x.max(o.x), self.y.max(o.y), self.z.max(o.z))
    }

    /// True when all three coordinates are finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }

    /// The coordinates as an array.
    #[inline]
    pub fn to_array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}

impl Index<usize> for Vec3 {
    type Output = f64;
    #[inline]
    fn index(&self, i: usize) -> &f64 {
        match i {
            0 => &self.x,
            1 => &self.y,
            2 => &self.z,
            _ => panic!("Vec3 index {i} out of range"),
        }
    }
}

impl IndexMut<usize> for Vec3 {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut f64 {
        match i {
            0 => &mut self.x,
            1 => &mut self.y,
            2 => &mut self.z,
            _ => panic!("Vec3 index {i} out of range"),
        }
    }
}

impl Add for Vec3 {
    type Output = Vec3;
    #[inline]
    fn add(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for Vec3 {
    type Output = Vec3;
    #[inline]
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl AddAssign for Vec3 {
    #[inline]
    fn add_assign(&mut self, o: Vec3) {
        *self = *self + o;
    }
}

impl SubAssign for Vec3 {
    #[inline]
    fn sub_assign(&mut self, o: Vec3) {
        *self = *self - o;
    }
}

impl Mul<f64> for Vec3 {
    type Output = Vec3;
    #[inline]
    fn mul(self, s: f64) -> Vec3 {
        Vec3::new(self.x * s, self.y * s, self.z * s)
    }
}

impl Mul<Vec3> for f64 {
    type Output = Vec3;
    #[inline]
    fn mul(self, v: Vec3) -> Vec3 {
        v * self
    }
}

impl Div<f64> for Vec3 {
    type Output = Vec3;
    #[inline]
    fn div(self, s: f64) -> Vec3 {
        Vec3::new(self.x / s, self.y / s, self.z / s)
    }
}

impl Neg for Vec3 {
    type Output = Vec3;
    #[inline]
    fn neg(self) -> Vec3 {
        Vec3::new(-self.x, -self.y, -self.z)
    }
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (absorbs nothing until a point is added).
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
        max: Vec3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY),
    };

    /// The smallest box holding all `points` (empty for no points).
    pub fn of_points<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> Aabb {
        let mut b = Aabb::EMPTY;
        for &p in points {
            b.add(p);
        }
        b
    }

    /// Grows the box to hold `p`.
    #[inline]
    pub fn add(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// True when nothing was added.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// Box diagonal (zero for an empty box).
    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// Largest side length.
    pub fn largest_extent(&self) -> f64 {
        let e = self.extent();
        e.x.max(e.y).max(e.z)
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cross_product_is_orthogonal_and_right_handed() {
        let x = Vec3::new(1.0, 0.0, 0.0);
        let y = Vec3::new(0.0, 1.0, 0.0);
        assert_eq!(x.cross(y), Vec3::new(0.0, 0.0, 1.0));
        let a = Vec3::new(0.3, -1.2, 2.5);
        let b = Vec3::new(-0.7, 0.4, 1.1);
        let c = a.cross(b);
        assert!(c.dot(a).abs() < 1e-12 && c.dot(b).abs() < 1e-12);
    }

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
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
        };
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
}

//! Second-order forward-mode derivatives: a value with its exact gradient and Hessian over
//! `N` variables, carried through `+ − × ÷ √ sin cos atan2`.
//!
//! Used for the pre-bent bending term ([`super::terms::bend_rest`]), the physical mode's clamp
//! and the material-frame bending and twist of a pre-bent rod (`rod::frame`), whose closed-form
//! Hessian (a minimal rotation composed with the curvature binormal) would be long and easy
//! to get wrong; the jet gives the same exact derivatives, and the term is finite-difference
//! checked like every other. A crate such as `num-dual` does the same but brings `nalgebra`
//! with it, for one 6-variable function; this file is the hundred lines it needs.
//!
//! Symmetry is exact: every Hessian update adds `a ⊗ b + b ⊗ a` or `s · g ⊗ g`, whose `(i, j)`
//! and `(j, i)` entries are the same sums.

use std::ops::{Add, Mul, Neg, Sub};

/// A value with its gradient and Hessian over `N` variables.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet<const N: usize> {
    /// Value.
    pub v: f64,
    /// Gradient.
    pub g: [f64; N],
    /// Hessian (symmetric).
    pub h: [[f64; N]; N],
}

impl<const N: usize> Jet<N> {
    /// A constant.
    #[inline]
    pub fn constant(v: f64) -> Self {
        Jet {
            v,
            g: [0.0; N],
            h: [[0.0; N]; N],
        }
    }

    /// Variable `i` at value `v`.
    #[inline]
    pub fn variable(v: f64, i: usize) -> Self {
        let mut j = Jet::constant(v);
        j.g[i] = 1.0;
        j
    }

    /// `f(self)` from `f`, `f'` and `f''` at `self.v` (the chain rule to second order).
    #[inline]
    fn chain(&self, f0: f64, f1: f64, f2: f64) -> Self {
        let mut out = Jet::constant(f0);
        for i in 0..N {
            out.g[i] = f1 * self.g[i];
            for j in 0..N {
                out.h[i][j] = f1 * self.h[i][j] + f2 * (self.g[i] * self.g[j]);
            }
        }
        out
    }

    /// `1 / self`.
    #[inline]
    pub fn recip(&self) -> Self {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }

    /// `√self`.
    #[inline]
    pub fn sqrt(&self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * s * s))
    }

    /// `(sin self, cos self)`.
    #[inline]
    pub fn sin_cos(&self) -> (Self, Self) {
        let (s, c) = self.v.sin_cos();
        (self.chain(s, c, -s), self.chain(c, -s, -c))
    }

    /// `atan2(self, x)`: the angle of the point `(x, self)`, in `(−π, π]`.
    #[inline]
    pub fn atan2(&self, x: &Self) -> Self {
        let y = self;
        let r2 = x.v * x.v + y.v * y.v;
        let (fy, fx) = (x.v / r2, -y.v / r2);
        let r4 = r2 * r2;
        let (fyy, fxx, fxy) = (
            -2.0 * x.v * y.v / r4,
            2.0 * x.v * y.v / r4,
            (y.v * y.v - x.v * x.v) / r4,
        );
        let mut out = Jet::constant(y.v.atan2(x.v));
        for i in 0..N {
            out.g[i] = fy * y.g[i] + fx * x.g[i];
            for j in 0..N {
                out.h[i][j] = fy * y.h[i][j]
                    + fx * x.h[i][j]
                    + fyy * (y.g[i] * y.g[j])
                    + fxx * (x.g[i] * x.g[j])
                    + fxy * (y.g[i] * x.g[j] + x.g[i] * y.g[j]);
            }
        }
        out
    }
}

impl<const N: usize> Add for Jet<N> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: Self) -> Self {
        self.v += o.v;
        for i in 0..N {
            self.g[i] += o.g[i];
            for j in 0..N {
                self.h[i][j] += o.h[i][j];
            }
        }
        self
    }
}

impl<const N: usize> Sub for Jet<N> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        self + (-o)
    }
}

impl<const N: usize> Neg for Jet<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self * -1.0
    }
}

impl<const N: usize> Mul<f64> for Jet<N> {
    type Output = Self;
    #[inline]
    fn mul(mut self, s: f64) -> Self {
        self.v *= s;
        for i in 0..N {
            self.g[i] *= s;
            for j in 0..N {
                self.h[i][j] *= s;
            }
        }
        self
    }
}

impl<const N: usize> Mul for Jet<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut out = Jet::constant(self.v * o.v);
        for i in 0..N {
            out.g[i] = self.v * o.g[i] + o.v * self.g[i];
            for j in 0..N {
                out.h[i][j] = self.v * o.h[i][j]
                    + o.v * self.h[i][j]
                    + (self.g[i] * o.g[j] + o.g[i] * self.g[j]);
            }
        }
        out
    }
}

/// A 3-vector of jets.
pub type JetVec<const N: usize> = [Jet<N>; 3];

/// `a · b`.
#[inline]
pub fn dot<const N: usize>(a: &JetVec<N>, b: &JetVec<N>) -> Jet<N> {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
#[inline]
pub fn cross<const N: usize>(a: &JetVec<N>, b: &JetVec<N>) -> JetVec<N> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `s a` for a jet `s`.
#[inline]
pub fn scale<const N: usize>(a: &JetVec<N>, s: Jet<N>) -> JetVec<N> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a + b`.
#[inline]
pub fn add<const N: usize>(a: &JetVec<N>, b: &JetVec<N>) -> JetVec<N> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
#[inline]
pub fn sub<const N: usize>(a: &JetVec<N>, b: &JetVec<N>) -> JetVec<N> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_of_a_rational_function() {
        // f(x, y) = √(x² + y) / (x y): check value, gradient and Hessian against the formulas.
        let (x0, y0) = (1.3, 0.7);
        let x = Jet::<2>::variable(x0, 0);
        let y = Jet::<2>::variable(y0, 1);
        let f = (x * x + y).sqrt() * (x * y).recip();
        let f_at = |x: f64, y: f64| (x * x + y).sqrt() / (x * y);
        assert!((f.v - f_at(x0, y0)).abs() < 1e-15);
        let h = 1e-4;
        for i in 0..2 {
            let d = |s: f64| {
                let (a, b) = if i == 0 { (x0 + s, y0) } else { (x0, y0 + s) };
                f_at(a, b)
            };
            let fd = (d(h) - d(-h)) / (2.0 * h);
            assert!((fd - f.g[i]).abs() < 1e-7, "g[{i}]: {} vs {fd}", f.g[i]);
        }
        let g_at = |x: f64, y: f64| {
            let xx = Jet::<2>::variable(x, 0);
            let yy = Jet::<2>::variable(y, 1);
            ((xx * xx + yy).sqrt() * (xx * yy).recip()).g
        };
        for j in 0..2 {
            let (xp, yp) = if j == 0 { (x0 + h, y0) } else { (x0, y0 + h) };
            let (xm, ym) = if j == 0 { (x0 - h, y0) } else { (x0, y0 - h) };
            let (gp, gm) = (g_at(xp, yp), g_at(xm, ym));
            for i in 0..2 {
                let fd = (gp[i] - gm[i]) / (2.0 * h);
                assert!((fd - f.h[i][j]).abs() < 1e-6, "h[{i}][{j}]");
            }
        }
        assert_eq!(f.h[0][1], f.h[1][0]);
    }

    #[test]
    fn derivatives_of_angles() {
        // f(x, y) = atan2(y sin x, x + cos y): against central differences.
        let f = |x: Jet<2>, y: Jet<2>| {
            let (sx, _) = x.sin_cos();
            let (_, cy) = y.sin_cos();
            (y * sx).atan2(&(x + cy))
        };
        let at = |a: f64, b: f64| f(Jet::variable(a, 0), Jet::variable(b, 1));
        let (x0, y0) = (0.7, -1.3);
        let j = at(x0, y0);
        let v = |a: f64, b: f64| at(a, b).v;
        let h = 1e-5;
        let shift = |k: usize, s: f64| if k == 0 { (x0 + s, y0) } else { (x0, y0 + s) };
        for k in 0..2 {
            let (p, m) = (shift(k, h), shift(k, -h));
            let fd = (v(p.0, p.1) - v(m.0, m.1)) / (2.0 * h);
            assert!((fd - j.g[k]).abs() < 1e-9, "g[{k}]");
            let (gp, gm) = (at(p.0, p.1).g, at(m.0, m.1).g);
            for i in 0..2 {
                let fd = (gp[i] - gm[i]) / (2.0 * h);
                assert!((fd - j.h[i][k]).abs() < 1e-8, "h[{i}][{k}]");
            }
        }
        assert_eq!(j.h[0][1], j.h[1][0]);
    }
}

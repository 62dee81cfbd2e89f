//! A follower pressure on curves: a load per length of curve normal to it, in the plane
//! perpendicular to an axis, that turns with the curve as it deflects.
//!
//! It is conservative through a potential: a uniform pressure `q` on a curve does the work
//! `q·ΔA`, `A` the signed area (about the unit axis `n`) of the polygon the curve closes
//! with the segments from its ends' rest positions `X_f`, `X_l` to the ends where they are:
//! `A = ½ [n·(X_f × x_f) + Σ_edges n·(x_a × x_b) + n·(x_l × X_l) + n·(X_l × X_f)]`. The
//! model's energy gains `−σ q ΔA` (σ = ±1 the side it pushes toward). Its gradient at an
//! interior vertex `i` is `½ σ q n × (x_{i+1} − x_{i−1})`, the pressure on the vertex's two
//! half edges turned with them; at an end it is the pressure on the end's half edge plus
//! that on the segment from the end's rest position to where it is (nothing when the end is
//! held in the plane, small while it moves little: a follower pressure on an end free to
//! move is not conservative, and this is its nearest conservative load). Its Hessian is
//! constant: the block `(a, b)` of an edge is `−½ σ q S`, `S` the skew matrix of
//! `x ↦ x × n`, and `(b, a)` its transpose. The area is measured in the plane perpendicular
//! to `n`: a curve that leaves the plane is loaded by the pressure on its projection.

use super::{EnergyModel, scatter_grad, vec3};
use crate::geom::Vec3;
use crate::rod::ActiveSet;

/// A pressure on the curves about one axis.
#[derive(Clone, Debug, PartialEq)]
pub struct PressurePart {
    /// The axis (unit): the pressure acts in the plane perpendicular to it.
    pub axis: Vec3,
    /// For each curve, its intensity times the side it pushes toward (force per length in
    /// the model's units): positive pushes to the right of the curve's direction seen from
    /// the axis's tip (`t × n`), negative to its left; zero leaves the curve unloaded.
    pub curves: Vec<f64>,
}

/// Follower pressures on the curves, with the rest positions they are measured from.
#[derive(Clone, Debug, PartialEq)]
pub struct Pressure {
    /// The pressures, summed.
    pub parts: Vec<PressurePart>,
    /// Every vertex's rest position (relative to any point: a point near the curves keeps
    /// the rounding small).
    pub rest: Vec<Vec3>,
}

impl Pressure {
    /// The same pressures times `factor`.
    pub fn scaled(&self, factor: f64) -> Pressure {
        Pressure {
            parts: (self.parts.iter())
                .map(|p| PressurePart {
                    axis: p.axis,
                    curves: p.curves.iter().map(|q| factor * q).collect(),
                })
                .collect(),
            rest: self.rest.clone(),
        }
    }
}

/// The skew matrix `S` with `a·S b = n·(a × b)`.
fn skew(n: Vec3) -> [[f64; 3]; 3] {
    [[0.0, n.z, -n.y], [-n.z, 0.0, n.x], [n.y, -n.x, 0.0]]
}

impl EnergyModel {
    /// Puts follower pressures on the curves (none: removes them). Their potential joins
    /// the energy, its gradient and its (constant) Hessian in [`Self::energy`] and
    /// [`Self::assemble`] (not in the Hessians summed from local Hessians, which are the
    /// rods' alone).
    ///
    /// # Panics
    ///
    /// When a part does not give every curve a value or the rest positions are not every
    /// vertex's.
    pub fn set_pressure(&mut self, pressure: Option<Pressure>) {
        if let Some(p) = &pressure {
            assert_eq!(p.rest.len(), self.n_vertices, "a rest position per vertex");
            for part in &p.parts {
                assert_eq!(part.curves.len(), self.rods.len(), "a pressure per curve");
            }
        }
        self.pressure =
            pressure.filter(|p| p.parts.iter().any(|x| x.curves.iter().any(|&q| q != 0.0)));
    }

    /// The follower pressures on the curves ([`Self::set_pressure`]).
    pub fn pressure(&self) -> Option<&Pressure> {
        self.pressure.as_ref()
    }

    /// The forces `pressure` (set or not) exerts at displacements `u` on the coordinates of
    /// `active`'s curves (minus its potential's gradient).
    pub fn pressure_forces(&self, pressure: &Pressure, u: &[f64], active: &ActiveSet) -> Vec<f64> {
        let mut g = vec![0.0; self.dofs()];
        let mut e = 0.0;
        self.add_pressure(pressure, u, active, &mut e, &mut g, None);
        g.iter().map(|x| -x).collect()
    }

    /// Adds the set pressures' potential at displacements `u` to `energy`, its gradient to
    /// `grad` and, given, its Hessian to `hess`.
    pub(super) fn assemble_pressure(
        &self,
        u: &[f64],
        active: &ActiveSet,
        energy: &mut f64,
        grad: &mut [f64],
        hess: Option<&mut [f64]>,
    ) {
        if let Some(p) = &self.pressure {
            self.add_pressure(p, u, active, energy, grad, hess);
        }
    }

    /// Adds `p`'s potential at displacements `u` to `energy`, its gradient to `grad` and,
    /// given, its Hessian to `hess`.
    fn add_pressure(
        &self,
        p: &Pressure,
        u: &[f64],
        active: &ActiveSet,
        energy: &mut f64,
        grad: &mut [f64],
        mut hess: Option<&mut [f64]>,
    ) {
        for part in &p.parts {
            let n = part.axis;
            let s = skew(n);
            for (c, r) in self.active_terms(active) {
                let q = part.curves[c];
                if q == 0.0 || r.stretch.is_empty() {
                    continue;
                }
                // The segments from the ends' rest positions (none on a closed curve).
                let (first, last) = (
                    self.stretch[r.stretch.start].v[0],
                    self.stretch[r.stretch.end - 1].v[1],
                );
                if first != last {
                    let (yf, yl) = (p.rest[first as usize], p.rest[last as usize]);
                    let (uf, ul) = (vec3(u, first), vec3(u, last));
                    *energy -= q * 0.5 * n.dot(yf.cross(uf) + ul.cross(yl));
                    let gf = n.cross(yf) * (-0.5 * q);
                    let gl = yl.cross(n) * (-0.5 * q);
                    scatter_grad(grad, &[first], &[gf.x, gf.y, gf.z]);
                    scatter_grad(grad, &[last], &[gl.x, gl.y, gl.z]);
                }
                for k in r.stretch.clone() {
                    let t = &self.stretch[k];
                    let (ua, ub) = (vec3(u, t.v[0]), vec3(u, t.v[1]));
                    let (ya, yb) = (p.rest[t.v[0] as usize], p.rest[t.v[1] as usize]);
                    // The change of the edge's swept area from the rest state.
                    let da = 0.5 * n.dot(ya.cross(ub) + ua.cross(yb) + ua.cross(ub));
                    *energy -= q * da;
                    let (xa, xb) = (ya + ua, yb + ub);
                    let ga = xb.cross(n) * (-0.5 * q);
                    let gb = n.cross(xa) * (-0.5 * q);
                    let local = [ga.x, ga.y, ga.z, gb.x, gb.y, gb.z];
                    scatter_grad(grad, &t.v, &local);
                    if let Some(h) = hess.as_deref_mut() {
                        let mut l = [[0.0; 6]; 6];
                        for i in 0..3 {
                            for j in 0..3 {
                                l[i][3 + j] = -0.5 * q * s[i][j];
                                l[3 + j][i] = -0.5 * q * s[i][j];
                            }
                        }
                        self.scatter_hess(h, &t.v, &self.stretch_pos[k], &l);
                    }
                }
            }
        }
    }
}

//! Singular faces of a computed field: degenerate, unreached, vanishing or non-finite faces,
//! faces around non-manifold vertices, and the fans of interior vertices of non-zero index.

use super::{FieldOptions, angle_in, wrap};
use crate::geom::Vec3;
use crate::trace::topology::MeshTopology;
use crate::trace::walk::vertex_fan;
use std::f64::consts::PI;

/// The per-face data of a solved field.
pub(super) struct Faces<'a> {
    /// Tangent frames.
    pub frames: &'a [(Vec3, Vec3)],
    /// Values `z_f`.
    pub values: &'a [(f64, f64)],
    /// Faces constrained by the boundary.
    pub constrained: &'a [bool],
    /// Faces connected to a constraint.
    pub reached: &'a [bool],
}

/// What the fan of an interior vertex says.
enum Fan {
    /// Index zero, or no fan to measure (a boundary or isolated vertex).
    Regular,
    /// The fan cannot be walked, or the field vanishes on one of its faces.
    Undefined(Vec<usize>),
    /// A non-zero index numerator `k` over the fan's faces.
    Index(i64, Vec<usize>),
}

impl Faces<'_> {
    /// Singular faces and the interior vertices of non-zero index numerator `k`.
    pub(super) fn singular(
        &self,
        topo: &MeshTopology,
        options: &FieldOptions,
    ) -> (Vec<bool>, Vec<(usize, i64)>) {
        let nf = topo.face_count();
        let mut singular = vec![false; nf];
        for (f, s) in singular.iter_mut().enumerate() {
            let m = f64::hypot(self.values[f].0, self.values[f].1);
            *s = topo.is_degenerate(f)
                || !self.reached[f]
                || !m.is_finite()
                || (!self.constrained[f] && m < options.magnitude_threshold);
        }
        let mut singular_vertices = Vec::new();
        for v in 0..topo.vertex_count() {
            match self.fan(topo, v, f64::from(options.degree)) {
                Fan::Regular => {}
                Fan::Undefined(faces) => faces.into_iter().for_each(|f| singular[f] = true),
                Fan::Index(k, faces) => {
                    singular_vertices.push((v, k));
                    faces.into_iter().for_each(|f| singular[f] = true);
                }
            }
        }
        (singular, singular_vertices)
    }

    /// The index of interior vertex `v`: the field's turning around its fan measured against
    /// parallel transport, `k = (Σ δ_t + N (2π − Θ)) / 2π`.
    fn fan(&self, topo: &MeshTopology, v: usize, n: f64) -> Fan {
        let vf = topo.vertex_faces(v);
        let Some(&start) = vf.first() else {
            return Fan::Regular;
        };
        if topo.is_boundary_vertex(v) {
            return Fan::Regular;
        }
        let fan = match vertex_fan(topo, v, start) {
            Ok(Some(fan)) => fan,
            Ok(None) => return Fan::Regular,
            Err(_) => return Fan::Undefined(vf.to_vec()),
        };
        let m = fan.faces.len();
        let pv = topo.position(v);
        let mut psi_local = Vec::with_capacity(m);
        for t in 0..m {
            let f = fan.faces[t];
            let (re, im) = self.values[f];
            if !(f64::hypot(re, im) > 0.0) {
                return Fan::Undefined(fan.faces);
            }
            let spoke = topo.position(fan.spokes[t]) - pv;
            let next = topo.position(fan.spokes[t + 1]) - pv;
            let frame = self.frames[f];
            let sigma = if spoke.cross(next).dot(frame.0.cross(frame.1)) >= 0.0 {
                1.0
            } else {
                -1.0
            };
            let beta = angle_in(frame, spoke);
            psi_local.push(sigma * (im.atan2(re) - n * beta));
        }
        let mut turning = 0.0;
        for t in 0..m {
            let next = psi_local[(t + 1) % m];
            turning += wrap(next - (psi_local[t] - n * fan.angles[t]));
        }
        let k = ((turning + n * (2.0 * PI - fan.total())) / (2.0 * PI)).round();
        if k != 0.0 && k.is_finite() {
            Fan::Index(k as i64, fan.faces)
        } else {
            Fan::Regular
        }
    }
}

//! Smooth N-direction fields aligned with the boundary (N-RoSy; paper §5 uses PolyVector
//! fields of degree 4 and 6, i.e. 2 or 3 line directions).
//!
//! # Representation
//!
//! Each face `f` has a tangent frame `(x_f, y_f)`: `x_f` along its first edge, `y_f = n_f × x_f`
//! with `n_f` the face normal after the mesh has been oriented consistently. A set of `N`
//! directions at angles `φ + 2πj/N` is stored as the complex number `z_f = e^{iNφ}`, which does
//! not depend on which of the `N` directions is called first.
//!
//! Across an interior edge `E` shared by faces `f` and `g`, parallel transport (the Levi-Civita
//! connection of the flattened hinge) keeps a direction's angle with `E`; in the frames this is
//! a rotation by `ang_f(E) − ang_g(E)`, and `z_g` is seen in `f` as `r_fg z_g` with
//! `r_fg = e^{iN(ang_f(E) − ang_g(E))}`.
//!
//! # The smoothest field
//!
//! The field minimises `Σ_E w_E |z_f − r_fg z_g|²` over interior manifold edges, with weights
//! `w_E = |E|² / (A_f + A_g)` (edge length over the distance between the faces' centres, up to
//! a constant). Faces with a boundary edge are constrained to align with it:
//! `z_f = e^{iN ang_f(E_b)}` (the sum over its boundary edges, normalised; a corner whose edges
//! disagree for this `N` is left free). The free values solve the sparse symmetric positive
//! definite system `K_FF z_F = −K_FC z_C`, written over the reals (two unknowns per face) and
//! factored with faer's sparse Cholesky (AMD ordering, sequential, so results are
//! bit-identical from run to run).
//!
//! # Singularities
//!
//! The index of an interior vertex is the field's turning around its fan of faces, measured
//! against parallel transport: `k = (Σ δ_t + N (2π − Θ)) / 2π` with `δ_t` the jump of `N·angle`
//! between consecutive faces (in `(−π, π]`) and `Θ` the total angle; the index is `k / N`.
//! Faces around a vertex with `k ≠ 0`, faces whose field magnitude `|z_f|` is below
//! [`FieldOptions::magnitude_threshold`], faces around non-manifold vertices, degenerate
//! faces and faces in components of the mesh without boundary constraint are *singular*:
//! streamlines that reach them are dropped.
//!
//! # Files
//!
//! - `frames`: consistent orientation, the faces' tangent frames and the boundary constraints;
//! - `system`: the smoothness links, the faces that get unknowns and the sparse solve (with the
//!   normalisation steps);
//! - `singular`: singular faces and the indices of interior vertices;
//! - `spd`: the sequential sparse Cholesky factor the solve uses.

mod frames;
mod singular;
mod spd;
mod system;

use super::TraceError;
use super::topology::MeshTopology;
use crate::geom::Vec3;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Parameters of [`smooth_field`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FieldOptions {
    /// Symmetry order `N`: 4 for two line directions (a cross field), 6 for three. Any value
    /// in `1..=12` is accepted (2 is a line field, 1 a vector field).
    pub degree: u32,
    /// Faces whose field magnitude `|z_f|` (boundary faces have 1) is below this value count
    /// as vanishing, hence singular. Default 1e-12: the magnitude of the smoothest field decays
    /// like `r^N` towards a singularity of index 1 (a disk's centre), so a larger threshold
    /// would flag wide regions where the directions are still well defined; singular points
    /// are found by their index instead.
    pub magnitude_threshold: f64,
    /// Normalisation steps after the linear solve (0: the plain smoothest field). Each step
    /// solves `(K + λM) z = b + λ M z/|z|`, pulling the field towards unit length away from
    /// singularities, which splits a high-index singularity into elementary ones (index
    /// ±1/N) as in Ginzburg–Landau relaxation. Default 100.
    pub iterations: usize,
    /// The penalty `λ` of the normalisation steps, relative to the smoothness weights (a
    /// larger value gives smaller singular cores but slower relaxation). Default 0.1.
    pub penalty: f64,
}

impl Default for FieldOptions {
    fn default() -> Self {
        FieldOptions {
            degree: 4,
            magnitude_threshold: 1e-12,
            iterations: 100,
            penalty: 0.1,
        }
    }
}

/// A direction field on a mesh: per face, `N` unit directions.
///
/// Accessors taking a face index panic when it is out of range (like slice indexing); the
/// field has one entry per face of the mesh it was computed on.
#[derive(Clone, Debug)]
pub struct DirectionField {
    degree: u32,
    /// Per-face frame `(x_f, y_f)`.
    frames: Vec<(Vec3, Vec3)>,
    /// Per-face value `z_f = (re, im)`, not normalised.
    values: Vec<(f64, f64)>,
    singular: Vec<bool>,
    /// Interior vertices with a non-zero index numerator `k` (index `k / N`).
    singular_vertices: Vec<(usize, i64)>,
}

impl DirectionField {
    /// Number of faces the field is defined on.
    pub fn face_count(&self) -> usize {
        self.values.len()
    }

    /// True when face `f` is singular (see the module documentation).
    pub fn is_singular(&self, f: usize) -> bool {
        self.singular[f]
    }

    /// Interior vertices of non-zero index, with the index numerator `k` (index = `k / N`).
    pub fn singular_vertices(&self) -> &[(usize, i64)] {
        &self.singular_vertices
    }

    /// The `N` unit directions of face `f` (empty where the field vanishes).
    pub fn directions(&self, f: usize) -> Vec<Vec3> {
        let (a, b) = self.values[f];
        if !(a.hypot(b) > 0.0) {
            return Vec::new();
        }
        let n = self.degree as f64;
        let phi = b.atan2(a) / n;
        let (x, y) = self.frames[f];
        (0..self.degree)
            .map(|j| {
                let ang = phi + 2.0 * PI * j as f64 / n;
                (x * ang.cos() + y * ang.sin()).normalized()
            })
            .collect()
    }

    /// The direction of face `f` closest to `d` (largest dot product), if the field is
    /// defined there.
    pub fn best_direction(&self, f: usize, d: Vec3) -> Option<Vec3> {
        let mut best: Option<(f64, Vec3)> = None;
        for v in self.directions(f) {
            let s = v.dot(d);
            if best.is_none_or(|(b, _)| s > b) {
                best = Some((s, v));
            }
        }
        best.map(|(_, v)| v)
    }
}

/// Angle of tangent vector `v` in frame `(x, y)`.
fn angle_in(frame: (Vec3, Vec3), v: Vec3) -> f64 {
    v.dot(frame.1).atan2(v.dot(frame.0))
}

/// Wraps an angle into `(−π, π]`.
fn wrap(a: f64) -> f64 {
    let mut r = a.rem_euclid(2.0 * PI);
    if r > PI {
        r -= 2.0 * PI;
    }
    r
}

/// Computes the smoothest `N`-direction field aligned with the boundary (see the module
/// documentation).
///
/// # Errors
///
/// [`TraceError::InvalidParameter`] for a degree outside `1..=12` or a negative or NaN
/// threshold, [`TraceError::NoBoundary`] when no face touches the boundary,
/// [`TraceError::NonOrientable`], and [`TraceError::Solver`] if the factorization fails.
pub fn smooth_field(
    topo: &MeshTopology,
    options: &FieldOptions,
) -> Result<DirectionField, TraceError> {
    validate(options)?;
    let n = options.degree as f64;
    let sign = frames::orient(topo)?;
    let frames = frames::face_frames(topo, &sign);
    let (mut values, constrained) = frames::boundary_values(topo, &frames, n);
    if !constrained.iter().any(|&c| c) {
        return Err(TraceError::NoBoundary);
    }
    let links = system::links(topo, &frames, n);
    let reached = system::reached(topo.face_count(), &links, &constrained);
    system::solve_free(topo, options, &links, &constrained, &reached, &mut values)?;
    let faces = singular::Faces {
        frames: &frames,
        values: &values,
        constrained: &constrained,
        reached: &reached,
    };
    let (singular, singular_vertices) = faces.singular(topo, options);
    Ok(DirectionField {
        degree: options.degree,
        frames,
        values,
        singular,
        singular_vertices,
    })
}

/// Checks the options' ranges.
fn validate(options: &FieldOptions) -> Result<(), TraceError> {
    if !(1..=12).contains(&options.degree) {
        return Err(TraceError::InvalidParameter {
            name: "degree",
            value: options.degree as f64,
            expected: "a symmetry order in 1..=12 (4: two directions, 6: three)",
        });
    }
    for (name, value) in [
        ("magnitude_threshold", options.magnitude_threshold),
        ("penalty", options.penalty),
    ] {
        if !(value >= 0.0) || !value.is_finite() {
            return Err(TraceError::InvalidParameter {
                name,
                value,
                expected: "a finite non-negative number",
            });
        }
    }
    Ok(())
}

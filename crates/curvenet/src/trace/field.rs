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

use super::TraceError;
use super::topology::MeshTopology;
use super::walk::vertex_fan;
use crate::geom::Vec3;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Par, Side};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
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
    constrained: Vec<bool>,
    singular: Vec<bool>,
    /// Interior vertices with a non-zero index numerator `k` (index `k / N`).
    singular_vertices: Vec<(usize, i64)>,
}

impl DirectionField {
    /// Number of faces the field is defined on.
    pub fn face_count(&self) -> usize {
        self.values.len()
    }

    /// The symmetry order `N`.
    pub fn degree(&self) -> u32 {
        self.degree
    }

    /// The face value `z_f` as `(re, im)` in the face's frame (magnitude 1 on constrained
    /// faces, at most about 1 elsewhere).
    pub fn value(&self, f: usize) -> (f64, f64) {
        self.values[f]
    }

    /// Magnitude `|z_f|`.
    pub fn magnitude(&self, f: usize) -> f64 {
        let (a, b) = self.values[f];
        a.hypot(b)
    }

    /// True when face `f` was constrained to follow the boundary.
    pub fn is_constrained(&self, f: usize) -> bool {
        self.constrained[f]
    }

    /// True when face `f` is singular (see the module documentation).
    pub fn is_singular(&self, f: usize) -> bool {
        self.singular[f]
    }

    /// Interior vertices of non-zero index, with the index numerator `k` (index = `k / N`).
    pub fn singular_vertices(&self) -> &[(usize, i64)] {
        &self.singular_vertices
    }

    /// The face's tangent frame `(x_f, y_f)`.
    pub fn frame(&self, f: usize) -> (Vec3, Vec3) {
        self.frames[f]
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

/// Orientation signs (+1 / −1) making adjacent faces agree, by breadth-first search.
fn orient(topo: &MeshTopology) -> Result<Vec<i8>, TraceError> {
    let nf = topo.face_count();
    let mut sign = vec![0i8; nf];
    let faces = topo.faces();
    // +1 when edge e runs a → b (sorted order) in face f.
    let runs_forward = |f: usize, e: usize| -> bool {
        let [a, b] = topo.edge(e);
        let t = faces[f];
        (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b)
    };
    let mut queue = VecDeque::new();
    for seed in 0..nf {
        if sign[seed] != 0 {
            continue;
        }
        sign[seed] = 1;
        queue.push_back(seed);
        while let Some(f) = queue.pop_front() {
            for e in topo.face_edges(f) {
                let fs = topo.edge_faces(e);
                if fs.len() != 2 {
                    continue;
                }
                let g = if fs[0] == f { fs[1] } else { fs[0] };
                let same = runs_forward(f, e) != runs_forward(g, e);
                let want = if same { sign[f] } else { -sign[f] };
                if sign[g] == 0 {
                    sign[g] = want;
                    queue.push_back(g);
                } else if sign[g] != want {
                    return Err(TraceError::NonOrientable);
                }
            }
        }
    }
    Ok(sign)
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
    if !(1..=12).contains(&options.degree) {
        return Err(TraceError::InvalidParameter {
            name: "degree",
            value: options.degree as f64,
            expected: "a symmetry order in 1..=12 (4: two directions, 6: three)",
        });
    }
    if !(options.magnitude_threshold >= 0.0) || !options.magnitude_threshold.is_finite() {
        return Err(TraceError::InvalidParameter {
            name: "magnitude_threshold",
            value: options.magnitude_threshold,
            expected: "a finite non-negative number",
        });
    }
    if !(options.penalty >= 0.0) || !options.penalty.is_finite() {
        return Err(TraceError::InvalidParameter {
            name: "penalty",
            value: options.penalty,
            expected: "a finite non-negative number",
        });
    }
    let n = options.degree as f64;
    let nf = topo.face_count();
    let sign = orient(topo)?;
    let mut frames = Vec::with_capacity(nf);
    for f in 0..nf {
        let [a, b, _] = topo.face_points(f);
        let x = (b - a).normalized();
        let nrm = topo.face_normal(f) * f64::from(sign[f]);
        frames.push((x, nrm.cross(x)));
    }

    // Boundary constraints.
    let mut values = vec![(0.0f64, 0.0f64); nf];
    let mut constrained = vec![false; nf];
    for f in 0..nf {
        if topo.is_degenerate(f) {
            continue;
        }
        let (mut re, mut im, mut count) = (0.0, 0.0, 0usize);
        for e in topo.face_edges(f) {
            if topo.is_boundary_edge(e) {
                let [a, b] = topo.edge(e);
                let ang = n * angle_in(frames[f], topo.position(b) - topo.position(a));
                re += ang.cos();
                im += ang.sin();
                count += 1;
            }
        }
        let m = f64::hypot(re, im);
        if count > 0 && m > 1e-6 * count as f64 {
            values[f] = (re / m, im / m);
            constrained[f] = true;
        }
    }
    if !constrained.iter().any(|&c| c) {
        return Err(TraceError::NoBoundary);
    }

    // Interior manifold edges between usable faces, with weights and transports.
    struct Link {
        f: usize,
        g: usize,
        w: f64,
        c: f64,
        s: f64,
    }
    let mut links = Vec::new();
    for e in 0..topo.edge_count() {
        let fs = topo.edge_faces(e);
        if fs.len() != 2 || topo.is_degenerate(fs[0]) || topo.is_degenerate(fs[1]) {
            continue;
        }
        let (f, g) = (fs[0], fs[1]);
        let [a, b] = topo.edge(e);
        let ev = topo.position(b) - topo.position(a);
        let rot = n * (angle_in(frames[f], ev) - angle_in(frames[g], ev));
        let w = ev.norm2() / (topo.face_area(f) + topo.face_area(g));
        links.push(Link {
            f,
            g,
            w,
            c: rot.cos(),
            s: rot.sin(),
        });
    }

    // Faces connected to a constraint get unknowns; the rest stay zero (singular).
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); nf];
    for l in &links {
        adj[l.f].push(l.g);
        adj[l.g].push(l.f);
    }
    let mut reached = constrained.clone();
    let mut queue: VecDeque<usize> = (0..nf).filter(|&f| constrained[f]).collect();
    while let Some(f) = queue.pop_front() {
        for &g in &adj[f] {
            if !reached[g] {
                reached[g] = true;
                queue.push_back(g);
            }
        }
    }
    let mut index = vec![usize::MAX; nf];
    let mut free = 0usize;
    for f in 0..nf {
        if reached[f] && !constrained[f] {
            index[f] = free;
            free += 1;
        }
    }

    if free > 0 {
        let dim = 2 * free;
        let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(6 * links.len());
        let mut rhs = vec![0.0f64; dim];
        // Block of −w r (rows f, columns g): [[−wc, ws], [−ws, −wc]].
        for l in &links {
            let blk = [[-l.w * l.c, l.w * l.s], [-l.w * l.s, -l.w * l.c]];
            let (fi, gi) = (index[l.f], index[l.g]);
            if fi != usize::MAX {
                triplets.push(Triplet::new(2 * fi, 2 * fi, l.w));
                triplets.push(Triplet::new(2 * fi + 1, 2 * fi + 1, l.w));
            }
            if gi != usize::MAX {
                triplets.push(Triplet::new(2 * gi, 2 * gi, l.w));
                triplets.push(Triplet::new(2 * gi + 1, 2 * gi + 1, l.w));
            }
            match (fi != usize::MAX, gi != usize::MAX) {
                (true, true) => {
                    for r in 0..2 {
                        for c in 0..2 {
                            // Upper triangle: row index below column index.
                            if fi < gi {
                                triplets.push(Triplet::new(2 * fi + r, 2 * gi + c, blk[r][c]));
                            } else {
                                triplets.push(Triplet::new(2 * gi + c, 2 * fi + r, blk[r][c]));
                            }
                        }
                    }
                }
                (true, false) if constrained[l.g] => {
                    let (x, y) = values[l.g];
                    rhs[2 * fi] -= blk[0][0] * x + blk[0][1] * y;
                    rhs[2 * fi + 1] -= blk[1][0] * x + blk[1][1] * y;
                }
                (false, true) if constrained[l.f] => {
                    // Block of −w r̄ (rows g, columns f) is the transpose.
                    let (x, y) = values[l.f];
                    rhs[2 * gi] -= blk[0][0] * x + blk[1][0] * y;
                    rhs[2 * gi + 1] -= blk[0][1] * x + blk[1][1] * y;
                }
                _ => {}
            }
        }
        let mut solution = SpdSolver::new(dim, &triplets)?.solve(rhs.clone())?;
        if options.iterations > 0 && options.penalty > 0.0 {
            // Ginzburg–Landau-like normalisation: repeatedly pull the field towards unit
            // length, `(K + λM) z = b + λ M z/|z|`, with M the face areas over their mean.
            let mean_area = (0..nf)
                .filter(|&f| index[f] != usize::MAX)
                .map(|f| topo.face_area(f))
                .sum::<f64>()
                / free as f64;
            let mass: Vec<f64> = (0..nf)
                .filter(|&f| index[f] != usize::MAX)
                .map(|f| options.penalty * topo.face_area(f) / mean_area)
                .collect();
            let mut shifted = triplets.clone();
            for (i, &m) in mass.iter().enumerate() {
                shifted.push(Triplet::new(2 * i, 2 * i, m));
                shifted.push(Triplet::new(2 * i + 1, 2 * i + 1, m));
            }
            let flow = SpdSolver::new(dim, &shifted)?;
            for _ in 0..options.iterations {
                let mut b = rhs.clone();
                for (i, &m) in mass.iter().enumerate() {
                    let (x, y) = (solution[2 * i], solution[2 * i + 1]);
                    let r = x.hypot(y);
                    if r > 0.0 {
                        b[2 * i] += m * x / r;
                        b[2 * i + 1] += m * y / r;
                    }
                }
                solution = flow.solve(b)?;
            }
        }
        for f in 0..nf {
            if index[f] != usize::MAX {
                values[f] = (solution[2 * index[f]], solution[2 * index[f] + 1]);
            }
        }
    }

    // Singular faces.
    let mut singular = vec![false; nf];
    for f in 0..nf {
        let m = f64::hypot(values[f].0, values[f].1);
        singular[f] = topo.is_degenerate(f)
            || !reached[f]
            || !m.is_finite()
            || (!constrained[f] && m < options.magnitude_threshold);
    }
    let mut singular_vertices = Vec::new();
    for v in 0..topo.vertex_count() {
        let vf = topo.vertex_faces(v);
        let Some(&start) = vf.first() else { continue };
        if topo.is_boundary_vertex(v) {
            continue;
        }
        let fan = match vertex_fan(topo, v, start) {
            Ok(Some(fan)) => fan,
            Ok(None) => continue,
            Err(_) => {
                for &f in vf {
                    singular[f] = true;
                }
                continue;
            }
        };
        let m = fan.faces.len();
        let pv = topo.position(v);
        let mut psi_local = Vec::with_capacity(m);
        let mut defined = true;
        for t in 0..m {
            let f = fan.faces[t];
            let (re, im) = values[f];
            if !(f64::hypot(re, im) > 0.0) {
                defined = false;
                break;
            }
            let spoke = topo.position(fan.spokes[t]) - pv;
            let next = topo.position(fan.spokes[t + 1]) - pv;
            let frame = frames[f];
            let sigma = if spoke.cross(next).dot(frame.0.cross(frame.1)) >= 0.0 {
                1.0
            } else {
                -1.0
            };
            let beta = angle_in(frame, spoke);
            psi_local.push(sigma * (im.atan2(re) - n * beta));
        }
        if !defined {
            for &f in &fan.faces {
                singular[f] = true;
            }
            continue;
        }
        let mut turning = 0.0;
        for t in 0..m {
            let next = psi_local[(t + 1) % m];
            turning += wrap(next - (psi_local[t] - n * fan.angles[t]));
        }
        let k = ((turning + n * (2.0 * PI - fan.total())) / (2.0 * PI)).round();
        if k != 0.0 && k.is_finite() {
            singular_vertices.push((v, k as i64));
            for &f in &fan.faces {
                singular[f] = true;
            }
        }
    }

    Ok(DirectionField {
        degree: options.degree,
        frames,
        values,
        constrained,
        singular,
        singular_vertices,
    })
}

/// A sparse Cholesky factor of a symmetric positive definite matrix, computed sequentially.
struct SpdSolver {
    sym: faer::sparse::linalg::cholesky::SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    dim: usize,
}

impl SpdSolver {
    /// Factors the matrix given by its upper-triangle `triplets` (duplicates summed).
    fn new(dim: usize, triplets: &[Triplet<usize, usize, f64>]) -> Result<Self, TraceError> {
        let solver = |e: &dyn std::fmt::Debug| TraceError::Solver(format!("{e:?}"));
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(dim, dim, triplets)
            .map_err(|e| solver(&e))?;
        let sym = factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| solver(&e))?;
        let par = Par::Seq;
        let mut l_values = vec![0.0f64; sym.len_val()];
        let mut mem =
            MemBuffer::new(sym.factorize_numeric_llt_scratch::<f64>(par, Default::default()));
        sym.factorize_numeric_llt::<f64>(
            &mut l_values,
            a.as_ref(),
            Side::Upper,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|e| solver(&e))?;
        Ok(SpdSolver { sym, l_values, dim })
    }

    /// Solves `A x = rhs`.
    fn solve(&self, mut rhs: Vec<f64>) -> Result<Vec<f64>, TraceError> {
        let par = Par::Seq;
        let mut mem = MemBuffer::new(self.sym.solve_in_place_scratch::<f64>(1, par));
        let x = faer::MatMut::from_column_major_slice_mut(&mut rhs, self.dim, 1);
        LltRef::new(&self.sym, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            x,
            par,
            MemStack::new(&mut mem),
        );
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(TraceError::Solver("non-finite solution".into()));
        }
        Ok(rhs)
    }
}

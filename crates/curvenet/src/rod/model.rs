//! The energy of a whole network as a flat list of terms, and its sparse assembly.
//!
//! [`EnergyModel`] holds every stretching, bending and anchor term of every rod, grouped by
//! rod, together with one fixed sparsity pattern for the Hessian (the upper triangle over all
//! `3·V` coordinates, in compressed columns). Any set of curves can be left out with an
//! [`ActiveSet`]: their terms are skipped and the vertices that belong to no remaining curve
//! ("loose" vertices) get a large diagonal entry instead, so the pattern, and hence one
//! symbolic factorization, serves every structure (SPEC §5). That device is equivalent to
//! deleting those rows and columns: the loose vertices then form a decoupled block whose
//! eigenvalues sit far above the structure's low spectrum; [`EnergyModel::explicit_deletion`]
//! builds the deleted version for tests.
//!
//! **Coordinates are displacements** `u` from the locked rest state, not positions: every term
//! is evaluated from its rest edge vectors plus differences of displacements. Positions of a
//! few thousand units carry an absolute rounding of ~1e-13 that, times the stiffness of the
//! shortest edges, floors the gradient near 1e-7 (SPEC §11); displacements are small, so the
//! gradient can be driven orders of magnitude lower and λ is measured at a truer equilibrium.

use super::terms::RestBend;
use super::{Material, RodStiffness, terms};
use crate::geom::Vec3;
use crate::material::RestShape;
use crate::network::Network;
use crate::profile::{Phase, Timer};
use std::ops::Range;

/// A stretching term (one edge) with its rod's stiffness `ks`. `e` is the rest edge vector
/// `X1 − X0`.
#[derive(Clone, Copy, Debug)]
struct StretchTerm {
    v: [u32; 2],
    rest: f64,
    ks: f64,
    e: Vec3,
}

/// A bending term (one interior vertex and its two edges) with its rod's stiffness `kb`.
/// `a = X0 − X1`, `b = X2 − X1` are the rest offsets of the outer vertices from the centre.
/// `rest` indexes the drawn shape of a pre-bent rod's term in `EnergyModel::bend_rest`
/// (`STRAIGHT` for a rod straight at rest).
#[derive(Clone, Copy, Debug)]
struct BendTerm {
    v: [u32; 3],
    rest: u32,
    r0: f64,
    r1: f64,
    kb: f64,
    a: Vec3,
    b: Vec3,
}

/// [`BendTerm::rest`] of a term of a rod straight at rest.
const STRAIGHT: u32 = u32::MAX;

/// An anchor spring on a supported vertex; `offset` is its target minus its rest position
/// (zero when the anchor holds the vertex where it was drawn).
#[derive(Clone, Copy, Debug)]
struct AnchorTerm {
    v: u32,
    offset: Vec3,
}

impl StretchTerm {
    /// End points relative to `x0`, from displacements `u`.
    #[inline]
    fn local(&self, u: &[f64]) -> (Vec3, Vec3) {
        (
            Vec3::ZERO,
            self.e + (vec3(u, self.v[1]) - vec3(u, self.v[0])),
        )
    }
}

impl BendTerm {
    /// The three vertices relative to the centre, from displacements `u`.
    #[inline]
    fn local(&self, u: &[f64]) -> (Vec3, Vec3, Vec3) {
        let c = vec3(u, self.v[1]);
        (
            self.a + (vec3(u, self.v[0]) - c),
            Vec3::ZERO,
            self.b + (vec3(u, self.v[2]) - c),
        )
    }
}

/// Index ranges of one rod's terms in the model's term lists.
#[derive(Clone, Debug, Default)]
struct RodTerms {
    stretch: Range<usize>,
    bend: Range<usize>,
    anchor: Range<usize>,
}

/// Which curves make up the structure being evaluated.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ActiveSet {
    active: Vec<bool>,
}

impl ActiveSet {
    /// Every curve of a network with `n` curves.
    pub fn all(n: usize) -> Self {
        ActiveSet {
            active: vec![true; n],
        }
    }

    /// Exactly the listed curves.
    pub fn from_curves(n: usize, curves: &[usize]) -> Self {
        let mut active = vec![false; n];
        for &c in curves {
            active[c] = true;
        }
        ActiveSet { active }
    }

    /// This set without curve `c`.
    pub fn without(&self, c: usize) -> Self {
        let mut s = self.clone();
        s.active[c] = false;
        s
    }

    /// Removes curve `c` in place.
    pub fn remove(&mut self, c: usize) {
        self.active[c] = false;
    }

    /// True when curve `c` is part of the structure.
    pub fn contains(&self, c: usize) -> bool {
        self.active[c]
    }

    /// Number of curves in the network (active or not).
    pub fn universe(&self) -> usize {
        self.active.len()
    }

    /// Active curve ids, ascending.
    pub fn curves(&self) -> Vec<usize> {
        (0..self.active.len()).filter(|&c| self.active[c]).collect()
    }

    /// Number of active curves.
    pub fn len(&self) -> usize {
        self.active.iter().filter(|&&a| a).count()
    }

    /// True when no curve is active.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Energy, gradient and Hessian values of one assembly.
#[derive(Clone, Debug, Default)]
pub struct Assembly {
    /// Total energy.
    pub energy: f64,
    /// Gradient over all `3·V` coordinates (zero on loose vertices).
    pub grad: Vec<f64>,
    /// Hessian values in the model's pattern (upper triangle, compressed columns).
    pub hess: Vec<f64>,
}

/// Local Hessians of every stretching and bending term at one state (anchors are constant);
/// when computed for a structure ([`EnergyModel::local_hessians_for`]), those of its curves,
/// the others zero.
#[derive(Clone, Debug)]
pub struct LocalHessians {
    stretch: Vec<[[f64; 6]; 6]>,
    bend: Vec<[[f64; 9]; 9]>,
}

/// Sparse upper-triangular pattern of the Hessian over `3·V` coordinates.
#[derive(Clone, Debug)]
pub struct Pattern {
    /// Number of rows and columns.
    pub n: usize,
    /// Column pointers (`n + 1` entries).
    pub col_ptr: Vec<usize>,
    /// Row indices, ascending within each column.
    pub row_idx: Vec<usize>,
    /// Slot of each diagonal entry.
    pub diag: Vec<usize>,
}

impl Pattern {
    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// The pattern as a faer symbolic matrix.
    pub fn symbolic(&self) -> faer::sparse::SymbolicSparseColMatRef<'_, usize> {
        faer::sparse::SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        )
    }

    /// `y = A x` for the symmetric matrix whose upper triangle `values` holds.
    pub fn sym_matvec(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for j in 0..self.n {
            let xj = x[j];
            let mut acc = 0.0;
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[k];
                let a = values[k];
                if i == j {
                    acc += a * xj;
                } else {
                    acc += a * x[i];
                    y[i] += a * xj;
                }
            }
            y[j] += acc;
        }
    }

    /// [`Pattern::sym_matvec`] for `K` vectors at once, stored interleaved (`x[i][c]`:
    /// coordinate `i` of vector `c`): one pass over the matrix instead of `K`. Each vector's
    /// result is the same, bit for bit, as `sym_matvec`'s.
    pub fn sym_matvec_many<const K: usize>(
        &self,
        values: &[f64],
        x: &[[f64; K]],
        y: &mut [[f64; K]],
    ) {
        y.iter_mut().for_each(|v| *v = [0.0; K]);
        for j in 0..self.n {
            let xj = x[j];
            let mut acc = [0.0; K];
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[k];
                let a = values[k];
                if i == j {
                    for c in 0..K {
                        acc[c] += a * xj[c];
                    }
                } else {
                    let xi = x[i];
                    let yi = &mut y[i];
                    for c in 0..K {
                        acc[c] += a * xi[c];
                        yi[c] += a * xj[c];
                    }
                }
            }
            for c in 0..K {
                y[j][c] += acc[c];
            }
        }
    }

    /// The principal sub-pattern of the coordinates `keep` selects (`keep.len() == n`): the
    /// pattern itself, for each of its stored entries the slot of the same entry in `self`,
    /// and for each of its coordinates the coordinate in `self`.
    pub fn principal(&self, keep: &[bool]) -> (Pattern, Vec<usize>, Vec<usize>) {
        assert_eq!(keep.len(), self.n, "one flag per coordinate");
        let dofs: Vec<usize> = (0..self.n).filter(|&j| keep[j]).collect();
        let mut new_of = vec![usize::MAX; self.n];
        for (i, &d) in dofs.iter().enumerate() {
            new_of[d] = i;
        }
        let mut col_ptr = Vec::with_capacity(dofs.len() + 1);
        let mut row_idx = Vec::new();
        let mut slots = Vec::new();
        let mut diag = Vec::with_capacity(dofs.len());
        col_ptr.push(0);
        for &j in &dofs {
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[k];
                if keep[i] {
                    if i == j {
                        diag.push(row_idx.len());
                    }
                    // Rows stay ascending: `new_of` is increasing.
                    row_idx.push(new_of[i]);
                    slots.push(k);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let sub = Pattern {
            n: dofs.len(),
            col_ptr,
            row_idx,
            diag,
        };
        (sub, slots, dofs)
    }

    /// The 1-norm of the symmetric matrix (largest absolute column sum).
    pub fn sym_norm1(&self, values: &[f64]) -> f64 {
        let mut col = vec![0.0; self.n];
        for j in 0..self.n {
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[k];
                let a = values[k].abs();
                col[j] += a;
                if i != j {
                    col[i] += a;
                }
            }
        }
        col.into_iter().fold(0.0, f64::max)
    }
}

/// The energy of a network: every term of every rod and the Hessian pattern.
#[derive(Clone, Debug)]
pub struct EnergyModel {
    n_vertices: usize,
    mu: f64,
    stretch: Vec<StretchTerm>,
    bend: Vec<BendTerm>,
    /// The drawn shapes of the pre-bent rods' bending terms.
    bend_rest: Vec<RestBend>,
    anchor: Vec<AnchorTerm>,
    rods: Vec<RodTerms>,
    /// For every vertex, the curves through it.
    vertex_curves: Vec<Vec<u32>>,
    /// For every curve, its vertices (ascending, no repeats).
    curve_vertices: Vec<Vec<u32>>,
    pattern: Pattern,
    /// Block positions for each term: `pos[p][q]` locates the 3×3 block of local vertices
    /// `(p, q)` in the column of the larger global vertex.
    stretch_pos: Vec<[[u32; 2]; 2]>,
    bend_pos: Vec<[[u32; 3]; 3]>,
    /// Diagonal entry used for coordinates of loose vertices.
    loose_diagonal: f64,
}

impl EnergyModel {
    /// Collects the terms of `network` with `material` (every rod alike, straight at rest)
    /// and builds the Hessian pattern.
    pub fn new(network: &Network, material: &Material) -> Self {
        let rods = vec![RodStiffness::from(material); network.rods.len()];
        Self::with_rods(network, &rods, material.anchor_weight)
    }

    /// Collects the terms of `network`, rod `i` with the stiffnesses and rest shape
    /// `rods[i]`, anchors of weight `anchor_weight`, and builds the Hessian pattern.
    pub fn with_rods(
        network: &Network,
        rods_stiffness: &[RodStiffness],
        anchor_weight: f64,
    ) -> Self {
        assert_eq!(
            rods_stiffness.len(),
            network.rods.len(),
            "one stiffness per rod"
        );
        let n_vertices = network.positions.len();
        let mut stretch = Vec::new();
        let mut bend = Vec::new();
        let mut bend_rest = Vec::new();
        let mut anchor = Vec::new();
        let mut rods = Vec::with_capacity(network.rods.len());
        for (rod, k) in network.rods.iter().zip(rods_stiffness) {
            let (s0, b0, a0) = (stretch.len(), bend.len(), anchor.len());
            let m = rod.vertices.len();
            let ne = rod.edge_count();
            for j in 0..ne {
                let (a, b) = rod.edge(j);
                let e = network.positions[b as usize] - network.positions[a as usize];
                stretch.push(StretchTerm {
                    v: [a, b],
                    rest: rod.rest_lengths[j],
                    ks: k.ks,
                    e,
                });
            }
            // Bending at every interior vertex, and at every vertex of a closed rod.
            let centers: Box<dyn Iterator<Item = usize>> = if rod.closed {
                Box::new(0..m)
            } else {
                Box::new(1..m.saturating_sub(1))
            };
            for i in centers {
                let (prev, next) = ((i + ne - 1) % ne, i % ne);
                let v0 = rod.vertices[(i + m - 1) % m];
                let v1 = rod.vertices[i];
                let v2 = rod.vertices[(i + 1) % m];
                let x1 = network.positions[v1 as usize];
                let (r0, r1) = (rod.rest_lengths[prev], rod.rest_lengths[next]);
                let (a, b) = (
                    network.positions[v0 as usize] - x1,
                    network.positions[v2 as usize] - x1,
                );
                let rest = match k.rest {
                    RestShape::Straight => STRAIGHT,
                    RestShape::PreBent => {
                        bend_rest.push(terms::rest_bend(-a, b, r0, r1));
                        (bend_rest.len() - 1) as u32
                    }
                };
                bend.push(BendTerm {
                    v: [v0, v1, v2],
                    rest,
                    r0,
                    r1,
                    kb: k.kb,
                    a,
                    b,
                });
            }
            for &v in &rod.anchors {
                anchor.push(AnchorTerm {
                    v,
                    offset: Vec3::ZERO,
                });
            }
            rods.push(RodTerms {
                stretch: s0..stretch.len(),
                bend: b0..bend.len(),
                anchor: a0..anchor.len(),
            });
        }
        let vertex_curves = network.vertex_curves();
        let curve_vertices = network
            .rods
            .iter()
            .map(|r| {
                let mut v = r.vertices.clone();
                v.sort_unstable();
                v.dedup();
                v
            })
            .collect();

        // Vertex adjacency: for each vertex j, the vertices i <= j sharing a term with it.
        let mut lower: Vec<Vec<u32>> = (0..n_vertices as u32).map(|j| vec![j]).collect();
        let mut link = |a: u32, b: u32| {
            let (i, j) = if a <= b { (a, b) } else { (b, a) };
            lower[j as usize].push(i);
        };
        for t in &stretch {
            link(t.v[0], t.v[1]);
        }
        for t in &bend {
            link(t.v[0], t.v[1]);
            link(t.v[0], t.v[2]);
            link(t.v[1], t.v[2]);
        }
        for l in &mut lower {
            l.sort_unstable();
            l.dedup();
        }
        let n = 3 * n_vertices;
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut diag = Vec::with_capacity(n);
        col_ptr.push(0);
        for (j, nbrs) in lower.iter().enumerate() {
            for b in 0..3 {
                for &i in nbrs {
                    let i = i as usize;
                    let rows = if i == j { 0..b + 1 } else { 0..3 };
                    for a in rows {
                        if i == j && a == b {
                            diag.push(row_idx.len());
                        }
                        row_idx.push(3 * i + a);
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let pos = |a: u32, b: u32| -> u32 {
            let (i, j) = if a <= b { (a, b) } else { (b, a) };
            lower[j as usize]
                .binary_search(&i)
                .expect("pattern holds every term") as u32
        };
        let stretch_pos = stretch
            .iter()
            .map(|t| {
                let mut p = [[0u32; 2]; 2];
                for (x, row) in p.iter_mut().enumerate() {
                    for (y, slot) in row.iter_mut().enumerate() {
                        *slot = pos(t.v[x], t.v[y]);
                    }
                }
                p
            })
            .collect();
        let bend_pos = bend
            .iter()
            .map(|t| {
                let mut p = [[0u32; 3]; 3];
                for (x, row) in p.iter_mut().enumerate() {
                    for (y, slot) in row.iter_mut().enumerate() {
                        *slot = pos(t.v[x], t.v[y]);
                    }
                }
                p
            })
            .collect();

        let mu = anchor_weight;
        // A loose vertex's diagonal: the stiffest scale in the model, far above the low
        // spectrum that stability is about.
        let stiffest = stretch
            .iter()
            .map(|t| t.ks / t.rest)
            .fold(f64::NEG_INFINITY, f64::max);
        let loose_diagonal = if stiffest.is_finite() {
            stiffest.max(2.0 * mu)
        } else {
            1.0
        };
        EnergyModel {
            n_vertices,
            mu,
            stretch,
            bend,
            bend_rest,
            anchor,
            rods,
            vertex_curves,
            curve_vertices,
            pattern: Pattern {
                n,
                col_ptr,
                row_idx,
                diag,
            },
            stretch_pos,
            bend_pos,
            loose_diagonal,
        }
    }

    /// The drawn shape of bending term `t`, when its rod is pre-bent.
    #[inline]
    fn rest_of(&self, t: &BendTerm) -> Option<&RestBend> {
        (t.rest != STRAIGHT).then(|| &self.bend_rest[t.rest as usize])
    }

    /// Bending term `t`'s energy, gradient and Hessian at the local positions `x0, x1, x2`.
    #[inline]
    fn bend_local(&self, t: &BendTerm, x0: Vec3, x1: Vec3, x2: Vec3) -> terms::Local<9> {
        match self.rest_of(t) {
            None => terms::bend(x0, x1, x2, t.r0, t.r1, t.kb),
            Some(rest) => terms::bend_rest(x0, x1, x2, t.r0, t.r1, t.kb, rest),
        }
    }

    /// The anchor weight `µ` (an anchor is a spring of stiffness `2µ`).
    pub fn anchor_weight(&self) -> f64 {
        self.mu
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.n_vertices
    }

    /// Number of coordinates (`3·V`).
    pub fn dofs(&self) -> usize {
        3 * self.n_vertices
    }

    /// Number of curves.
    pub fn curve_count(&self) -> usize {
        self.rods.len()
    }

    /// The Hessian's sparsity pattern.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// The diagonal value placed on loose vertices' coordinates.
    pub fn loose_diagonal(&self) -> f64 {
        self.loose_diagonal
    }

    /// For each vertex, whether it belongs to at least one active curve.
    pub fn vertex_mask(&self, active: &ActiveSet) -> Vec<bool> {
        self.vertex_curves
            .iter()
            .map(|cs| cs.iter().any(|&c| active.contains(c as usize)))
            .collect()
    }

    /// Ids of the terms of the active curves.
    fn active_terms<'a>(
        &'a self,
        active: &'a ActiveSet,
    ) -> impl Iterator<Item = (usize, &'a RodTerms)> + 'a {
        self.rods
            .iter()
            .enumerate()
            .filter(move |(c, _)| active.contains(*c))
    }

    /// Total energy of the active curves at displacements `u`.
    pub fn energy(&self, u: &[f64], active: &ActiveSet) -> f64 {
        let mut e = 0.0;
        for (_, r) in self.active_terms(active) {
            for t in &self.stretch[r.stretch.clone()] {
                let (x0, x1) = t.local(u);
                e += terms::stretch_energy(x0, x1, t.rest, t.ks);
            }
            for t in &self.bend[r.bend.clone()] {
                let (x0, x1, x2) = t.local(u);
                e += match self.rest_of(t) {
                    None => terms::bend_energy(x0, x1, x2, t.r0, t.r1, t.kb),
                    Some(rest) => terms::bend_rest_energy(x0, x1, x2, t.r0, t.r1, t.kb, rest),
                };
            }
            for t in &self.anchor[r.anchor.clone()] {
                e += terms::anchor_energy(vec3(u, t.v), t.offset, self.mu);
            }
        }
        e
    }

    /// Energy and gradient; with `hessian`, also the Hessian values (loose vertices get the
    /// loose diagonal).
    pub fn assemble(&self, u: &[f64], active: &ActiveSet, hessian: bool) -> Assembly {
        let mut out = Assembly {
            energy: 0.0,
            grad: vec![0.0; self.dofs()],
            hess: if hessian {
                vec![0.0; self.pattern.nnz()]
            } else {
                Vec::new()
            },
        };
        self.assemble_into(u, active, hessian, &mut out);
        out
    }

    /// [`Self::assemble`] into existing buffers (resized as needed).
    pub fn assemble_into(&self, u: &[f64], active: &ActiveSet, hessian: bool, out: &mut Assembly) {
        let _timer = Timer::new(Phase::Assemble);
        assert_eq!(
            u.len(),
            self.dofs(),
            "displacement vector of the wrong length"
        );
        out.energy = 0.0;
        out.grad.clear();
        out.grad.resize(self.dofs(), 0.0);
        out.hess.clear();
        if hessian {
            out.hess.resize(self.pattern.nnz(), 0.0);
        }
        for (_, r) in self.active_terms(active) {
            for k in r.stretch.clone() {
                let t = &self.stretch[k];
                let (x0, x1) = t.local(u);
                let l = terms::stretch(x0, x1, t.rest, t.ks);
                out.energy += l.energy;
                scatter_grad(&mut out.grad, &t.v, &l.grad);
                if hessian {
                    self.scatter_hess(&mut out.hess, &t.v, &self.stretch_pos[k], &l.hess);
                }
            }
            for k in r.bend.clone() {
                let t = &self.bend[k];
                let (x0, x1, x2) = t.local(u);
                if !hessian {
                    // The gradient alone: a third of the bending term's work.
                    let (energy, grad) = match self.rest_of(t) {
                        None => terms::bend_energy_grad(x0, x1, x2, t.r0, t.r1, t.kb),
                        Some(rest) => {
                            terms::bend_rest_energy_grad(x0, x1, x2, t.r0, t.r1, t.kb, rest)
                        }
                    };
                    out.energy += energy;
                    scatter_grad(&mut out.grad, &t.v, &grad);
                    continue;
                }
                let l = self.bend_local(t, x0, x1, x2);
                out.energy += l.energy;
                scatter_grad(&mut out.grad, &t.v, &l.grad);
                self.scatter_hess(&mut out.hess, &t.v, &self.bend_pos[k], &l.hess);
            }
            for t in &self.anchor[r.anchor.clone()] {
                let l = terms::anchor(vec3(u, t.v), t.offset, self.mu);
                out.energy += l.energy;
                scatter_grad(&mut out.grad, &[t.v], &l.grad);
                if hessian {
                    let v = t.v as usize;
                    for a in 0..3 {
                        out.hess[self.pattern.diag[3 * v + a]] += l.hess[a][a];
                    }
                }
            }
        }
        if hessian {
            for (v, on) in self.vertex_mask(active).into_iter().enumerate() {
                if !on {
                    for a in 0..3 {
                        out.hess[self.pattern.diag[3 * v + a]] = self.loose_diagonal;
                    }
                }
            }
        }
    }

    fn scatter_hess<const K: usize, const D: usize>(
        &self,
        hess: &mut [f64],
        v: &[u32; K],
        pos: &[[u32; K]; K],
        local: &[[f64; D]; D],
    ) {
        self.hess_entries(v, pos, |k, row, col| hess[k] += local[row][col]);
    }

    /// Calls `f(slot, row, col)` for every entry a term over vertices `v` (block positions
    /// `pos`) adds to the upper-triangle values: `slot` in the pattern's values, `(row, col)`
    /// in the term's local Hessian. The order is the assembly's.
    #[inline]
    fn hess_entries<const K: usize>(
        &self,
        v: &[u32; K],
        pos: &[[u32; K]; K],
        mut f: impl FnMut(usize, usize, usize),
    ) {
        let cp = &self.pattern.col_ptr;
        for p in 0..K {
            for q in 0..K {
                let (vi, vj) = (v[p] as usize, v[q] as usize);
                if vi > vj {
                    continue;
                }
                let off = 3 * pos[p][q] as usize;
                for b in 0..3 {
                    let base = cp[3 * vj + b] + off;
                    let rows = if vi == vj { b + 1 } else { 3 };
                    for a in 0..rows {
                        f(base + a, 3 * p + a, 3 * q + b);
                    }
                }
            }
        }
    }

    /// The Hessian of `active` without curve `c` (which `active` holds), from `h`, the
    /// Hessian of `active` from the same `locals` ([`Self::hessian_from_locals`]): a copy of
    /// `h` in which only the entries `c`'s terms touch are summed again, over the other
    /// curves' terms in the assembly's order — the same values, bit for bit, as
    /// `hessian_from_locals(locals, &active.without(c))`, for the cost of a copy.
    pub fn hessian_without(
        &self,
        locals: &LocalHessians,
        active: &ActiveSet,
        h: &[f64],
        c: usize,
        out: &mut Vec<f64>,
    ) {
        let _timer = Timer::new(Phase::Assemble);
        assert!(active.contains(c), "curve {c} is not in the structure");
        out.clear();
        out.extend_from_slice(h);
        let r = &self.rods[c];
        let mut touched: Vec<usize> = Vec::new();
        for k in r.stretch.clone() {
            self.hess_entries(&self.stretch[k].v, &self.stretch_pos[k], |i, _, _| {
                touched.push(i)
            });
        }
        for k in r.bend.clone() {
            self.hess_entries(&self.bend[k].v, &self.bend_pos[k], |i, _, _| {
                touched.push(i)
            });
        }
        for t in &self.anchor[r.anchor.clone()] {
            touched.extend((0..3).map(|a| self.pattern.diag[3 * t.v as usize + a]));
        }
        touched.sort_unstable();
        touched.dedup();
        for &i in &touched {
            out[i] = 0.0;
        }
        let hit = |i: usize| touched.binary_search(&i).is_ok();
        let on_c = |v: u32| self.curve_vertices[c].binary_search(&v).is_ok();
        // Only terms through one of `c`'s vertices reach those entries; their curves in the
        // assembly's order.
        let mut others: Vec<usize> = self.curve_vertices[c]
            .iter()
            .flat_map(|&v| self.vertex_curves[v as usize].iter().map(|&o| o as usize))
            .filter(|&o| o != c && active.contains(o))
            .collect();
        others.sort_unstable();
        others.dedup();
        for o in others {
            let ro = &self.rods[o];
            for k in ro.stretch.clone() {
                let t = &self.stretch[k];
                if t.v.iter().any(|&v| on_c(v)) {
                    let l = &locals.stretch[k];
                    self.hess_entries(&t.v, &self.stretch_pos[k], |i, row, col| {
                        if hit(i) {
                            out[i] += l[row][col];
                        }
                    });
                }
            }
            for k in ro.bend.clone() {
                let t = &self.bend[k];
                if t.v.iter().any(|&v| on_c(v)) {
                    let l = &locals.bend[k];
                    self.hess_entries(&t.v, &self.bend_pos[k], |i, row, col| {
                        if hit(i) {
                            out[i] += l[row][col];
                        }
                    });
                }
            }
            for t in &self.anchor[ro.anchor.clone()] {
                if on_c(t.v) {
                    for a in 0..3 {
                        let i = self.pattern.diag[3 * t.v as usize + a];
                        if hit(i) {
                            out[i] += 2.0 * self.mu;
                        }
                    }
                }
            }
        }
        // `c`'s vertices no other curve of the structure holds: the loose diagonal.
        for &v in &self.curve_vertices[c] {
            let held = self.vertex_curves[v as usize]
                .iter()
                .any(|&o| o as usize != c && active.contains(o as usize));
            if !held {
                for a in 0..3 {
                    out[self.pattern.diag[3 * v as usize + a]] = self.loose_diagonal;
                }
            }
        }
    }

    /// The local Hessian of every term at displacements `u`, for assembling the Hessians of
    /// many structures at the same state ([`Self::hessian_from_locals`]).
    pub fn local_hessians(&self, u: &[f64]) -> LocalHessians {
        self.local_hessians_impl(u, None, false)
    }

    /// [`Self::local_hessians`] for the structure `active` and its sub-structures only: the
    /// terms of the other curves are left zero (the bunny's late iterations hold a third of
    /// its curves).
    pub fn local_hessians_for(&self, u: &[f64], active: &ActiveSet) -> LocalHessians {
        self.local_hessians_impl(u, Some(active), false)
    }

    /// [`Self::local_hessians_for`] with every local Hessian projected to be positive
    /// semidefinite ([`terms::project_psd_stretch`], [`terms::project_psd_bend`]): a convex
    /// model for Newton's direction far from equilibrium, never for the stability analysis.
    pub fn local_hessians_projected(&self, u: &[f64], active: &ActiveSet) -> LocalHessians {
        self.local_hessians_impl(u, Some(active), true)
    }

    fn local_hessians_impl(
        &self,
        u: &[f64],
        active: Option<&ActiveSet>,
        project: bool,
    ) -> LocalHessians {
        use rayon::prelude::*;
        let _timer = Timer::new(Phase::Assemble);
        assert_eq!(
            u.len(),
            self.dofs(),
            "displacement vector of the wrong length"
        );
        // Which terms to compute: those of the structure's curves (every term without one).
        let mut stretch_on = vec![active.is_none(); self.stretch.len()];
        let mut bend_on = vec![active.is_none(); self.bend.len()];
        if let Some(active) = active {
            for (_, r) in self.active_terms(active) {
                stretch_on[r.stretch.clone()].fill(true);
                bend_on[r.bend.clone()].fill(true);
            }
        }
        let stretch = self
            .stretch
            .par_iter()
            .zip(&stretch_on)
            .map(|(t, &on)| {
                if !on {
                    return [[0.0; 6]; 6];
                }
                let (x0, x1) = t.local(u);
                let mut h = terms::stretch(x0, x1, t.rest, t.ks).hess;
                if project {
                    terms::project_psd_stretch(&mut h);
                }
                h
            })
            .collect();
        let bend = self
            .bend
            .par_iter()
            .zip(&bend_on)
            .map(|(t, &on)| {
                if !on {
                    return [[0.0; 9]; 9];
                }
                let (x0, x1, x2) = t.local(u);
                let mut h = self.bend_local(t, x0, x1, x2).hess;
                if project {
                    terms::project_psd_bend(&mut h);
                }
                h
            })
            .collect();
        LocalHessians { stretch, bend }
    }

    /// The Hessian of the structure `active` from precomputed local Hessians: bit-identical
    /// to `assemble(u, active, true).hess` at the `u` the locals were computed at (same terms,
    /// same order).
    pub fn hessian_from_locals(
        &self,
        locals: &LocalHessians,
        active: &ActiveSet,
        hess: &mut Vec<f64>,
    ) {
        let _timer = Timer::new(Phase::Assemble);
        hess.clear();
        hess.resize(self.pattern.nnz(), 0.0);
        for (_, r) in self.active_terms(active) {
            for k in r.stretch.clone() {
                self.scatter_hess(
                    hess,
                    &self.stretch[k].v,
                    &self.stretch_pos[k],
                    &locals.stretch[k],
                );
            }
            for k in r.bend.clone() {
                self.scatter_hess(hess, &self.bend[k].v, &self.bend_pos[k], &locals.bend[k]);
            }
            for t in &self.anchor[r.anchor.clone()] {
                let v = t.v as usize;
                for a in 0..3 {
                    hess[self.pattern.diag[3 * v + a]] += 2.0 * self.mu;
                }
            }
        }
        for (v, on) in self.vertex_mask(active).into_iter().enumerate() {
            if !on {
                for a in 0..3 {
                    hess[self.pattern.diag[3 * v + a]] = self.loose_diagonal;
                }
            }
        }
    }

    /// `Σ_c weights[c]·H_c` from precomputed local Hessians, where `H_c` holds every term of
    /// curve `c` (stretching, bending, anchors): the Hessian of the structure in which curve
    /// `c`'s stiffness is scaled by `weights[c]` (the relaxation of SPEC §7). Vertices whose
    /// curves all have weight 0 get the loose diagonal, as in [`Self::hessian_from_locals`];
    /// with 0/1 weights the two agree bit for bit.
    pub fn hessian_weighted(&self, locals: &LocalHessians, weights: &[f64], hess: &mut Vec<f64>) {
        assert_eq!(weights.len(), self.rods.len(), "one weight per curve");
        let _timer = Timer::new(Phase::Assemble);
        hess.clear();
        hess.resize(self.pattern.nnz(), 0.0);
        let mut scaled9 = [[0.0; 9]; 9];
        let mut scaled6 = [[0.0; 6]; 6];
        for (c, r) in self.rods.iter().enumerate() {
            let w = weights[c];
            if w == 0.0 {
                continue;
            }
            for k in r.stretch.clone() {
                let l = &locals.stretch[k];
                let src = if w == 1.0 {
                    l
                } else {
                    for (d, s) in scaled6.iter_mut().zip(l) {
                        for (x, y) in d.iter_mut().zip(s) {
                            *x = w * y;
                        }
                    }
                    &scaled6
                };
                self.scatter_hess(hess, &self.stretch[k].v, &self.stretch_pos[k], src);
            }
            for k in r.bend.clone() {
                let l = &locals.bend[k];
                let src = if w == 1.0 {
                    l
                } else {
                    for (d, s) in scaled9.iter_mut().zip(l) {
                        for (x, y) in d.iter_mut().zip(s) {
                            *x = w * y;
                        }
                    }
                    &scaled9
                };
                self.scatter_hess(hess, &self.bend[k].v, &self.bend_pos[k], src);
            }
            for t in &self.anchor[r.anchor.clone()] {
                let v = t.v as usize;
                for a in 0..3 {
                    hess[self.pattern.diag[3 * v + a]] += w * (2.0 * self.mu);
                }
            }
        }
        for (v, cs) in self.vertex_curves.iter().enumerate() {
            if cs.iter().all(|&c| weights[c as usize] == 0.0) {
                for a in 0..3 {
                    hess[self.pattern.diag[3 * v + a]] = self.loose_diagonal;
                }
            }
        }
    }

    /// Curves through each vertex.
    pub fn vertex_curves(&self) -> &[Vec<u32>] {
        &self.vertex_curves
    }

    /// Vertices of curve `c`, ascending.
    pub fn curve_vertices(&self, c: usize) -> &[u32] {
        &self.curve_vertices[c]
    }

    /// `H_c X` restricted to curve `c`'s vertices: the Hessian of `c`'s own terms (from
    /// `locals`) times the columns of `x` (`3V × k`). Row block `i` of the result (3 rows)
    /// belongs to vertex `curve_vertices(c)[i]`; the result is `3·|vertices| × k`.
    pub fn curve_hessian_product(
        &self,
        locals: &LocalHessians,
        c: usize,
        x: faer::MatRef<'_, f64>,
    ) -> faer::Mat<f64> {
        let verts = &self.curve_vertices[c];
        let k = x.ncols();
        let mut out = faer::Mat::<f64>::zeros(3 * verts.len(), k);
        let slot = |v: u32| verts.binary_search(&v).expect("vertex of the curve");
        let r = &self.rods[c];
        let mut add = |vs: &[u32], h: &dyn Fn(usize, usize) -> f64| {
            for (p, &vp) in vs.iter().enumerate() {
                let row = 3 * slot(vp);
                for (q, &vq) in vs.iter().enumerate() {
                    let col = 3 * vq as usize;
                    for a in 0..3 {
                        for b in 0..3 {
                            let hv = h(3 * p + a, 3 * q + b);
                            if hv != 0.0 {
                                for j in 0..k {
                                    out[(row + a, j)] += hv * x[(col + b, j)];
                                }
                            }
                        }
                    }
                }
            }
        };
        for t in r.stretch.clone() {
            let l = &locals.stretch[t];
            add(&self.stretch[t].v, &|i, j| l[i][j]);
        }
        for t in r.bend.clone() {
            let l = &locals.bend[t];
            add(&self.bend[t].v, &|i, j| l[i][j]);
        }
        let two_mu = 2.0 * self.mu;
        for t in &self.anchor[r.anchor.clone()] {
            add(&[t.v], &|i, j| if i == j { two_mu } else { 0.0 });
        }
        out
    }

    /// `Σ ‖H_t‖_F` over the terms `t` of curve `c` (local Hessians in `locals`): an upper bound
    /// on the spectral norm of `|H_c|`, the entrywise absolute value of the curve's Hessian.
    pub fn curve_hessian_norm(&self, locals: &LocalHessians, c: usize) -> f64 {
        let r = &self.rods[c];
        let frob = |h: &mut dyn Iterator<Item = &f64>| h.map(|v| v * v).sum::<f64>().sqrt();
        let stretch: f64 = locals.stretch[r.stretch.clone()]
            .iter()
            .map(|l| frob(&mut l.iter().flatten()))
            .sum();
        let bend: f64 = locals.bend[r.bend.clone()]
            .iter()
            .map(|l| frob(&mut l.iter().flatten()))
            .sum();
        stretch + bend + r.anchor.len() as f64 * 2.0 * self.mu * 3f64.sqrt()
    }

    /// The Hessian of the active structure with the rows and columns of loose vertices deleted
    /// (the normative definition of SPEC §5), as a dense matrix, and the kept vertices.
    /// For tests and small networks.
    pub fn explicit_deletion(&self, u: &[f64], active: &ActiveSet) -> (faer::Mat<f64>, Vec<usize>) {
        let a = self.assemble(u, active, true);
        let mask = self.vertex_mask(active);
        let kept: Vec<usize> = (0..self.n_vertices).filter(|&v| mask[v]).collect();
        let mut index = vec![usize::MAX; self.dofs()];
        for (k, &v) in kept.iter().enumerate() {
            for c in 0..3 {
                index[3 * v + c] = 3 * k + c;
            }
        }
        let m = 3 * kept.len();
        let mut dense = faer::Mat::<f64>::zeros(m, m);
        for j in 0..self.pattern.n {
            for s in self.pattern.col_ptr[j]..self.pattern.col_ptr[j + 1] {
                let i = self.pattern.row_idx[s];
                let (ii, jj) = (index[i], index[j]);
                if ii == usize::MAX || jj == usize::MAX {
                    continue;
                }
                dense[(ii, jj)] = a.hess[s];
                dense[(jj, ii)] = a.hess[s];
            }
        }
        (dense, kept)
    }
}

#[inline]
fn vec3(x: &[f64], v: u32) -> Vec3 {
    let i = 3 * v as usize;
    Vec3::new(x[i], x[i + 1], x[i + 2])
}

#[inline]
fn scatter_grad<const K: usize>(grad: &mut [f64], v: &[u32; K], local: &[f64]) {
    for p in 0..K {
        let i = 3 * v[p] as usize;
        for a in 0..3 {
            grad[i + a] += local[3 * p + a];
        }
    }
}

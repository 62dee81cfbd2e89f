//! The energy of a whole network as a flat list of terms, and its sparse assembly.
//!
//! [`EnergyModel`] holds every stretching, bending and anchor term of every rod, grouped by
//! rod, together with one fixed sparsity pattern for the Hessian (the upper triangle over all
//! `3·V` coordinates, in compressed columns). In the physical mode it also holds the clamps
//! and, for pre-bent rods, a twist unknown per edge after the `3·V` vertex coordinates with
//! the frame terms that bend and twist them (`twist`); loose twists (of rods not in the
//! structure) get the loose diagonal like loose vertices. Any set of curves can be left out with an
//! [`ActiveSet`]: their terms are skipped and the vertices that belong to no remaining curve
//! ("loose" vertices) get a large diagonal entry instead, so the pattern, and hence one
//! symbolic factorization, serves every structure (`docs/model.md`, *Stability*). That device is equivalent to
//! deleting those rows and columns: the loose vertices then form a decoupled block whose
//! eigenvalues sit far above the structure's low spectrum (tested against the deleted version).
//!
//! **Coordinates are displacements** `u` from the locked rest state, not positions: every term
//! is evaluated from its rest edge vectors plus differences of displacements. Positions of a
//! few thousand units carry an absolute rounding of ~1e-13 that, times the stiffness of the
//! shortest edges, floors the gradient near 1e-7 (`docs/model.md`, *Numerical hazards*); displacements are small, so the
//! gradient can be driven orders of magnitude lower and λ is measured at a truer equilibrium.

mod assemble;
mod build;
mod locals;
mod pressure;
mod twist;

pub use locals::{LocalHessians, Terms};
pub use pressure::{Pressure, PressurePart};
pub use twist::TwistDof;
use twist::{ClampTwistTerm, FrameTerm};

use super::ActiveSet;
use super::terms::{self, ClampRest, RestBend};
use crate::geom::Vec3;
use crate::sparse::Pattern;
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

/// The physical mode's clamp at an end vertex `v[0]` with neighbour `v[1]` (`rod::terms::clamp`):
/// `e` is the rest edge `X1 − X0`, `rest` its rest length, `shape` the drawn end tangent and
/// rest curvature.
#[derive(Clone, Copy, Debug)]
struct ClampTerm {
    v: [u32; 2],
    rest: f64,
    kb: f64,
    e: Vec3,
    shape: ClampRest,
}

impl ClampTerm {
    /// End points relative to `x0`, from displacements `u`.
    #[inline]
    fn local(&self, u: &[f64]) -> (Vec3, Vec3) {
        (
            Vec3::ZERO,
            self.e + (vec3(u, self.v[1]) - vec3(u, self.v[0])),
        )
    }

    /// The term's energy, gradient and Hessian at displacements `u`.
    #[inline]
    fn eval(&self, u: &[f64]) -> terms::Local<6> {
        let (x0, x1) = self.local(u);
        terms::clamp(x0, x1, self.rest, self.kb, &self.shape)
    }
}

/// An anchor spring on a supported vertex; `offset` is its target minus its rest position
/// (zero when the anchor holds the vertex where it was drawn); `axes` is the weight matrix
/// `W = Σ d dᵀ` over the unit directions it fixes (the identity when it fixes x, y and z;
/// diagonal with zeros for a support given per end that fixes some world axes only; full for
/// directions taken from the surface: `Rod::anchor_weights`).
#[derive(Clone, Copy, Debug)]
struct AnchorTerm {
    v: u32,
    offset: Vec3,
    axes: [[f64; 3]; 3],
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

/// Index ranges of one rod's terms in the model's term lists, and its bending stiffness.
#[derive(Clone, Debug, Default)]
struct RodTerms {
    kb: f64,
    stretch: Range<usize>,
    bend: Range<usize>,
    clamp: Range<usize>,
    frame: Range<usize>,
    twist_clamp: Range<usize>,
    anchor: Range<usize>,
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

/// The energy of a network: every term of every rod and the Hessian pattern.
#[derive(Clone, Debug)]
pub struct EnergyModel {
    n_vertices: usize,
    mu: f64,
    stretch: Vec<StretchTerm>,
    bend: Vec<BendTerm>,
    /// The drawn shapes of the pre-bent rods' bending terms.
    bend_rest: Vec<RestBend>,
    /// The physical mode's clamps (empty in the paper's).
    clamp: Vec<ClampTerm>,
    /// The physical mode's frame terms of pre-bent rods (empty in the paper's).
    frame: Vec<FrameTerm>,
    /// Their slots in the pattern's values.
    frame_slots: Vec<[[u32; 11]; 11]>,
    /// The clamps' hold on pre-bent rods' twists, and their slots.
    twist_clamp: Vec<ClampTwistTerm>,
    twist_clamp_slots: Vec<[[u32; 7]; 7]>,
    /// The twist unknowns, coordinates `3·V …` in order.
    twists: Vec<TwistDof>,
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
    clamp_pos: Vec<[[u32; 2]; 2]>,
    /// Diagonal entry used for coordinates of loose vertices.
    loose_diagonal: f64,
    /// External forces on the coordinates (empty: none): the energy is the rods' minus
    /// `load · u` ([`Self::set_load`]).
    load: Vec<f64>,
    /// Follower pressures on the curves ([`Self::set_pressure`]).
    pressure: Option<Pressure>,
}

impl EnergyModel {
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

    /// Bending term `t`'s energy and gradient at the local positions `x0, x1, x2` (a third of
    /// the work of [`Self::bend_local`]).
    #[inline]
    fn bend_energy_grad(&self, t: &BendTerm, x0: Vec3, x1: Vec3, x2: Vec3) -> (f64, [f64; 9]) {
        match self.rest_of(t) {
            None => terms::bend_energy_grad(x0, x1, x2, t.r0, t.r1, t.kb),
            Some(rest) => terms::bend_rest_energy_grad(x0, x1, x2, t.r0, t.r1, t.kb, rest),
        }
    }

    /// Bending term `t`'s energy at the local positions `x0, x1, x2`.
    #[inline]
    fn bend_energy(&self, t: &BendTerm, x0: Vec3, x1: Vec3, x2: Vec3) -> f64 {
        match self.rest_of(t) {
            None => terms::bend_energy(x0, x1, x2, t.r0, t.r1, t.kb),
            Some(rest) => terms::bend_rest_energy(x0, x1, x2, t.r0, t.r1, t.kb, rest),
        }
    }

    /// Puts the external forces `load` on the coordinates (a dead load: `−load · u` joins
    /// the energy, `−load` the gradient; the Hessian is the rods'); an empty vector removes
    /// them. A shorter vector loads the first coordinates (the vertices', three each).
    pub fn set_load(&mut self, mut load: Vec<f64>) {
        assert!(
            load.len() <= self.dofs(),
            "a load longer than the coordinates"
        );
        if load.iter().all(|&f| f == 0.0) {
            load.clear();
        }
        self.load = load;
    }

    /// The external forces on the coordinates ([`Self::set_load`]; empty: none).
    pub fn load(&self) -> &[f64] {
        &self.load
    }

    /// The anchor weight `µ` (an anchor is a spring of stiffness `2µ`).
    pub fn anchor_weight(&self) -> f64 {
        self.mu
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.n_vertices
    }

    /// Number of coordinates: `3·V`, then the twist unknowns ([`Self::twist_count`]).
    pub fn dofs(&self) -> usize {
        3 * self.n_vertices + self.twists.len()
    }

    /// Number of curves.
    pub fn curve_count(&self) -> usize {
        self.rods.len()
    }

    /// The Hessian's sparsity pattern.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// The natural scale of the forces in structure `active`, the scale below which residual
    /// forces are negligible: the smallest bending force `k_b / L²` of its curves (Euler's
    /// buckling load without its `π²`, the force under which the structure's softest members
    /// give way; with one material, that of the longest curve) at each of its vertices, as a
    /// norm over them (`k_b / L² · √V`). A drawn state with forces (curved rods, anchors out
    /// of place) has a gradient far above it; unloaded straight rods have only round-off.
    pub fn natural_force_scale(&self, active: &ActiveSet) -> f64 {
        // kb / (L L) is monotone in L, so with one kb the minimum is exactly the longest
        // curve's value.
        let softest = self
            .active_terms(active)
            .filter_map(|(_, r)| {
                let l: f64 = self.stretch[r.stretch.clone()].iter().map(|t| t.rest).sum();
                (l > 0.0).then(|| r.kb / (l * l))
            })
            .fold(f64::INFINITY, f64::min);
        let held = self.vertex_mask(active).iter().filter(|&&h| h).count();
        if !softest.is_finite() {
            return 0.0;
        }
        softest * (held as f64).sqrt()
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

    /// The Hessian's stored entries of anchor `t` (the upper triangle of its vertex's block,
    /// `2µ W`, nonzero entries only; the diagonal first, in axis order) as (slot, value).
    fn anchor_entries(&self, t: &AnchorTerm) -> impl Iterator<Item = (usize, f64)> + '_ {
        let base = 3 * t.v as usize;
        let w = t.axes;
        let two_mu = 2.0 * self.mu;
        let diag = (0..3).map(move |a| (self.pattern.diag[base + a], two_mu * w[a][a]));
        let off = [(0, 1), (0, 2), (1, 2)]
            .into_iter()
            .filter(move |&(a, b)| w[a][b] != 0.0)
            .filter_map(move |(a, b)| {
                let (i, j) = (base + a, base + b);
                let col =
                    &self.pattern.row_idx[self.pattern.col_ptr[j]..self.pattern.col_ptr[j + 1]];
                let k = col.binary_search(&i).ok()?;
                Some((self.pattern.col_ptr[j] + k, two_mu * w[a][b]))
            });
        diag.chain(off)
    }

    /// For each vertex, whether an anchor holds it along some axis (in the model's rules: a
    /// clamp of the physical mode anchors the end vertex only).
    pub fn anchored_vertices(&self) -> Vec<bool> {
        let mut a = vec![false; self.n_vertices];
        for t in self
            .anchor
            .iter()
            .filter(|t| (0..3).any(|a| t.axes[a][a] > 0.0))
        {
            a[t.v as usize] = true;
        }
        a
    }

    /// Curves through each vertex.
    pub fn vertex_curves(&self) -> &[Vec<u32>] {
        &self.vertex_curves
    }

    /// Vertices of curve `c`, ascending.
    pub fn curve_vertices(&self, c: usize) -> &[u32] {
        &self.curve_vertices[c]
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

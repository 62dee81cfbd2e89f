//! Twist unknowns of pre-bent rods (the physical mode, [`ModelRules::PHYSICAL`]): which edges
//! carry one, the frame terms that replace a pre-bent rod's bending terms (`rod::frame`), and
//! the Hessian pattern's twist columns with each frame term's slots in it.
//!
//! Every edge of a pre-bent rod carries one unknown `s = r θ` after the `3·V` vertex
//! coordinates (coordinate `3·V + k` for the `k`-th). A clamp holds the end's twist by a term
//! between its frame and the end edge's (`rod::clamp_twist`); a pinned end leaves it free.
//! Joints share translations only; each rod's twist is its own. The paper's
//! mode and rods straight at rest carry none (a round rod straight at rest has a twist that
//! decouples from its bending), so their models, patterns and results are unchanged.
//!
//! [`ModelRules::PHYSICAL`]: crate::rod::ModelRules::PHYSICAL

use super::{EnergyModel, LocalHessians, RodTerms, vec3};
use crate::geom::Vec3;
use crate::rod::clamp_twist::{self, ClampTwistRest};
use crate::rod::frame::{self, FrameRest, FrameStiffness};
use crate::rod::terms::Local;
use crate::rod::{Network, RodStiffness};
use crate::sparse::Pattern;

/// One twist unknown: the rod and the edge whose twist it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TwistDof {
    /// The rod (curve).
    pub curve: u32,
    /// The edge along it.
    pub edge: u32,
}

/// A pre-bent rod's bending and twist term at an interior vertex (`rod::frame::frame`):
/// vertices `v`, the coordinates `s` of its edges' twist unknowns, rest lengths, the rest
/// offsets `a = X0 − X1`, `b = X2 − X1`, stiffnesses and drawn state.
#[derive(Clone, Copy, Debug)]
pub(super) struct FrameTerm {
    pub v: [u32; 3],
    pub s: [u32; 2],
    pub r0: f64,
    pub r1: f64,
    pub a: Vec3,
    pub b: Vec3,
    pub k: FrameStiffness,
    pub rest: FrameRest,
}

/// A frame term's local Hessian over `(x₀, x₁, x₂, s_a, s_b)`.
pub(super) type FrameHessian = [[f64; 11]; 11];

/// A clamp twist term's local Hessian over `(x₀, x₁, s)`.
pub(super) type ClampTwistHessian = [[f64; 7]; 7];

/// A clamp's hold on a pre-bent rod's twist (`rod::clamp_twist`): the end vertex `v[0]`, its
/// neighbour `v[1]`, the end edge's twist coordinate `s` and orientation `sign` (+1 at the
/// first end, −1 at the last), its rest length `len` and rest vector `e = X1 − X0`.
#[derive(Clone, Copy, Debug)]
pub(super) struct ClampTwistTerm {
    pub v: [u32; 2],
    pub s: u32,
    pub sign: f64,
    pub len: f64,
    pub e: Vec3,
    pub k: FrameStiffness,
    pub rest: ClampTwistRest,
}

impl ClampTwistTerm {
    /// The end points relative to the end vertex and the twist, from the unknowns `u`.
    #[inline]
    fn local(&self, u: &[f64]) -> ([Vec3; 2], f64) {
        (
            [
                Vec3::ZERO,
                self.e + (vec3(u, self.v[1]) - vec3(u, self.v[0])),
            ],
            u[self.s as usize],
        )
    }

    /// Energy, gradient and Hessian over `(x₀, x₁, s)` at the unknowns `u`.
    pub fn eval(&self, u: &[f64]) -> Local<7> {
        let (x, s) = self.local(u);
        clamp_twist::clamp_twist(x, s, self.sign, self.len, &self.k, &self.rest)
    }

    /// Energy at the unknowns `u`.
    pub fn energy(&self, u: &[f64]) -> f64 {
        let (x, s) = self.local(u);
        clamp_twist::clamp_twist_energy(x, s, self.sign, self.len, &self.k, &self.rest)
    }

    /// The global coordinates of the local unknowns.
    pub fn coordinates(&self) -> [usize; 7] {
        std::array::from_fn(|l| {
            if l < 6 {
                3 * self.v[l / 3] as usize + l % 3
            } else {
                self.s as usize
            }
        })
    }
}

impl FrameTerm {
    /// The three vertices relative to the centre and the two twists, from the unknowns `u`.
    #[inline]
    fn local(&self, u: &[f64]) -> ([Vec3; 3], [f64; 2]) {
        let c = vec3(u, self.v[1]);
        (
            [
                self.a + (vec3(u, self.v[0]) - c),
                Vec3::ZERO,
                self.b + (vec3(u, self.v[2]) - c),
            ],
            self.s.map(|i| u[i as usize]),
        )
    }

    /// Energy, gradient and Hessian over `(x₀, x₁, x₂, s_a, s_b)` at the unknowns `u`.
    pub fn eval(&self, u: &[f64]) -> Local<11> {
        let (x, s) = self.local(u);
        frame::frame(x, s, self.r0, self.r1, &self.k, &self.rest)
    }

    /// Energy at the unknowns `u`.
    pub fn energy(&self, u: &[f64]) -> f64 {
        let (x, s) = self.local(u);
        frame::frame_energy(x, s, self.r0, self.r1, &self.k, &self.rest)
    }

    /// The global coordinates of the local unknowns.
    pub fn coordinates(&self) -> [usize; 11] {
        std::array::from_fn(|l| {
            if l < 9 {
                3 * self.v[l / 3] as usize + l % 3
            } else {
                self.s[l - 9] as usize
            }
        })
    }
}

/// The frame terms, clamp twist terms and twist unknowns of pre-bent rod `c` (stiffness `k`),
/// appended to `frames`, `clamps` and `twists` (a twist unknown's coordinate is
/// `3 · n_vertices` plus its index in `twists`).
pub(super) fn collect_rod(
    c: usize,
    network: &Network,
    k: &RodStiffness,
    frames: &mut Vec<FrameTerm>,
    clamps: &mut Vec<ClampTwistTerm>,
    twists: &mut Vec<TwistDof>,
) {
    let rod = &network.rods[c];
    let p = &network.positions;
    let (m, ne) = (rod.vertices.len(), rod.edge_count());
    let n_vertices = p.len();
    let edge_vec = |j: usize| {
        let (a, b) = rod.edge(j);
        p[b as usize] - p[a as usize]
    };
    let tangents: Vec<Vec3> = (0..ne).map(|j| frame::rest_tangent(edge_vec(j))).collect();
    let directors = frame::rest_directors(&tangents);
    let coords: Vec<u32> = (0..ne)
        .map(|j| {
            twists.push(TwistDof {
                curve: c as u32,
                edge: j as u32,
            });
            (3 * n_vertices + twists.len() - 1) as u32
        })
        .collect();
    let stiffness = FrameStiffness {
        kb: k.kb,
        gj: k.gj,
        arm: k.arm,
    };
    let centers = if rod.closed {
        0..m
    } else {
        1..m.saturating_sub(1)
    };
    for i in centers {
        let (prev, next) = ((i + ne - 1) % ne, i % ne);
        let v0 = rod.vertices[(i + m - 1) % m];
        let v1 = rod.vertices[i];
        let v2 = rod.vertices[(i + 1) % m];
        let x1 = p[v1 as usize];
        let (r0, r1) = (rod.rest_lengths[prev], rod.rest_lengths[next]);
        let (a, b) = (p[v0 as usize] - x1, p[v2 as usize] - x1);
        frames.push(FrameTerm {
            v: [v0, v1, v2],
            s: [coords[prev], coords[next]],
            r0,
            r1,
            a,
            b,
            k: stiffness,
            rest: frame::frame_rest(-a, b, r0, r1, [directors[prev], directors[next]]),
        });
    }
    for at_start in [true, false] {
        if !rod.is_clamped_at(at_start) {
            continue;
        }
        // The end, its neighbour and the next one, from the end inwards.
        let idx = |k: usize| rod.vertices[if at_start { k } else { m - 1 - k }];
        let (edge, sign) = if at_start { (0, 1.0) } else { (ne - 1, -1.0) };
        let (x0, x1) = (p[idx(0) as usize], p[idx(1) as usize]);
        let x2 = (m > 2).then(|| p[idx(2) as usize]);
        let end_tangent = crate::rod::terms::end_tangent(x0, x1, x2);
        clamps.push(ClampTwistTerm {
            v: [idx(0), idx(1)],
            s: coords[edge],
            sign,
            len: rod.rest_lengths[edge],
            e: x1 - x0,
            k: stiffness,
            rest: clamp_twist::clamp_twist_rest(x1 - x0, directors[edge], end_tangent),
        });
    }
}

/// `pattern` (over the `3 · n_vertices` vertex coordinates) with the columns of `n_twists`
/// twist unknowns appended: each couples with the coordinates of the terms it belongs to
/// (`terms`: each term's global coordinates, vertex coordinates first).
pub(super) fn with_twist_columns<'a>(
    mut pattern: Pattern,
    n_vertices: usize,
    n_twists: usize,
    terms: impl Iterator<Item = &'a [usize]>,
) -> Pattern {
    if n_twists == 0 {
        return pattern;
    }
    let base = 3 * n_vertices;
    let mut rows: Vec<Vec<usize>> = (0..n_twists).map(|k| vec![base + k]).collect();
    for coords in terms {
        for &j in coords.iter().filter(|&&j| j >= base) {
            rows[j - base].extend(coords.iter().filter(|&&i| i <= j));
        }
    }
    for (k, mut col) in rows.into_iter().enumerate() {
        col.sort_unstable();
        col.dedup();
        for i in col {
            if i == base + k {
                pattern.diag.push(pattern.row_idx.len());
            }
            pattern.row_idx.push(i);
        }
        pattern.col_ptr.push(pattern.row_idx.len());
    }
    pattern.n = base + n_twists;
    pattern
}

/// A term's slots: `slots[l][m]` the position in the pattern's values of the entry of local
/// unknowns `(l, m)` (global coordinates `coords`) when it lies in the upper triangle,
/// `u32::MAX` otherwise.
pub(super) fn term_slots<const D: usize>(pattern: &Pattern, coords: &[usize; D]) -> [[u32; D]; D] {
    let mut slots = [[u32::MAX; D]; D];
    for (l, row) in slots.iter_mut().enumerate() {
        for (m, slot) in row.iter_mut().enumerate() {
            let (i, j) = (coords[l], coords[m]);
            if i > j {
                continue;
            }
            let col = &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]];
            let at = col
                .binary_search(&i)
                .expect("the pattern holds every twist entry");
            *slot = (pattern.col_ptr[j] + at) as u32;
        }
    }
    slots
}

/// Adds a term's local Hessian `local` to the values `hess` through its `slots`.
#[inline]
pub(super) fn scatter_slots<const D: usize>(
    hess: &mut [f64],
    slots: &[[u32; D]; D],
    local: &[[f64; D]; D],
) {
    for (row, slots) in slots.iter().enumerate() {
        for (col, &slot) in slots.iter().enumerate() {
            if slot != u32::MAX {
                hess[slot as usize] += local[row][col];
            }
        }
    }
}

/// Adds a term's local gradient `local` to `grad` at its global coordinates `coords`.
#[inline]
pub(super) fn scatter_coords<const D: usize>(
    grad: &mut [f64],
    coords: &[usize; D],
    local: &[f64; D],
) {
    for (&i, g) in coords.iter().zip(local) {
        grad[i] += g;
    }
}

impl EnergyModel {
    /// The energy of rod `r`'s frame and clamp twist terms at the unknowns `u`.
    pub(super) fn twist_terms_energy(&self, r: &RodTerms, u: &[f64]) -> f64 {
        let mut e = 0.0;
        for t in &self.frame[r.frame.clone()] {
            e += t.energy(u);
        }
        for t in &self.twist_clamp[r.twist_clamp.clone()] {
            e += t.energy(u);
        }
        e
    }

    /// Adds rod `r`'s frame and clamp twist terms at `u` to `energy`, `grad` and (when
    /// `hess` is given) the Hessian values.
    pub(super) fn assemble_twist_terms(
        &self,
        r: &RodTerms,
        u: &[f64],
        energy: &mut f64,
        grad: &mut [f64],
        mut hess: Option<&mut [f64]>,
    ) {
        for k in r.frame.clone() {
            let t = &self.frame[k];
            let l = t.eval(u);
            *energy += l.energy;
            scatter_coords(grad, &t.coordinates(), &l.grad);
            if let Some(h) = hess.as_deref_mut() {
                scatter_slots(h, &self.frame_slots[k], &l.hess);
            }
        }
        for k in r.twist_clamp.clone() {
            let t = &self.twist_clamp[k];
            let l = t.eval(u);
            *energy += l.energy;
            scatter_coords(grad, &t.coordinates(), &l.grad);
            if let Some(h) = hess.as_deref_mut() {
                scatter_slots(h, &self.twist_clamp_slots[k], &l.hess);
            }
        }
    }

    /// The local Hessians of the frame and clamp twist terms whose flags are on (zero for
    /// the others), each projected to be positive semidefinite with `project`.
    pub(super) fn twist_locals(
        &self,
        u: &[f64],
        frame_on: &[bool],
        clamp_on: &[bool],
        project: bool,
    ) -> (Vec<FrameHessian>, Vec<ClampTwistHessian>) {
        use rayon::prelude::*;
        let frame = self
            .frame
            .par_iter()
            .zip(frame_on)
            .map(|(t, &on)| {
                if !on {
                    return [[0.0; 11]; 11];
                }
                let mut h = t.eval(u).hess;
                if project {
                    crate::rod::terms::project_psd(&mut h);
                }
                h
            })
            .collect();
        let clamp = self
            .twist_clamp
            .iter()
            .zip(clamp_on)
            .map(|(t, &on)| {
                if !on {
                    return [[0.0; 7]; 7];
                }
                let mut h = t.eval(u).hess;
                if project {
                    crate::rod::terms::project_psd(&mut h);
                }
                h
            })
            .collect();
        (frame, clamp)
    }

    /// Adds `w` times rod `r`'s frame and clamp twist terms' local Hessians (from `locals`)
    /// to the values `hess`.
    pub(super) fn scatter_twist_locals(
        &self,
        hess: &mut [f64],
        r: &RodTerms,
        locals: &LocalHessians,
        w: f64,
    ) {
        for k in r.frame.clone() {
            let mut l = locals.frame[k];
            if w != 1.0 {
                l.iter_mut().flatten().for_each(|x| *x *= w);
            }
            scatter_slots(hess, &self.frame_slots[k], &l);
        }
        for k in r.twist_clamp.clone() {
            let mut l = locals.twist_clamp[k];
            if w != 1.0 {
                l.iter_mut().flatten().for_each(|x| *x *= w);
            }
            scatter_slots(hess, &self.twist_clamp_slots[k], &l);
        }
    }

    /// Calls `f(slot, value)` for every entry rod `r`'s frame and clamp twist terms add to
    /// the Hessian values (from `locals`).
    pub(super) fn twist_entries(
        &self,
        r: &RodTerms,
        locals: &LocalHessians,
        mut f: impl FnMut(usize, f64),
    ) {
        for k in r.frame.clone() {
            for (row, slots) in self.frame_slots[k].iter().enumerate() {
                for (col, &slot) in slots.iter().enumerate() {
                    if slot != u32::MAX {
                        f(slot as usize, locals.frame[k][row][col]);
                    }
                }
            }
        }
        for k in r.twist_clamp.clone() {
            for (row, slots) in self.twist_clamp_slots[k].iter().enumerate() {
                for (col, &slot) in slots.iter().enumerate() {
                    if slot != u32::MAX {
                        f(slot as usize, locals.twist_clamp[k][row][col]);
                    }
                }
            }
        }
    }

    /// Whether a frame or clamp twist term of rod `r` touches one of the vertices `on`.
    pub(super) fn twist_terms_touch(&self, r: &RodTerms, on: impl Fn(u32) -> bool) -> bool {
        self.frame[r.frame.clone()]
            .iter()
            .any(|t| t.v.iter().any(|&v| on(v)))
            || self.twist_clamp[r.twist_clamp.clone()]
                .iter()
                .any(|t| t.v.iter().any(|&v| on(v)))
    }

    /// The twist strains at rod `c`'s clamps at the unknowns `u`: for each clamped end, the
    /// end vertex and the twist per length between the clamp and the end edge (`m / (ē/2)`).
    /// Empty for a rod without twist unknowns.
    pub fn clamp_twist_strains(&self, u: &[f64], c: usize) -> Vec<(u32, f64)> {
        self.twist_clamp[self.rods[c].twist_clamp.clone()]
            .iter()
            .map(|t| {
                let (x, s) = t.local(u);
                let m = clamp_twist::clamp_twist_strain(x, s, t.sign, &t.k, &t.rest);
                (t.v[0], 2.0 * m / t.len)
            })
            .collect()
    }

    /// Number of twist unknowns (zero in the paper's mode and without pre-bent rods).
    pub fn twist_count(&self) -> usize {
        self.twists.len()
    }

    /// The twist unknowns, in coordinate order after the `3·V` vertex coordinates.
    pub fn twist_dofs(&self) -> &[TwistDof] {
        &self.twists
    }

    /// For every coordinate (`3·V` vertex coordinates, then the twists), whether the
    /// structure `active` holds it: its vertex belongs to an active curve, or its twist to an
    /// active rod.
    pub fn coordinate_mask(&self, active: &crate::rod::ActiveSet) -> Vec<bool> {
        let mut mask: Vec<bool> = self
            .vertex_mask(active)
            .into_iter()
            .flat_map(|m| [m; 3])
            .collect();
        mask.extend(
            self.twists
                .iter()
                .map(|t| active.contains(t.curve as usize)),
        );
        mask
    }

    /// The bending and twist strains of rod `c`'s frame terms at the unknowns `u`: for each
    /// of its interior vertices (in order), the vertex, the curvature the material feels
    /// (`2 √(½ Σ|κ_j − κ̄_j|²) / (ē_a + ē_b)`) and the twist per length
    /// (`2 (m − m̄) / (ē_a + ē_b)`). Empty for a rod without frame terms.
    pub fn frame_strains(&self, u: &[f64], c: usize) -> Vec<(u32, f64, f64)> {
        self.frame[self.rods[c].frame.clone()]
            .iter()
            .map(|t| {
                let (x, s) = t.local(u);
                let (bend, twist) = frame::frame_strain(x, s, t.r0, t.r1, &t.k, &t.rest);
                let dual = 0.5 * (t.r0 + t.r1);
                (t.v[1], bend / dual, twist / dual)
            })
            .collect()
    }
}

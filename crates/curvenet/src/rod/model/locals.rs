//! Local Hessians of the terms at one state, and the Hessians assembled from them: of any
//! structure, of weighted curves, and one curve's products and norms.

use super::{ActiveSet, EnergyModel};
use crate::profile::{Phase, Timer};
use crate::rod::terms;

/// Local Hessians of every stretching and bending term at one state (anchors are constant);
/// when computed for a structure ([`Terms::Of`]), those of its curves,
/// the others zero.
#[derive(Clone, Debug)]
pub struct LocalHessians {
    pub(super) stretch: Vec<[[f64; 6]; 6]>,
    pub(super) bend: Vec<[[f64; 9]; 9]>,
    pub(super) clamp: Vec<[[f64; 6]; 6]>,
    pub(super) frame: Vec<[[f64; 11]; 11]>,
    pub(super) twist_clamp: Vec<[[f64; 7]; 7]>,
}

/// Which terms' local Hessians [`EnergyModel::local_hessians`] computes.
#[derive(Clone, Copy, Debug)]
pub enum Terms<'a> {
    /// Every term's: for the Hessians of many structures at the same state.
    All,
    /// The terms of a structure's curves, the others left zero: for it and its
    /// sub-structures.
    Of(&'a ActiveSet),
    /// A structure's, each projected to be positive semidefinite
    /// ([`terms::project_psd_stretch`], [`terms::project_psd_bend`]): a convex model for
    /// Newton's direction far from equilibrium, never for the stability analysis.
    ProjectedOf(&'a ActiveSet),
}

impl EnergyModel {
    /// The local Hessians of `which` terms at displacements `u` (anchors are constant), for
    /// assembling the Hessians of many structures at that state
    /// ([`Self::hessian_from_locals`]).
    pub fn local_hessians(&self, u: &[f64], which: Terms<'_>) -> LocalHessians {
        let (active, project) = match which {
            Terms::All => (None, false),
            Terms::Of(a) => (Some(a), false),
            Terms::ProjectedOf(a) => (Some(a), true),
        };
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
        let mut clamp_on = vec![active.is_none(); self.clamp.len()];
        let mut frame_on = vec![active.is_none(); self.frame.len()];
        let mut twist_clamp_on = vec![active.is_none(); self.twist_clamp.len()];
        if let Some(active) = active {
            for (_, r) in self.active_terms(active) {
                stretch_on[r.stretch.clone()].fill(true);
                bend_on[r.bend.clone()].fill(true);
                clamp_on[r.clamp.clone()].fill(true);
                frame_on[r.frame.clone()].fill(true);
                twist_clamp_on[r.twist_clamp.clone()].fill(true);
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
        let clamp = self
            .clamp
            .iter()
            .zip(&clamp_on)
            .map(|(t, &on)| {
                if !on {
                    return [[0.0; 6]; 6];
                }
                let mut h = t.eval(u).hess;
                if project {
                    terms::project_psd_stretch(&mut h);
                }
                h
            })
            .collect();
        let (frame, twist_clamp) = self.twist_locals(u, &frame_on, &twist_clamp_on, project);
        LocalHessians {
            stretch,
            bend,
            clamp,
            frame,
            twist_clamp,
        }
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
            for k in r.clamp.clone() {
                self.scatter_hess(hess, &self.clamp[k].v, &self.clamp_pos[k], &locals.clamp[k]);
            }
            self.scatter_twist_locals(hess, r, locals, 1.0);
            for t in &self.anchor[r.anchor.clone()] {
                for (i, h) in self.anchor_entries(t) {
                    hess[i] += h;
                }
            }
        }
        self.set_loose_diagonal(hess, |c| active.contains(c));
    }

    /// `Σ_c weights[c]·H_c` from precomputed local Hessians, where `H_c` holds every term of
    /// curve `c` (stretching, bending, anchors): the Hessian of the structure in which curve
    /// `c`'s stiffness is scaled by `weights[c]` (the continuous relaxation: `docs/model.md`, *Relaxation and certificate*). Vertices whose
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
            for k in r.clamp.clone() {
                let l = &locals.clamp[k];
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
                self.scatter_hess(hess, &self.clamp[k].v, &self.clamp_pos[k], src);
            }
            self.scatter_twist_locals(hess, r, locals, w);
            for t in &self.anchor[r.anchor.clone()] {
                for (i, h) in self.anchor_entries(t) {
                    hess[i] += w * h;
                }
            }
        }
        self.set_loose_diagonal(hess, |c| weights[c] != 0.0);
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
        assert!(
            self.rods[c].frame.is_empty() && self.rods[c].twist_clamp.is_empty(),
            "curve {c} carries twist unknowns, which the searches' products do not"
        );
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
        for t in r.clamp.clone() {
            let l = &locals.clamp[t];
            add(&self.clamp[t].v, &|i, j| l[i][j]);
        }
        let two_mu = 2.0 * self.mu;
        for t in &self.anchor[r.anchor.clone()] {
            add(&[t.v], &|i, j| two_mu * t.axes[i][j]);
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
        let clamp: f64 = locals.clamp[r.clamp.clone()]
            .iter()
            .map(|l| frob(&mut l.iter().flatten()))
            .sum();
        let frame: f64 = locals.frame[r.frame.clone()]
            .iter()
            .map(|l| frob(&mut l.iter().flatten()))
            .chain(
                locals.twist_clamp[r.twist_clamp.clone()]
                    .iter()
                    .map(|l| frob(&mut l.iter().flatten())),
            )
            .sum();
        let anchor: f64 = self.anchor[r.anchor.clone()]
            .iter()
            .map(|t| 2.0 * self.mu * frob(&mut t.axes.iter().flatten()))
            .sum();
        stretch + bend + clamp + frame + anchor
    }
}

//! Energy, gradient and Hessian assembly of a structure, and the Hessian of a structure
//! without one curve from the structure's.

use super::{ActiveSet, Assembly, EnergyModel, LocalHessians, scatter_grad, vec3};
use crate::profile::{Phase, Timer};
use crate::rod::terms;

impl EnergyModel {
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
                e += self.bend_energy(t, x0, x1, x2);
            }
            for t in &self.clamp[r.clamp.clone()] {
                let (x0, x1) = t.local(u);
                e += terms::clamp_energy(x0, x1, t.rest, t.kb, &t.shape);
            }
            e += self.twist_terms_energy(r, u);
            for t in &self.anchor[r.anchor.clone()] {
                e += terms::anchor_energy(vec3(u, t.v), t.offset, self.mu, &t.axes);
            }
        }
        if self.pressure.is_some() {
            let mut grad = vec![0.0; self.dofs()];
            self.assemble_pressure(u, active, &mut e, &mut grad, None);
        }
        e - self.load.iter().zip(u).map(|(f, x)| f * x).sum::<f64>()
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
                    let (energy, grad) = self.bend_energy_grad(t, x0, x1, x2);
                    out.energy += energy;
                    scatter_grad(&mut out.grad, &t.v, &grad);
                    continue;
                }
                let l = self.bend_local(t, x0, x1, x2);
                out.energy += l.energy;
                scatter_grad(&mut out.grad, &t.v, &l.grad);
                self.scatter_hess(&mut out.hess, &t.v, &self.bend_pos[k], &l.hess);
            }
            for k in r.clamp.clone() {
                let t = &self.clamp[k];
                let l = t.eval(u);
                out.energy += l.energy;
                scatter_grad(&mut out.grad, &t.v, &l.grad);
                if hessian {
                    self.scatter_hess(&mut out.hess, &t.v, &self.clamp_pos[k], &l.hess);
                }
            }
            self.assemble_twist_terms(
                r,
                u,
                &mut out.energy,
                &mut out.grad,
                hessian.then_some(&mut out.hess[..]),
            );
            for t in &self.anchor[r.anchor.clone()] {
                let l = terms::anchor(vec3(u, t.v), t.offset, self.mu, &t.axes);
                out.energy += l.energy;
                scatter_grad(&mut out.grad, &[t.v], &l.grad);
                if hessian {
                    for (i, h) in self.anchor_entries(t) {
                        out.hess[i] += h;
                    }
                }
            }
        }
        self.assemble_pressure(
            u,
            active,
            &mut out.energy,
            &mut out.grad,
            hessian.then_some(&mut out.hess[..]),
        );
        for (g, f) in out.grad.iter_mut().zip(&self.load) {
            *g -= f;
        }
        out.energy -= self.load.iter().zip(u).map(|(f, x)| f * x).sum::<f64>();
        if hessian {
            self.set_loose_diagonal(&mut out.hess, |c| active.contains(c));
        }
    }

    /// Puts the loose diagonal on the coordinates no curve `held` marks holds (vertices of
    /// no such curve, twists of rods it does not mark), in the order the assemblies always
    /// used.
    pub(super) fn set_loose_diagonal(&self, hess: &mut [f64], held: impl Fn(usize) -> bool) {
        for (v, cs) in self.vertex_curves.iter().enumerate() {
            if !cs.iter().any(|&c| held(c as usize)) {
                for a in 0..3 {
                    hess[self.pattern.diag[3 * v + a]] = self.loose_diagonal;
                }
            }
        }
        let base = 3 * self.n_vertices;
        for (k, t) in self.twists.iter().enumerate() {
            if !held(t.curve as usize) {
                hess[self.pattern.diag[base + k]] = self.loose_diagonal;
            }
        }
    }

    pub(super) fn scatter_hess<const K: usize, const D: usize>(
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
        for k in r.clamp.clone() {
            self.hess_entries(&self.clamp[k].v, &self.clamp_pos[k], |i, _, _| {
                touched.push(i)
            });
        }
        self.twist_entries(r, locals, |i, _| touched.push(i));
        for t in &self.anchor[r.anchor.clone()] {
            touched.extend(self.anchor_entries(t).map(|(i, _)| i));
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
            for k in ro.clamp.clone() {
                let t = &self.clamp[k];
                if t.v.iter().any(|&v| on_c(v)) {
                    let l = &locals.clamp[k];
                    self.hess_entries(&t.v, &self.clamp_pos[k], |i, row, col| {
                        if hit(i) {
                            out[i] += l[row][col];
                        }
                    });
                }
            }
            if self.twist_terms_touch(ro, on_c) {
                self.twist_entries(ro, locals, |i, h| {
                    if hit(i) {
                        out[i] += h;
                    }
                });
            }
            for t in &self.anchor[ro.anchor.clone()] {
                if on_c(t.v) {
                    for (i, h) in self.anchor_entries(t) {
                        if hit(i) {
                            out[i] += h;
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
        // `c`'s own twists are loose now.
        let base = 3 * self.n_vertices;
        for (k, t) in self.twists.iter().enumerate() {
            if t.curve as usize == c {
                out[self.pattern.diag[base + k]] = self.loose_diagonal;
            }
        }
    }
}

//! The candidates' upper bounds: plain Rayleigh–Ritz on the structure's low modes, extended
//! by a carried test vector, refined by one preconditioned step.

use super::dense::{columns, combine, gram, lower, ritz, zero_rows};
use super::{Bound, Candidates};
use crate::solve::Schedule;
use crate::solve::factor::SOLVE_GROUP;
use crate::sparse::Pattern;
use faer::{Mat, MatRef};
use rayon::prelude::*;

/// A plain Rayleigh–Ritz bound and what its refinement reuses.
#[derive(Debug)]
pub(super) struct RitzBound {
    bound: Bound,
    /// Ritz coefficients (columns, ascending values) in the modes' space.
    coeffs: Mat<f64>,
    /// Coordinates of the candidate's loose vertices.
    pub(super) loose_rows: Vec<usize>,
    /// `H_c V` on the candidate's vertices (`3·|vertices| × k`).
    hcv: Mat<f64>,
}

/// A refined bound between its two halves (see [`Candidates::refined_bounds`]).
pub(super) enum RefineStep {
    /// Nothing to refine (the modes vanish on `A \ {c}`): the plain bound.
    Done(Bound),
    /// Ritz vectors `x`, their product `hx` with `H'`, residuals `z` to precondition.
    Step {
        bound: Bound,
        x: Mat<f64>,
        hx: Mat<f64>,
        z: Mat<f64>,
    },
}

/// The plain bound extended by a carried vector (see [`Candidates::extended_bound`]).
#[derive(Debug)]
pub(super) struct Extended {
    /// The smallest Ritz value of `[X, y]`, with its margin.
    bound: Bound,
    /// The carried vector on `A \ {c}`'s coordinates (one column) and `H'y`.
    pub(super) y: Mat<f64>,
    pub(super) hy: Mat<f64>,
    /// The two lowest Ritz vectors of `[X, y]` and their products with `H'`.
    xb: Mat<f64>,
    hxb: Mat<f64>,
}

impl Candidates<'_> {
    /// The Rayleigh–Ritz bound of candidate `c` with its Ritz coefficients and what the
    /// refined bound reuses.
    pub(super) fn ritz_bound(&self, c: usize) -> &RitzBound {
        self.ritz[c].get_or_init(|| self.compute_ritz_bound(c))
    }

    /// [`Self::ritz_bound`], computed.
    fn compute_ritz_bound(&self, c: usize) -> RitzBound {
        let _timer = crate::profile::Timer::new(crate::profile::Phase::Bound);
        let model = self.analyzer.model();
        let k = self.modes.ncols();
        let verts = model.curve_vertices(c);
        let vc = model.vertex_curves();
        let loose: Vec<bool> = verts
            .iter()
            .map(|&v| {
                !vc[v as usize]
                    .iter()
                    .any(|&o| o as usize != c && self.active.contains(o as usize))
            })
            .collect();
        let hcv = model.curve_hessian_product(&self.locals, c, self.modes.as_ref());
        let mut kk = self.vthv.clone();
        let mut gg = self.vtv.clone();
        let mut abs_sum = 0.0;
        let mut loose_rows = Vec::new();
        for (s, &v) in verts.iter().enumerate() {
            if loose[s] {
                loose_rows.extend((0..3).map(|a| 3 * v as usize + a));
            }
            for a in 0..3 {
                let row = 3 * v as usize + a;
                let (src, local) = if loose[s] {
                    (&self.hv, row)
                } else {
                    (&hcv, 3 * s + a)
                };
                for i in 0..k {
                    let vi = self.modes[(row, i)];
                    for j in 0..k {
                        let p = vi * src[(local, j)];
                        kk[(i, j)] -= p;
                        abs_sum += p.abs();
                    }
                    if loose[s] {
                        for j in 0..k {
                            gg[(i, j)] -= vi * self.modes[(row, j)];
                        }
                    }
                }
                if loose[s] {
                    abs_sum += self.hv_abs[row];
                }
            }
        }
        let (values, coeffs) = ritz(kk.as_ref(), gg.as_ref());
        let value = values.first().copied().unwrap_or(f64::INFINITY);
        let bound = Bound {
            value,
            margin: 64.0 * f64::EPSILON * abs_sum + 1e-9 * value.abs(),
        };
        RitzBound {
            bound,
            coeffs,
            loose_rows,
            hcv,
        }
    }

    /// The Rayleigh–Ritz upper bound on candidate `c`'s score.
    pub fn bound(&self, c: usize) -> Bound {
        if self.analyzer.mass_metric() {
            // The modes are the mass metric's and the bound's update formulas the identity
            // metric's: no bound (every candidate is tested or scored).
            return Bound {
                value: f64::INFINITY,
                margin: 0.0,
            };
        }
        self.ritz_bound(c).bound
    }

    /// The plain bound's two lowest Ritz vectors `X = V·C` (loose rows zeroed) and `H'X`;
    /// `None` when the modes vanish on `A \ {c}`.
    ///
    /// `H'X` needs no sparse product: `H'X = (H_A V)·C − H_c (V·C)` on the kept rows and zero
    /// on the loose ones (the loose vertices' rows of `H_A` hold only `c`'s terms), from the
    /// iteration's `H_A V` and the bound's `H_c V`.
    fn plain_ritz_vectors(&self, c: usize) -> Option<(Mat<f64>, Mat<f64>)> {
        let RitzBound {
            coeffs,
            loose_rows,
            hcv,
            ..
        } = self.ritz_bound(c);
        if coeffs.ncols() == 0 {
            return None;
        }
        let r = coeffs.ncols().min(2);
        let coeffs = coeffs.get(.., ..r);
        let mut x = self.modes.as_ref() * coeffs;
        zero_rows(&mut x, loose_rows);
        let mut hx = self.hv.as_ref() * coeffs;
        let hcx = hcv.as_ref() * coeffs;
        let model = self.analyzer.model();
        for (s, &v) in model.curve_vertices(c).iter().enumerate() {
            for a in 0..3 {
                for j in 0..r {
                    hx[(3 * v as usize + a, j)] -= hcx[(3 * s + a, j)];
                }
            }
        }
        zero_rows(&mut hx, loose_rows);
        Some((x, hx))
    }

    /// The plain bound extended by the vector carried over from the previous iteration
    /// (`None` without one): Rayleigh–Ritz on `[X, y]`, one product with `H_A`.
    fn extended(&self, c: usize) -> Option<&Extended> {
        self.extended[c]
            .get_or_init(|| self.compute_extended(c))
            .as_ref()
    }

    /// [`Self::extended`], computed.
    fn compute_extended(&self, c: usize) -> Option<Extended> {
        let y = self.carried_y(c)?;
        let hy = self.candidate_matvec(c, y.as_ref());
        self.finish_extended(c, y, hy)
    }

    /// Computes the extended bounds of candidates `cs` not computed yet, their carried
    /// vectors' products with `H_A` in shared passes over it.
    fn extend_many(&self, cs: &[usize]) {
        let todo: Vec<(usize, Mat<f64>)> = cs
            .iter()
            .filter(|&&c| self.extended[c].get().is_none())
            .filter_map(|&c| match self.carried_y(c) {
                Some(y) => Some((c, y)),
                None => {
                    let _ = self.extended[c].set(None);
                    None
                }
            })
            .collect();
        if todo.is_empty() {
            return;
        }
        let _timer = crate::profile::Timer::new(crate::profile::Phase::Bound);
        let n = self.modes.nrows();
        let ys = Mat::<f64>::from_fn(n, todo.len(), |i, j| todo[j].1[(i, 0)]);
        let hys = self.h_products(ys.as_ref());
        todo.into_par_iter().enumerate().for_each(|(j, (c, y))| {
            let mut hy = hys.get(.., j..j + 1).to_owned();
            self.subtract_curve(c, y.as_ref(), &mut hy);
            let _ = self.extended[c].set(self.finish_extended(c, y, hy));
        });
    }

    /// The extended bound of candidate `c` from its carried vector `y` and `H'y`.
    fn finish_extended(&self, c: usize, y: Mat<f64>, hy: Mat<f64>) -> Option<Extended> {
        let (x, hx) = self.plain_ritz_vectors(c)?;
        let basis = columns(&[&x, &y]);
        let hbasis = columns(&[&hx, &hy]);
        let (values, q) = ritz(
            gram(&basis, &hbasis).as_ref(),
            gram(&basis, &basis).as_ref(),
        );
        let value = *values.first()?;
        let r = x.ncols().min(q.ncols());
        let xb = combine(&basis, q.get(.., ..r));
        let hxb = combine(&hbasis, q.get(.., ..r));
        let bound = Bound {
            value,
            margin: self.margin(c, xb.get(.., ..1), value),
        };
        self.offer(c, value, xb.as_ref());
        Some(Extended {
            bound,
            y,
            hy,
            xb,
            hxb,
        })
    }

    /// The extended bound if it was computed already (never computes it).
    fn known_extended(&self, c: usize) -> Option<&Extended> {
        self.extended[c].get().and_then(Option::as_ref)
    }

    /// The round-off margin of the Rayleigh quotient `value` of `y` (one column) in `H'`:
    /// `|y|ᵀ|H'||y| ε`, with `|H'| ≤ |H_A| + |H_c|`, `|y|ᵀ|H_A||y| ≤ Σᵢ rᵢ yᵢ²` (`rᵢ`: row sums
    /// of `|H_A|`; from `|yᵢ||yⱼ| ≤ (yᵢ² + yⱼ²)/2`) and `|y|ᵀ|H_c||y| ≤ (Σ_t ‖H_t‖_F) ‖y_c‖²`
    /// over `c`'s terms `t`; plus `1e-9` of the value.
    fn margin(&self, c: usize, y: MatRef<'_, f64>, value: f64) -> f64 {
        let model = self.analyzer.model();
        let yy: f64 = y.col(0).iter().map(|v| v * v).sum();
        let ya: f64 = y
            .col(0)
            .iter()
            .zip(&self.row_abs)
            .map(|(v, r)| r * v * v)
            .sum();
        let yc: f64 = model
            .curve_vertices(c)
            .iter()
            .flat_map(|&v| (0..3).map(move |a| 3 * v as usize + a))
            .map(|i| y[(i, 0)] * y[(i, 0)])
            .sum();
        let curve = model.curve_hessian_norm(&self.locals, c) * yc;
        let spread: f64 = (ya + curve) / yy.max(f64::MIN_POSITIVE);
        64.0 * f64::EPSILON * spread + 1e-9 * value.abs()
    }

    /// The upper bound from the plain Ritz vectors and the carried one (the plain bound
    /// without a carried vector): the lower of the two once margins are counted.
    pub fn extended_bound(&self, c: usize) -> Bound {
        let plain = self.bound(c);
        match self.extended(c) {
            Some(e) => lower(plain, e.bound),
            None => plain,
        }
    }

    /// [`Self::extended_bound`] of candidates `cs`, their carried vectors' products with
    /// `H_A` in shared passes.
    pub fn extended_bounds(&self, cs: &[usize]) -> Vec<Bound> {
        self.extend_many(cs);
        cs.iter().map(|&c| self.extended_bound(c)).collect()
    }

    /// The lowest Ritz vectors (two at most) of the extended bound's space when that was
    /// computed (else the plain bound's), with their products with `H'`.
    fn best_ritz_vectors(&self, c: usize) -> Option<(Mat<f64>, Mat<f64>)> {
        match self.known_extended(c) {
            Some(e) => Some((e.xb.clone(), e.hxb.clone())),
            None => self.plain_ritz_vectors(c),
        }
    }

    /// Warm start for candidate `c`: its two lowest Ritz vectors (loose rows zeroed); `None`
    /// when the model carries twist unknowns (pre-bent rods under the frequency objective),
    /// whose terms the curve products behind the Ritz vectors leave out: the iteration's
    /// modes start the solve instead.
    pub(super) fn ritz_vectors(&self, c: usize) -> Option<Mat<f64>> {
        if self.analyzer.model().twist_count() > 0 {
            return None;
        }
        self.best_ritz_vectors(c).map(|(x, _)| x)
    }

    /// Tighter upper bounds for candidates `cs` (`None` without a preconditioner): one
    /// preconditioned (LOBPCG-like) step from the Ritz vectors of each plain bound. With `X`
    /// those vectors and `θ` their values in `H' = H_{A∖c}`, the residuals `R = H'X − Xθ`
    /// are preconditioned by `(H_A − σI)⁻¹` (the factorization `A`'s spectrum used; `H'`
    /// differs from `H_A` only around `c`), and Rayleigh–Ritz on `[X, Z]` gives the bound.
    /// Everything lives on `A \ {c}`'s coordinates (loose rows zero), so by Courant–Fischer
    /// the smallest Ritz value is at least `λ_min(H')`. Costs a few sparse products and a
    /// share of one solve call — no factorization. With a vector carried over from the
    /// previous iteration, `X` are the lowest Ritz vectors of the plain Ritz vectors and the
    /// carried one, and the last Rayleigh–Ritz runs on all of them and `Z`.
    ///
    /// The candidates' residuals are solved together: the solves are bound by memory traffic
    /// (reading `L`), so several columns in one call cost little more than one, and one call
    /// for two candidates halves the cost of the step. The
    /// result for a candidate depends on which candidates share its call (the solver's
    /// rounding does); callers group candidates deterministically.
    pub fn refined_bounds(&self, cs: &[usize]) -> Vec<Option<Bound>> {
        let Some(f) = self.preconditioner.as_ref() else {
            return vec![None; cs.len()];
        };
        self.extend_many(cs);
        let _timer = crate::profile::Timer::new(crate::profile::Phase::Bound);
        let steps: Vec<RefineStep> = cs.par_iter().map(|&c| self.refine_start(c)).collect();
        let widths: Vec<usize> = steps
            .iter()
            .map(|s| match s {
                RefineStep::Done(_) => 0,
                RefineStep::Step { z, .. } => z.ncols(),
            })
            .collect();
        let n = self.modes.nrows();
        let mut rhs = Mat::<f64>::zeros(n, widths.iter().sum());
        let mut at = 0;
        for s in &steps {
            if let RefineStep::Step { z, .. } = s {
                rhs.get_mut(.., at..at + z.ncols()).copy_from(z);
                at += z.ncols();
            }
        }
        if rhs.ncols() > 0 {
            f.solve_in_place(rhs.as_mut(), Schedule::Groups(SOLVE_GROUP));
        }
        let mut offsets = Vec::with_capacity(cs.len());
        let mut at = 0;
        for (&c, w) in cs.iter().zip(&widths) {
            offsets.push(at);
            for &row in &self.ritz_bound(c).loose_rows {
                for j in at..at + w {
                    rhs[(row, j)] = 0.0;
                }
            }
            at += w;
        }
        // `H_A Z` for every candidate in shared passes over `H_A`.
        let hrhs = self.h_products(rhs.as_ref());
        steps
            .into_par_iter()
            .zip(cs.par_iter().zip(offsets.par_iter()))
            .map(|(step, (&c, &at))| match step {
                RefineStep::Done(b) => Some(b),
                RefineStep::Step { bound, x, hx, z } => {
                    let w = z.ncols();
                    let z = rhs.get(.., at..at + w).to_owned();
                    let mut hz = hrhs.get(.., at..at + w).to_owned();
                    self.subtract_curve(c, z.as_ref(), &mut hz);
                    Some(self.refine_finish(c, bound, x, hx, z, hz))
                }
            })
            .collect()
    }

    /// `H' m = H_A m − H_c m` for `m` zero on `c`'s loose rows (whose only terms are `c`'s):
    /// one product with the iteration's `H_A` and the curve's few terms, instead of
    /// assembling `H'`.
    pub(super) fn candidate_matvec(&self, c: usize, m: MatRef<'_, f64>) -> Mat<f64> {
        let mut out = self.h_products(m);
        self.subtract_curve(c, m, &mut out);
        out
    }

    /// `H_A M`, in passes over `H_A` of up to eight columns (the products are bound by
    /// reading `H_A`; each column's values are those of one product alone).
    fn h_products(&self, m: MatRef<'_, f64>) -> Mat<f64> {
        fn pass<const K: usize>(
            values: &[f64],
            p: &Pattern,
            m: MatRef<'_, f64>,
            out: &mut Mat<f64>,
            at: usize,
        ) {
            let x: Vec<[f64; K]> = (0..m.nrows())
                .map(|i| std::array::from_fn(|j| m[(i, at + j)]))
                .collect();
            let mut y = vec![[0.0; K]; m.nrows()];
            p.sym_matvec_many(values, &x, &mut y);
            for (i, v) in y.iter().enumerate() {
                for (j, &vj) in v.iter().enumerate() {
                    out[(i, at + j)] = vj;
                }
            }
        }
        let p = self.analyzer.model().pattern();
        let mut out = Mat::<f64>::zeros(m.nrows(), m.ncols());
        let mut at = 0;
        while at < m.ncols() {
            let k = (m.ncols() - at).min(8);
            match k {
                1 => pass::<1>(&self.h, p, m, &mut out, at),
                2 => pass::<2>(&self.h, p, m, &mut out, at),
                3 => pass::<3>(&self.h, p, m, &mut out, at),
                4 => pass::<4>(&self.h, p, m, &mut out, at),
                5 => pass::<5>(&self.h, p, m, &mut out, at),
                6 => pass::<6>(&self.h, p, m, &mut out, at),
                7 => pass::<7>(&self.h, p, m, &mut out, at),
                _ => pass::<8>(&self.h, p, m, &mut out, at),
            }
            at += k;
        }
        out
    }

    /// Turns `hm = H_A m` into `H' m`: subtracts `c`'s terms' product with `m`.
    fn subtract_curve(&self, c: usize, m: MatRef<'_, f64>, hm: &mut Mat<f64>) {
        let model = self.analyzer.model();
        let hc = model.curve_hessian_product(&self.locals, c, m);
        for (s, &v) in model.curve_vertices(c).iter().enumerate() {
            for a in 0..3 {
                for j in 0..m.ncols() {
                    hm[(3 * v as usize + a, j)] -= hc[(3 * s + a, j)];
                }
            }
        }
    }

    /// The refined bound's first half: the best Ritz vectors `X` ([`Self::best_ritz_vectors`]),
    /// `H'X`, and the residuals to precondition (loose rows zero).
    pub(super) fn refine_start(&self, c: usize) -> RefineStep {
        let bound = self.extended_bound(c);
        let Some((x, hx)) = self.best_ritz_vectors(c) else {
            return RefineStep::Done(bound);
        };
        let n = x.nrows();
        // Rayleigh quotients of X (not exactly θ: X is only orthogonal in exact arithmetic).
        let mut z = hx.clone();
        for j in 0..x.ncols() {
            let xj = x.col(j);
            let q = xj.transpose() * hx.col(j) / (xj.transpose() * xj);
            for i in 0..n {
                z[(i, j)] -= q * x[(i, j)];
            }
        }
        zero_rows(&mut z, &self.ritz_bound(c).loose_rows);
        RefineStep::Step { bound, x, hx, z }
    }

    /// The refined bound's second half, from the preconditioned residuals `z`: Rayleigh–Ritz
    /// on `[X, Z]` (with a carried vector: on the plain Ritz vectors, the carried one and
    /// `Z`, a space holding `X`) and its round-off margin; the lower of it and `bound`. The
    /// minimising Ritz vector is offered to the next iteration ([`Self::take_carried`]).
    fn refine_finish(
        &self,
        c: usize,
        bound: Bound,
        x: Mat<f64>,
        hx: Mat<f64>,
        z: Mat<f64>,
        hz: Mat<f64>,
    ) -> Bound {
        // With a carried vector `y`: Rayleigh–Ritz on `[X, y, Z]` (`X` holds the best Ritz
        // vectors of the plain ones and `y`: with `y` they span all three).
        let (basis, hbasis) = match self.known_extended(c) {
            Some(e) => (columns(&[&x, &e.y, &z]), columns(&[&hx, &e.hy, &hz])),
            None => (columns(&[&x, &z]), columns(&[&hx, &hz])),
        };
        let (values, coefficients) = ritz(
            gram(&basis, &hbasis).as_ref(),
            gram(&basis, &basis).as_ref(),
        );
        let Some(&value) = values.first() else {
            return bound;
        };
        let y = combine(&basis, coefficients.get(.., ..1));
        let refined = Bound {
            value,
            margin: self.margin(c, y.as_ref(), value),
        };
        self.offer(c, value, y.as_ref());
        lower(bound, refined)
    }
}

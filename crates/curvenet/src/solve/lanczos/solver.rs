//! The state of one block Lanczos run and its steps: expand the basis by a block, compute
//! the Ritz pairs, restart thickly, assemble the result.

use super::dense::{normalize_signs, sym_eig_ascending};
use super::orthogonal::{
    DGKS_RATIO, EXPAND_DROP_TOL, NewBlock, START_DROP_TOL, col_norms, orthonormalize_block,
};
use super::{BlockLanczosInfo, BlockLanczosParams, EigenPairs, LanczosError};
use crate::rng::SplitMix64;
use faer::linalg::matmul::matmul;
use faer::prelude::*;
use faer::{Accum, Mat, MatMut, MatRef, Par};

/// Rows per chunk when rotating the basis at a restart (bounds the scratch memory).
const ROTATE_CHUNK: usize = 1024;

/// Ritz values (descending), vectors (columns of `y`, same order) and residual norms.
struct Ritz {
    theta: Vec<f64>,
    y: Mat<f64>,
    res: Vec<f64>,
}

/// State of one block Lanczos run.
///
/// Invariants between steps: `v[:, 0..m]` is the orthonormal basis whose operator images
/// are known, `v[:, m..m+p]` the pending block (orthonormal to it, not yet applied);
/// `t[0..m, 0..m] = Vᵀ·Op·V` and `t[m..m+p, 0..m] = C`, with `Op·V = V·T + P·C`.
pub(super) struct Solver<'p, F> {
    n: usize,
    apply: F,
    params: &'p BlockLanczosParams,
    v: Mat<f64>,
    t: Mat<f64>,
    w: Mat<f64>,
    m: usize,
    p: usize,
    rng: SplitMix64,
    applications: usize,
    restarts: usize,
}

impl<'p, F: FnMut(MatRef<'_, f64>, MatMut<'_, f64>)> Solver<'p, F> {
    pub(super) fn new(
        n: usize,
        apply: F,
        width: usize,
        params: &'p BlockLanczosParams,
    ) -> Result<Self, LanczosError> {
        // Active basis ≤ max_basis, pending block ≤ width on top; never more than n. The
        // basis storage is reserved up front (fallibly) but its columns are initialised
        // only as the basis grows into them.
        let cap = params.max_basis.saturating_add(width).min(n);
        let mut v = Mat::new();
        let mut t = Mat::new();
        let mut w = Mat::new();
        let reserved = v
            .try_reserve(n, cap)
            .and_then(|()| t.try_reserve(cap, cap))
            .and_then(|()| w.try_reserve(n, width));
        if reserved.is_err() {
            return Err(LanczosError::InvalidParams(format!(
                "cannot allocate a {n} × {cap} Krylov basis (reduce max_basis)"
            )));
        }
        v.resize_with(n, 0, |_, _| 0.0);
        t.resize_with(cap, cap, |_, _| 0.0);
        w.resize_with(n, width, |_, _| 0.0);
        Ok(Solver {
            n,
            apply,
            params,
            v,
            t,
            w,
            m: 0,
            p: 0,
            rng: SplitMix64::new(params.seed),
            applications: 0,
            restarts: 0,
        })
    }

    /// Builds the first (pending) block from the warm start and random columns.
    pub(super) fn start(
        &mut self,
        warm_start: Option<MatRef<'_, f64>>,
    ) -> Result<(), LanczosError> {
        let width = self.w.ncols();
        let used = warm_start.map_or(0, |ws| ws.ncols().min(width));
        if let Some(ws) = warm_start {
            for j in 0..used {
                for i in 0..self.n {
                    let x = ws[(i, j)];
                    if !x.is_finite() {
                        return Err(LanczosError::NonFinite(format!(
                            "warm start entry ({i}, {j}) is {x}"
                        )));
                    }
                }
            }
            self.w.subcols_mut(0, used).copy_from(ws.subcols(0, used));
        }
        let w = self.w.as_mut().subcols_mut(0, used);
        let a0 = col_norms(w.rb());
        let block = NewBlock {
            start: 0,
            q_target: width,
            a0: &a0,
            a1: &a0,
            drop_tol: START_DROP_TOL,
        };
        let r = orthonormalize_block(&mut self.v, w, &block, None, &mut self.rng);
        self.m = 0;
        self.p = r.nrows();
        Ok(())
    }

    /// Main loop: expand, check, restart.
    pub(super) fn run(mut self) -> Result<EigenPairs, LanczosError> {
        let nev = self.params.nev;
        // Basis size from which the next convergence check is due (see below).
        let mut next_check = nev;
        loop {
            if self.p == 0 && self.m < nev {
                // Only reachable if random injection failed, which needs an exhausted space.
                return Err(LanczosError::Breakdown(format!(
                    "Krylov basis stuck at {} < nev = {nev} columns",
                    self.m
                )));
            }
            self.expand()?;
            let at_restart = self.m + self.p > self.params.max_basis;
            // A check costs O(m³) for the dense eigensolver against O(n·m·p) per block
            // for the reorthogonalisation: check every block unless m² ≫ n·p (only for
            // huge max_basis), and always before a restart or at the end of the space.
            if self.m < nev || (self.m < next_check && !at_restart && self.p > 0) {
                continue;
            }
            let ritz = self.ritz()?;
            let scale = ritz
                .theta
                .iter()
                .fold(f64::MIN_POSITIVE, |acc, t| acc.max(t.abs()));
            let converged = (0..nev)
                .filter(|&j| ritz.res[j] <= self.params.tolerance(j) * scale)
                .count();
            // p == 0: the basis spans an invariant subspace (the whole space for n ≤
            // max_basis), so T is exact.
            if converged == nev || self.p == 0 {
                return Ok(self.finish(&ritz, converged));
            }
            if at_restart {
                if self.restarts >= self.params.max_restarts {
                    return Err(LanczosError::NotConverged(Box::new(
                        self.finish(&ritz, converged),
                    )));
                }
                self.restart(&ritz);
            }
            next_check =
                self.m + self.m.saturating_mul(self.m) / self.n.saturating_mul(4 * self.p.max(1));
        }
    }

    /// Applies the operator to the pending block, orthogonalises the images against the
    /// whole basis and forms the next pending block.
    fn expand(&mut self) -> Result<(), LanczosError> {
        let (n, m, p) = (self.n, self.m, self.p);
        let mp = m + p;
        let mut w = self.w.as_mut().subcols_mut(0, p);
        w.fill(0.0);
        (self.apply)(self.v.as_ref().subcols(m, p), w.rb_mut());
        self.applications += p;
        let a0 = col_norms(w.rb());
        if let Some(j) = a0.iter().position(|x| !x.is_finite()) {
            return Err(LanczosError::NonFinite(format!(
                "operator output column {j} contains NaN or infinity"
            )));
        }
        let mut h = local_pass(self.v.as_ref(), self.t.as_ref(), m, w.rb_mut());
        let a1 = reorthogonalize(self.v.as_ref().subcols(0, mp), w.rb_mut(), &mut h);
        let block = NewBlock {
            start: mp,
            q_target: p.min(n - mp),
            a0: &a0,
            a1: &a1,
            drop_tol: EXPAND_DROP_TOL,
        };
        let r = orthonormalize_block(&mut self.v, w, &block, Some(h.as_mut()), &mut self.rng);
        extend_projection(&mut self.t, m, &h, &r);
        self.m = mp;
        self.p = r.nrows();
        Ok(())
    }

    /// Ritz pairs of the current basis, with residual norms `‖C·y‖`.
    fn ritz(&self) -> Result<Ritz, LanczosError> {
        let (m, p) = (self.m, self.p);
        let (asc, u) = sym_eig_ascending(self.t.as_ref().submatrix(0, 0, m, m))?;
        if asc.iter().any(|x| !x.is_finite()) {
            return Err(LanczosError::NonFinite(
                "projected matrix has non-finite eigenvalues".into(),
            ));
        }
        let theta: Vec<f64> = asc.iter().rev().copied().collect();
        let mut y = Mat::<f64>::zeros(m, m);
        for j in 0..m {
            y.col_mut(j).copy_from(u.col(m - 1 - j));
        }
        let mut cy = Mat::<f64>::zeros(p, m);
        matmul(
            cy.as_mut(),
            Accum::Replace,
            self.t.as_ref().submatrix(m, 0, p, m),
            y.as_ref(),
            1.0,
            Par::Seq,
        );
        let res = col_norms(cy.as_ref());
        Ok(Ritz { theta, y, res })
    }

    /// Thick restart: compresses the basis to the leading Ritz vectors.
    fn restart(&mut self, ritz: &Ritz) {
        let (n, m, p) = (self.n, self.m, self.p);
        let nev = self.params.nev;
        // Keep the wanted pairs plus about half of the free room; at least nev + 1 fits
        // because p ≤ max_basis − nev − 1.
        let free = self.params.max_basis - p - nev;
        let k = (nev + free.div_ceil(2)).min(m - 1);
        let yk = ritz.y.as_ref().subcols(0, k);

        // V[:, :k] = V[:, :m]·Y_k, by row chunks to bound the scratch memory.
        let mut tmp = Mat::<f64>::zeros(ROTATE_CHUNK.min(n), k);
        let mut r0 = 0;
        while r0 < n {
            let rows = ROTATE_CHUNK.min(n - r0);
            let mut tmp_rows = tmp.as_mut().subrows_mut(0, rows);
            matmul(
                tmp_rows.rb_mut(),
                Accum::Replace,
                self.v.as_ref().submatrix(r0, 0, rows, m),
                yk,
                1.0,
                Par::Seq,
            );
            self.v
                .as_mut()
                .submatrix_mut(r0, 0, rows, k)
                .copy_from(tmp_rows.rb());
            r0 += rows;
        }
        // Move the pending block from columns m.. to k.. (k < m: increasing order is safe).
        for j in 0..p {
            let (left, right) = self.v.as_mut().split_at_col_mut(m + j);
            left.col_mut(k + j).copy_from(right.col(0));
        }
        // New coupling C·Y_k, and T = diag(θ) bordered by it.
        let mut cy = Mat::<f64>::zeros(p, k);
        matmul(
            cy.as_mut(),
            Accum::Replace,
            self.t.as_ref().submatrix(m, 0, p, m),
            yk,
            1.0,
            Par::Seq,
        );
        let t = &mut self.t;
        t.as_mut().submatrix_mut(0, 0, k + p, k + p).fill(0.0);
        for i in 0..k {
            t[(i, i)] = ritz.theta[i];
        }
        for i in 0..p {
            for j in 0..k {
                t[(k + i, j)] = cy[(i, j)];
                t[(j, k + i)] = cy[(i, j)];
            }
        }
        self.m = k;
        self.restarts += 1;
    }

    /// Assembles the output from the current Ritz pairs.
    fn finish(&self, ritz: &Ritz, converged: usize) -> EigenPairs {
        #[cfg(test)]
        super::tests::record_basis_orthogonality(self.v.as_ref().subcols(0, self.m + self.p));
        let nev = self.params.nev;
        let mut x = Mat::<f64>::zeros(self.n, nev);
        matmul(
            x.as_mut(),
            Accum::Replace,
            self.v.as_ref().subcols(0, self.m),
            ritz.y.as_ref().subcols(0, nev),
            1.0,
            Par::Seq,
        );
        normalize_signs(x.as_mut());
        EigenPairs {
            values: ritz.theta[..nev].to_vec(),
            vectors: x,
            info: BlockLanczosInfo {
                restarts: self.restarts,
                applications: self.applications,
                converged,
                residuals: ritz.res[..nev].to_vec(),
            },
        }
    }
}

/// The local pass over the images `w = Op·P` of the pending block `P = v[:, m..m + p]` (the
/// block Lanczos recurrence): by symmetry and the relation `Op·V = V·T + P·C`, the projection
/// of `Op·P` on the old basis is `Cᵀ` and needs no pass over `V`; only the diagonal block
/// `A = Pᵀ·Op·P` is computed. `C` is zero left of column `c0` (it is `[0, R]` after a plain
/// step, dense after a thick restart). Returns the coefficients `[Cᵀ; A]` (`(m + p) × p`),
/// `w` left orthogonal to them.
fn local_pass(
    v: MatRef<'_, f64>,
    t: MatRef<'_, f64>,
    m: usize,
    mut w: MatMut<'_, f64>,
) -> Mat<f64> {
    let p = w.ncols();
    let mp = m + p;
    let mut h = Mat::<f64>::zeros(mp, p);
    matmul(
        h.as_mut().subrows_mut(m, p),
        Accum::Replace,
        v.subcols(m, p).transpose(),
        w.rb(),
        1.0,
        Par::Seq,
    );
    let c0 = (0..m)
        .find(|&i| (0..p).any(|j| t[(m + j, i)] != 0.0))
        .unwrap_or(m);
    for i in c0..m {
        for j in 0..p {
            h[(i, j)] = t[(m + j, i)];
        }
    }
    matmul(
        w.rb_mut(),
        Accum::Add,
        v.subcols(c0, mp - c0),
        h.as_ref().subrows(c0, mp - c0),
        -1.0,
        Par::Seq,
    );
    h
}

/// Full reorthogonalisation of `w` against the whole `basis` (incl. the pending block): a
/// block classical Gram–Schmidt pass, made a second time if it removed more than `1 − 1/√2`
/// of some column's norm (Daniel–Gragg–Kaufman–Stewart criterion). With the local pass as
/// the first orthogonalisation this is "twice is enough" at one sweep over `V` in the usual
/// case (two near an invariant subspace), instead of two to four. The coefficients are added
/// into `h`; returns the columns' norms after the last pass.
fn reorthogonalize(basis: MatRef<'_, f64>, mut w: MatMut<'_, f64>, h: &mut Mat<f64>) -> Vec<f64> {
    let mut before = col_norms(w.rb());
    let mut h2 = Mat::<f64>::zeros(basis.ncols(), w.ncols());
    for _ in 0..2 {
        matmul(
            h2.as_mut(),
            Accum::Replace,
            basis.transpose(),
            w.rb(),
            1.0,
            Par::Seq,
        );
        matmul(w.rb_mut(), Accum::Add, basis, h2.as_ref(), -1.0, Par::Seq);
        *h += &h2;
        let after = col_norms(w.rb());
        let again = after.iter().zip(&before).any(|(a, b)| *a < DGKS_RATIO * b);
        before = after;
        if !again {
            break;
        }
    }
    before
}

/// `T[:, m..m + p] = H` (and its transpose, the diagonal block symmetrised), and the new
/// coupling `C = [0 … 0, R]` between the new pending block and the basis.
fn extend_projection(t: &mut Mat<f64>, m: usize, h: &Mat<f64>, r: &Mat<f64>) {
    let p = h.ncols();
    let mp = m + p;
    let q = r.nrows();
    for j in 0..p {
        for i in 0..m {
            t[(i, m + j)] = h[(i, j)];
            t[(m + j, i)] = h[(i, j)];
        }
        for i in 0..p {
            t[(m + i, m + j)] = 0.5 * (h[(m + i, j)] + h[(m + j, i)]);
        }
    }
    for i in 0..q {
        for j in 0..mp + q {
            t[(mp + i, j)] = 0.0;
            t[(j, mp + i)] = 0.0;
        }
        for j in 0..p {
            t[(mp + i, m + j)] = r[(i, j)];
            t[(m + j, mp + i)] = r[(i, j)];
        }
    }
}

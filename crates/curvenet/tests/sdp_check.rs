//! The relaxation's bounds (`stability::fixed`, `simplify::certificate`) against an SDP solver (Clarabel) on tiny
//! networks. Needs the `sdp-check` feature and the system's OpenBLAS
//! (`apt-get install libopenblas-dev`):
//!
//! ```text
//! cargo test --release -p curvenet --features sdp-check --test sdp_check -- --nocapture
//! ```
//!
//! It is not part of the default build: Clarabel's SDP support needs BLAS and LAPACK, so
//! `clarabel` is an optional dependency of `curvenet` enabled only by the feature (`build.rs`
//! then links `-lopenblas`), and this test has `required-features = ["sdp-check"]`. CI
//! installs `libopenblas-dev` and runs it (`.ci/run`).
//!
//! # What is solved
//!
//! The relaxation of a node of the search (a face: its `In` curves at `α = 1`, its `Out` curves
//! at 0, its free curves in `[0, 1]` within the budget left) is the generalized-eigenvalue
//! problem the code maximizes (module docs of `relaxation.rs`):
//!
//! ```text
//! μ* = max_α μ(α),  μ(α) = λ_min(H(α), P(α)),  H(α) = Σ_c α_c H_c,  P(α) = diag_v(max_{c∋v} α_c),
//! ```
//!
//! the fixed point `B(ρ*) = ρ*` of docs/model.md's (*Relaxation and certificate*) `B(ρ) = max t : Σ α_c H_c + ρ diag(β) ⪰ tI`,
//! `β_v ≤ 1 − α_c`. `B(ρ)` itself cannot be handed to a solver here: `λ/‖H‖ ≈ 4e-10` on these
//! rods, below Clarabel's relative accuracy (1e-8). For fixed `ρ ≥ 0`, `μ* ≥ ρ` iff the LMI
//! `H(α) − ρ·diag(p) ⪰ 0`, `p_v ≥ α_c` (c ∋ v), `α` in the node's polytope, is feasible (a
//! larger `p` only lowers the matrix, so `p_v = max α_c` is no loss). The test solves
//!
//! ```text
//! G(ρ) = max t  s.t.  Tᵀ(H(α) − ρ·diag(p))T ⪰ tI,  α ∈ node polytope,  α_c ≤ p_g ≤ 1,
//! ```
//!
//! with Clarabel; `G(ρ) ≥ 0` iff `μ* ≥ ρ`. `T = |H(α̃)|^{-1/2}` (by a dense eigendecomposition,
//! `α̃` the current iterate with free curves raised to at least 0.01) is a congruence: it does
//! not change which `ρ` are feasible, but brings every matrix to norm ~1 and the soft modes
//! that decide `μ` near `α̃` to the same scale as the stiff ones. The transformed matrices
//! `TᵀH_cT` are formed in double-double arithmetic (Ogita–Rump–Oishi `Dot2`): formed in plain
//! `f64` they carry errors of `ε·κ(H) ≈ 5e-7`, which is what Clarabel would then see.
//! Coordinates of vertices only `Out` curves hold are left out (`H(α)` and `P(α)` vanish
//! there). One `p` per group of vertices on the same curves (the optimum has equal `p` within a
//! group). Clarabel's equilibration is off (it fails on the tiny `p` columns; the data are
//! scaled already).
//!
//! `μ*` is found by Dinkelbach's iteration: from `α` = the better of the node's `In` curves and
//! the code's relaxed point, `ρ ← μ(α)`, then `α ←` the maximizer of `G(ρ(1 + δ))` while
//! `G(ρ(1 + δ)) ≥ −η`. `μ(α)` of every iterate is evaluated independently of both the code and
//! Clarabel: a dense eigendecomposition of `P^{-1/2}H(α)P^{-1/2}` and a Rayleigh–Ritz step on
//! its four lowest vectors with the projected matrices in double-double (a plain dense `f64`
//! eigenvalue is only good to `nε‖H‖/λ ≈ 1e-5` relative here). The result is a verified
//! bracket `μ(α) ≤ μ* < ρ_hi = μ(α)(1 + δ)`: the left end is the value of a feasible point,
//! the right end an SDP certificate (`G(ρ_hi) < −η`). The threshold `η = 1e-7` is Clarabel's
//! accuracy (1e-8) with room: `G` is exactly 0, not positive, below `μ*` when the best `α`
//! leaves a free curve at 0 (the rows of its own vertices vanish), so its sign alone cannot
//! be trusted. `δ = 1e-6`, widened tenfold (up to 1e-3) when `G(ρ_hi)` is within `η` of 0 and
//! its maximizer is no better. Below the code's round-off margin `G` is evaluated at the
//! margin (it is a test only for `ρ ≥ 0`): such faces are reported as unstable.
//!
//! # What is asserted
//!
//! On five tiny networks (three coarse clamped arches, 15 vertices, LMIs of 30–45
//! coordinates; one with a keep list, four with fractional relaxed optima), for every face of
//! `certify` with free curves and a tight [`FixedProblem::relax_node`] of it:
//!
//! - (a) the code's certified bounds are at least `μ*` (bound valid);
//! - (b) the code's relaxed values are at most `μ*` (the relaxed point is feasible);
//! - (c) where the tight relaxation converged (to its tolerance 1e-6 or to twice the
//!   round-off margin), its value and bound are that close to `μ*`;
//! - (d) for binary `α = 1_S` (the best subset and each face's first curve) the SDP's `λ`
//!   (the root of `G` with `α` fixed, bracketed within `δ` of the code's value and
//!   interpolated) equals the code's `lambda_fix(S)`;
//! - and the relaxation bounds the exhaustive optimum: `max_faces μ* ≥ max_S λ_fix(S)`.
//!
//! Comparisons with the code's eigenvalues allow the code's declared round-off floor,
//! [`FixedProblem::margin`] (`128·ε·‖H‖₁`, about 3e-6…1e-4 of `λ` here): the code adds it to
//! every bound, so (a) needs no tolerance at all, and (b), (c) compare eigenvalues the code
//! computes to about that accuracy. Measured (printed with `--nocapture`, recorded in
//! `docs/compare.md`): (d) agrees to 5e-11 relative, (b) to 1e-12 where the code converged.
//!
//! Networks are made coarse on purpose: Clarabel factors the KKT system with a dense block of
//! the PSD cone's `n(n+1)/2` entries (`O(n⁶)` work), so a 45-coordinate LMI takes ~1–2 s and a
//! 66-coordinate one ~5 s per iteration.

mod common;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT::*};
use common::build;
use curvenet::cancel::Cancel;
use curvenet::rod::Supports;
use curvenet::simplify::Budget;
use curvenet::simplify::certificate::{CertifyParams, certify};
use curvenet::simplify::exhaustive::exhaustive_fixed;
use curvenet::stability::fixed::{FixedProblem, Node, RelaxParams, Status};
use curvenet::stability::{Analyzer, StabilityParams};
use faer::{Mat, Side};
use std::collections::BTreeMap;
use std::time::Instant;

/// The SDP bracket's relative width.
const DELTA: f64 = 1e-6;
/// `G(ρ) < −NOISE` proves `μ* < ρ`: Clarabel's accuracy on the scaled LMI (its gap and
/// feasibility tolerances are 1e-8) with a factor 10 to spare. `G` is exactly 0, not
/// positive, below `μ*` when the best `α` sets a free curve to 0 (the rows of its own
/// vertices vanish), so the sign alone is not enough.
const NOISE: f64 = 1e-7;

// ---------------------------------------------------------------------------------------
// Double-double dot products (Ogita, Rump, Oishi 2005).

/// `a + b = s + e` exactly.
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let z = s - a;
    (s, (a - (s - z)) + (b - z))
}

/// Compensated sum of products, as if accumulated in twice the working precision.
#[derive(Clone, Copy, Default)]
struct Dot2 {
    s: f64,
    c: f64,
}

impl Dot2 {
    fn add(&mut self, a: f64, b: f64) {
        let p = a * b;
        let ep = a.mul_add(b, -p);
        let (s, es) = two_sum(self.s, p);
        self.s = s;
        self.c += ep + es;
    }

    /// The sum as an unevaluated pair `hi + lo`.
    fn pair(self) -> (f64, f64) {
        two_sum(self.s, self.c)
    }

    fn value(self) -> f64 {
        self.s + self.c
    }
}

/// `TᵀMT` (symmetric `M`) with every entry accurate to a few units in its last place:
/// `X = MT` is kept as a double-double pair, then `Tᵀ(X_hi + X_lo)` by `Dot2`.
fn congruence(t: &Mat<f64>, m: &Mat<f64>) -> Mat<f64> {
    let k = t.nrows();
    let mut xh = Mat::<f64>::zeros(k, k);
    let mut xl = Mat::<f64>::zeros(k, k);
    for j in 0..k {
        for i in 0..k {
            let mut d = Dot2::default();
            for l in 0..k {
                let v = m[(i, l)];
                if v != 0.0 {
                    d.add(v, t[(l, j)]);
                }
            }
            let (h, l) = d.pair();
            xh[(i, j)] = h;
            xl[(i, j)] = l;
        }
    }
    let mut y = Mat::<f64>::zeros(k, k);
    for j in 0..k {
        for i in 0..=j {
            let mut d = Dot2::default();
            for l in 0..k {
                d.add(t[(l, i)], xh[(l, j)]);
                d.add(t[(l, i)], xl[(l, j)]);
            }
            y[(i, j)] = d.value();
            y[(j, i)] = y[(i, j)];
        }
    }
    y
}

// ---------------------------------------------------------------------------------------
// The problem as dense matrices.

/// The per-curve Hessians `H_c` of a [`FixedProblem`] as dense matrices over all coordinates,
/// assembled from the same local Hessians the code uses.
struct Dense {
    dofs: usize,
    h: Vec<Mat<f64>>,
    /// Curves through each vertex, ascending.
    vertex_curves: Vec<Vec<usize>>,
}

impl Dense {
    fn new(p: &FixedProblem<'_>) -> Dense {
        let model = p.analyzer().model();
        let locals = model.local_hessians(p.displacement(), curvenet::rod::model::Terms::All);
        let pat = model.pattern();
        let n = p.curve_count();
        let vertex_curves: Vec<Vec<usize>> = model
            .vertex_curves()
            .iter()
            .map(|cs| {
                let mut v: Vec<usize> = cs.iter().map(|&c| c as usize).collect();
                v.sort_unstable();
                v.dedup();
                v
            })
            .collect();
        let h = (0..n)
            .map(|c| {
                let mut w = vec![0.0; n];
                w[c] = 1.0;
                let mut vals = Vec::new();
                model.hessian_weighted(&locals, &w, &mut vals);
                let mut m = Mat::<f64>::zeros(pat.n, pat.n);
                for j in 0..pat.n {
                    for s in pat.col_ptr[j]..pat.col_ptr[j + 1] {
                        let i = pat.row_idx[s];
                        m[(i, j)] = vals[s];
                        m[(j, i)] = vals[s];
                    }
                }
                // `hessian_weighted` puts the loose diagonal on the other curves' vertices.
                for (v, cs) in vertex_curves.iter().enumerate() {
                    if !cs.contains(&c) {
                        for a in 0..3 {
                            m[(3 * v + a, 3 * v + a)] = 0.0;
                        }
                    }
                }
                m
            })
            .collect();
        Dense {
            dofs: pat.n,
            h,
            vertex_curves,
        }
    }

    /// `P(α)` per vertex.
    fn p_of(&self, alpha: &[f64]) -> Vec<f64> {
        self.vertex_curves
            .iter()
            .map(|cs| cs.iter().map(|&c| alpha[c]).fold(0.0, f64::max))
            .collect()
    }

    /// `μ(α) = λ_min(H(α), P(α))` on the coordinates with `p_v > 0`: a dense eigensolve of
    /// `P^{-1/2}H(α)P^{-1/2}`, then Rayleigh–Ritz on its four lowest vectors with the
    /// projected matrices in double-double.
    fn mu(&self, alpha: &[f64]) -> f64 {
        let p = self.p_of(alpha);
        let idx: Vec<usize> = (0..self.dofs).filter(|&i| p[i / 3] > 0.0).collect();
        let k = idx.len();
        let w: Vec<f64> = idx.iter().map(|&i| 1.0 / p[i / 3].sqrt()).collect();
        let mut a = Mat::<f64>::zeros(k, k);
        for (jj, &j) in idx.iter().enumerate() {
            for (ii, &i) in idx.iter().enumerate() {
                let mut s = 0.0;
                for (c, h) in self.h.iter().enumerate() {
                    if alpha[c] != 0.0 {
                        s += alpha[c] * h[(i, j)];
                    }
                }
                a[(ii, jj)] = s * w[ii] * w[jj];
            }
        }
        let eig = a.self_adjoint_eigen(Side::Lower).expect("dense eigen");
        let m = k.min(4);
        let ys: Vec<Vec<f64>> = (0..m)
            .map(|j| (0..k).map(|i| eig.U()[(i, j)] * w[i]).collect())
            .collect();
        let mut ah = Mat::<f64>::zeros(m, m);
        let mut bh = Mat::<f64>::zeros(m, m);
        for r in 0..m {
            for s in r..m {
                let mut num = Dot2::default();
                for (c, h) in self.h.iter().enumerate() {
                    if alpha[c] == 0.0 {
                        continue;
                    }
                    for (jj, &j) in idx.iter().enumerate() {
                        let mut col = Dot2::default();
                        for (ii, &i) in idx.iter().enumerate() {
                            let v = h[(i, j)];
                            if v != 0.0 {
                                col.add(ys[r][ii], v);
                            }
                        }
                        let (hi, lo) = col.pair();
                        num.add(hi, alpha[c] * ys[s][jj]);
                        num.add(lo, alpha[c] * ys[s][jj]);
                    }
                }
                let mut den = Dot2::default();
                for (ii, &i) in idx.iter().enumerate() {
                    den.add(ys[r][ii] * p[i / 3], ys[s][ii]);
                }
                ah[(r, s)] = num.value();
                ah[(s, r)] = ah[(r, s)];
                bh[(r, s)] = den.value();
                bh[(s, r)] = bh[(r, s)];
            }
        }
        // B ≈ I (orthonormal x, y = P^{-1/2}x): reduce with B's Cholesky factor.
        let li = inverse_cholesky(&bh);
        let c = &li * &ah * li.transpose();
        let mut cs = Mat::<f64>::zeros(m, m);
        for i in 0..m {
            for j in 0..m {
                cs[(i, j)] = 0.5 * (c[(i, j)] + c[(j, i)]);
            }
        }
        cs.self_adjoint_eigenvalues(Side::Lower)
            .expect("small eigen")[0]
    }
}

/// `L⁻¹` for the Cholesky factor `L` of a small positive definite `B = LLᵀ`.
fn inverse_cholesky(b: &Mat<f64>) -> Mat<f64> {
    let m = b.nrows();
    let mut l = Mat::<f64>::zeros(m, m);
    for j in 0..m {
        let d = b[(j, j)] - (0..j).map(|k| l[(j, k)] * l[(j, k)]).sum::<f64>();
        assert!(d > 0.0, "B positive definite");
        l[(j, j)] = d.sqrt();
        for i in j + 1..m {
            l[(i, j)] =
                (b[(i, j)] - (0..j).map(|k| l[(i, k)] * l[(j, k)]).sum::<f64>()) / l[(j, j)];
        }
    }
    let mut li = Mat::<f64>::zeros(m, m);
    for j in 0..m {
        li[(j, j)] = 1.0 / l[(j, j)];
        for i in j + 1..m {
            li[(i, j)] = -(j..i).map(|k| l[(i, k)] * li[(k, j)]).sum::<f64>() / l[(i, i)];
        }
    }
    li
}

// ---------------------------------------------------------------------------------------
// The SDP of one node.

/// `G(ρ)`'s data for one node: the congruence-transformed matrices over the node's
/// coordinates.
struct NodeLmi {
    /// Free curves, ascending, and their lengths.
    free: Vec<usize>,
    free_len: Vec<f64>,
    /// Budget left for the free curves.
    cap: f64,
    /// The node's status per curve.
    status: Vec<Status>,
    /// Groups of coordinates held by free curves only: the free curves (indices into
    /// `free`).
    groups: Vec<Vec<usize>>,
    /// `TᵀH_InT`, `TᵀE_InT` (`E` = identity on a set of coordinates), `TᵀH_cT` per free curve,
    /// `TᵀE_gT` per group.
    h_in: Mat<f64>,
    e_in: Mat<f64>,
    h_free: Vec<Mat<f64>>,
    e_groups: Vec<Mat<f64>>,
}

/// One solve of `G(ρ)`.
struct GSolve {
    g: f64,
    /// The maximizer, per curve, projected onto the node's polytope.
    alpha: Vec<f64>,
    seconds: f64,
}

impl NodeLmi {
    /// `alpha_ref` (per curve): where the congruence `T = |H(α̃)|^{-1/2}` is taken, with
    /// `α̃_c = max(α_ref_c, 0.01)` on the free curves.
    fn new(d: &Dense, node: &Node, lengths: &[f64], budget: f64, alpha_ref: &[f64]) -> NodeLmi {
        let status = node.status.clone();
        let n = status.len();
        let free: Vec<usize> = (0..n).filter(|&c| status[c] == Status::Free).collect();
        let in_len: f64 = (0..n)
            .filter(|&c| status[c] == Status::In)
            .map(|c| lengths[c])
            .sum();
        let mut idx = Vec::new();
        let mut in_coords = Vec::new();
        let mut gmap: BTreeMap<Vec<usize>, Vec<usize>> = BTreeMap::new();
        for (v, cs) in d.vertex_curves.iter().enumerate() {
            let has_in = cs.iter().any(|&c| status[c] == Status::In);
            let fr: Vec<usize> = cs
                .iter()
                .filter_map(|&c| free.iter().position(|&f| f == c))
                .collect();
            if !has_in && fr.is_empty() {
                continue;
            }
            for a in 0..3 {
                let local = idx.len();
                idx.push(3 * v + a);
                if has_in {
                    in_coords.push(local);
                } else {
                    gmap.entry(fr.clone()).or_default().push(local);
                }
            }
        }
        let k = idx.len();
        let restrict =
            |m: &Mat<f64>| -> Mat<f64> { Mat::from_fn(k, k, |i, j| m[(idx[i], idx[j])]) };
        let mut h_in = Mat::<f64>::zeros(k, k);
        for c in (0..n).filter(|&c| status[c] == Status::In) {
            h_in += restrict(&d.h[c]);
        }
        let h_free_raw: Vec<Mat<f64>> = free.iter().map(|&c| restrict(&d.h[c])).collect();
        let mut h_all = h_in.clone();
        for (h, &c) in h_free_raw.iter().zip(&free) {
            h_all += h * faer::Scale(alpha_ref[c].max(0.01));
        }
        // T = |H_all|^{-1/2} (any invertible T is exact; this one scales the matrices to ~1).
        let eig = h_all.self_adjoint_eigen(Side::Lower).expect("dense eigen");
        let vals = eig.S().column_vector();
        let top = (0..k).map(|i| vals[i].abs()).fold(0.0, f64::max);
        let scale: Vec<f64> = (0..k)
            .map(|i| 1.0 / vals[i].abs().max(1e-14 * top).sqrt())
            .collect();
        let u = eig.U();
        let t = Mat::from_fn(k, k, |j, l| {
            (0..k)
                .map(|i| u[(j, i)] * u[(l, i)] * scale[i])
                .sum::<f64>()
        });
        let diag = |coords: &[usize]| -> Mat<f64> {
            let mut y = Mat::<f64>::zeros(k, k);
            for j in 0..k {
                for i in 0..=j {
                    let mut s = Dot2::default();
                    for &l in coords {
                        s.add(t[(l, i)], t[(l, j)]);
                    }
                    y[(i, j)] = s.value();
                    y[(j, i)] = y[(i, j)];
                }
            }
            y
        };
        let groups: Vec<(Vec<usize>, Vec<usize>)> = gmap.into_iter().collect();
        NodeLmi {
            free_len: free.iter().map(|&c| lengths[c]).collect(),
            free,
            cap: budget - in_len,
            status,
            h_in: congruence(&t, &h_in),
            e_in: diag(&in_coords),
            h_free: h_free_raw.iter().map(|h| congruence(&t, h)).collect(),
            e_groups: groups.iter().map(|(_, cs)| diag(cs)).collect(),
            groups: groups.into_iter().map(|(g, _)| g).collect(),
        }
    }

    /// Coordinates of the LMI.
    fn size(&self) -> usize {
        self.h_in.nrows()
    }

    /// The node's `In` curves at 1, the free ones at `free_alpha` projected onto the polytope
    /// (clamped to `[0, 1]`, scaled into the budget).
    fn full_alpha(&self, free_alpha: &[f64]) -> Vec<f64> {
        let mut a: Vec<f64> = self
            .status
            .iter()
            .map(|s| if *s == Status::In { 1.0 } else { 0.0 })
            .collect();
        // An interior-point solution never reaches 0: a curve at 1e-7 is a curve left out
        // (its own vertices' modes would count in full at any positive α).
        let fa: Vec<f64> = free_alpha
            .iter()
            .map(|&x| if x < 1e-7 { 0.0 } else { x.min(1.0) })
            .collect();
        let used: f64 = fa.iter().zip(&self.free_len).map(|(x, l)| x * l).sum();
        let shrink = if used > self.cap {
            self.cap / used
        } else {
            1.0
        };
        for (i, &c) in self.free.iter().enumerate() {
            a[c] = fa[i] * shrink;
        }
        a
    }

    /// `G(ρ) = max t s.t. Tᵀ(H(α) − ρ·diag(p))T − tI ⪰ 0`, `α` in the polytope,
    /// `α_c ≤ p_g ≤ 1`. Variables `x = (α_free, p_groups, t)`; Clarabel's form
    /// `min qᵀx, b − Ax ∈ K` with `K` = nonnegative orthant × PSD triangle (upper triangle by
    /// columns, off-diagonals scaled by √2).
    fn solve(&self, rho: f64) -> GSolve {
        let k = self.size();
        let f = self.free.len();
        let g = self.groups.len();
        let nx = f + g + 1;
        let svec = |m: &Mat<f64>, scale: f64| -> Vec<f64> {
            let mut out = Vec::with_capacity(k * (k + 1) / 2);
            for j in 0..k {
                for i in 0..=j {
                    let v = m[(i, j)] * scale;
                    out.push(if i == j {
                        v
                    } else {
                        std::f64::consts::SQRT_2 * v
                    });
                }
            }
            out
        };
        // Linear rows `Σ a_j x_j ≤ b`.
        let mut rows: Vec<(Vec<(usize, f64)>, f64)> = Vec::new();
        for i in 0..f {
            rows.push((vec![(i, -1.0)], 0.0));
            rows.push((vec![(i, 1.0)], 1.0));
        }
        if f > 0 {
            // Σ L_c α_c ≤ cap, scaled to unit right-hand side.
            let cap = self.cap.max(f64::MIN_POSITIVE);
            rows.push(((0..f).map(|i| (i, self.free_len[i] / cap)).collect(), 1.0));
        }
        for (gi, cs) in self.groups.iter().enumerate() {
            for &c in cs {
                rows.push((vec![(c, 1.0), (f + gi, -1.0)], 0.0));
            }
            rows.push((vec![(f + gi, 1.0)], 1.0));
        }
        let m1 = rows.len();
        // s = svec(C + Σ x_j M_j) = b − Ax: b = svec(C), column j of A = −svec(M_j).
        let c0 = &self.h_in - &self.e_in * faer::Scale(rho);
        let b_psd = svec(&c0, 1.0);
        let mut cols: Vec<Vec<f64>> = Vec::with_capacity(nx);
        cols.extend(self.h_free.iter().map(|h| svec(h, -1.0)));
        cols.extend(self.e_groups.iter().map(|e| svec(e, rho)));
        cols.push(svec(&Mat::<f64>::identity(k, k), 1.0));
        let mut colptr = vec![0usize];
        let mut rowval = Vec::new();
        let mut nzval = Vec::new();
        for (j, col) in cols.iter().enumerate() {
            for (r, (entries, _)) in rows.iter().enumerate() {
                for &(jj, v) in entries {
                    if jj == j {
                        rowval.push(r);
                        nzval.push(v);
                    }
                }
            }
            for (r, &v) in col.iter().enumerate() {
                if v != 0.0 {
                    rowval.push(m1 + r);
                    nzval.push(v);
                }
            }
            colptr.push(rowval.len());
        }
        let a = CscMatrix::new(m1 + b_psd.len(), nx, colptr, rowval, nzval);
        let mut b: Vec<f64> = rows.iter().map(|r| r.1).collect();
        b.extend(b_psd);
        let mut q = vec![0.0; nx];
        q[nx - 1] = -1.0;
        let p = CscMatrix::zeros((nx, nx));
        let cones = [NonnegativeConeT(m1), PSDTriangleConeT(k)];
        let settings = DefaultSettings {
            // `SDP_VERBOSE=1` prints Clarabel's iterations.
            verbose: std::env::var_os("SDP_VERBOSE").is_some(),
            // Clarabel's equilibration fails on the `p` columns (`ρ·TᵀE_gT`, ~1e-9 where the
            // coordinates are stiff); the data are scaled to ~1 already.
            equilibrate_enable: false,
            ..DefaultSettings::default()
        };
        let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).expect("Clarabel");
        solver.solve();
        let sol = &solver.solution;
        assert!(
            matches!(
                sol.status,
                SolverStatus::Solved | SolverStatus::AlmostSolved
            ),
            "Clarabel: {:?} at ρ = {rho:e} ({k} coordinates)",
            sol.status
        );
        GSolve {
            g: sol.x[nx - 1],
            alpha: self.full_alpha(&sol.x[..f]),
            seconds: sol.solve_time,
        }
    }
}

/// The SDP's answer for one node.
struct SdpValue {
    /// Verified bracket: `lo = μ(α)` of a feasible `α`, `G(hi) < 0`.
    lo: f64,
    hi: f64,
    /// The feasible point reaching `lo`.
    alpha: Vec<f64>,
    solves: usize,
    seconds: f64,
    /// Coordinates of the LMI.
    size: usize,
}

/// `μ*` of a node by Dinkelbach's iteration on `G` (see the module documentation).
fn sdp_optimum(
    d: &Dense,
    p: &FixedProblem<'_>,
    node: &Node,
    floor: f64,
    start: &[f64],
) -> SdpValue {
    let mut alpha: Vec<f64> = node
        .status
        .iter()
        .map(|s| if *s == Status::In { 1.0 } else { 0.0 })
        .collect();
    let mut lo = d.mu(&alpha);
    let m = d.mu(start);
    if m > lo {
        (alpha, lo) = (start.to_vec(), m);
    }
    let mut seconds = 0.0;
    let mut delta = DELTA;
    for solves in 1..=30 {
        // The congruence at the current point: the modes that decide μ there are scaled
        // to ~1 even where α is small.
        let lmi = NodeLmi::new(d, node, p.lengths(), p.budget(), &alpha);
        // `G` is only a feasibility test for ρ ≥ 0: below `floor` (the code's round-off
        // margin) the node counts as unstable.
        let hi = lo.max(floor) * (1.0 + delta);
        let s = lmi.solve(hi);
        seconds += s.seconds;
        if s.g < -NOISE {
            return SdpValue {
                lo,
                hi,
                alpha,
                solves,
                seconds,
                size: lmi.size(),
            };
        }
        let m = d.mu(&s.alpha);
        if m > lo {
            lo = m;
            alpha = s.alpha;
        } else {
            // G(hi) ≈ 0 within the solver's accuracy but no better point: widen the bracket.
            assert!(
                delta < 1e-3,
                "G({hi:e}) = {:e} but its maximizer has μ = {m:e} ≤ {lo:e}",
                s.g
            );
            delta *= 10.0;
        }
    }
    panic!("Dinkelbach did not converge in 30 steps");
}

/// The SDP's `λ` of one subset: the root of `G` with `α = 1_S` fixed, bracketed around
/// `guess`.
fn sdp_subset(d: &Dense, p: &FixedProblem<'_>, curves: &[usize], guess: f64) -> f64 {
    let node = Node::new(p, curves, &[]);
    let ones = vec![1.0; p.curve_count()];
    let lmi = NodeLmi::new(d, &node, p.lengths(), f64::INFINITY, &ones);
    let (lo, hi) = (guess * (1.0 - DELTA), guess * (1.0 + DELTA));
    let (g0, g1) = (lmi.solve(lo).g, lmi.solve(hi).g);
    assert!(
        g0 > 0.0 && g1 < 0.0,
        "{curves:?}: G({lo:e}) = {g0:e}, G({hi:e}) = {g1:e}: the SDP's λ is not within \
         {DELTA:e} of λ_fix = {guess:e}"
    );
    lo + (hi - lo) * g0 / (g0 - g1)
}

// ---------------------------------------------------------------------------------------
// The networks and the test.

/// `n` arches over the paraboloid `z = 350·(1 − (x² + y²)/1000²)` above random chords of the
/// ground circle (as `common::random_arches`, but coarse: the chord's ends, its midpoint
/// and its crossings with the other chords, shared exactly), so the SDP stays small.
fn tiny_arches(seed: u64, n: usize) -> Vec<curvenet::io::Polyline> {
    common::arches_over_chords(
        seed,
        n,
        &common::ArchLayout {
            spread: (0.6, 1.4),
            samples: &[0.0, 0.5, 1.0],
            crossings: (0.05, 0.95),
            merge: 0.04,
        },
    )
}

struct Case {
    name: &'static str,
    seed: u64,
    arches: usize,
    h: f64,
    fraction: f64,
    keep: Vec<usize>,
}

fn cases() -> Vec<Case> {
    let case = |name, seed, h, fraction, keep: &[usize]| Case {
        name,
        seed,
        arches: 3,
        h,
        fraction,
        keep: keep.to_vec(),
    };
    vec![
        case("A", 32, 700.0, 0.7, &[]),
        case("B", 33, 700.0, 0.7, &[]),
        case("C", 31, 500.0, 0.7, &[]),
        case("D", 34, 700.0, 0.7, &[]),
        case("E-keep", 32, 700.0, 0.7, &[1]),
    ]
}

#[test]
fn relaxation_bounds_agree_with_an_sdp_solver() {
    let tight = RelaxParams {
        max_evals: 300,
        tolerance: 1e-6,
        max_stalled: 30,
    };
    let mut table = Vec::new();
    for case in cases() {
        let net = build(
            &tiny_arches(case.seed, case.arches),
            case.h,
            Supports::Clamped,
        );
        let an = Analyzer::new(net, StabilityParams::default()).expect("analyzer");
        let p =
            FixedProblem::new(&an, Budget::Fraction(case.fraction), &case.keep).expect("problem");
        let d = Dense::new(&p);
        let margin = p.margin();
        let t0 = Instant::now();
        let never = Cancel::never();
        let report = certify(&p, &CertifyParams::default(), &[], &never).expect("certify");
        let certify_s = t0.elapsed().as_secs_f64();
        let all = exhaustive_fixed(&p, 1 << 12, &never).expect("exhaustive");
        let best = all.best.lambda;
        let mut face_max = f64::NEG_INFINITY;
        for fb in &report.faces {
            let node = p.face(fb.curve);
            if node.curves(Status::Free).is_empty() {
                continue;
            }
            let t1 = Instant::now();
            let r = p
                .relax_node(&node, &tight, None, &[], &never)
                .expect("relax_node");
            let relax_s = t1.elapsed().as_secs_f64();
            // Dinkelbach starts from the better of the node's own structure and the code's
            // relaxed point: only the speed depends on it (the bracket's ends are a dense
            // evaluation and an SDP certificate).
            let sdp = sdp_optimum(&d, &p, &node, margin, &r.alpha);
            face_max = face_max.max(sdp.hi);
            let mu = sdp.lo;
            let fractional = sdp.alpha.iter().any(|&a| a > 1e-6 && a < 1.0 - 1e-6);
            let face = fb.curve.map_or("root".to_string(), |c| c.to_string());
            let what = format!("{} face {face}", case.name);
            // (a) the certified bounds are valid.
            assert!(
                fb.upper >= sdp.lo,
                "{what}: certify's bound {:e} < μ* ≥ {:e}",
                fb.upper,
                sdp.lo
            );
            assert!(
                r.upper >= sdp.lo,
                "{what}: relax_node's bound {:e} < μ* ≥ {:e}",
                r.upper,
                sdp.lo
            );
            // (b) the relaxed values are reached by feasible points.
            assert!(
                r.value <= sdp.hi + margin,
                "{what}: relaxed {:e} > μ* ≤ {:e}; dense μ at the code's α {:?}: {:e}; SDP's α {:?} lo {:e}",
                r.value,
                sdp.hi,
                r.alpha,
                d.mu(&r.alpha),
                sdp.alpha,
                sdp.lo
            );
            if fb.relaxed.is_finite() {
                assert!(
                    fb.relaxed <= sdp.hi + margin,
                    "{what}: relaxed {:e} > μ*",
                    fb.relaxed
                );
            }
            // (c) converged (to the tolerance or to the round-off floor) means close to μ*.
            let slack = tight.tolerance * r.upper.abs() + 2.0 * margin;
            let converged = r.upper - r.value <= slack;
            if converged {
                assert!(
                    r.upper <= sdp.hi + slack,
                    "{what}: converged bound {:e} far above μ* ≤ {:e}",
                    r.upper,
                    sdp.hi
                );
                assert!(
                    r.value >= sdp.lo - slack,
                    "{what}: converged value {:e} far below μ* ≥ {:e}",
                    r.value,
                    sdp.lo
                );
            }
            table.push(format!(
                "{:<7} {:>4} {:>3} {:>12.6e} {:>12.6e} {:>12.6e} {:>12.6e} {:>7.0e} {:>9.2e} {:>9.2e} {:>5} {:>4} {:>4} {:>6.2} {:>6.3}  {}",
                case.name,
                face,
                sdp.size,
                fb.upper,
                r.upper,
                r.value,
                mu,
                sdp.hi / sdp.lo.max(margin) - 1.0,
                (r.upper - mu) / mu,
                1.0 - r.value / mu,
                r.evals,
                if converged { "yes" } else { "no" },
                sdp.solves,
                sdp.seconds,
                relax_s,
                if sdp.lo < margin {
                    "unstable (μ* < margin)".to_string()
                } else if fractional {
                    format!("{:?}", sdp.alpha.iter().map(|a| (a * 1e3).round() / 1e3).collect::<Vec<_>>())
                } else {
                    "binary".to_string()
                }
            ));
        }
        // The relaxation bounds every feasible subset.
        assert!(
            face_max >= best,
            "{}: max μ* {face_max:e} < best λ_fix {best:e}",
            case.name
        );
        assert!(report.upper >= best);
        // (d) binary α: the SDP's λ is the code's λ_fix.
        let mut subsets = vec![all.best.curves.clone()];
        for fb in &report.faces {
            if let Some(c) = fb.curve {
                subsets.push(vec![c]);
            }
        }
        subsets.sort();
        subsets.dedup();
        for s in &subsets {
            let lf = p.lambda_fix(s).expect("lambda_fix");
            if lf <= 0.0 {
                continue;
            }
            let sdp_l = sdp_subset(&d, &p, s, lf);
            let dense = {
                let mut a = vec![0.0; p.curve_count()];
                for &c in s {
                    a[c] = 1.0;
                }
                d.mu(&a)
            };
            println!(
                "{} {s:?}: lambda_fix {lf:.9e}  SDP {sdp_l:.9e}  dense {dense:.9e}  rel {:.1e}",
                case.name,
                (sdp_l - lf) / lf
            );
        }
        println!(
            "{}: certify {certify_s:.2} s, bound {:e}, best λ_fix {best:e} {:?}",
            case.name, report.upper, all.best.curves
        );
    }
    println!(
        "{:<7} {:>4} {:>3} {:>12} {:>12} {:>12} {:>12} {:>7} {:>9} {:>9} {:>5} {:>4} {:>4} {:>6} {:>6}  SDP α*",
        "network",
        "face",
        "n",
        "certify",
        "relax upper",
        "relax value",
        "SDP μ*",
        "δ",
        "up/μ*−1",
        "1−val/μ*",
        "evals",
        "conv",
        "SDPs",
        "SDP s",
        "code s"
    );
    for row in table {
        println!("{row}");
    }
}

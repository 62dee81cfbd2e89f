//! Scoring the candidates of one greedy iteration, with pruning by Rayleigh–Ritz bounds.
//!
//! The score of candidate `c` is `λ_fix(A \ {c} | A)`, the smallest eigenvalue of
//! `H' = H_{A∖c}` at `A`'s equilibrium. Computing it takes a sparse factorization; a cheap
//! upper bound often shows that `c` cannot win:
//!
//! **Bound.** Let `V` hold `A`'s `k` lowest modes and `W` be `V` with the rows of `c`'s loose
//! vertices zeroed. By Courant–Fischer, the smallest Ritz value of `H'` on `span(W)` is at
//! least `λ_min(H')`. Because `H'` equals `H_A − H_c` on the kept coordinates (`H_c`: the
//! Hessian of `c`'s own terms), `WᵀH'W = VᵀH_AV − Σ_{v∈L} V_vᵀ(H_AV)_v − Σ_{v∈c∖L} V_vᵀ(H_cV)_v`
//! and `WᵀW = VᵀV − Σ_{v∈L} V_vᵀV_v`, where `L` are `c`'s loose vertices: with `H_AV` computed
//! once per iteration, each bound costs `O(|c|·k²)` — nothing next to a factorization.
//!
//! **Pruning.** Candidates are evaluated in a fixed order — by decreasing bound, ties by id —
//! in fixed batches of [`PruneParams::batch`]. After each batch the best score so far is
//! known; a later candidate whose bound (plus a round-off margin) lies below
//! `best·(1 − tie)` can neither win nor tie, so it is skipped. Which candidates are skipped
//! depends only on the scores, never on thread timing, and the choice is the same as without
//! pruning (tested).

use super::{Evaluation, Scorer, Work};
use crate::rod::ActiveSet;
use crate::rod::model::{LocalHessians, Terms};
use crate::solve::eigen::Spectrum;
use crate::solve::factor::SOLVE_GROUP;
use crate::solve::{Cholesky, Reuse, Schedule, SymbolicFactor};
use crate::sparse::Pattern;
use crate::stability::StabilityError;
use faer::{Mat, MatRef};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// Pruning parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PruneParams {
    /// Skip candidates whose bound shows they cannot win.
    pub enabled: bool,
    /// Candidates evaluated per batch (fixed, so the result does not depend on threads).
    pub batch: usize,
    /// Once a score is known, factor each further candidate's `H − σI` with `σ` the best
    /// score minus the tie tolerance: a failed factorization proves the candidate cannot win
    /// (Sylvester's inertia) without any eigen solve, and a successful one is the
    /// shift-and-invert operator of its eigen solve, close to `λ` (faster convergence).
    /// A best score inside the zero-mode band (round-off) is tested at the band's lower edge
    /// instead, and a candidate that passes there is scored about zero.
    pub inertia: bool,
    /// The first candidate of an iteration (nothing known yet to shift about) is scored
    /// about `first_shift` × its refined bound when the Cholesky of `H − σI` there succeeds
    /// (proof that its score lies above). A failed factorization proves the score below that
    /// shift, which becomes the candidate's bound: it stays in the best-first search (after
    /// two failed guesses it is scored about zero). When the preconditioner's shift (0.9 ×
    /// the last winner's score, see [`crate::simplify::Warm::lambda`]) lies between that
    /// guess and 0.95 × the bound, the first guess is that shift instead: nearer the score,
    /// and its factorization copies from the preconditioner's. 0 always scores it about zero.
    /// Shift-and-invert near `λ` converges in fewer solves (roof: 38 → about 15 for these
    /// scores; scores sit at 0.84–1 of their refined bound for three quarters of them), but
    /// only a score about zero passes its factorization on as the next relaxation's first
    /// Newton matrix when the candidate wins.
    pub first_shift: f64,
    /// The inertia tests about one shift copy the supernodes a candidate cannot reach from a
    /// factorization of `H_A − σI` when that saves work ([`crate::solve::Reuse`]; the
    /// factors, hence the results, are the same either way).
    #[serde(default = "default_true")]
    pub reuse: bool,
    /// While each iteration's first candidate is scored (one core mostly idle), refine the
    /// bounds of the next candidates its score is unlikely to prune, as many as its cost
    /// allows; off, only the usual batch (which candidates are refined never depends on
    /// timing either way).
    #[serde(default = "default_true")]
    pub ahead: bool,
    /// Hand each candidate's best test vector to the next iteration ([`Carried`]): its bound
    /// there extends the plain Rayleigh–Ritz bound with it (one product with `H_A`, no
    /// solve), and its refinement starts from it.
    #[serde(default = "default_true")]
    pub carry: bool,
    /// The carried vectors are used in an iteration when the previous one settled at least
    /// this many candidates by an inertia test (which a carried vector often spares) or by a
    /// carried vector's bound; 0 uses them always. Where the plain and refined bounds settle
    /// nearly everything (tower, shells, kagome) the carried vectors' bounds cost more than
    /// they save; where many candidates sit just below the best (roof, hill, tent) they spare
    /// most inertia tests.
    #[serde(default = "default_carry_after")]
    pub carry_after: usize,
}

fn default_carry_after() -> usize {
    2
}

fn default_true() -> bool {
    true
}

impl Default for PruneParams {
    fn default() -> Self {
        PruneParams {
            enabled: true,
            batch: 2,
            inertia: true,
            first_shift: 0.8,
            reuse: true,
            ahead: true,
            carry: true,
            carry_after: default_carry_after(),
        }
    }
}

impl PruneParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), String> {
        if !(0.0..1.0).contains(&self.first_shift) {
            return Err(format!(
                "first shift must lie in [0, 1), got {}",
                self.first_shift
            ));
        }
        Ok(())
    }
}

/// Test vectors handed from one greedy iteration's candidate search to the next, per curve:
/// each the best approximation found of the lowest mode of the structure without that curve
/// (the candidate's eigenvector when it was scored, else its refined bound's Ritz vector).
/// A structure changes little from one iteration to the next, so the vector is a good test
/// vector again: with the plain Ritz vectors it gives a bound that often prunes the candidate
/// without a solve, and each refinement starts where the last one ended (an iterated
/// preconditioned step across iterations). Stored in single precision: a test vector's
/// Rayleigh quotient is exact for whatever vector it is, so rounding it costs only a
/// second-order change in the bound.
pub type Carried = Vec<Option<CarriedVector>>;

/// One carried test vector (see [`Carried`]).
#[derive(Clone, Debug, PartialEq)]
pub struct CarriedVector {
    /// Its Rayleigh quotient in the structure it was found for (the candidate's score or
    /// bound there).
    pub value: f64,
    /// The vector (all coordinates of the network).
    pub vector: Vec<f32>,
}

/// The score of one candidate removal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CandidateScore {
    /// Curve removed.
    pub curve: usize,
    /// `λ_fix(A \ {curve} | A)`; `None` when pruned or when the eigen solve failed.
    pub score: Option<f64>,
    /// Rayleigh–Ritz upper bound on the score (`None` when not computed).
    #[serde(default)]
    pub bound: Option<f64>,
    /// The bound extended by the vector carried over from the previous iteration, when one
    /// was computed (see [`Carried`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extended_bound: Option<f64>,
    /// The refined bound (one preconditioned step), when one was computed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refined_bound: Option<f64>,
    /// True when the bound (or the inertia test, see `below`) showed the candidate cannot win
    /// and no eigen solve was done.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub pruned: bool,
    /// When the inertia test pruned the candidate: the shift `σ` below which one failed
    /// Cholesky factorization of `H − σI` proved its score lies.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub below: Option<f64>,
    /// When the score was computed by shift-and-invert about a shift (the inertia
    /// test's `σ`, see [`PruneParams::inertia`]) rather than about zero: that shift.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shift: Option<f64>,
    /// The failure, if any.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub error: Option<String>,
}

/// An upper bound with its round-off margin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// Smallest Ritz value (`+∞` when the subspace vanishes on `A \ {c}`).
    pub value: f64,
    /// Estimated absolute round-off in `value`.
    pub margin: f64,
}

/// The part of a [`CandidateContext`] that needs only the structure's equilibrium, not its
/// modes: the local Hessians of its terms and `H_A` assembled from them. The greedy computes
/// it beside the structure's spectrum, whose solves leave a core idle.
#[derive(Debug)]
pub struct CandidateTerms {
    locals: LocalHessians,
    h: Vec<f64>,
}

impl CandidateTerms {
    /// The terms of structure `active` at displacements `u`.
    pub fn compute(scorer: &Scorer<'_>, active: &ActiveSet, u: &[f64]) -> Self {
        let model = scorer.analyzer().model();
        let locals = model.local_hessians(u, Terms::Of(active));
        let mut h = Vec::new();
        model.hessian_from_locals(&locals, active, &mut h);
        CandidateTerms { locals, h }
    }
}

/// Everything shared by the candidates of one iteration.
#[derive(Debug)]
pub struct CandidateContext<'s, 'a> {
    scorer: &'s Scorer<'a>,
    active: ActiveSet,
    locals: LocalHessians,
    modes: Mat<f64>,
    hv: Mat<f64>,
    vtv: Mat<f64>,
    vthv: Mat<f64>,
    hv_abs: Vec<f64>,
    /// `H_A` (upper triangle in the model's pattern): every candidate's Hessian is `H_A` minus
    /// its curve's terms.
    h: Vec<f64>,
    /// Row sums of `|H_A|`, for round-off margins: `|y|ᵀ|H_A||y| ≤ Σᵢ rᵢ yᵢ²`.
    row_abs: Vec<f64>,
    factorizations: AtomicUsize,
    solves: AtomicUsize,
    /// A factorization of `H_A − σI`, for refined bounds.
    preconditioner: Option<Arc<Cholesky>>,
    /// The symbolic analysis for `A`'s matrices (and its candidates').
    symbolic: Arc<SymbolicFactor>,
    /// Solves `A`'s spectrum took (0 when unknown): the first candidate's eigen solve, about
    /// a shift near its score too, costs about as many.
    spectrum_solves: usize,
    /// Each curve's plain Rayleigh–Ritz bound, computed once (the plain bound, its refinement
    /// and the warm start all start from it).
    ritz: Vec<OnceLock<RitzBound>>,
    /// Whether each vertex is held by a curve of `A`.
    held: Vec<bool>,
    /// Per curve: a test vector handed over from the previous iteration (its best known
    /// approximation then of the lowest mode without the curve; see [`Carried`]).
    carried: Carried,
    /// Each curve's extended bound, computed once.
    extended: Vec<OnceLock<Option<Extended>>>,
    /// Per curve: the best test vector found in this iteration, for the next one.
    carry_out: Vec<std::sync::Mutex<Option<CarriedVector>>>,
}

impl<'s, 'a> CandidateContext<'s, 'a> {
    /// Prepares the iteration of structure `active` at displacements `u`, with its low
    /// `modes` (columns). `symbolic`: the analysis for `active`'s matrices when the caller has
    /// it ([`crate::simplify::Evaluation::symbolic`]), else computed
    /// ([`crate::stability::Analyzer::symbolic_for`], the same analysis).
    pub fn new(
        scorer: &'s Scorer<'a>,
        active: &ActiveSet,
        u: &[f64],
        modes: MatRef<'_, f64>,
        symbolic: Option<Arc<SymbolicFactor>>,
    ) -> Self {
        let terms = CandidateTerms::compute(scorer, active, u);
        Self::with_terms(scorer, active, terms, modes, symbolic)
    }

    /// [`Self::new`] from the structure's terms at its equilibrium, computed beforehand
    /// (beside its spectrum: [`Scorer::evaluate_warm_beside`]).
    pub fn with_terms(
        scorer: &'s Scorer<'a>,
        active: &ActiveSet,
        terms: CandidateTerms,
        modes: MatRef<'_, f64>,
        symbolic: Option<Arc<SymbolicFactor>>,
    ) -> Self {
        let symbolic = symbolic.unwrap_or_else(|| scorer.analyzer().symbolic_for(active));
        let model = scorer.analyzer().model();
        let CandidateTerms { locals, h } = terms;
        let (n, k) = (modes.nrows(), modes.ncols());
        let mut hv = Mat::<f64>::zeros(n, k);
        let mut col = vec![0.0; n];
        let mut x = vec![0.0; n];
        for j in 0..k {
            for i in 0..n {
                x[i] = modes[(i, j)];
            }
            model.pattern().sym_matvec(&h, &x, &mut col);
            for i in 0..n {
                hv[(i, j)] = col[i];
            }
        }
        let vtv = modes.transpose() * modes;
        let vthv = modes.transpose() * hv.as_ref();
        let hv_abs = (0..n)
            .map(|i| (0..k).map(|j| hv[(i, j)].abs()).fold(0.0, f64::max))
            .collect();
        let h_abs: Vec<f64> = h.iter().map(|v| v.abs()).collect();
        let mut row_abs = vec![0.0; n];
        model
            .pattern()
            .sym_matvec(&h_abs, &vec![1.0; n], &mut row_abs);
        CandidateContext {
            scorer,
            active: active.clone(),
            locals,
            modes: modes.to_owned(),
            hv,
            vtv,
            vthv,
            hv_abs,
            h,
            row_abs,
            factorizations: AtomicUsize::new(0),
            solves: AtomicUsize::new(0),
            preconditioner: None,
            symbolic,
            spectrum_solves: 0,
            ritz: (0..scorer.analyzer().network().rods.len())
                .map(|_| OnceLock::new())
                .collect(),
            held: model.vertex_mask(active),
            carried: Vec::new(),
            extended: (0..scorer.analyzer().network().rods.len())
                .map(|_| OnceLock::new())
                .collect(),
            carry_out: (0..scorer.analyzer().network().rods.len())
                .map(|_| std::sync::Mutex::new(None))
                .collect(),
        }
    }

    /// The context of structure `active` evaluated as `eval`: its equilibrium, low modes and
    /// analysis, and its spectrum's factorization as the refined bounds' preconditioner.
    pub fn of_evaluation(scorer: &'s Scorer<'a>, active: &ActiveSet, eval: &Evaluation) -> Self {
        let terms = CandidateTerms::compute(scorer, active, &eval.displacement);
        Self::of_evaluation_with(scorer, active, eval, terms)
    }

    /// [`Self::of_evaluation`] with the structure's terms at `eval`'s equilibrium computed
    /// beforehand ([`CandidateTerms::compute`]).
    pub fn of_evaluation_with(
        scorer: &'s Scorer<'a>,
        active: &ActiveSet,
        eval: &Evaluation,
        terms: CandidateTerms,
    ) -> Self {
        CandidateContext::with_terms(
            scorer,
            active,
            terms,
            eval.spectrum.vectors.as_ref(),
            Some(eval.symbolic.clone()),
        )
        .with_preconditioner(eval.factor.clone())
        .with_spectrum_solves(eval.spectrum.solves)
    }

    /// Test vectors handed over from the previous iteration ([`Self::take_carried`] of its
    /// context): they extend the plain bounds ([`Self::extended_bound`]).
    pub fn with_carried(mut self, carried: Carried) -> Self {
        self.carried = carried;
        self
    }

    /// The best test vector found per curve in this iteration: a candidate's eigenvector
    /// when it was scored, else the minimising Ritz vector of its refined or extended bound,
    /// else the vector carried into this iteration.
    pub fn take_carried(&mut self) -> Carried {
        let mut old = std::mem::take(&mut self.carried);
        self.carry_out
            .iter()
            .enumerate()
            .map(|(c, m)| {
                let new = m.lock().map(|mut g| g.take()).unwrap_or(None);
                new.or_else(|| old.get_mut(c).and_then(Option::take))
            })
            .collect()
    }

    /// Records `v` as candidate `c`'s best test vector so far.
    fn offer(&self, c: usize, value: f64, v: MatRef<'_, f64>) {
        let vector = v.col(0).iter().map(|&x| x as f32).collect();
        if let Ok(mut g) = self.carry_out[c].lock() {
            *g = Some(CarriedVector { value, vector });
        }
    }

    /// Whether candidate `c` has a vector carried over from the previous iteration.
    pub fn has_carried(&self, c: usize) -> bool {
        self.carried.get(c).is_some_and(Option::is_some)
    }

    /// Records how many solves `A`'s spectrum took: the first candidate's eigen solve costs
    /// about [`FIRST_SCORE_COST`] times as many, which sets how many bounds are refined beside
    /// it.
    pub fn with_spectrum_solves(mut self, solves: usize) -> Self {
        self.spectrum_solves = solves;
        self
    }

    /// How many candidates' bounds to refine while the first candidate is scored: its eigen
    /// solve takes about [`FIRST_SCORE_COST`] times the solves of `A`'s spectrum, and refining
    /// a candidate's bound costs about two (half a call of four columns and a product with
    /// `H_A`; the factorization takes about four more). Roof: 16 solves per spectrum, 8
    /// candidates; arched shell 9, 3; shell 8, 2; tower 6, 1.
    fn first_ahead(&self) -> usize {
        ((self.spectrum_solves as f64 * FIRST_SCORE_COST) as usize / 2)
            .saturating_sub(4)
            .min(FIRST_AHEAD)
    }

    /// Uses `factor`, a factorization of `H_A − σI` (the one `A`'s spectrum was computed
    /// with), to refine bounds ([`Self::refined_bounds`]).
    pub fn with_preconditioner(mut self, factor: Option<Arc<Cholesky>>) -> Self {
        self.preconditioner = factor;
        self
    }

    /// The Rayleigh–Ritz bound of candidate `c` with its Ritz coefficients and what the
    /// refined bound reuses.
    fn ritz_bound(&self, c: usize) -> &RitzBound {
        self.ritz[c].get_or_init(|| self.compute_ritz_bound(c))
    }

    /// [`Self::ritz_bound`], computed.
    fn compute_ritz_bound(&self, c: usize) -> RitzBound {
        let _timer = crate::profile::Timer::new(crate::profile::Phase::Bound);
        let model = self.scorer.analyzer().model();
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
        let model = self.scorer.analyzer().model();
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

    /// Candidate `c`'s carried vector on `A \ {c}`'s coordinates (one column; `None` without
    /// one, or if it vanishes there): zero on the vertices no curve of `A` holds (it may
    /// still have values on the last winner's) and on `c`'s loose ones.
    fn carried_y(&self, c: usize) -> Option<Mat<f64>> {
        let carried = &self.carried.get(c)?.as_ref()?.vector;
        let mut y = Mat::<f64>::from_fn(carried.len(), 1, |i, _| {
            if self.held[i / 3] {
                carried[i] as f64
            } else {
                0.0
            }
        });
        zero_rows(&mut y, &self.ritz_bound(c).loose_rows);
        let nonzero = y.col(0).iter().any(|v| *v != 0.0);
        nonzero.then_some(y)
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
        let model = self.scorer.analyzer().model();
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

    /// Warm start for candidate `c`: its two lowest Ritz vectors (loose rows zeroed).
    fn ritz_vectors(&self, c: usize) -> Option<Mat<f64>> {
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
    /// (reading `L`), so four columns in one call cost little more than one (roof: 1.1 ms
    /// against 0.65 ms), and one call for two candidates halves the cost of the step. The
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
    fn candidate_matvec(&self, c: usize, m: MatRef<'_, f64>) -> Mat<f64> {
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
        let p = self.scorer.analyzer().model().pattern();
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
        let model = self.scorer.analyzer().model();
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
    fn refine_start(&self, c: usize) -> RefineStep {
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

    /// Candidate `c`'s exact score, warm-started from the iteration's modes, with the
    /// factorization it used.
    pub fn score(&self, c: usize) -> Result<(Spectrum, Cholesky), StabilityError> {
        let warm = self.ritz_vectors(c);
        let warm = warm.as_ref().map_or(self.modes.as_ref(), |w| w.as_ref());
        let r = self.scorer.lambda_fixed(
            &self.locals,
            &self.active.without(c),
            Some(warm),
            &self.symbolic,
        );
        if let Ok((sp, _)) = &r {
            self.factorizations
                .fetch_add(sp.factorizations, Ordering::Relaxed);
            self.solves.fetch_add(sp.solves, Ordering::Relaxed);
            if sp.vectors.ncols() > 0 {
                self.offer(c, sp.lambda(), sp.vectors.as_ref());
            }
        }
        r
    }

    /// [`Self::score`] about the shift `sigma`: `Ok(None)` when one factorization proves
    /// the score below `sigma`. The factorization returned is of `H − σI`. With `reference`,
    /// a factorization of `H_A − σI` ([`Self::reference`]), that factorization copies the
    /// supernodes `c`'s removal cannot reach (the same factor, less work).
    pub fn score_above(
        &self,
        c: usize,
        sigma: f64,
        reference: Option<&Cholesky>,
    ) -> Result<Option<(Spectrum, Cholesky)>, StabilityError> {
        let warm = || Some(self.ritz_vectors(c).unwrap_or_else(|| self.modes.clone()));
        let changed = reference.map(|_| self.curve_coordinates(c));
        let reuse = reference.zip(changed.as_deref()).map(|(f, changed)| Reuse {
            reference: f,
            changed,
        });
        let h = self.candidate_hessian(c);
        let r = self.scorer.lambda_fixed_above(
            &h,
            &self.active.without(c),
            warm,
            sigma,
            &self.symbolic,
            reuse,
        );
        match &r {
            Ok(Some((sp, _))) => {
                self.factorizations
                    .fetch_add(sp.factorizations, Ordering::Relaxed);
                self.solves.fetch_add(sp.solves, Ordering::Relaxed);
                if sp.vectors.ncols() > 0 {
                    self.offer(c, sp.lambda(), sp.vectors.as_ref());
                }
            }
            Ok(None) => {
                self.factorizations.fetch_add(1, Ordering::Relaxed);
            }
            Err(_) => {}
        }
        r
    }

    /// Whether one factorization proves candidate `c`'s score below `sigma` (Sylvester's
    /// inertia: the Cholesky of `H_{A∖c} − σI` fails), without an eigen solve when it does
    /// not. `reference` as in [`Self::score_above`].
    pub fn proves_below(
        &self,
        c: usize,
        sigma: f64,
        reference: Option<&Cholesky>,
    ) -> Result<bool, StabilityError> {
        let h = self.candidate_hessian(c);
        let model = self.scorer.analyzer().model();
        self.factorizations.fetch_add(1, Ordering::Relaxed);
        let changed = reference.map(|_| self.curve_coordinates(c));
        let reuse = reference.zip(changed.as_deref()).map(|(f, changed)| Reuse {
            reference: f,
            changed,
        });
        let factor = Cholesky::factorize(&self.symbolic, model.pattern(), &h, -sigma, reuse);
        // A matrix with NaN or infinity fails too: that is an error, not a proof (checked only
        // then, as the eigen solver does).
        if factor.is_err() && h.iter().any(|v| !v.is_finite()) {
            return Err(StabilityError::Eigen(
                crate::solve::eigen::EigenError::NoShift(f64::NAN),
            ));
        }
        Ok(factor.is_err())
    }

    /// `H_{A∖c}`: `H_A` with the entries of `c`'s terms summed again (the same values as a
    /// whole assembly).
    fn candidate_hessian(&self, c: usize) -> Vec<f64> {
        let mut h = Vec::new();
        self.scorer.analyzer().model().hessian_without(
            &self.locals,
            &self.active,
            &self.h,
            c,
            &mut h,
        );
        h
    }

    /// The coordinates of curve `c`'s vertices: `H_{A∖c}` differs from `H_A` only in entries
    /// whose row and column both lie among them (its own terms, its loose vertices).
    fn curve_coordinates(&self, c: usize) -> Vec<usize> {
        let model = self.scorer.analyzer().model();
        model
            .curve_vertices(c)
            .iter()
            .flat_map(|&v| (0..3).map(move |a| 3 * v as usize + a))
            .collect()
    }

    /// The share of a factorization's work that a factorization reusing one of `H_A − σI`
    /// still does for candidate `c` ([`Reuse`]).
    fn changed_share(&self, c: usize) -> f64 {
        self.symbolic.changed_work_share(&self.curve_coordinates(c))
    }

    /// A factorization of `H_A − σI` for the candidates' factorizations about `σ` to copy
    /// from; `None` when `H_A − σI` is not positive definite.
    pub fn reference(&self, sigma: f64) -> Option<Cholesky> {
        let model = self.scorer.analyzer().model();
        self.factorizations.fetch_add(1, Ordering::Relaxed);
        Cholesky::factorize(&self.symbolic, model.pattern(), &self.h, -sigma, None).ok()
    }

    /// Factorizations and solves spent on scores so far.
    pub fn work(&self) -> Work {
        Work {
            factorizations: self.factorizations.load(Ordering::Relaxed),
            solves: self.solves.load(Ordering::Relaxed),
        }
    }

    /// Scores `candidates`, skipping those that cannot win when pruning is enabled.
    /// The scores are in the order of `candidates`; the factorizations of the candidates
    /// scoring within `tie` of the best are returned too (the winner's serves the next
    /// relaxation).
    pub fn score_all(
        &self,
        candidates: &[usize],
        prune: &PruneParams,
        tie: f64,
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> (Vec<CandidateScore>, Vec<(usize, Cholesky)>) {
        let mut search = Search {
            ctx: self,
            candidates,
            tie,
            batch: prune.batch.max(1),
            inertia: prune.inertia,
            first_shift: prune.first_shift,
            reuse: prune.reuse,
            ahead: prune.ahead,
            cancelled,
            out: candidates
                .iter()
                .map(|&c| CandidateScore {
                    curve: c,
                    score: None,
                    bound: None,
                    extended_bound: None,
                    refined_bound: None,
                    pruned: false,
                    below: None,
                    shift: None,
                    error: None,
                })
                .collect(),
            best: f64::NEG_INFINITY,
            kept: Vec::new(),
            plain: Vec::new(),
            extended: vec![None; candidates.len()],
            refined: vec![None; candidates.len()],
            alive: (0..candidates.len()).collect(),
            guesses: vec![0; candidates.len()],
            best_threshold: f64::INFINITY,
            reference: None,
            shares: vec![None; candidates.len()],
        };
        if !prune.enabled {
            let all: Vec<usize> = (0..candidates.len()).collect();
            let results = all
                .par_iter()
                .map(|&i| search.evaluate(candidates[i], None, None, false))
                .collect();
            search.record(&all, results);
            return search.finish();
        }
        search.plain = candidates.par_iter().map(|&c| self.bound(c)).collect();
        for (o, b) in search.out.iter_mut().zip(&search.plain) {
            o.bound = Some(b.value);
        }
        while search.step() {}
        search.finish()
    }
}

/// The state of [`CandidateContext::score_all`]'s best-first search.
///
/// Best first: candidates are taken by decreasing bound (the refined bound once known, else
/// the extended one, else the plain one; ties by curve id) and skipped once their bound falls
/// below the best score. A candidate with a carried vector gets its extended bound before it
/// is considered for refinement (the extended bound, no solve, often drops it out of the top
/// for good), and is evaluated only after its refined bound, so the first exact score goes
/// to the most promising candidate by the tightest bound and later candidates are mostly
/// settled by their bound or the inertia test. Every decision depends only on the values,
/// never on thread timing.
struct Search<'c, 's, 'a> {
    ctx: &'c CandidateContext<'s, 'a>,
    candidates: &'c [usize],
    tie: f64,
    batch: usize,
    inertia: bool,
    first_shift: f64,
    reuse: bool,
    ahead: bool,
    cancelled: &'c (dyn Fn() -> bool + Sync),
    out: Vec<CandidateScore>,
    best: f64,
    /// Candidates scored about zero within `tie` of the best, with their factorizations.
    kept: Vec<(usize, f64, Cholesky)>,
    plain: Vec<Bound>,
    /// Extended bounds computed so far (candidates with a carried vector).
    extended: Vec<Option<Bound>>,
    /// Refined bounds computed so far (the plain bound when there is no preconditioner).
    refined: Vec<Option<Bound>>,
    /// Candidates (indices into `candidates`) neither evaluated nor pruned.
    alive: Vec<usize>,
    /// Failed first-shift guesses per candidate.
    guesses: Vec<u8>,
    /// The zero-mode threshold of the best score's spectrum.
    best_threshold: f64,
    /// The inertia tests' shift `σ` and a factorization of `H_A − σI` they copy from (`None`
    /// when not worth it or not positive definite).
    reference: Option<(f64, Option<Cholesky>)>,
    /// Per candidate: the share of a factorization's work left when copying from the
    /// reference.
    shares: Vec<Option<f64>>,
}

/// What evaluating one candidate gave.
enum Outcome {
    /// Its score, about `shift` (`None`: about zero, with the factorization of `H − σI`,
    /// `σ ≤ 0`: a Newton matrix for the next relaxation).
    Scored {
        score: f64,
        shift: Option<f64>,
        factor: Option<Cholesky>,
        /// The spectrum's zero-mode threshold `C·ε·‖H‖₁`.
        threshold: f64,
    },
    /// The inertia test at the best score's floor proved the score below it: pruned.
    Below(f64),
    /// The first-shift guess failed: the score lies below it (a new upper bound; the
    /// candidate stays in the search).
    BelowGuess(f64),
    /// The eigen solve failed (or the search was cancelled).
    Failed(String),
}

/// A negative best score serves as the inertia test's floor only beyond this many times its
/// spectrum's zero-mode threshold.
const NEGATIVE_FLOOR: f64 = 10.0;

/// The inertia tests about one shift copy from a factorization of `H_A − σI` when that saves
/// at least this many factorizations' work (it costs one).
const REUSE_MIN_SAVING: f64 = 5.0;

/// The preconditioner's shift serves as a candidate's first guess only below this share of
/// its bound (closer, the guess would fail too often: refined bounds lie a few percent above
/// the scores).
const PRECONDITIONER_GUESS: f64 = 0.95;

/// Failed first-shift guesses after which a candidate is scored about zero.
const MAX_GUESSES: u8 = 2;

impl Search<'_, '_, '_> {
    /// The scores and the kept factorizations.
    fn finish(self) -> (Vec<CandidateScore>, Vec<(usize, Cholesky)>) {
        let factors = self.kept.into_iter().map(|(c, _, f)| (c, f)).collect();
        (self.out, factors)
    }

    /// Evaluates candidate `c`: about `sigma` (the inertia test) when given, else about
    /// `guess` when given and below the score, else about zero. With `test_only`, `sigma`
    /// only decides: a candidate it does not prune is scored about zero.
    fn evaluate(
        &self,
        c: usize,
        sigma: Option<f64>,
        guess: Option<f64>,
        test_only: bool,
    ) -> Outcome {
        if (self.cancelled)() {
            return Outcome::Failed("cancelled".into());
        }
        if let Some(shift) = sigma.or(guess) {
            // A factorization of `H_A − σI` about the same shift to copy from: the inertia
            // tests' reference, or the preconditioner for a first guess at its shift.
            let reference = match (&self.reference, sigma) {
                (Some((s, Some(f))), Some(sigma)) if s.to_bits() == sigma.to_bits() => Some(f),
                (_, Some(_)) => None,
                (_, None) => self
                    .ctx
                    .preconditioner
                    .as_deref()
                    .filter(|f| (-f.shift).to_bits() == shift.to_bits()),
            };
            if test_only && sigma.is_some() {
                return match self.ctx.proves_below(c, shift, reference) {
                    Ok(true) => Outcome::Below(shift),
                    Ok(false) => self.evaluate(c, None, None, false),
                    Err(e) => Outcome::Failed(e.to_string()),
                };
            }
            return match self.ctx.score_above(c, shift, reference) {
                Ok(Some((sp, _))) => Outcome::Scored {
                    score: sp.lambda(),
                    shift: Some(shift),
                    factor: None,
                    threshold: sp.zero_threshold,
                },
                Ok(None) if sigma.is_some() => Outcome::Below(shift),
                Ok(None) => Outcome::BelowGuess(shift),
                Err(e) => Outcome::Failed(e.to_string()),
            };
        }
        match self.ctx.score(c) {
            Ok((sp, f)) => Outcome::Scored {
                score: sp.lambda(),
                shift: None,
                factor: Some(f),
                threshold: sp.zero_threshold,
            },
            Err(e) => Outcome::Failed(e.to_string()),
        }
    }

    /// Records one evaluated group; the candidates whose guess failed stay in the search.
    fn record(&mut self, group: &[usize], results: Vec<Outcome>) {
        let mut settled = Vec::with_capacity(group.len());
        for (&i, outcome) in group.iter().zip(results) {
            let o = &mut self.out[i];
            match outcome {
                Outcome::Scored {
                    score,
                    shift,
                    factor,
                    threshold,
                } => {
                    o.score = Some(score);
                    o.shift = shift;
                    o.below = None;
                    if score.is_finite() {
                        if score > self.best {
                            self.best_threshold = threshold;
                        }
                        self.best = self.best.max(score);
                        if let Some(f) = factor {
                            self.kept.push((self.candidates[i], score, f));
                        }
                    }
                }
                Outcome::Below(sigma) => {
                    o.pruned = true;
                    o.below = Some(sigma);
                }
                Outcome::BelowGuess(g) => {
                    // Proved: λ < g. Recorded as `below` if that is what prunes it.
                    o.below = Some(g);
                    self.guesses[i] += 1;
                    self.refined[i] = Some(Bound {
                        value: g,
                        margin: 0.0,
                    });
                    continue;
                }
                Outcome::Failed(e) => o.error = Some(e),
            }
            settled.push(i);
        }
        self.alive.retain(|i| !settled.contains(i));
        let floor = self.floor();
        self.kept.retain(|k| k.1 >= floor);
    }

    /// Factors `H_A − σI` for the inertia tests about `σ` to copy from, when the alive
    /// candidates' factorizations would save more than it costs: the saving is estimated from
    /// the share of each one's factorization its curve reaches ([`Reuse`]).
    /// A pure function of the values, like every decision of the search.
    fn prepare_reference(&mut self, sigma: f64) {
        if self
            .reference
            .as_ref()
            .is_some_and(|(s, _)| s.to_bits() == sigma.to_bits())
        {
            return;
        }
        let mut saving = 0.0;
        for &i in &self.alive {
            let share =
                *self.shares[i].get_or_insert_with(|| self.ctx.changed_share(self.candidates[i]));
            saving += 1.0 - share;
        }
        let factor = (self.reuse && saving >= REUSE_MIN_SAVING)
            .then(|| self.ctx.reference(sigma))
            .flatten();
        self.reference = Some((sigma, factor));
    }

    fn floor(&self) -> f64 {
        self.best - self.tie * self.best.abs()
    }

    fn key(&self, i: usize) -> Bound {
        self.refined[i]
            .or(self.extended[i])
            .unwrap_or(self.plain[i])
    }

    fn refine(&mut self, group: &[usize]) {
        let cs: Vec<usize> = group.iter().map(|&i| self.candidates[i]).collect();
        let values = self.ctx.refined_bounds(&cs);
        self.store_refined(group, values);
    }

    fn store_refined(&mut self, group: &[usize], values: Vec<Option<Bound>>) {
        for (&i, r) in group.iter().zip(values) {
            // `None` only without a preconditioner: keep the plain bound.
            self.refined[i] = Some(r.unwrap_or(self.plain[i]));
            self.out[i].refined_bound = r.map(|r| r.value);
        }
    }

    /// One step: prune, then refine the best candidates' bounds or evaluate the best ones.
    /// False when every candidate is settled.
    fn step(&mut self) -> bool {
        if (self.cancelled)() {
            for &i in &self.alive {
                self.out[i].error = Some("cancelled".into());
            }
            self.alive.clear();
            return false;
        }
        let floor = self.floor();
        let mut alive = std::mem::take(&mut self.alive);
        alive.retain(|&i| {
            let b = self.key(i);
            let prune = b.value + b.margin < floor;
            if prune {
                self.out[i].pruned = true;
            }
            !prune
        });
        if alive.is_empty() {
            return false;
        }
        alive.sort_by(|&a, &b| {
            self.key(b)
                .value
                .total_cmp(&self.key(a).value)
                .then(self.candidates[a].cmp(&self.candidates[b]))
        });
        self.alive = alive;
        let refinable = self.ctx.preconditioner.is_some();
        let top = self.batch.min(self.alive.len());
        if refinable && self.alive[..top].iter().any(|&i| self.refined[i].is_none()) {
            let group: Vec<usize> = self
                .alive
                .iter()
                .copied()
                .take(REFINE_AHEAD * self.batch)
                .filter(|&i| self.refined[i].is_none())
                .collect();
            // The carried vectors' bounds first: a share of a pass over `H_A` each, no solve;
            // the next step re-sorts, and refines those still on top.
            let extend: Vec<usize> = group
                .iter()
                .copied()
                .filter(|&i| self.extended[i].is_none() && self.ctx.has_carried(self.candidates[i]))
                .collect();
            if !extend.is_empty() {
                let cs: Vec<usize> = extend.iter().map(|&i| self.candidates[i]).collect();
                let values = self.ctx.extended_bounds(&cs);
                for (&i, b) in extend.iter().zip(values) {
                    self.extended[i] = Some(b);
                    self.out[i].extended_bound = Some(b.value);
                }
                return true;
            }
            self.refine(&group);
            return true;
        }
        // The first score (about zero) alone: it sets the best at once. Meanwhile the other
        // thread refines the bounds of the next candidates (pure values: the decisions above
        // do not depend on when they were computed).
        let take = if self.best.is_finite() { top } else { 1 };
        let group: Vec<usize> = self.alive[..take].to_vec();
        // The inertia test needs a shift clear of the zero-mode band (round-off): the floor
        // when positive, or negative beyond ten times the best score's zero-mode threshold
        // (a structure every removal makes unstable: the bunny's last thirty iterations).
        // A floor inside the band tests at its lower edge instead: a failed factorization
        // still proves the score below the floor, and most candidates there score far below
        // it (the bunny's: −1e-5 against a best of −1e-8), where an eigen solve about zero
        // took 47 solves each.
        // Such a test only decides: a candidate it does not prune is scored about zero, where
        // scores inside the band were computed before too (no first guess about a positive
        // shift: those fail for the negative scores here), and the winner's factorization
        // serves the next relaxation. Pruned candidates hand no eigenvector to the next
        // iteration's search, whose warm starts, hence last bits, change (bunny: the same
        // removals; `λ_eq` of the near-mechanisms after iteration 44 within 5e-4 relative,
        // the last, three curves at 8e-12, within 4%).
        let edge = -NEGATIVE_FLOOR * self.best_threshold;
        let (sigma, test_only) = if !(self.inertia && floor.is_finite()) {
            (None, false)
        } else if floor > 0.0 || floor < edge {
            (Some(floor), false)
        } else {
            (edge.is_finite().then_some(edge), true)
        };
        if let Some(sigma) = sigma {
            self.prepare_reference(sigma);
        }
        let ctx = self.ctx;
        let candidates = self.candidates;
        let first = self.first_shift;
        // The first guess: `first_shift` × the bound, or the preconditioner's shift when it
        // lies between that and `PRECONDITIONER_GUESS` × the bound (nearer the score, and the
        // preconditioner, a factorization of `H_A − σI`, is a reference to copy from).
        let pre_shift = self
            .ctx
            .preconditioner
            .as_ref()
            .map(|f| -f.shift)
            .filter(|s| s.is_finite() && *s > 0.0);
        let guess = |i: usize| {
            let r = self.key(i).value;
            if !(first > 0.0 && self.guesses[i] < MAX_GUESSES && r.is_finite() && r > 0.0) {
                return None;
            }
            let g = first * r;
            Some(match pre_shift {
                Some(s) if self.guesses[i] == 0 && s > g && s <= PRECONDITIONER_GUESS * r => s,
                _ => g,
            })
        };
        // While the first candidate is scored, the other thread refines the bounds of the next
        // ones its score is unlikely to prune: those whose plain bound lies above the shift it
        // is scored about (its score lies above that shift when the factorization there
        // succeeds) and above `AHEAD_SHARE` of its bound, as many as the score's expected
        // cost allows ([`CandidateContext::first_ahead`]). Pure values decide which, so the
        // search is the same on any number of threads.
        let ahead: Vec<usize> = if !self.best.is_finite() && refinable {
            let above = group
                .first()
                .filter(|_| self.ahead)
                .and_then(|&i| guess(i).map(|g| g.max(AHEAD_SHARE * self.key(i).value)));
            let limit = match above {
                Some(_) => self.ctx.first_ahead().max(self.batch),
                None => self.batch,
            };
            self.alive[take..]
                .iter()
                .copied()
                .filter(|&i| self.refined[i].is_none())
                .filter(|&i| above.is_none_or(|g| self.plain[i].value + self.plain[i].margin >= g))
                .take(limit)
                .collect()
        } else {
            Vec::new()
        };
        let (results, values): (Vec<Outcome>, Vec<Option<Bound>>) = rayon::join(
            || {
                group
                    .par_iter()
                    .map(|&i| self.evaluate(candidates[i], sigma, guess(i), test_only))
                    .collect()
            },
            || {
                let cs: Vec<usize> = ahead.iter().map(|&i| candidates[i]).collect();
                ctx.refined_bounds(&cs)
            },
        );
        self.store_refined(&ahead, values);
        self.record(&group, results);
        true
    }
}

/// When the next candidates to evaluate lack a refined bound, the refined bounds of this many
/// batches of the best candidates are computed together (one solve call of four columns per
/// two candidates, the calls in parallel).
const REFINE_AHEAD: usize = 2;

/// At most this many candidates' bounds are refined while the first candidate of an
/// iteration is scored (see [`Search::step`]).
const FIRST_AHEAD: usize = 10;

/// A first score's solves per solve of `A`'s spectrum: the score converges its pair to a
/// residual of 1e-8, the spectrum its lowest to 1e-6 ([`crate::simplify::SPECTRUM_TOL`]).
/// When the spectrum converged to 1e-10 it took about as many solves as a first score (roof
/// 26); now it takes 16 (arched shell 15 → 9, shell 15 → 8, tower 8 → 6).
const FIRST_SCORE_COST: f64 = 1.6;

/// Candidates refined while the first one is scored have a plain bound above this share of
/// its bound: scores sit at 0.84–1 of their refined bound, so lower ones are likely pruned by
/// the first score alone.
const AHEAD_SHARE: f64 = 0.95;

/// A plain Rayleigh–Ritz bound and what its refinement reuses.
#[derive(Debug)]
struct RitzBound {
    bound: Bound,
    /// Ritz coefficients (columns, ascending values) in the modes' space.
    coeffs: Mat<f64>,
    /// Coordinates of the candidate's loose vertices.
    loose_rows: Vec<usize>,
    /// `H_c V` on the candidate's vertices (`3·|vertices| × k`).
    hcv: Mat<f64>,
}

/// A refined bound between its two halves (see [`CandidateContext::refined_bounds`]).
enum RefineStep {
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

/// The plain bound extended by a carried vector (see [`CandidateContext::extended_bound`]).
#[derive(Debug)]
struct Extended {
    /// The smallest Ritz value of `[X, y]`, with its margin.
    bound: Bound,
    /// The carried vector on `A \ {c}`'s coordinates (one column) and `H'y`.
    y: Mat<f64>,
    hy: Mat<f64>,
    /// The two lowest Ritz vectors of `[X, y]` and their products with `H'`.
    xb: Mat<f64>,
    hxb: Mat<f64>,
}

/// The columns of `ms`, in order: a basis made of several blocks, without copying them.
fn columns<'m>(ms: &[&'m Mat<f64>]) -> Vec<&'m [f64]> {
    ms.iter()
        .flat_map(|m| (0..m.ncols()).map(move |j| col(m, j)))
        .collect()
}

/// Column `j` of `m` as a slice (faer stores columns contiguously).
fn col(m: &Mat<f64>, j: usize) -> &[f64] {
    m.col(j)
        .try_as_col_major()
        .expect("contiguous column")
        .as_slice()
}

/// `AᵀB` for the bases `a` and `b` (lists of columns).
fn gram(a: &[&[f64]], b: &[&[f64]]) -> Mat<f64> {
    Mat::from_fn(a.len(), b.len(), |i, j| dot(a[i], b[j]))
}

/// `xᵀy`, summed in eight interleaved lanes (vectorized).
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0; 8];
    let (xc, yc) = (x.chunks_exact(8), y.chunks_exact(8));
    let tail: f64 = xc
        .remainder()
        .iter()
        .zip(yc.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in xc.zip(yc) {
        for l in 0..8 {
            acc[l] += a[l] * b[l];
        }
    }
    acc.iter().sum::<f64>() + tail
}

/// `A·Q` for the basis `a` (a list of columns).
fn combine(a: &[&[f64]], q: MatRef<'_, f64>) -> Mat<f64> {
    let n = a.first().map_or(0, |c| c.len());
    let mut out = Mat::<f64>::zeros(n, q.ncols());
    for j in 0..q.ncols() {
        let o = out
            .col_mut(j)
            .try_as_col_major_mut()
            .expect("contiguous column")
            .as_slice_mut();
        for (i, c) in a.iter().enumerate() {
            let w = q[(i, j)];
            for (o, x) in o.iter_mut().zip(c.iter()) {
                *o += w * x;
            }
        }
    }
    out
}

/// The lower of two bounds once their margins are counted (`a` on a tie).
fn lower(a: Bound, b: Bound) -> Bound {
    if b.value + b.margin < a.value + a.margin {
        b
    } else {
        a
    }
}

/// Zeroes `rows` of `m`.
fn zero_rows(m: &mut Mat<f64>, rows: &[usize]) {
    for &row in rows {
        for j in 0..m.ncols() {
            m[(row, j)] = 0.0;
        }
    }
}

/// The smallest Ritz values of the pencil `(K, G)` over the range of `G`, ascending, with
/// their coefficient vectors (columns, in the `k`-dimensional space of `K`); empty if `G`
/// vanishes.
fn ritz(k: MatRef<'_, f64>, g: MatRef<'_, f64>) -> (Vec<f64>, Mat<f64>) {
    let n = g.nrows();
    let none = (Vec::new(), Mat::<f64>::zeros(n, 0));
    let sym = |m: MatRef<'_, f64>| Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (m[(i, j)] + m[(j, i)]));
    let Ok(eg) = sym(g).self_adjoint_eigen(faer::Side::Lower) else {
        return none;
    };
    let s = eg.S();
    let gmax = (0..n).map(|i| s[i]).fold(0.0, f64::max);
    let keep: Vec<usize> = (0..n)
        .filter(|&i| s[i] > 1e-8 * gmax.max(1e-300) && s[i] > 0.0)
        .collect();
    if keep.is_empty() {
        return none;
    }
    let u = eg.U();
    let b = Mat::<f64>::from_fn(n, keep.len(), |i, j| u[(i, keep[j])] / s[keep[j]].sqrt());
    let m = b.transpose() * sym(k).as_ref() * b.as_ref();
    let r = keep.len();
    let m = Mat::<f64>::from_fn(r, r, |i, j| 0.5 * (m[(i, j)] + m[(j, i)]));
    let Ok(em) = m.self_adjoint_eigen(faer::Side::Lower) else {
        return none;
    };
    let values = (0..r).map(|i| em.S()[i]).collect();
    (values, b * em.U())
}

#[cfg(test)]
mod tests {
    use crate::simplify::{Budget, GreedyParams};

    #[test]
    fn first_shifts_outside_zero_to_one_are_rejected() {
        let mut p = GreedyParams::new(Budget::Fraction(0.5));
        assert!(p.validate(3).is_ok());
        for bad in [1.0, 1.5, -0.1, f64::NAN, f64::INFINITY] {
            p.prune.first_shift = bad;
            let e = p.validate(3).expect_err("rejected");
            assert!(e.contains("first shift must lie in [0, 1)"), "{e}");
        }
        p.prune.first_shift = 0.0;
        assert!(p.validate(3).is_ok(), "0 switches it off");
    }

    /// The 3×3 dome of arcs (clamped, h = 150) and its analyzer.
    fn dome_analyzer() -> crate::stability::Analyzer {
        use crate::network::{BuildParams, build_network};
        use crate::rod::Supports;
        use crate::stability::{Analyzer, StabilityParams};
        let scene = crate::builtin::dome_arcs(2000.0, 700.0, 3, 3);
        let build = BuildParams {
            edge_length: 150.0,
            supports: Supports::Clamped,
            ..Default::default()
        };
        let (net, _) = build_network(&scene.curves, &build).expect("builds");
        Analyzer::new(net, StabilityParams::default()).expect("analyzer")
    }

    /// The refined bound's `H'X`, formed from the iteration's `H_A V` and the curve's terms
    /// without a sparse product, equals the product of the assembled candidate Hessian; the
    /// refined bounds bound the exact scores from above.
    #[test]
    fn refined_bounds_use_the_candidate_hessian() {
        use super::{CandidateContext, RefineStep};
        use crate::rod::ActiveSet;
        use crate::simplify::Scorer;
        let an = dome_analyzer();
        let n = an.network().rods.len();
        let scorer = Scorer::new(&an).with_modes(2);
        // Without one curve: the structure has loose vertices of its own.
        let active = ActiveSet::all(n).without(1);
        let eval = scorer.evaluate(&active, None).expect("evaluates");
        let ctx = CandidateContext::of_evaluation(&scorer, &active, &eval);
        let cs: Vec<usize> = active.curves();
        let refined = ctx.refined_bounds(&cs);
        for (&c, r) in cs.iter().zip(&refined) {
            let RefineStep::Step { x, hx, .. } = ctx.refine_start(c) else {
                panic!("curve {c}: the modes vanish on A \\ {{c}}");
            };
            let direct = ctx.candidate_matvec(c, x.as_ref());
            let scale = direct.norm_max();
            let diff = (&hx - &direct).norm_max();
            assert!(
                diff <= 1e-9 * scale,
                "curve {c}: H'X off by {diff:e} (scale {scale:e})"
            );
            let r = r.expect("a preconditioner");
            let (exact, _) = ctx.score(c).expect("scores");
            let lambda = exact.lambda();
            assert!(
                lambda <= r.value + r.margin + 1e-9 * lambda.abs(),
                "curve {c}: score {lambda:e} above its refined bound {:e}",
                r.value
            );
            assert!(r.value <= ctx.bound(c).value + ctx.bound(c).margin);
        }
    }

    /// One factorization proves a score below a shift exactly when it is: shifts 0.1% above
    /// (with and without a reference factorization of `H_A − σI` to copy from) and below each
    /// candidate's exact score, and far below zero.
    #[test]
    fn an_inertia_test_alone_proves_exactly_the_scores_below_its_shift() {
        use super::CandidateContext;
        use crate::rod::ActiveSet;
        use crate::simplify::Scorer;
        let an = dome_analyzer();
        let n = an.network().rods.len();
        let scorer = Scorer::new(&an).with_modes(2);
        let active = ActiveSet::all(n);
        let eval = scorer.evaluate(&active, None).expect("evaluates");
        let ctx = CandidateContext::of_evaluation(&scorer, &active, &eval);
        let mut proved = 0;
        for c in active.curves() {
            let (exact, _) = ctx.score(c).expect("scores");
            let lambda = exact.lambda();
            let (above, below) = (lambda + 1e-3 * lambda.abs(), lambda - 1e-3 * lambda.abs());
            let reference = ctx.reference(above);
            for r in [None, reference.as_ref()] {
                assert!(ctx.proves_below(c, above, r).expect("factors"), "curve {c}");
                proved += 1;
            }
            assert!(
                !ctx.proves_below(c, below, None).expect("factors"),
                "curve {c}"
            );
            // Far below zero: never proved (the structure is stable).
            assert!(!ctx.proves_below(c, -lambda.abs(), None).expect("factors"));
        }
        assert!(proved >= 2 * 6, "every candidate tested");
    }
}

//! The numerics of one greedy iteration's candidates: each candidate `c` of structure `A` is
//! scored by `λ_fix(A \ {c} | A)`, the smallest eigenvalue of `H' = H_{A∖c}` at `A`'s
//! equilibrium, and bounded from above without a factorization.
//!
//! - **Plain bound** ([`Candidates::bound`]). Let `V` hold `A`'s `k` lowest modes and `W` be
//!   `V` with the rows of `c`'s loose vertices zeroed. By Courant–Fischer the smallest Ritz
//!   value of `H'` on `span(W)` is at least `λ_min(H')`. Because `H'` equals `H_A − H_c` on
//!   the kept coordinates (`H_c`: the Hessian of `c`'s own terms),
//!   `WᵀH'W = VᵀH_AV − Σ_{v∈L} V_vᵀ(H_AV)_v − Σ_{v∈c∖L} V_vᵀ(H_cV)_v` and
//!   `WᵀW = VᵀV − Σ_{v∈L} V_vᵀV_v`, `L` being `c`'s loose vertices: with `H_AV` computed once
//!   per iteration, each bound costs `O(|c|·k²)`.
//! - **Extended bound** ([`Candidates::extended_bounds`]): Rayleigh–Ritz on the plain Ritz
//!   vectors and a test vector carried over from the previous iteration ([`Carried`]).
//! - **Refined bound** ([`Candidates::refined_bounds`]): one preconditioned step from the
//!   best Ritz vectors, preconditioned by the factorization `A`'s spectrum used.
//! - **Tests** ([`Candidates::test`]): the exact score about zero or about a shift, or an
//!   inertia test (one Cholesky of `H' − σI`: its failure proves the score below `σ`), the
//!   factorizations copying what a candidate cannot reach from one of `H_A − σI` when many
//!   are tested about one shift ([`Candidates::prepare_shift`]).
//!
//! Every value depends only on the inputs and on which candidates share a solve call (the
//! caller groups them deterministically), never on thread timing. Which candidates to bound,
//! refine, test or score, and in what order, is the caller's policy (the greedy's best-first
//! search).

mod bounds;
mod carried;
mod dense;
mod score;

pub use carried::{Carried, CarriedVector};
pub use score::{Outcome, Test};

use super::Analyzer;
use super::evaluate::{Evaluation, Warm, Work};
use crate::rod::ActiveSet;
use crate::rod::model::{LocalHessians, Terms as TermSet};
use crate::solve::{Cholesky, SymbolicFactor};
use bounds::{Extended, RitzBound};
use faer::{Mat, MatRef};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// An upper bound with its round-off margin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// Smallest Ritz value (`+∞` when the subspace vanishes on `A \ {c}`).
    pub value: f64,
    /// Estimated absolute round-off in `value`.
    pub margin: f64,
}

impl Bound {
    /// `value + margin`: the bound once round-off is counted.
    pub fn top(self) -> f64 {
        self.value + self.margin
    }
}

/// The part of [`Candidates`] that needs only the structure's equilibrium, not its modes:
/// the local Hessians of its terms and `H_A` assembled from them (computed beside the
/// structure's spectrum, [`super::Prepare::Candidates`]).
#[derive(Debug)]
pub(super) struct Terms {
    locals: LocalHessians,
    h: Vec<f64>,
}

impl Terms {
    /// The terms of structure `active` at displacements `u`.
    pub(super) fn compute(analyzer: &Analyzer, active: &ActiveSet, u: &[f64]) -> Self {
        let model = analyzer.model();
        let locals = model.local_hessians(u, TermSet::Of(active));
        let mut h = Vec::new();
        model.hessian_from_locals(&locals, active, &mut h);
        Terms { locals, h }
    }
}

/// Everything shared by the candidates of one iteration.
#[derive(Debug)]
pub struct Candidates<'a> {
    analyzer: &'a Analyzer,
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
    /// Per curve: a test vector handed over from the previous iteration.
    carried: Carried,
    /// Each curve's extended bound, computed once.
    extended: Vec<OnceLock<Option<Extended>>>,
    /// Per curve: the best test vector found in this iteration, for the next one.
    carry_out: Vec<Mutex<Option<CarriedVector>>>,
    /// The inertia tests' shift `σ` and a factorization of `H_A − σI` they copy from (`None`
    /// when not worth it or not positive definite).
    reference: Option<(f64, Option<Cholesky>)>,
    /// Per curve: the share of a factorization's work left when copying from the reference.
    shares: Vec<OnceLock<f64>>,
    /// Candidates scored about zero, with their scores and factorizations (the winner's
    /// starts the next relaxation).
    kept: Mutex<Vec<(usize, f64, Cholesky)>>,
}

impl<'a> Candidates<'a> {
    /// The candidates of structure `active` evaluated as `eval` (with
    /// [`super::Prepare::Candidates`], else its terms are computed here): its equilibrium,
    /// low modes and analysis, its spectrum's factorization as the refined bounds'
    /// preconditioner, and the test vectors `carried` over from the previous iteration
    /// ([`Self::take_carried`] of its candidates; empty for none).
    pub fn new(
        analyzer: &'a Analyzer,
        active: &ActiveSet,
        eval: &mut Evaluation,
        carried: Carried,
    ) -> Self {
        let terms = eval
            .terms
            .take()
            .unwrap_or_else(|| Terms::compute(analyzer, active, &eval.displacement));
        let mut c = Self::with_terms(
            analyzer,
            active,
            terms,
            eval.spectrum.vectors.as_ref(),
            eval.symbolic.clone(),
        );
        c.preconditioner = Some(eval.factor.clone());
        c.spectrum_solves = eval.spectrum.solves;
        c.carried = carried;
        c
    }

    /// The candidates of structure `active` at displacements `u` with low `modes`
    /// (columns), without a preconditioner (no refined bounds) or carried vectors.
    pub fn at(
        analyzer: &'a Analyzer,
        active: &ActiveSet,
        u: &[f64],
        modes: MatRef<'_, f64>,
    ) -> Self {
        let terms = Terms::compute(analyzer, active, u);
        Self::with_terms(
            analyzer,
            active,
            terms,
            modes,
            analyzer.symbolic_for(active),
        )
    }

    fn with_terms(
        analyzer: &'a Analyzer,
        active: &ActiveSet,
        terms: Terms,
        modes: MatRef<'_, f64>,
        symbolic: Arc<SymbolicFactor>,
    ) -> Self {
        let model = analyzer.model();
        let Terms { locals, h } = terms;
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
        let curves = analyzer.curve_count();
        Candidates {
            analyzer,
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
            ritz: (0..curves).map(|_| OnceLock::new()).collect(),
            held: model.vertex_mask(active),
            carried: Vec::new(),
            extended: (0..curves).map(|_| OnceLock::new()).collect(),
            carry_out: (0..curves).map(|_| Mutex::new(None)).collect(),
            reference: None,
            shares: (0..curves).map(|_| OnceLock::new()).collect(),
            kept: Mutex::default(),
        }
    }

    /// Whether refined bounds can be computed (a preconditioner is known).
    pub fn refinable(&self) -> bool {
        self.preconditioner.is_some() && !self.analyzer.mass_metric()
    }

    /// The preconditioner's shift `σ > 0` (its factorization is of `H_A − σI`), if positive.
    pub fn preconditioner_shift(&self) -> Option<f64> {
        self.preconditioner
            .as_ref()
            .filter(|_| !self.analyzer.mass_metric())
            .map(|f| -f.shift)
            .filter(|s| s.is_finite() && *s > 0.0)
    }

    /// How many candidates' bounds can be refined while the first candidate is scored: its
    /// eigen solve takes about [`super::Tuning::first_score_cost`] times the solves of `A`'s
    /// spectrum, and refining a candidate's bound costs about two (half a call of four
    /// columns and a product with `H_A`; the factorization takes about four more); at most
    /// [`super::Tuning::first_ahead`].
    pub fn first_ahead(&self) -> usize {
        let t = self.analyzer.tuning();
        ((self.spectrum_solves as f64 * t.first_score_cost) as usize / 2)
            .saturating_sub(4)
            .min(t.first_ahead)
    }

    /// Factorizations and solves spent on scores and tests so far.
    pub fn work(&self) -> Work {
        Work {
            factorizations: self.factorizations.load(Ordering::Relaxed),
            solves: self.solves.load(Ordering::Relaxed),
        }
    }

    /// Forgets the factorizations of the candidates scoring below `floor` (they cannot win).
    pub fn release_below(&self, floor: f64) {
        if let Ok(mut kept) = self.kept.lock() {
            kept.retain(|k| k.1 >= floor);
        }
    }

    /// What the evaluation of the structure without `winner` may reuse: `eval`'s (this
    /// structure's) equilibrium, low modes and symbolic analysis, the winner's factorization
    /// when it was scored about zero (the next structure's Hessian at that start), and the
    /// estimate `lambda` of its `λ_eq`.
    pub fn hand_on(&self, winner: usize, eval: Evaluation, lambda: f64) -> Warm {
        // In the mass metric a score's factorization is not of the Hessian Newton needs.
        let metric = self.analyzer.mass_metric();
        let factor = self
            .kept
            .lock()
            .ok()
            .filter(|_| !metric)
            .and_then(|mut kept| {
                let i = kept.iter().position(|k| k.0 == winner)?;
                Some(kept.swap_remove(i).2)
            });
        Warm {
            start: Some(eval.displacement),
            factor,
            modes: Some(eval.spectrum.vectors),
            superset: Some(eval.symbolic),
            lambda: Some(lambda),
        }
    }
}

impl Candidates<'_> {
    /// What the evaluation of the structure without a removed set (scored by
    /// [`Self::score_set`]) may reuse: `eval`'s equilibrium, low modes and symbolic analysis,
    /// and the estimate `lambda` of its `λ_eq`; no factorization (a set's score keeps none).
    pub fn hand_on_set(&self, eval: Evaluation, lambda: f64) -> Warm {
        Warm {
            start: Some(eval.displacement),
            factor: None,
            modes: Some(eval.spectrum.vectors),
            superset: Some(eval.symbolic),
            lambda: Some(lambda),
        }
    }
}

impl Analyzer {
    /// What a greedy resumed after recording structure `prev` (equilibrium `u`, low `modes`)
    /// and its removal of `winner` hands the next evaluation — the same as an uninterrupted
    /// run ([`Candidates::hand_on`]): the winner's factorization is recomputed when it was
    /// scored about zero (it depends only on the recorded state).
    pub fn resume_warm(
        &self,
        prev: &ActiveSet,
        u: Vec<f64>,
        modes: Mat<f64>,
        winner: usize,
        about_zero: bool,
        lambda: Option<f64>,
    ) -> Warm {
        let factor = if about_zero && !self.mass_metric() {
            let ctx = Candidates::at(self, prev, &u, modes.as_ref());
            ctx.score(winner).ok().map(|(_, f)| f)
        } else {
            None
        };
        Warm {
            start: Some(u),
            factor,
            modes: Some(modes),
            superset: Some(self.symbolic_for(prev)),
            lambda,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Candidates;
    use super::bounds::RefineStep;
    use crate::stability::{Prepare, Preset, Warm};

    use crate::stability::test_support::dome_analyzer;

    const GREEDY: Preset = Preset::Greedy { modes: 2 };

    /// The refined bound's `H'X`, formed from the iteration's `H_A V` and the curve's terms
    /// without a sparse product, equals the product of the assembled candidate Hessian; the
    /// refined bounds bound the exact scores from above.
    #[test]
    fn refined_bounds_use_the_candidate_hessian() {
        let an = dome_analyzer();
        // Without one curve: the structure has loose vertices of its own.
        let active = an.all().without(1);
        let mut eval = an
            .evaluate(&active, Warm::default(), GREEDY, Prepare::Nothing)
            .expect("evaluates");
        let ctx = Candidates::new(&an, &active, &mut eval, Vec::new());
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

    /// A set's score is the score of its removal: one curve's equals the single-curve score,
    /// and a pair's equals the score of the second curve in the structure without the first,
    /// at the same (fixed) equilibrium.
    #[test]
    fn a_set_is_scored_as_its_removal() {
        use super::Outcome;
        let an = dome_analyzer();
        let active = an.all();
        let mut eval = an
            .evaluate(&active, Warm::default(), GREEDY, Prepare::Candidates)
            .expect("evaluates");
        let ctx = Candidates::new(&an, &active, &mut eval, Vec::new());
        let set_score = |s: &[usize]| match ctx.score_set(s) {
            Outcome::Scored { score, .. } => score,
            o => panic!("{s:?}: {o:?}"),
        };
        for c in [0, 2, 4] {
            let (exact, _) = ctx.score(c).expect("scores");
            let (a, b) = (set_score(&[c]), exact.lambda());
            assert!((a - b).abs() <= 1e-8 * b.abs(), "curve {c}: {a:e} vs {b:e}");
        }
        for (a, b) in [(0, 1), (1, 4), (2, 5)] {
            let first = active.without(a);
            let at = Candidates::at(
                &an,
                &first,
                &eval.displacement,
                eval.spectrum.vectors.as_ref(),
            );
            let (exact, _) = at.score(b).expect("scores");
            let (x, y) = (set_score(&[a, b]), exact.lambda());
            assert!(
                (x - y).abs() <= 1e-8 * y.abs(),
                "{{{a}, {b}}}: {x:e} vs {y:e}"
            );
        }
        assert!(matches!(
            ctx.score_set(&active.curves()),
            Outcome::Failed(_)
        ));
    }

    /// One factorization proves a score below a shift exactly when it is: shifts 0.1% above
    /// (with and without a reference factorization of `H_A − σI` to copy from) and below each
    /// candidate's exact score, and far below zero.
    #[test]
    fn an_inertia_test_alone_proves_exactly_the_scores_below_its_shift() {
        let an = dome_analyzer();
        let active = an.all();
        let mut eval = an
            .evaluate(&active, Warm::default(), GREEDY, Prepare::Candidates)
            .expect("evaluates");
        let ctx = Candidates::new(&an, &active, &mut eval, Vec::new());
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

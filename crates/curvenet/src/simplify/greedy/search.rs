//! The greedy's candidate search: which candidate to bound, refine, test or score, in what
//! order, and which to prune (the numbers come from [`Candidates`]).
//!
//! Best first: candidates are taken by decreasing bound (the refined bound once known, else
//! the extended one, else the plain one; ties by curve id) and skipped once their bound
//! (plus its round-off margin) falls below `best·(1 − tie)`, where they can neither win nor
//! tie. A candidate with a carried vector gets its extended bound before it is considered
//! for refinement (the extended bound, no solve, often drops it out of the top for good), and
//! is evaluated only after its refined bound, so the first exact score goes to the most
//! promising candidate by the tightest bound and later candidates are mostly settled by their
//! bound or the inertia test. Every decision depends only on the values, never on thread
//! timing, and the choice is the same as without pruning (tested).

use crate::stability::Tuning;
use crate::stability::candidates::{Bound, Candidates, Outcome, Test};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

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
    /// was computed.
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
    /// When the score was computed by shift-and-invert about a shift (the inertia test's `σ`
    /// or a first guess) rather than about zero: that shift.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shift: Option<f64>,
    /// The failure, if any.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub error: Option<String>,
    /// Under design constraints, when the candidate is a group removed as a whole: its curves
    /// (ascending; `curve` is the smallest). Empty for a single curve.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub group: Vec<usize>,
}

impl CandidateScore {
    fn new(curve: usize) -> Self {
        CandidateScore {
            curve,
            score: None,
            bound: None,
            extended_bound: None,
            refined_bound: None,
            pruned: false,
            below: None,
            shift: None,
            error: None,
            group: Vec::new(),
        }
    }

    /// The exact score of removing the unit `curves` as a whole (several curves: recorded as
    /// its group).
    pub(super) fn of_group(curves: &[usize], outcome: Outcome) -> Self {
        let mut s = CandidateScore::new(curves[0]);
        if curves.len() > 1 {
            s.group = curves.to_vec();
        }
        match outcome {
            Outcome::Scored { score, .. } => s.score = Some(score),
            Outcome::Below(_) => s.error = Some("no exact score".into()),
            Outcome::Failed(e) => s.error = Some(e),
        }
        s
    }
}

/// Scores `candidates` (curves of the structure), skipping those that cannot win when
/// [`Tuning::prune`] is on; scores within `tie` of the best tie. The scores come in the order
/// of `candidates`. `cancelled` is polled before every evaluation.
pub fn score_all(
    ctx: &mut Candidates<'_>,
    candidates: &[usize],
    tuning: &Tuning,
    tie: f64,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Vec<CandidateScore> {
    let n = candidates.len();
    let mut search = Search {
        ctx,
        candidates,
        tie,
        tuning,
        cancelled,
        out: candidates.iter().map(|&c| CandidateScore::new(c)).collect(),
        best: f64::NEG_INFINITY,
        plain: Vec::new(),
        extended: vec![None; n],
        refined: vec![None; n],
        alive: (0..n).collect(),
        guesses: vec![0; n],
        best_threshold: f64::INFINITY,
    };
    if !tuning.prune {
        let all: Vec<usize> = (0..n).collect();
        let results = search.evaluate_group(&all, None, false);
        search.record(&all, results);
        return search.out;
    }
    let ctx = &*search.ctx;
    search.plain = candidates.par_iter().map(|&c| ctx.bound(c)).collect();
    for (o, b) in search.out.iter_mut().zip(&search.plain) {
        o.bound = Some(b.value);
    }
    while search.step() {}
    search.out
}

/// The state of [`score_all`]'s best-first search.
struct Search<'c, 'a> {
    ctx: &'c mut Candidates<'a>,
    candidates: &'c [usize],
    tie: f64,
    tuning: &'c Tuning,
    cancelled: &'c (dyn Fn() -> bool + Sync),
    out: Vec<CandidateScore>,
    best: f64,
    plain: Vec<Bound>,
    /// Extended bounds computed so far (candidates with a carried vector).
    extended: Vec<Option<Bound>>,
    /// Refined bounds computed so far (the plain bound when there is no preconditioner).
    refined: Vec<Option<Bound>>,
    /// Candidates (indices into `candidates`) neither evaluated nor pruned.
    alive: Vec<usize>,
    /// Failed first guesses per candidate.
    guesses: Vec<u8>,
    /// The zero-mode threshold of the best score's spectrum.
    best_threshold: f64,
}

impl Search<'_, '_> {
    fn floor(&self) -> f64 {
        self.best - self.tie * self.best.abs()
    }

    fn key(&self, i: usize) -> Bound {
        self.refined[i]
            .or(self.extended[i])
            .unwrap_or(self.plain[i])
    }

    fn curves(&self, group: &[usize]) -> Vec<usize> {
        group.iter().map(|&i| self.candidates[i]).collect()
    }

    /// One step: prune, then bound or refine the best candidates or evaluate the best ones.
    /// False when every candidate is settled.
    fn step(&mut self) -> bool {
        if (self.cancelled)() {
            for &i in &self.alive {
                self.out[i].error = Some("cancelled".into());
            }
            self.alive.clear();
            return false;
        }
        if !self.prune_and_sort() {
            return false;
        }
        let top = self.tuning.batch.max(1).min(self.alive.len());
        let refinable = self.ctx.refinable();
        if refinable && self.alive[..top].iter().any(|&i| self.refined[i].is_none()) {
            self.bound_top();
            return true;
        }
        self.evaluate_top(top, refinable);
        true
    }

    /// Prunes the alive candidates whose bound lies below the floor and sorts the others by
    /// decreasing bound (ties by curve id); false when none is left.
    fn prune_and_sort(&mut self) -> bool {
        let floor = self.floor();
        let mut alive = std::mem::take(&mut self.alive);
        alive.retain(|&i| {
            let prune = self.key(i).top() < floor;
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
        true
    }

    /// The best candidates lack a refined bound: the extended bounds of those with a carried
    /// vector first (a share of a pass over `H_A` each, no solve; the next step re-sorts and
    /// refines those still on top), else the refined bounds of the best
    /// [`Tuning::refine_ahead`] batches.
    fn bound_top(&mut self) {
        let group: Vec<usize> = self
            .alive
            .iter()
            .copied()
            .take(self.tuning.refine_ahead * self.tuning.batch.max(1))
            .filter(|&i| self.refined[i].is_none())
            .collect();
        let extend: Vec<usize> = group
            .iter()
            .copied()
            .filter(|&i| self.extended[i].is_none() && self.ctx.has_carried(self.candidates[i]))
            .collect();
        if !extend.is_empty() {
            let values = self.ctx.extended_bounds(&self.curves(&extend));
            for (&i, b) in extend.iter().zip(values) {
                self.extended[i] = Some(b);
                self.out[i].extended_bound = Some(b.value);
            }
            return;
        }
        let values = self.ctx.refined_bounds(&self.curves(&group));
        self.store_refined(&group, values);
    }

    fn store_refined(&mut self, group: &[usize], values: Vec<Option<Bound>>) {
        for (&i, r) in group.iter().zip(values) {
            // `None` only without a preconditioner: keep the plain bound.
            self.refined[i] = Some(r.unwrap_or(self.plain[i]));
            self.out[i].refined_bound = r.map(|r| r.value);
        }
    }

    /// Evaluates the best candidates: the first score (about zero or a first guess) alone,
    /// which sets the best at once, while the other thread refines the bounds of the next
    /// candidates ([`Self::ahead`]); once a score is known, a batch at the inertia test's
    /// shift ([`Self::test_shift`]).
    fn evaluate_top(&mut self, top: usize, refinable: bool) {
        let take = if self.best.is_finite() { top } else { 1 };
        let group: Vec<usize> = self.alive[..take].to_vec();
        let (sigma, decide) = self.test_shift();
        if let Some(sigma) = sigma {
            let alive = self.curves(&self.alive);
            self.ctx.prepare_shift(sigma, &alive);
        }
        let ahead = if !self.best.is_finite() && refinable {
            self.ahead(&group, take)
        } else {
            Vec::new()
        };
        let this = &*self;
        let (results, values) = rayon::join(
            || this.evaluate_group(&group, sigma, decide),
            || this.ctx.refined_bounds(&this.curves(&ahead)),
        );
        self.store_refined(&ahead, values);
        self.record(&group, results);
    }

    /// The inertia test's shift and whether it only decides. It needs a shift clear of the
    /// zero-mode band (round-off): the floor when positive, or negative beyond
    /// [`Tuning::negative_floor`] times the best score's zero-mode threshold (a structure
    /// every removal makes unstable). A floor inside the band tests at its lower edge
    /// instead and only decides: a failed factorization still proves the score below the
    /// floor, and a candidate it does not prune is scored about zero (no first guess about a
    /// positive shift: those fail for negative scores), where scores inside the band were
    /// computed before too.
    fn test_shift(&self) -> (Option<f64>, bool) {
        let floor = self.floor();
        let edge = -self.tuning.negative_floor * self.best_threshold;
        if !(self.tuning.inertia && floor.is_finite()) {
            (None, false)
        } else if floor > 0.0 || floor < edge {
            (Some(floor), false)
        } else {
            (edge.is_finite().then_some(edge), true)
        }
    }

    /// Candidate `i`'s first guess: [`Tuning::first_shift`] × its bound, or the
    /// preconditioner's shift when it lies between that and
    /// [`Tuning::preconditioner_guess`] × the bound (nearer the score, and the preconditioner,
    /// a factorization of `H_A − σI`, is a reference to copy from); none after
    /// [`Tuning::max_guesses`] failed guesses.
    fn guess(&self, i: usize) -> Option<f64> {
        let t = self.tuning;
        let r = self.key(i).value;
        if !(t.first_shift > 0.0 && self.guesses[i] < t.max_guesses && r.is_finite() && r > 0.0) {
            return None;
        }
        let g = t.first_shift * r;
        Some(match self.ctx.preconditioner_shift() {
            Some(s) if self.guesses[i] == 0 && s > g && s <= t.preconditioner_guess * r => s,
            _ => g,
        })
    }

    /// The candidates whose bounds are refined while the first one is scored: those whose
    /// plain bound lies above the shift it is scored about (its score lies above that shift
    /// when the factorization there succeeds) and above [`Tuning::ahead_share`] of its bound,
    /// as many as the score's expected cost allows ([`Candidates::first_ahead`]); without a
    /// guess, the usual batch.
    fn ahead(&self, group: &[usize], take: usize) -> Vec<usize> {
        let t = self.tuning;
        let above = group.first().filter(|_| t.ahead).and_then(|&i| {
            self.guess(i)
                .map(|g| g.max(t.ahead_share * self.key(i).value))
        });
        let batch = t.batch.max(1);
        let limit = match above {
            Some(_) => self.ctx.first_ahead().max(batch),
            None => batch,
        };
        self.alive[take..]
            .iter()
            .copied()
            .filter(|&i| self.refined[i].is_none())
            .filter(|&i| above.is_none_or(|g| self.plain[i].top() >= g))
            .take(limit)
            .collect()
    }

    /// Evaluates the candidates of `group` in parallel: at the inertia test's `sigma` when
    /// given (only deciding with `decide`), else about their first guess, else about zero.
    fn evaluate_group(&self, group: &[usize], sigma: Option<f64>, decide: bool) -> Vec<Scored> {
        group
            .par_iter()
            .map(|&i| {
                if (self.cancelled)() {
                    return Scored::Failed("cancelled".into());
                }
                let guess = if self.tuning.prune {
                    self.guess(i)
                } else {
                    None
                };
                let test = match (sigma, guess) {
                    (Some(s), _) if decide => Test::Decide(s),
                    (Some(s), _) => Test::Inertia(s),
                    (None, Some(g)) => Test::Guess(g),
                    (None, None) => Test::AboutZero,
                };
                match (self.ctx.test(self.candidates[i], test), test) {
                    (Outcome::Below(g), Test::Guess(_)) => Scored::BelowGuess(g),
                    (o, _) => Scored::Settled(o),
                }
            })
            .collect()
    }

    /// Records one evaluated group; the candidates whose guess failed stay in the search.
    fn record(&mut self, group: &[usize], results: Vec<Scored>) {
        let mut settled = Vec::with_capacity(group.len());
        for (&i, scored) in group.iter().zip(results) {
            let o = &mut self.out[i];
            match scored {
                Scored::Settled(Outcome::Scored {
                    score,
                    shift,
                    threshold,
                }) => {
                    o.score = Some(score);
                    o.shift = shift;
                    o.below = None;
                    if score.is_finite() {
                        if score > self.best {
                            self.best_threshold = threshold;
                        }
                        self.best = self.best.max(score);
                    }
                }
                Scored::Settled(Outcome::Below(sigma)) => {
                    o.pruned = true;
                    o.below = Some(sigma);
                }
                Scored::BelowGuess(g) => {
                    // Proved: λ < g. Recorded as `below` if that is what prunes it.
                    o.below = Some(g);
                    self.guesses[i] += 1;
                    self.refined[i] = Some(Bound {
                        value: g,
                        margin: 0.0,
                    });
                    continue;
                }
                Scored::Settled(Outcome::Failed(e)) | Scored::Failed(e) => o.error = Some(e),
            }
            settled.push(i);
        }
        self.alive.retain(|i| !settled.contains(i));
        self.ctx.release_below(self.floor());
    }
}

/// What evaluating one candidate gave the search.
enum Scored {
    /// Settled: scored, proved below the inertia test's shift, or failed.
    Settled(Outcome),
    /// The first guess failed: the score lies below it (a new upper bound; the candidate
    /// stays in the search).
    BelowGuess(f64),
    /// Not evaluated (cancelled).
    Failed(String),
}

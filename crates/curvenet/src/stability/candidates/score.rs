//! A candidate's exact score, about zero or about a shift, and the inertia tests that prove
//! a score below a shift with one factorization.

use super::super::StabilityError;
use super::super::evaluate::restrict;
use super::super::presets::Preset;
use super::Candidates;
use crate::rod::ActiveSet;
use crate::solve::eigen::{EigenError, Spectrum, Start};
use crate::solve::{Cholesky, Reuse};
use faer::MatRef;
use std::sync::atomic::Ordering;

/// How to evaluate one candidate ([`Candidates::test`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Test {
    /// Its score by shift-and-invert about zero; the factorization is kept (the winner's
    /// starts the next relaxation, [`Candidates::hand_on`]).
    AboutZero,
    /// The inertia test at the search's shift `σ` ([`Candidates::prepare_shift`] first): one
    /// factorization of `H' − σI`, whose failure proves the score below `σ`
    /// ([`Outcome::Below`]); otherwise the score about `σ`.
    Inertia(f64),
    /// The inertia test at `σ` that only decides: a candidate it does not prove below `σ` is
    /// scored about zero (for shifts inside the zero-mode band).
    Decide(f64),
    /// A guess `g` below the score: the score about `g`, or [`Outcome::Below`] `g` when the
    /// guess was not below it.
    Guess(f64),
}

/// What evaluating one candidate gave.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Its score, computed about `shift` (`None`: about zero).
    Scored {
        /// `λ_fix(A \ {c} | A)`.
        score: f64,
        /// The shift of its shift-and-invert solve, when not zero.
        shift: Option<f64>,
        /// The spectrum's zero-mode threshold `C·ε·‖H‖₁`.
        threshold: f64,
    },
    /// One factorization proved the score below this shift.
    Below(f64),
    /// The eigen solve failed.
    Failed(String),
}

impl Candidates<'_> {
    /// Evaluates candidate `c` as `test` says.
    pub fn test(&self, c: usize, test: Test) -> Outcome {
        let (shift, inertia) = match test {
            Test::AboutZero => return self.about_zero(c),
            Test::Inertia(s) | Test::Decide(s) => (s, true),
            Test::Guess(g) => (g, false),
        };
        // A factorization of `H_A − σI` about the same shift to copy from: the inertia tests'
        // reference, or the preconditioner for a guess at its shift.
        let reference = if inertia {
            match &self.reference {
                Some((s, Some(f))) if s.to_bits() == shift.to_bits() => Some(f),
                _ => None,
            }
        } else {
            self.preconditioner
                .as_deref()
                .filter(|f| (-f.shift).to_bits() == shift.to_bits())
        };
        if let Test::Decide(_) = test {
            return match self.proves_below(c, shift, reference) {
                Ok(true) => Outcome::Below(shift),
                Ok(false) => self.about_zero(c),
                Err(e) => Outcome::Failed(e.to_string()),
            };
        }
        match self.score_above(c, shift, reference) {
            Ok(Some((sp, _))) => Outcome::Scored {
                score: sp.lambda(),
                shift: Some(shift),
                threshold: sp.zero_threshold,
            },
            Ok(None) => Outcome::Below(shift),
            Err(e) => Outcome::Failed(e.to_string()),
        }
    }

    /// [`Test::AboutZero`]: the score, its factorization kept when the score is finite.
    fn about_zero(&self, c: usize) -> Outcome {
        match self.score(c) {
            Ok((sp, f)) => {
                let score = sp.lambda();
                if score.is_finite()
                    && let Ok(mut kept) = self.kept.lock()
                {
                    kept.push((c, score, f));
                }
                Outcome::Scored {
                    score,
                    shift: None,
                    threshold: sp.zero_threshold,
                }
            }
            Err(e) => Outcome::Failed(e.to_string()),
        }
    }

    /// The score of removing the whole set `removed` at once (a group of curves kept or removed
    /// together): `λ_fix(A \ U | A)`, the smallest eigenvalue of `H_{A∖U}` at `A`'s
    /// equilibrium, about zero and warm-started from the iteration's modes. The single-curve
    /// bounds, tests and carried vectors do not apply to a set: every set is scored exactly.
    /// Its factorization is not kept (a set's winner hands on no factorization).
    pub fn score_set(&self, removed: &[usize]) -> Outcome {
        let mut active = self.active.clone();
        for &c in removed {
            active.remove(c);
        }
        if active.is_empty() {
            return Outcome::Failed(StabilityError::Empty.to_string());
        }
        match self.spectrum_of(&active, self.modes.as_ref()) {
            Ok((sp, _)) => {
                self.count(&sp);
                Outcome::Scored {
                    score: sp.lambda(),
                    shift: None,
                    threshold: sp.zero_threshold,
                }
            }
            Err(e) => Outcome::Failed(StabilityError::from(e).to_string()),
        }
    }

    /// Makes `sigma` the inertia tests' shift: factors `H_A − σI` for their factorizations
    /// to copy from when the candidates `alive` would save more than it costs (each saves
    /// the share of its factorization its curve cannot reach,
    /// [`Reuse`]). A pure function of the values.
    pub fn prepare_shift(&mut self, sigma: f64, alive: &[usize]) {
        if self
            .reference
            .as_ref()
            .is_some_and(|(s, _)| s.to_bits() == sigma.to_bits())
        {
            return;
        }
        let mut saving = 0.0;
        for &c in alive {
            let share = *self.shares[c].get_or_init(|| self.changed_share(c));
            saving += 1.0 - share;
        }
        let t = self.analyzer.tuning();
        // In the mass metric a removal rescales whole rows of its vertices' neighbours too:
        // no reference to copy from.
        let reuse = t.reuse && !self.analyzer.mass_metric();
        let factor = (reuse && saving >= t.reuse_min_saving)
            .then(|| self.reference(sigma))
            .flatten();
        self.reference = Some((sigma, factor));
    }

    /// Candidate `c`'s exact score, warm-started from the iteration's modes, with the
    /// factorization it used.
    pub(super) fn score(&self, c: usize) -> Result<(Spectrum, Cholesky), StabilityError> {
        let warm = self.ritz_vectors(c);
        let warm = warm.as_ref().map_or(self.modes.as_ref(), |w| w.as_ref());
        let active = self.active.without(c);
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let r = self.spectrum_of(&active, warm);
        if let Ok((sp, _)) = &r {
            self.count(sp);
            if sp.vectors.ncols() > 0 {
                self.offer(c, sp.lambda(), sp.vectors.as_ref());
            }
        }
        Ok(r?)
    }

    /// The spectrum of `active`'s Hessian (from the iteration's local Hessians, in the
    /// objective's metric) about zero, warm-started from `warm` restricted to `active`, with
    /// its factorization.
    fn spectrum_of(
        &self,
        active: &ActiveSet,
        warm: MatRef<'_, f64>,
    ) -> Result<(Spectrum, Cholesky), EigenError> {
        let model = self.analyzer.model();
        let mut h = Vec::new();
        model.hessian_from_locals(&self.locals, active, &mut h);
        self.analyzer.to_metric(active, &mut h);
        let warm = restrict(warm, &model.coordinate_mask(active));
        super::super::numerics::factored(
            model.pattern(),
            &h,
            &self.symbolic,
            Some(warm.as_ref()),
            &self.analyzer.eigen(Preset::Score, &self.symbolic),
        )
    }

    /// [`Self::score`] about the shift `sigma`: `Ok(None)` when one factorization proves
    /// the score below `sigma`. The factorization returned is of `H − σI`. With `reference`,
    /// a factorization of `H_A − σI` ([`Self::reference`]), that factorization copies the
    /// supernodes `c`'s removal cannot reach (the same factor, less work).
    pub(super) fn score_above(
        &self,
        c: usize,
        sigma: f64,
        reference: Option<&Cholesky>,
    ) -> Result<Option<(Spectrum, Cholesky)>, StabilityError> {
        let active = self.active.without(c);
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let model = self.analyzer.model();
        // The warm start only once the factorization about `σ` succeeds.
        let warm = || {
            let w = self.ritz_vectors(c).unwrap_or_else(|| self.modes.clone());
            Some(restrict(w.as_ref(), &model.coordinate_mask(&active)))
        };
        let changed = reference.map(|_| self.curve_coordinates(c));
        let reuse = reference.zip(changed.as_deref()).map(|(f, changed)| Reuse {
            reference: f,
            changed,
        });
        let h = self.candidate_hessian(c);
        let r = super::super::numerics::above(
            model.pattern(),
            &h,
            &self.symbolic,
            Start::Lazy(Box::new(warm)),
            &self.analyzer.eigen(Preset::Score, &self.symbolic),
            sigma,
            reuse,
        );
        match &r {
            Ok(Some((sp, _))) => {
                self.count(sp);
                if sp.vectors.ncols() > 0 {
                    self.offer(c, sp.lambda(), sp.vectors.as_ref());
                }
            }
            Ok(None) => {
                self.factorizations.fetch_add(1, Ordering::Relaxed);
            }
            Err(_) => {}
        }
        Ok(r?)
    }

    /// Whether one factorization proves candidate `c`'s score below `sigma` (Sylvester's
    /// inertia: the Cholesky of `H_{A∖c} − σI` fails), without an eigen solve when it does
    /// not. `reference` as in [`Self::score_above`].
    pub(super) fn proves_below(
        &self,
        c: usize,
        sigma: f64,
        reference: Option<&Cholesky>,
    ) -> Result<bool, StabilityError> {
        let h = self.candidate_hessian(c);
        let model = self.analyzer.model();
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
            return Err(StabilityError::Eigen(EigenError::NoShift(f64::NAN)));
        }
        Ok(factor.is_err())
    }

    fn count(&self, sp: &Spectrum) {
        self.factorizations
            .fetch_add(sp.factorizations, Ordering::Relaxed);
        self.solves.fetch_add(sp.solves, Ordering::Relaxed);
    }

    /// `H_{A∖c}`: `H_A` with the entries of `c`'s terms summed again (the same values as a
    /// whole assembly), in the objective's metric (`M_{A∖c}^{-1/2} H_{A∖c} M_{A∖c}^{-1/2}`
    /// under the frequency objective).
    fn candidate_hessian(&self, c: usize) -> Vec<f64> {
        let mut h = Vec::new();
        self.analyzer
            .model()
            .hessian_without(&self.locals, &self.active, &self.h, c, &mut h);
        self.analyzer.to_metric(&self.active.without(c), &mut h);
        h
    }

    /// The coordinates of curve `c`'s vertices: `H_{A∖c}` differs from `H_A` only in entries
    /// whose row and column both lie among them (its own terms, its loose vertices).
    fn curve_coordinates(&self, c: usize) -> Vec<usize> {
        self.analyzer
            .model()
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
    pub(super) fn reference(&self, sigma: f64) -> Option<Cholesky> {
        self.factorizations.fetch_add(1, Ordering::Relaxed);
        let model = self.analyzer.model();
        Cholesky::factorize(&self.symbolic, model.pattern(), &self.h, -sigma, None).ok()
    }
}

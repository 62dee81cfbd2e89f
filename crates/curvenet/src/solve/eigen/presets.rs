//! Named eigen parameter presets: what each kind of spectrum a search asks for needs, derived
//! from the user's [`EigenParams`] (never looser than them, except where a preset's accuracy
//! is all its use needs). The one place these choices live; the measurements behind them are
//! in `docs/benchmarks.md`.

use super::EigenParams;
use crate::solve::factor::SOLVE_GROUP;

/// Residual tolerance of the lowest pair of the greedy's spectra (at least). Its value
/// `λ_eq` comes out accurate to about the square of it over the relative gap to the next
/// eigenvalue (`1e-12 / gap`), below what fixes the equilibrium itself (a benign change of
/// Newton's path moves `λ_eq` by more).
pub const SPECTRUM_TOL: f64 = 1e-6;

/// Residual tolerance of the greedy spectra's other pairs: their vectors only span the
/// candidates' bound subspace and the next spectrum's start (any subspace gives valid
/// bounds); their values stay accurate to about `1e-8 / gap`.
pub const SPECTRUM_TRAILING_TOL: f64 = 1e-4;

/// Residual tolerance of a candidate's score (at least): the value's error is about its
/// square over the gap, below the tie tolerance's `1e-7`.
pub const SCORE_TOL: f64 = 1e-8;

impl EigenParams {
    /// The greedy's `λ_eq` spectra: `modes` pairs for the candidates' bounds, the lowest to
    /// [`SPECTRUM_TOL`] (the record), the others to [`SPECTRUM_TRAILING_TOL`] (a subspace), in
    /// blocks of up to a solver's column group whose columns are solved side by side (the
    /// spectrum runs while a core is idle).
    pub fn greedy_spectrum(&self, modes: usize) -> EigenParams {
        let mut p = self.clone();
        let k = modes.max(1);
        p.count = k;
        p.tol = p.tol.max(SPECTRUM_TOL);
        p.trailing_tol = Some(SPECTRUM_TRAILING_TOL.max(p.tol));
        p.block_size = SOLVE_GROUP.min(k);
        p.solve_group = 1;
        p.max_basis = p.max_basis.max(p.count + 6 * p.block_size);
        p
    }

    /// A candidate's score (and a set's `λ_eq` in the searches): only `λ`, one converged pair
    /// in a block of two that holds its neighbour (the smallest eigenvalues cluster), to
    /// [`SCORE_TOL`].
    pub fn candidate_score(&self) -> EigenParams {
        let mut p = self.clone();
        p.count = 1;
        p.block_size = 2.min(p.block_size);
        p.max_basis = p.max_basis.min(40);
        p.tol = p.tol.max(SCORE_TOL);
        p
    }

    /// `λ_fix` of a set at the full network's equilibrium (the certificates of its low modes):
    /// four pairs in a block of four, to the user's tolerance, at least `1e-10`.
    pub fn fixed_spectrum(&self) -> EigenParams {
        self.four_pairs(1e-10)
    }

    /// One step of the continuous relaxation (and its clamped certificates): as
    /// [`Self::fixed_spectrum`], to `1e-8` (the certificates are valid whatever the vectors).
    pub fn relaxation_step(&self) -> EigenParams {
        self.four_pairs(1e-8)
    }

    /// These parameters with every column of a block solved on a core of its own (factors far
    /// beyond the caches, where one pass for two columns costs nearly two passes).
    pub fn column_by_column(&self) -> EigenParams {
        EigenParams {
            solve_group: 1,
            ..self.clone()
        }
    }

    fn four_pairs(&self, tol: f64) -> EigenParams {
        let mut p = self.clone();
        p.count = 4;
        p.block_size = 4;
        p.max_basis = p.max_basis.clamp(32, 48);
        p.tol = self.tol.max(tol);
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_of_the_defaults_is_valid() {
        let base = EigenParams::default();
        for p in [
            base.greedy_spectrum(1),
            base.greedy_spectrum(6),
            base.candidate_score(),
            base.fixed_spectrum(),
            base.relaxation_step(),
            base.candidate_score().column_by_column(),
        ] {
            p.validate().expect("valid");
        }
        assert_eq!(base.greedy_spectrum(2).count, 2);
        assert_eq!(base.candidate_score().count, 1);
        assert_eq!(base.column_by_column().solve_group, 1);
    }

    #[test]
    fn presets_are_never_looser_than_the_users_tolerance_where_it_matters() {
        let strict = EigenParams {
            tol: 1e-12,
            ..Default::default()
        };
        assert_eq!(strict.fixed_spectrum().tol, 1e-10);
        let loose = EigenParams {
            tol: 1e-5,
            ..Default::default()
        };
        assert_eq!(loose.fixed_spectrum().tol, 1e-5);
        assert_eq!(loose.candidate_score().tol, 1e-5);
        assert_eq!(loose.greedy_spectrum(2).tol, 1e-5);
        assert_eq!(loose.greedy_spectrum(2).trailing_tol, Some(1e-4));
    }
}

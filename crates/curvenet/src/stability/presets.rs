//! The eigen solver's presets: how accurate each kind of spectrum needs to be, derived from
//! the user's [`EigenParams`] (never looser than them, except where a preset's accuracy is
//! all its use needs).

use super::Tuning;
use crate::solve::eigen::EigenParams;
use crate::solve::factor::SOLVE_GROUP;

/// Residual tolerance of the lowest pair of the greedy's spectra (at least). Its value
/// `λ_eq` comes out accurate to about the square of it over the relative gap to the next
/// eigenvalue (1e-12 / gap), below what fixes the equilibrium itself (a benign change of
/// Newton's path moves `λ_eq` by more).
pub const SPECTRUM_TOL: f64 = 1e-6;

/// Residual tolerance of the greedy spectra's other pairs: their vectors only span the
/// candidates' bound subspace and the next spectrum's start (any subspace gives valid
/// bounds); their values stay accurate to about 1e-8 / gap.
pub const SPECTRUM_TRAILING_TOL: f64 = 1e-4;

/// Pairs an edit computes ([`Preset::Edit`]): `λ` and the next eigenvalue, which shows how
/// isolated `λ` is (two modes of a symmetric network share one value). The start of the next
/// edit's eigen solve holds both modes.
pub const EDIT_PAIRS: usize = 2;

/// Residual tolerance of a candidate's score and a set's `λ_eq` (at least): the value's error
/// is about its square over the gap, below the tie tolerance's 1e-7.
pub const SCORE_TOL: f64 = 1e-8;

/// What a spectrum is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// A structure's analysis ([`super::Analyzer::analyze`]): the user's parameters as they
    /// are.
    Analysis,
    /// The greedy's `λ_eq` spectra: `modes` pairs for the candidates' bounds, the lowest to
    /// [`SPECTRUM_TOL`] (the record), the others to [`SPECTRUM_TRAILING_TOL`] (a subspace),
    /// in blocks of a solver's column group solved side by side (the spectrum runs while a
    /// core is idle).
    Greedy {
        /// Pairs computed.
        modes: usize,
    },
    /// A candidate's score and a set's `λ_eq`: only `λ`, one converged pair in a block of two
    /// that holds its neighbour (clustered smallest eigenvalues), its residual to
    /// [`SCORE_TOL`].
    Score,
    /// An edit's spectrum ([`super::Analyzer::analyze_edit`]): [`EDIT_PAIRS`] pairs (fewer if
    /// the user asks for fewer), the lowest (`λ`, served) to [`SPECTRUM_TOL`] at least, the
    /// other (shown) to [`SPECTRUM_TRAILING_TOL`]: values accurate far beyond what is
    /// displayed.
    Edit,
    /// `λ_fix` of a set at the full network's equilibrium: four pairs (the certificates of
    /// its low modes) to the user's tolerance, at most 1e-10.
    Fixed,
    /// One step of the relaxation (and the clamped certificates): as [`Preset::Fixed`], to
    /// 1e-8 (the certificates are valid whatever the vectors).
    Relaxation,
}

impl Preset {
    /// The eigen parameters of this preset, from the user's `base`.
    pub fn params(self, base: &EigenParams) -> EigenParams {
        let mut p = base.clone();
        match self {
            Preset::Analysis => {}
            Preset::Greedy { modes } => {
                let k = modes.max(1);
                p.count = k;
                p.tol = p.tol.max(SPECTRUM_TOL);
                p.trailing_tol = Some(SPECTRUM_TRAILING_TOL.max(p.tol));
                p.block_size = SOLVE_GROUP.min(k);
                p.solve_group = 1;
                p.max_basis = p.max_basis.max(p.count + 6 * p.block_size);
            }
            Preset::Edit => {
                p.count = p.count.min(EDIT_PAIRS);
                p.tol = p.tol.max(SPECTRUM_TOL);
                p.trailing_tol = Some(SPECTRUM_TRAILING_TOL.max(p.tol));
            }
            Preset::Score => {
                p.count = 1;
                p.block_size = 2.min(p.block_size);
                p.max_basis = p.max_basis.min(40);
                p.tol = p.tol.max(SCORE_TOL);
            }
            Preset::Fixed | Preset::Relaxation => {
                p.count = 4;
                p.block_size = 4;
                p.max_basis = p.max_basis.clamp(32, 48);
                p.tol = base
                    .tol
                    .max(if self == Preset::Fixed { 1e-10 } else { 1e-8 });
            }
        }
        p
    }

    /// [`Self::params`] for a factor storing `factor_values` values: beyond
    /// [`Tuning::large_factor_values`] each column of a block is solved on a core of its own.
    pub fn params_for(
        self,
        base: &EigenParams,
        tuning: &Tuning,
        factor_values: usize,
    ) -> EigenParams {
        let mut p = self.params(base);
        if factor_values > tuning.large_factor_values {
            p.solve_group = 1;
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_is_valid_from_the_defaults() {
        let base = EigenParams::default();
        for p in [
            Preset::Analysis,
            Preset::Greedy { modes: 1 },
            Preset::Greedy { modes: 6 },
            Preset::Edit,
            Preset::Score,
            Preset::Fixed,
            Preset::Relaxation,
        ] {
            p.params(&base).validate().expect("valid");
        }
        assert_eq!(Preset::Analysis.params(&base), base);
        assert_eq!(Preset::Greedy { modes: 2 }.params(&base).count, 2);
        assert_eq!(Preset::Score.params(&base).count, 1);
        let tuning = Tuning::default();
        let large = Preset::Score.params_for(&base, &tuning, tuning.large_factor_values + 1);
        assert_eq!(large.solve_group, 1);
    }

    #[test]
    fn presets_are_never_looser_than_the_users_tolerance_where_it_matters() {
        let strict = EigenParams {
            tol: 1e-12,
            ..Default::default()
        };
        assert_eq!(Preset::Fixed.params(&strict).tol, 1e-10);
        assert_eq!(Preset::Relaxation.params(&strict).tol, 1e-8);
        let loose = EigenParams {
            tol: 1e-5,
            ..Default::default()
        };
        assert_eq!(Preset::Fixed.params(&loose).tol, 1e-5);
        assert_eq!(Preset::Score.params(&loose).tol, 1e-5);
        let greedy = Preset::Greedy { modes: 2 }.params(&loose);
        assert_eq!(greedy.tol, 1e-5);
        assert_eq!(greedy.trailing_tol, Some(1e-4));
    }
}

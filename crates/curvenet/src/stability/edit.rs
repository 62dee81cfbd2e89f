//! [`Analyzer::analyze_edit`]: a structure's analysis warm-started from a nearby structure
//! already analysed — what an interactive edit (curves removed or restored) needs.
//!
//! The edit's Newton solve starts from the previous equilibrium, restricted to the new
//! structure (vertices no kept curve holds go back to their drawn state, where a cold solve
//! leaves them) and extended to it (the vertices of a restored curve that the previous
//! structure did not hold are interpolated along the curve, by rest arc length, between its
//! held vertices); the eigen solver starts from the previous low modes. Newton's tolerance is
//! judged against the structure's drawn-state gradient whatever the start, so the equilibrium
//! is solved as accurately as a cold analysis solves it.
//!
//! **The work.** Near an equilibrium the Hessian changes little from step to step: Newton
//! factors it at the start and solves the later steps by conjugate gradients preconditioned
//! with that factorization (Krylov steps, [`crate::solve::Equilibrium::relax_near`]),
//! factoring afresh only once the factored Hessian has drifted. The spectrum, in the
//! objective's metric as a cold analysis's, converges `λ` (served) to a residual of
//! [`super::SPECTRUM_TOL`] and the other pairs (shown) to [`super::SPECTRUM_TRAILING_TOL`]
//! ([`Preset::Edit`]): `λ` comes out accurate to about the square of that over the gap, far
//! below the equilibrium's own tolerance.
//!
//! **Which equilibrium.** A cold analysis relaxes from the drawn state; a warm start could in
//! principle reach another equilibrium. Only a stable structure has an isolated one that a
//! warm start is trusted to share with the cold solve: the warm answer is kept when Newton
//! converged without meeting a saddle (the warm relaxation stops at the first indefinite
//! Hessian instead of walking over it) and the spectrum is positive. Otherwise (a mechanism,
//! whose equilibria form a family; an unstable or unconverged state; a path that met a saddle)
//! the structure is analysed again from the drawn state, exactly as [`Analyzer::analyze`]
//! does, and [`Edit::start`] says so.

use super::presets::Preset;
use super::{Analysis, Analyzer, StabilityError, numerics};
use crate::rod::ActiveSet;
use faer::MatRef;
use serde::Serialize;

/// An analysed structure an edit starts from: its curves, its equilibrium and its low modes.
#[derive(Clone, Copy, Debug)]
pub struct EditStart<'a> {
    /// The structure's curves.
    pub active: &'a ActiveSet,
    /// Its displacements at equilibrium (3 per vertex).
    pub displacement: &'a [f64],
    /// Its lowest eigenvectors (columns, 3 rows per vertex).
    pub modes: MatRef<'a, f64>,
}

/// Where an edit's equilibrium was relaxed from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EditFrom {
    /// From the previous structure's equilibrium (the warm start held).
    Warm,
    /// From the drawn state, as a cold analysis: the warm answer was not a stable, converged
    /// equilibrium, or there was no previous structure.
    Drawn,
}

/// An edit's analysis and where its equilibrium was relaxed from.
#[derive(Clone, Debug)]
pub struct Edit {
    /// The analysis (no gravity deflection: [`Analysis::gravity`] is `None`).
    pub analysis: Analysis,
    /// The relaxation's start.
    pub start: EditFrom,
}

impl Analyzer {
    /// The analysis of `active` warm-started from `from` (see the module documentation):
    /// the same `λ`, modes and equilibrium as [`Self::analyze`] from the drawn state, to the
    /// solvers' tolerances, in a fraction of its work. The gravity deflection is left out.
    ///
    /// # Errors
    ///
    /// An empty structure or a failed eigen solve.
    pub fn analyze_edit(
        &self,
        active: &ActiveSet,
        from: EditStart<'_>,
    ) -> Result<Edit, StabilityError> {
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let model = self.model();
        let mask = model.vertex_mask(active);
        let mut u = self.edit_displacement(from, active, &mask);
        let keep = model.coordinate_mask(active);
        let start_block = edit_start_block(from.modes, &keep, &self.params().eigen);
        let symbolic = self.symbolic_for(active);
        let (newton, h) = self.relax_near(active, &mut u, &symbolic);
        // `relax_near` stops at a saddle: converged means it never passed one.
        if newton.converged {
            let eigen = Preset::Edit.params(&self.params().eigen);
            let start = Some(start_block.as_ref());
            let (spectrum, ()) = self.in_metric(active, &h, |h| {
                let s = numerics::spectrum(model.pattern(), h, &symbolic, start, &eigen)?;
                Ok((s, ()))
            })?;
            if spectrum.zero_modes == 0 && spectrum.negative_modes == 0 {
                let mode_curves = self.mode_curves(active, spectrum.vectors.col(0).iter().copied());
                return Ok(Edit {
                    analysis: Analysis {
                        newton,
                        displacement: u,
                        spectrum,
                        mode_curves,
                        gravity: None,
                    },
                    start: EditFrom::Warm,
                });
            }
        }
        let mut analysis = self.analyze(active, None)?;
        analysis.gravity = None;
        Ok(Edit {
            analysis,
            start: EditFrom::Drawn,
        })
    }

    /// The start of an edit's relaxation: `from`'s displacements on the vertices both
    /// structures hold, the drawn state on vertices `active` leaves loose (`mask` false), and
    /// on the vertices `active` holds that `from` did not, an interpolation along each curve
    /// between its vertices `from` held (by rest arc length; the nearest one past the last).
    fn edit_displacement(
        &self,
        from: EditStart<'_>,
        active: &ActiveSet,
        mask: &[bool],
    ) -> Vec<f64> {
        let model = self.model();
        let before = model.vertex_mask(from.active);
        let mut u = vec![0.0; model.dofs()];
        for (v, (&now, &then)) in mask.iter().zip(&before).enumerate() {
            if now && then {
                u[3 * v..3 * v + 3].copy_from_slice(&from.displacement[3 * v..3 * v + 3]);
            }
        }
        for (c, rod) in self.network().rods.iter().enumerate() {
            if active.contains(c) && !from.active.contains(c) {
                extend_along(rod, &before, from.displacement, &mut u);
            }
        }
        // A pre-bent rod's twists (the physical mode): kept where both structures hold its
        // rod, untwisted where it comes back.
        let first = 3 * mask.len();
        for (k, t) in model.twist_dofs().iter().enumerate() {
            let c = t.curve as usize;
            if active.contains(c) && from.active.contains(c) {
                u[first + k] = from.displacement[first + k];
            }
        }
        u
    }
}

/// The eigen solver's start block for an edit: the previous structure's lowest modes
/// restricted to the new one, all but one column of a block, and one random column over the
/// held coordinates (`keep`: `EnergyModel::coordinate_mask`). The previous modes alone can miss the new structure's lowest mode
/// entirely: a symmetric network's modes are symmetric or antisymmetric, and a Krylov space
/// grown from vectors orthogonal to the new lowest mode never holds it (a 3 × 3 grid of arcs
/// reported its second-lowest eigenvalue as `λ`). The random column gives every mode a part
/// of the start, and the inverted operator brings the lowest to the front at once.
fn edit_start_block(
    modes: MatRef<'_, f64>,
    keep: &[bool],
    eigen: &crate::solve::eigen::EigenParams,
) -> faer::Mat<f64> {
    let warm = modes.ncols().min(eigen.block_size.saturating_sub(1));
    let restricted = super::evaluate::restrict(modes.subcols(0, warm), keep);
    let mut block = faer::Mat::<f64>::zeros(modes.nrows(), warm + 1);
    block.subcols_mut(0, warm).copy_from(&restricted);
    let mut rng = crate::rng::SplitMix64::new(eigen.seed);
    for (i, &held) in keep.iter().enumerate() {
        let x = rng.uniform(-1.0, 1.0);
        if held {
            block[(i, warm)] = x;
        }
    }
    block
}

/// Sets the displacements in `u` of `rod`'s vertices not `held` by interpolating `from`
/// along the rod between its held vertices (by rest arc length; around a closed rod; past an
/// open rod's last held vertex, that vertex's). A rod with no held vertex stays drawn.
fn extend_along(rod: &crate::rod::Rod, held: &[bool], from: &[f64], u: &mut [f64]) {
    let n = rod.vertices.len();
    let at: Vec<usize> = rod.vertices.iter().map(|&v| v as usize).collect();
    let anchors: Vec<usize> = (0..n).filter(|&i| held[at[i]]).collect();
    let (Some(&first), Some(&last)) = (anchors.first(), anchors.last()) else {
        return;
    };
    // Arc length at each vertex along the rod; `total` closes a closed rod's loop.
    let mut s = vec![0.0; n];
    for i in 1..n {
        s[i] = s[i - 1] + rod.rest_lengths[i - 1];
    }
    let total = rod.rest_length();
    let value = |i: usize| &from[3 * at[i]..3 * at[i] + 3];
    for i in 0..n {
        if held[at[i]] {
            continue;
        }
        let next = anchors.iter().copied().find(|&a| a > i);
        let prev = anchors.iter().copied().rev().find(|&a| a < i);
        let (a, b, sa, sb) = match (prev, next) {
            (Some(a), Some(b)) => (a, b, s[a], s[b]),
            (None, Some(b)) if rod.closed => (last, b, s[last] - total, s[b]),
            (Some(a), None) if rod.closed => (a, first, s[a], s[first] + total),
            (None, Some(b)) => (b, b, s[b], s[b]),
            (Some(a), None) => (a, a, s[a], s[a]),
            (None, None) => return,
        };
        let t = if sb > sa {
            (s[i] - sa) / (sb - sa)
        } else {
            0.0
        };
        let (va, vb) = (value(a), value(b));
        for k in 0..3 {
            u[3 * at[i] + k] = (1.0 - t) * va[k] + t * vb[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::stability::test_support::{dome_analyzer as dome, dome_analyzer_with};
    use crate::stability::{Analyzer, EditFrom, EditStart, Objective, StabilityParams};

    /// A removal and a restore, warm-started, give the cold analysis's `λ` and equilibrium;
    /// the loose vertices stay drawn. The warm relaxations factor once and take Krylov steps.
    #[test]
    fn warm_edits_give_the_cold_lambda() {
        let krylov = edits_match_cold(&dome());
        assert!(krylov > 0, "no Krylov step");
    }

    /// An edit whose new lowest mode is orthogonal to every previous mode (a symmetric grid:
    /// curve 4's mode after curves 1 and 5 go, from modes living on curve 1) still finds it:
    /// the start block holds a random column.
    #[test]
    fn an_edit_finds_a_lowest_mode_the_previous_modes_miss() {
        let an = crate::stability::test_support::grid_analyzer();
        let all = an.all();
        let from_set = all.without(4);
        let before = an.analyze(&from_set, None).unwrap();
        for next in [all.without(1).without(5), all.without(3).without(5)] {
            let from = EditStart {
                active: &from_set,
                displacement: &before.displacement,
                modes: before.spectrum.vectors.as_ref(),
            };
            let edit = an.analyze_edit(&next, from).unwrap();
            let cold = an.analyze(&next, None).unwrap();
            let (w, c) = (edit.analysis.lambda(), cold.lambda());
            assert!((w - c).abs() <= 1e-6 * c.abs(), "warm {w:e}, cold {c:e}");
        }
    }

    /// Under the frequency objective an edit's value is `μ_min` of the mass metric, as the
    /// cold analysis's.
    #[test]
    fn warm_edits_give_the_cold_frequency_objective() {
        let params = StabilityParams {
            objective: Objective::Frequency,
            ..Default::default()
        };
        edits_match_cold(&dome_analyzer_with(params));
    }

    /// Warm edits of `an` (two removals, then restores) against cold analyses of the same
    /// sets; the Krylov steps the warm relaxations took.
    fn edits_match_cold(an: &Analyzer) -> usize {
        let mut krylov = 0;
        let all = an.all();
        let full = an.analyze(&all, None).unwrap();
        let mut prev = (all.clone(), full);
        for next in [
            all.without(2),
            all.without(2).without(4),
            all.without(4),
            all.clone(),
        ] {
            let from = EditStart {
                active: &prev.0,
                displacement: &prev.1.displacement,
                modes: prev.1.spectrum.vectors.as_ref(),
            };
            let edit = an.analyze_edit(&next, from).unwrap();
            krylov += edit.analysis.newton.krylov_steps;
            let cold = an.analyze(&next, None).unwrap();
            let (w, c) = (edit.analysis.lambda(), cold.lambda());
            assert!((w - c).abs() <= 1e-6 * c.abs(), "warm {w:e}, cold {c:e}");
            if edit.start == EditFrom::Warm {
                let du = edit
                    .analysis
                    .displacement
                    .iter()
                    .zip(&cold.displacement)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                let scale = cold
                    .displacement
                    .iter()
                    .fold(0.0, |m: f64, x| m.max(x.abs()));
                assert!(
                    du <= 1e-6 * scale,
                    "equilibria {du:e} apart (scale {scale:e})"
                );
            }
            prev = (next, edit.analysis);
        }
        krylov
    }
}

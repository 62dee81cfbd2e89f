//! Which modes of `H v = μ M v` are zero or negative, judged where round-off lives.
//!
//! The mass-metric eigenvalues come from `H̃ = M^{-1/2} H M^{-1/2}`, whose 1-norm grows
//! without bound next to a vertex that carries almost no mass (two joints a hair apart along
//! a curve leave a tiny rest edge between them). A zero band `C·ε·‖H̃‖₁` then swallows the
//! clearly positive `μ` of a stable structure. Round-off, though, is that of `H` itself: the
//! assembly and the factorization work on `H`'s entries, so a mode is a mechanism when its
//! energy per unit squared displacement is at `H`'s round-off level.
//!
//! The rule: for a unit eigenvector `ṽ` of `H̃` with eigenvalue `μ`, the displacement is
//! `v = M^{-1/2} ṽ` and its Rayleigh quotient in the identity metric is
//! `ρ = vᵀHv / vᵀv = μ / Σᵢ ṽᵢ² / mᵢ`. The mode is zero when `|ρ| ≤ C·ε·‖H‖₁` (the same `C` and
//! the same band as the paper's λ, over the coordinates the structure holds), negative when
//! `ρ` lies below it, positive otherwise. Signs agree with `H`'s own inertia (Sylvester's law:
//! `H̃` is congruent to `H`), so only the width of the band changes, and it is the one the
//! identity-metric analysis already uses.

use crate::solve::eigen::Spectrum;
use crate::sparse::Pattern;

/// How each computed mode of the mass-metric problem is classified.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeSigns {
    /// Modes whose identity-metric Rayleigh quotient lies in the zero band.
    pub zero: usize,
    /// Modes below the band.
    pub negative: usize,
    /// Per computed mode (in the spectrum's order): above the band.
    pub positive: Vec<bool>,
    /// The band's half-width in the identity metric, `C·ε·‖H‖₁` over the held coordinates.
    pub threshold: f64,
}

impl ModeSigns {
    /// No zero or negative mode and at least one positive one.
    pub fn stable(&self) -> bool {
        self.zero == 0 && self.negative == 0 && self.positive.first().copied().unwrap_or(false)
    }
}

/// Classifies the modes of `modes` (pairs of `M^{-1/2} H M^{-1/2}`, see the module's docs).
/// `hess` holds `H`'s upper-triangle values over `pattern`, `inv_sqrt` the per-coordinate
/// `1/√m`, `keep` the coordinates the structure holds, `zero_factor` the band's `C`.
pub fn classify(
    modes: &Spectrum,
    pattern: &Pattern,
    hess: &[f64],
    inv_sqrt: &[f64],
    keep: &[bool],
    zero_factor: f64,
) -> ModeSigns {
    let threshold = zero_factor * f64::EPSILON * held_norm1(pattern, hess, keep);
    let mut signs = ModeSigns {
        zero: 0,
        negative: 0,
        positive: Vec::with_capacity(modes.values.len()),
        threshold,
    };
    for (k, &mu) in modes.values.iter().enumerate() {
        let weight: f64 = (0..inv_sqrt.len())
            .filter(|&i| keep[i])
            .map(|i| (inv_sqrt[i] * modes.vectors[(i, k)]).powi(2))
            .sum();
        let rho = mu / weight;
        let positive = rho > threshold;
        if rho < -threshold {
            signs.negative += 1;
        } else if !positive {
            signs.zero += 1;
        }
        signs.positive.push(positive);
    }
    signs
}

/// `‖H‖₁` of the principal submatrix of the coordinates `keep` marks.
fn held_norm1(pattern: &Pattern, values: &[f64], keep: &[bool]) -> f64 {
    let (sub, slots, _) = pattern.principal(keep);
    let held: Vec<f64> = slots.iter().map(|&k| values[k]).collect();
    sub.sym_norm1(&held)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    /// A diagonal `H` over three coordinates as a pattern and values.
    fn diagonal(d: &[f64]) -> (Pattern, Vec<f64>) {
        let n = d.len();
        let pattern = Pattern {
            n,
            col_ptr: (0..=n).collect(),
            row_idx: (0..n).collect(),
            diag: (0..n).collect(),
        };
        (pattern, d.to_vec())
    }

    fn spectrum(values: Vec<f64>, n: usize) -> Spectrum {
        let k = values.len();
        Spectrum {
            values,
            vectors: Mat::from_fn(n, k, |i, j| if i == j { 1.0 } else { 0.0 }),
            residuals: vec![0.0; k],
            norm1: 0.0,
            zero_threshold: 0.0,
            zero_modes: 0,
            negative_modes: 0,
            shift: 0.0,
            factorizations: 1,
            solves: 0,
            restarts: 0,
            unconverged: 0,
        }
    }

    #[test]
    fn a_nearly_massless_coordinate_does_not_widen_the_zero_band() {
        // H = diag(1, 2, 1e6), masses (1, 1, 1e-12): H̃ = diag(1, 2, 1e18). A band of
        // 5 ε ‖H̃‖₁ ≈ 1100 would call μ = 1 and μ = 2 zero; in the identity metric they are
        // clearly positive.
        let (pattern, hess) = diagonal(&[1.0, 2.0, 1e6]);
        let masses = [1.0, 1.0, 1e-12];
        let inv_sqrt: Vec<f64> = masses.iter().map(|m: &f64| 1.0 / m.sqrt()).collect();
        let modes = spectrum(vec![1.0, 2.0], 3);
        let signs = classify(&modes, &pattern, &hess, &inv_sqrt, &[true; 3], 5.0);
        assert_eq!((signs.zero, signs.negative), (0, 0));
        assert_eq!(signs.positive, vec![true, true]);
        assert!(signs.stable());
        // The band scaled by H̃'s norm would have swallowed both.
        let scaled_band = 5.0 * f64::EPSILON * 1e18;
        assert!(modes.values.iter().all(|&mu| mu < scaled_band));
    }

    #[test]
    fn mechanisms_and_negative_modes_are_named() {
        let (pattern, hess) = diagonal(&[-1.0, 1e-20, 1.0]);
        let inv_sqrt = vec![1.0; 3];
        let modes = spectrum(vec![-1.0, 1e-20, 1.0], 3);
        let signs = classify(&modes, &pattern, &hess, &inv_sqrt, &[true; 3], 5.0);
        assert_eq!((signs.zero, signs.negative), (1, 1));
        assert_eq!(signs.positive, vec![false, false, true]);
        assert!(!signs.stable());
    }

    #[test]
    fn coordinates_the_structure_does_not_hold_are_left_out_of_the_norm() {
        let (pattern, hess) = diagonal(&[1.0, 1e30]);
        let keep = [true, false];
        let modes = spectrum(vec![1.0], 2);
        let signs = classify(&modes, &pattern, &hess, &[1.0, 1.0], &keep, 5.0);
        assert!(signs.stable());
        assert!(signs.threshold < 1e-14);
    }
}

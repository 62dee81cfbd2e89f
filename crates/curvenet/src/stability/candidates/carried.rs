//! Test vectors carried from one iteration's candidates to the next.

use super::Candidates;
use super::dense::zero_rows;
use faer::{Mat, MatRef};

/// Test vectors handed from one greedy iteration's candidates to the next, per curve: each
/// the best approximation found of the lowest mode of the structure without that curve (the
/// candidate's eigenvector when it was scored, else its refined or extended bound's Ritz
/// vector). A structure changes little from one iteration to the next, so the vector is a
/// good test vector again: with the plain Ritz vectors it gives a bound that often prunes the
/// candidate without a solve, and each refinement starts where the last one ended (an
/// iterated preconditioned step across iterations). Stored in single precision: a test
/// vector's Rayleigh quotient is exact for whatever vector it is, so rounding it costs only
/// a second-order change in the bound.
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

impl Candidates<'_> {
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

    /// Whether candidate `c` has a vector carried over from the previous iteration.
    pub fn has_carried(&self, c: usize) -> bool {
        !self.analyzer.mass_metric() && self.carried.get(c).is_some_and(Option::is_some)
    }

    /// Records `v` as candidate `c`'s best test vector so far.
    pub(super) fn offer(&self, c: usize, value: f64, v: MatRef<'_, f64>) {
        let vector = v.col(0).iter().map(|&x| x as f32).collect();
        if let Ok(mut g) = self.carry_out[c].lock() {
            *g = Some(CarriedVector { value, vector });
        }
    }

    /// Candidate `c`'s carried vector on `A \ {c}`'s coordinates (one column; `None` without
    /// one, or if it vanishes there): zero on the vertices no curve of `A` holds (it may
    /// still have values on the last winner's) and on `c`'s loose ones.
    pub(super) fn carried_y(&self, c: usize) -> Option<Mat<f64>> {
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
}

//! `λ_eq` of any set of curves, the way every search ranks a subset: relaxed from the drawn
//! state (path-independent, so the searches' answers compare), by connected parts, each part
//! computed once per analyzer, with its equilibrium's largest displacement (the
//! `--max-deviation` of the part in the paper's mode: a set's is the largest of its parts'; in
//! the physical mode the largest deviation is the physical model's under self-weight,
//! [`crate::physics::deviation`], measured per part when first asked for).

use super::presets::Preset;
use super::{Analyzer, StabilityError, StabilityParams};
use crate::rod::ActiveSet;

impl Analyzer {
    /// `λ_eq(active)` relaxed from the drawn state.
    ///
    /// Curves that share no vertex are independent structures: the Hessian is block diagonal
    /// and each part relaxes on its own, so `λ_eq` is the smallest `λ_eq` of the connected
    /// parts. Each part's value is computed once and remembered (searches over subsets meet
    /// the same parts again and again).
    pub fn lambda_eq(&self, active: &ActiveSet) -> Result<f64, StabilityError> {
        Ok(self
            .lambda_eq_parts(active)?
            .iter()
            .map(|p| p.1)
            .fold(f64::INFINITY, f64::min))
    }

    /// The connected parts of `active` ([`Self::components`]) with the `λ_eq` of each,
    /// relaxed on its own (remembered); [`Self::lambda_eq`] is the smallest of them.
    pub fn lambda_eq_parts(
        &self,
        active: &ActiveSet,
    ) -> Result<Vec<(Vec<usize>, f64)>, StabilityError> {
        Ok(self
            .parts_of(active)?
            .into_iter()
            .map(|p| (p.curves, p.lambda))
            .collect())
    }

    /// The connected parts of `active` ([`Self::components`]), each relaxed on its own
    /// (remembered) with its `λ_eq` and its equilibrium's largest displacement.
    pub fn parts_of(&self, active: &ActiveSet) -> Result<Vec<Part>, StabilityError> {
        if active.is_empty() {
            return Err(StabilityError::Empty);
        }
        let mut parts = Vec::new();
        for part in self.components(active) {
            let cached = self.parts.lock().expect("cache lock").get(&part).copied();
            let (lambda, deviation) = match cached {
                Some(v) => v,
                None => {
                    let v = self.lambda_eq_connected(&part)?;
                    self.parts
                        .lock()
                        .expect("cache lock")
                        .insert(part.clone(), v);
                    v
                }
            };
            parts.push(Part {
                curves: part,
                lambda,
                deviation,
            });
        }
        Ok(parts)
    }

    /// The largest deviation of a vertex of `active` from its designed place (by parts, as
    /// [`Self::lambda_eq`]; remembered): [`Self::part_deviation`]'s largest.
    pub fn deviation(&self, active: &ActiveSet) -> Result<f64, StabilityError> {
        Ok(self.parts_deviation(&self.parts_of(active)?))
    }

    /// The largest deviation of a vertex of the connected `part` from its designed place,
    /// scene units, what the largest-deviation constraint bounds: in the paper's mode its
    /// equilibrium's largest displacement ([`Part::deviation`]); in the physical mode the
    /// physical model's, its equilibrium plus its self-weight deflection
    /// ([`crate::physics::deviation`]), measured on first use and remembered.
    pub fn part_deviation(&self, part: &Part) -> f64 {
        let Some(params) = self.physical() else {
            return part.deviation;
        };
        let known = self
            .physical_deviations
            .lock()
            .expect("cache lock")
            .get(&part.curves)
            .copied();
        if let Some(d) = known {
            return d;
        }
        let model = self
            .deviation_model
            .get_or_init(|| crate::physics::DeviationModel::new(self.network(), params));
        let d = model.measure(self.network(), &self.set(&part.curves));
        self.physical_deviations
            .lock()
            .expect("cache lock")
            .insert(part.curves.clone(), d);
        d
    }

    /// The largest of the parts' deviations ([`Self::part_deviation`]; 0 for none).
    pub fn parts_deviation(&self, parts: &[Part]) -> f64 {
        parts
            .iter()
            .map(|p| self.part_deviation(p))
            .fold(0.0, f64::max)
    }

    /// The largest deviation from its designed place of a vertex of the structure `curves`
    /// whose equilibrium in the searches' model is `u` (three displacements per vertex of the
    /// network): in the paper's mode the largest of `u` over the structure's vertices, in the
    /// physical mode the physical model's ([`Self::part_deviation`], by parts).
    ///
    /// # Errors
    ///
    /// The physical mode's parts could not be evaluated.
    pub fn structure_deviation(&self, curves: &[usize], u: &[f64]) -> Result<f64, StabilityError> {
        if self.physical().is_some() {
            return self.deviation(&self.set(curves));
        }
        let network = self.network();
        let mut worst = 0.0f64;
        for &c in curves {
            for &v in &network.rods[c].vertices {
                let i = 3 * v as usize;
                if let Some(d) = u.get(i..i + 3) {
                    worst = worst.max((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
                }
            }
        }
        Ok(worst)
    }

    /// Connected structures whose `λ_eq` this analyzer has computed and remembers (each one
    /// relaxation and one eigen solve; see [`Self::lambda_eq`]).
    pub fn cached_structures(&self) -> usize {
        self.parts.lock().expect("cache lock").len()
    }

    /// `λ_eq` (or under the frequency objective `μ_min`: the lumped mass of a vertex comes
    /// from the curves through it, so `M` is block diagonal over the parts too) of a
    /// connected structure, on its own network (the loose vertices deleted, so
    /// the factorizations only see the structure's own unknowns), and the largest
    /// displacement of a vertex at that equilibrium.
    fn lambda_eq_connected(&self, curves: &[usize]) -> Result<(f64, f64), StabilityError> {
        let (network, _) = self.network().sub_network(curves);
        let params = StabilityParams {
            eigen: Preset::Score.params(&self.params().eigen),
            ..self.params().clone()
        };
        let sub = self
            .for_sub_network(network, curves, params)
            .map_err(StabilityError::Params)?;
        let active = sub.all();
        let mut u = vec![0.0; sub.model().dofs()];
        sub.relax(&active, &mut u);
        let lambda = sub.spectrum(&active, &u, None)?.lambda();
        Ok((lambda, largest_displacement(sub.network(), &u)))
    }
}

/// A connected part of a set of curves, relaxed on its own.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Its curves, ascending.
    pub curves: Vec<usize>,
    /// Its `λ_eq`.
    pub lambda: f64,
    /// The largest displacement of one of its vertices at its equilibrium in the searches'
    /// model (scene units): the largest deviation in the paper's mode
    /// ([`Analyzer::part_deviation`] gives the physical mode's).
    pub deviation: f64,
}

/// `max_v |u_v|` over the vertices of `network`'s rods (3 displacements per vertex).
fn largest_displacement(network: &crate::network::Network, u: &[f64]) -> f64 {
    let mut worst = 0.0f64;
    for rod in &network.rods {
        for &v in &rod.vertices {
            let i = 3 * v as usize;
            if let Some(d) = u.get(i..i + 3) {
                worst = worst.max((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
            }
        }
    }
    worst
}

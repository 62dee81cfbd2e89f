//! A structure under its load cases ([`super::cases`]): the equilibrium under each case and
//! combination, what it deflects and how hard its rods work there, and the load factor at
//! which it buckles.
//!
//! - **The loaded equilibrium** is geometrically nonlinear: the load grows in steps from the
//!   unloaded equilibrium (a tenth of it first, steps growing by half after each success up
//!   to a tenth of the factor reached, and halving after each failure), each step relaxed by Newton's method from the
//!   tangent's prediction `u + Δα H⁻¹ f` ([`Equilibrium::relax_near`]: it never walks over
//!   a saddle), and accepted when Newton converges within half the predicted change of the
//!   prediction (farther, it has jumped to another branch, e.g. past a snap) and the
//!   Hessian there factors (is positive definite: the equilibrium is stable).
//! - **The critical load factor** `α_cr` is the smallest multiple of the load at which the
//!   loaded equilibrium stops being stable: the steps go on past 1 (up to
//!   [`MAX_LOAD_FACTOR`]) until one fails, then halve between the last stable factor and the
//!   failed one until they are [`FACTOR_TOLERANCE`] apart (relative); `α_cr` is the last
//!   stable factor. Its **mode** is the lowest eigenvector of the Hessian there. A *limit
//!   point* (the load reaches a maximum, the structure snaps) is told from a *bifurcation*
//!   (another equilibrium branches off) by the work the load does on the mode: a limit
//!   point's mode is loaded (`|f·v| / (|f| |v|)` above [`LIMIT_POINT_WORK`]), a bifurcation's
//!   is orthogonal to the load.
//! - **The linearised estimate** is the classical one from the unloaded state `u₀`: the
//!   smallest `α` at which `H₀ + α D` stops being positive definite, `D` the change of the
//!   Hessian along the linear response `H₀⁻¹ f` (by central differences), found by the same
//!   halving on factorizations. Where the structure deflects much before it buckles, the two
//!   differ, and the nonlinear one is the structure's.
//! - **A pressure** (a follower load, [`crate::rod::Pressure`]) grows with the same factor as
//!   the case's dead forces; the load is then the forces at the state (the pressure turns
//!   with the curves): the tangent's prediction and the work share use the forces where the
//!   structure is, and the linearised estimate adds the pressure's own stiffness (its
//!   constant Hessian) to `D`.

use super::cases::{CaseForces, Snap};
use super::loads::max_displacement;
use super::stress::assembly_stresses;
use crate::geom::Vec3;
use crate::material::{Physical, RestShape};
use crate::rod::{ActiveSet, EnergyModel, Network, Pressure};
use crate::solve::{Cholesky, Equilibrium, NewtonParams, SolverTuning, SymbolicFactor};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;

/// The largest load factor followed: a structure that stands this multiple of its load has
/// no critical factor reported.
pub const MAX_LOAD_FACTOR: f64 = 100.0;

/// How close (relative) the critical load factor is bracketed.
pub const FACTOR_TOLERANCE: f64 = 1e-3;

/// The first load step, as a fraction of the load.
const FIRST_STEP: f64 = 0.1;

/// The largest load step, as a fraction of the factor reached (of the load below 1): small
/// enough that a step past a limit point lands far from the tangent's prediction.
const MAX_STEP: f64 = 0.1;

/// The work share `|f·v| / (|f| |v|)` above which a loss of stability is a limit point.
pub const LIMIT_POINT_WORK: f64 = 1e-3;

/// What a structure does under one load case or combination.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadCaseReport {
    /// The case's or combination's name.
    pub name: String,
    /// A combination's factors on its cases (absent for a case).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub factors: BTreeMap<String, f64>,
    /// Whether the structure has a stable equilibrium under the whole load.
    pub holds: bool,
    /// The largest deflection under the load (from the unloaded equilibrium), scene units
    /// (absent when it does not hold).
    pub max_deflection: Option<f64>,
    /// Where it occurs.
    pub max_deflection_vertex: Option<usize>,
    /// The largest utilisation there (combined stress over strength).
    pub max_utilisation: Option<f64>,
    /// The critical load factor `α_cr` (absent when the structure stands
    /// [`MAX_LOAD_FACTOR`] times the load).
    pub buckling_factor: Option<f64>,
    /// How it loses stability there: `limit point` or `bifurcation`.
    pub buckling: Option<String>,
    /// The linearised estimate of the critical factor from the unloaded state (absent above
    /// [`MAX_LOAD_FACTOR`]).
    pub linear_buckling_factor: Option<f64>,
    /// The deflection limit checked, scene units.
    pub deflection_limit: Option<f64>,
    /// Holds, within the deflection limit, no rod over its strength, and a critical factor
    /// at least the required one.
    pub passes: bool,
    /// Why it does not pass (empty when it does).
    pub failures: Vec<String>,
    /// Where its point loads act.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub snaps: Vec<Snap>,
}

impl LoadCaseReport {
    /// One line for a summary, lengths in `units`.
    pub fn to_text(&self, units: &str) -> String {
        use crate::fmt::significant as sig;
        let what = if self.factors.is_empty() {
            format!("load case {}", self.name)
        } else {
            let terms: Vec<String> = (self.factors.iter())
                .map(|(c, f)| format!("{}·{c}", sig(*f, 3)))
                .collect();
            format!("combination {} ({})", self.name, terms.join(" + "))
        };
        let mut parts = Vec::new();
        if let (Some(d), Some(v)) = (self.max_deflection, self.max_deflection_vertex) {
            parts.push(format!("max deflection {d:.4e} {units} at vertex {v}"));
        }
        if let Some(u) = self.max_utilisation {
            parts.push(format!("utilisation {}", sig(u, 3)));
        }
        parts.push(match (&self.buckling_factor, &self.buckling) {
            (Some(a), Some(kind)) => format!("buckles at {} × the load ({kind})", sig(*a, 3)),
            _ => format!("stands {MAX_LOAD_FACTOR} × the load without buckling"),
        });
        if let Some(a) = self.linear_buckling_factor {
            parts.push(format!("linearised estimate {} ×", sig(a, 3)));
        }
        let verdict = if self.passes {
            "passes".to_string()
        } else {
            format!("FAILS: {}", self.failures.join("; "))
        };
        format!("{what}: {}; {verdict}", parts.join(", "))
    }
}

/// What a load case's analysis needs.
pub struct LoadedStructure<'a> {
    /// The network.
    pub network: &'a Network,
    /// The structure.
    pub active: &'a ActiveSet,
    /// The physical description.
    pub physical: &'a Physical,
    /// Each curve's rest shape.
    pub rest: &'a [RestShape],
    /// The vertices of the structure.
    pub held: &'a [bool],
    /// The unloaded equilibrium.
    pub u0: &'a [f64],
    /// Its Hessian.
    pub h0: &'a [f64],
    /// The symbolic analysis of the model's pattern.
    pub symbolic: &'a Arc<SymbolicFactor>,
    /// What an equilibrium is.
    pub newton: &'a NewtonParams,
    /// The deflection limit, scene units.
    pub deflection_limit: Option<f64>,
    /// The smallest acceptable critical load factor.
    pub required_factor: f64,
}

/// A case's load at unit factor: dead forces and follower pressures.
struct Load {
    dead: Vec<f64>,
    pressure: Option<Pressure>,
}

/// Every vertex's rest position about the network's centroid (a pressure's potential is the
/// same about any point; one near the curves keeps its rounding small).
fn rest_about_centroid(network: &Network) -> Vec<Vec3> {
    let n = network.positions.len().max(1) as f64;
    let c = network.positions.iter().fold(Vec3::ZERO, |s, &p| s + p) * (1.0 / n);
    network.positions.iter().map(|&p| p - c).collect()
}

/// The forces `case` puts on the coordinates of `active`'s vertices in the drawn state: its
/// dead forces and its pressures' as they act at rest (what a linear model of the structure
/// carries: the pressure's turning with the curves is of the next order).
pub fn forces_at_rest(network: &Network, case: &CaseForces, active: &ActiveSet) -> Vec<f64> {
    let mut f = case.forces.clone();
    f.resize(network.dofs(), 0.0);
    if !case.pressure.is_empty() {
        let model = EnergyModel::new(network, &crate::rod::Material::default());
        let pressure = Pressure {
            parts: case.pressure.clone(),
            rest: rest_about_centroid(network),
        };
        let at_rest = model.pressure_forces(&pressure, &vec![0.0; model.dofs()], active);
        for (a, b) in f.iter_mut().zip(at_rest) {
            *a += b;
        }
    }
    f
}

/// A stable equilibrium at a load factor.
struct Stable {
    alpha: f64,
    u: Vec<f64>,
    hess: Vec<f64>,
}

impl LoadedStructure<'_> {
    /// The report of `case` on the structure, `model` its energy (its load is set and
    /// removed again).
    pub fn analyze(&self, model: &mut EnergyModel, case: &CaseForces) -> LoadCaseReport {
        let n = model.dofs();
        let mut f = case.forces.clone();
        f.resize(n, 0.0);
        let load = Load {
            dead: f,
            pressure: (!case.pressure.is_empty()).then(|| Pressure {
                parts: case.pressure.clone(),
                rest: rest_about_centroid(self.network),
            }),
        };
        let f = &load;
        let mut last = Stable {
            alpha: 0.0,
            u: self.u0.to_vec(),
            hess: self.h0.to_vec(),
        };
        let mut at_one: Option<Stable> = None;
        let mut step = FIRST_STEP;
        let mut failed: Option<f64> = None;
        // Follow the load to 1, then on to the largest factor, until a step fails.
        while last.alpha < MAX_LOAD_FACTOR {
            let stop = if last.alpha < 1.0 {
                1.0
            } else {
                MAX_LOAD_FACTOR
            };
            let next = (last.alpha + step).min(stop);
            match self.step(model, f, &last, next) {
                Some(s) => {
                    if s.alpha == 1.0 {
                        at_one = Some(Stable {
                            alpha: 1.0,
                            u: s.u.clone(),
                            hess: Vec::new(),
                        });
                    }
                    last = s;
                    step = (1.5 * step).min(MAX_STEP * last.alpha.max(1.0));
                }
                None => {
                    failed = Some(next);
                    break;
                }
            }
        }
        // Bracket the critical factor between the last stable factor and the failed one.
        let mut buckling = None;
        if let Some(mut high) = failed {
            while high - last.alpha > FACTOR_TOLERANCE * last.alpha.max(FACTOR_TOLERANCE) {
                let mid = 0.5 * (last.alpha + high);
                match self.step(model, f, &last, mid) {
                    Some(s) => {
                        if s.alpha >= 1.0 && at_one.is_none() {
                            at_one = Some(Stable {
                                alpha: 1.0,
                                u: s.u.clone(),
                                hess: Vec::new(),
                            });
                        }
                        last = s;
                    }
                    None => high = mid,
                }
            }
            buckling = Some((last.alpha, self.kind(model, f, &last)));
        }
        model.set_load(Vec::new());
        model.set_pressure(None);
        let linear = self.linear_factor(model, f);
        self.report(case, at_one, buckling, linear)
    }

    /// The forces of `load` at unit factor at displacements `u`.
    fn forces_at(&self, model: &EnergyModel, load: &Load, u: &[f64]) -> Vec<f64> {
        let mut f = load.dead.clone();
        if let Some(p) = &load.pressure {
            let fp = model.pressure_forces(p, u, self.active);
            for (a, b) in f.iter_mut().zip(&fp) {
                *a += b;
            }
        }
        f
    }

    /// The stable equilibrium at factor `alpha` on the path through `from`, if Newton reaches
    /// one: it starts from the tangent's prediction `u + Δα H⁻¹ f` (`f` the load's forces
    /// at `u`) and must end within half
    /// the predicted change of it (a step that lands farther has jumped to another branch,
    /// e.g. past a snap, and is refused).
    fn step(
        &self,
        model: &mut EnergyModel,
        load: &Load,
        from: &Stable,
        alpha: f64,
    ) -> Option<Stable> {
        let factor = Cholesky::factorize(self.symbolic, model.pattern(), &from.hess, 0.0, None);
        let mut tangent = self.forces_at(model, load, &from.u);
        factor.ok()?.solve_vec(&mut tangent);
        let da = alpha - from.alpha;
        let predicted: Vec<f64> = (from.u.iter().zip(&tangent))
            .map(|(u, t)| u + da * t)
            .collect();
        model.set_load(load.dead.iter().map(|x| alpha * x).collect());
        model.set_pressure(load.pressure.as_ref().map(|p| p.scaled(alpha)));
        let mut u = predicted.clone();
        let relaxed = Equilibrium {
            model,
            active: self.active,
            symbolic: self.symbolic,
            params: self.newton,
            tuning: &SolverTuning::default(),
        }
        .relax_near(&mut u);
        let norm = |x: &mut dyn Iterator<Item = f64>| x.map(|a| a * a).sum::<f64>().sqrt();
        let change = norm(&mut tangent.iter().map(|t| da * t));
        let miss = norm(&mut u.iter().zip(&predicted).map(|(a, b)| a - b));
        let on_path = miss <= 0.5 * change + 1e-9 * self.network.edge_length_stats().median;
        let stable = relaxed.info.converged
            && on_path
            && Cholesky::factorize(self.symbolic, model.pattern(), &relaxed.hess, 0.0, None)
                .is_ok();
        stable.then_some(Stable {
            alpha,
            u,
            hess: relaxed.hess,
        })
    }

    /// How the structure loses stability at the equilibrium `at`: its lowest mode, loaded by
    /// the load's forces there or not.
    fn kind(&self, model: &EnergyModel, load: &Load, at: &Stable) -> String {
        let f = &self.forces_at(model, load, &at.u);
        let hess = &at.hess;
        let keep = model.coordinate_mask(self.active);
        let ones = vec![1.0; model.dofs()];
        let Some(v) = lowest_vector(self.symbolic, model, hess, &keep, &ones) else {
            return "limit point".into();
        };
        let dot: f64 = f.iter().zip(&v).map(|(a, b)| a * b).sum();
        let norm = |x: &[f64]| x.iter().map(|a| a * a).sum::<f64>().sqrt();
        let share = dot.abs() / (norm(f) * norm(&v)).max(f64::MIN_POSITIVE);
        if share > LIMIT_POINT_WORK {
            "limit point".into()
        } else {
            "bifurcation".into()
        }
    }

    /// The linearised critical factor from the unloaded state (see the module's docs).
    fn linear_factor(&self, model: &mut EnergyModel, load: &Load) -> Option<f64> {
        // The pressure's own stiffness at unit factor (constant).
        let stiffness = load.pressure.as_ref().map(|p| {
            model.set_pressure(Some(p.clone()));
            let with = model.assemble(self.u0, self.active, true).hess;
            model.set_pressure(None);
            let without = model.assemble(self.u0, self.active, true).hess;
            let k: Vec<f64> = with.iter().zip(&without).map(|(a, b)| a - b).collect();
            k
        });
        let model = &*model;
        let pattern = model.pattern();
        let h0 = Cholesky::factorize(self.symbolic, pattern, self.h0, 0.0, None).ok()?;
        let mut du = self.forces_at(model, load, self.u0);
        h0.solve_vec(&mut du);
        let largest = du.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if largest == 0.0 {
            return None;
        }
        let eps = 1e-3 * self.network.edge_length_stats().median / largest;
        let at = |s: f64| {
            let u: Vec<f64> = self.u0.iter().zip(&du).map(|(a, b)| a + s * b).collect();
            model.assemble(&u, self.active, true).hess
        };
        let (plus, minus) = (at(eps), at(-eps));
        let mut d: Vec<f64> = plus
            .iter()
            .zip(&minus)
            .map(|(p, m)| (p - m) / (2.0 * eps))
            .collect();
        if let Some(k) = &stiffness {
            for (a, b) in d.iter_mut().zip(k) {
                *a += b;
            }
        }
        let positive = |alpha: f64| {
            let h: Vec<f64> = self.h0.iter().zip(&d).map(|(h, d)| h + alpha * d).collect();
            Cholesky::factorize(self.symbolic, pattern, &h, 0.0, None).is_ok()
        };
        let (mut low, mut high) = (0.0, 1.0);
        while positive(high) {
            low = high;
            high *= 2.0;
            if low >= MAX_LOAD_FACTOR {
                return None;
            }
        }
        while high - low > FACTOR_TOLERANCE * low.max(FACTOR_TOLERANCE) {
            let mid = 0.5 * (low + high);
            if positive(mid) {
                low = mid;
            } else {
                high = mid;
            }
        }
        (low <= MAX_LOAD_FACTOR).then_some(low)
    }

    fn report(
        &self,
        case: &CaseForces,
        at_one: Option<Stable>,
        buckling: Option<(f64, String)>,
        linear: Option<f64>,
    ) -> LoadCaseReport {
        let mut failures = Vec::new();
        let (mut deflection, mut vertex, mut utilisation) = (None, None, None);
        match &at_one {
            Some(s) => {
                let d: Vec<f64> =
                    s.u.iter()
                        .zip(self.u0)
                        .take(3 * self.network.vertex_count())
                        .map(|(a, b)| a - b)
                        .collect();
                let (v, max) = max_displacement(&d, self.held);
                deflection = Some(max);
                vertex = Some(v);
                let stresses = assembly_stresses(
                    self.network,
                    self.physical,
                    self.rest,
                    self.active,
                    &s.u,
                    None,
                );
                utilisation = stresses.max_utilisation().map(|c| c.utilisation());
            }
            None => failures.push(match &buckling {
                Some((alpha, kind)) => format!(
                    "it has no stable equilibrium under the whole load: it buckles at {} × \
                     the load ({kind})",
                    crate::fmt::significant(*alpha, 3)
                ),
                None => "it has no stable equilibrium under the load".into(),
            }),
        }
        if let (Some(d), Some(limit)) = (deflection, self.deflection_limit)
            && d > limit
        {
            let unit = self.physical.units.symbol();
            failures.push(format!(
                "it deflects {} {unit} (limit {} {unit})",
                crate::fmt::significant(d, 4),
                crate::fmt::significant(limit, 4)
            ));
        }
        if let Some(u) = utilisation.filter(|&u| u > 1.0) {
            failures.push(format!(
                "a rod works at {}% of its strength",
                crate::fmt::significant(100.0 * u, 3)
            ));
        }
        if let Some((alpha, _)) = &buckling
            && at_one.is_some()
            && *alpha < self.required_factor
        {
            failures.push(format!(
                "it buckles at {} × the load, below the required {}",
                crate::fmt::significant(*alpha, 3),
                crate::fmt::significant(self.required_factor, 3)
            ));
        }
        LoadCaseReport {
            name: case.name.clone(),
            factors: case.factors.clone(),
            holds: at_one.is_some(),
            max_deflection: deflection,
            max_deflection_vertex: vertex,
            max_utilisation: utilisation,
            buckling_factor: buckling.as_ref().map(|b| b.0),
            buckling: buckling.map(|b| b.1),
            linear_buckling_factor: linear,
            deflection_limit: self.deflection_limit,
            passes: failures.is_empty(),
            failures,
            snaps: case.snaps.clone(),
        }
    }
}

/// The lowest eigenvector of `hess` on the kept coordinates (identity metric).
fn lowest_vector(
    symbolic: &Arc<SymbolicFactor>,
    model: &EnergyModel,
    hess: &[f64],
    keep: &[bool],
    _ones: &[f64],
) -> Option<Vec<f64>> {
    use crate::solve::eigen::{EigenOptions, EigenParams, smallest_eigenpairs};
    let eigen = EigenParams::default().with_count(1);
    let options = EigenOptions {
        keep: Some(keep),
        ..EigenOptions::default()
    };
    let found = smallest_eigenpairs(symbolic, model.pattern(), hess, &eigen, options).ok()??;
    Some(
        (0..model.dofs())
            .map(|i| found.spectrum.vectors[(i, 0)])
            .collect(),
    )
}

//! Equilibrium by Newton's method (`docs/model.md`, *Equilibrium*).
//!
//! Each step solves `(H + τI) d = ∇E` with the structure's symbolic analysis; `τ = 0` unless
//! the factorization fails or `−d` is not a descent direction. Where the Hessian is
//! indefinite (a saddle on the way) the step comes from the Hessian with every term projected
//! to be positive semidefinite (a convex model), shifted only if even that is singular, and a
//! full such step is doubled while the energy keeps falling
//! ([`SolverTuning::escape_doublings`]). A backtracking (Armijo) line search follows; once
//! energy differences are below round-off, a step is accepted if it reduces `‖∇E‖`. In the
//! quadratic phase a step may reuse the last factorization ([`SolverTuning::chord_below`]).
//!
//! **Near an equilibrium** ([`Equilibrium::relax_near`]: a structure relaxed from a nearby
//! structure's equilibrium) every step after the first solves its Newton system by conjugate
//! gradients preconditioned with the last factorization ([`super::pcg`]), to a forcing
//! tolerance that tightens as `‖∇E‖` falls (inexact Newton: superlinear convergence), so one
//! factorization serves the whole solve while the Hessian stays close to the factored one. A
//! step whose solve needs more than [`KRYLOV_MAX_SOLVES`] solves, meets non-positive
//! curvature or fails its line search is taken afresh; one that took more than a few solves
//! or did not halve `‖∇E‖` is followed by a fresh factorization, which then preconditions the
//! later steps. Such a relaxation stops where the Hessian is indefinite ([`NewtonStop::Saddle`])
//! rather than walk over the saddle: its caller trusts only a path that met none, and analyses
//! the structure from the drawn state otherwise.
//!
//! **Convergence** is judged against a scale `g₀`: the structure's gradient norm in the drawn
//! state (so the tolerance means the same for every solve of it, whatever state it starts
//! from), but never below the forces' natural scale
//! ([`EnergyModel::natural_force_scale`]): a structure already at rest in its drawn state
//! (unloaded straight rods), whose drawn gradient is pure round-off, converges at once instead
//! of chasing a tolerance below round-off. Converged when `‖∇E‖ ≤ rel_tol · g₀`, or when `‖∇E‖` stops
//! decreasing at the round-off floor within [`NewtonParams::floor_max_rel`]; every way of
//! stopping is reported ([`NewtonStop`]), never hidden.

use super::factor::{Cholesky, Schedule, SymbolicFactor};
use super::pcg;
use super::tuning::SolverTuning;
use crate::rod::model::{Assembly, Terms};
use crate::rod::{ActiveSet, EnergyModel};
use crate::words::Message;
use serde::{Deserialize, Serialize};
use std::convert::Infallible;
use std::sync::Arc;

/// Newton parameters: what an equilibrium is, and how hard to look for it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NewtonParams {
    /// Relative gradient tolerance (against the convergence scale; the paper's `1e-10`).
    pub rel_tol: f64,
    /// Iteration cap. Structures near a mechanism relax by long walks along their soft mode
    /// (hundreds of steps: `docs/benchmarks.md`).
    pub max_iterations: usize,
    /// Armijo sufficient-decrease constant.
    pub armijo: f64,
    /// Largest number of step halvings per line search.
    pub max_backtracks: usize,
    /// Iterations in a row without halving `‖∇E‖` (relative to its best value so far) after
    /// which the solve is declared stuck at the round-off floor.
    pub stall_iterations: usize,
    /// A stall at a relative gradient above this is a failure, not a round-off floor.
    pub floor_max_rel: f64,
}

impl Default for NewtonParams {
    fn default() -> Self {
        NewtonParams {
            rel_tol: 1e-10,
            max_iterations: 1000,
            armijo: 1e-4,
            max_backtracks: 60,
            stall_iterations: 4,
            floor_max_rel: 1e-6,
        }
    }
}

impl NewtonParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), Message> {
        if !(self.rel_tol > 0.0 && self.rel_tol < 1.0) {
            return Err(
                format!("Newton tolerance must lie in (0, 1), got {}", self.rel_tol).into(),
            );
        }
        if self.max_iterations == 0 {
            return Err("Newton needs at least one iteration".into());
        }
        if !(self.armijo > 0.0 && self.armijo < 0.5) {
            return Err(
                format!("Armijo constant must lie in (0, 0.5), got {}", self.armijo).into(),
            );
        }
        Ok(())
    }
}

/// A chord step in the quadratic phase must cut `‖∇E‖` by this factor (a fresh
/// factorization's step by its square), or the next step factors afresh.
const CHORD_CUT: f64 = 0.25;

/// A Krylov step's forcing term: its Newton system is solved to `η‖∇E‖` with
/// `η = min(KRYLOV_ETA, √(‖∇E‖/g₀))`, and at least to half the tolerance.
const KRYLOV_ETA: f64 = 0.1;

/// Solves a Krylov step may take; beyond them the step factors afresh (a factorization costs
/// some tens of solves).
pub const KRYLOV_MAX_SOLVES: usize = 12;

/// A Krylov step must cut `‖∇E‖` by this factor, or the next step factors afresh.
const KRYLOV_CUT: f64 = 0.5;

/// A Krylov step that took more solves than this makes the next step factor afresh: the
/// factored Hessian has drifted from the current one, and the later steps, which solve to
/// tighter tolerances, would take ever more (a solve, bound by memory bandwidth, costs a
/// sixth to a twentieth of a factorization).
const KRYLOV_REFACTOR_AFTER: usize = 3;

/// Shifts of the projected Hessian tried (each ten times the last) before giving up.
const MAX_SHIFTS: usize = 40;

/// Energy differences below this share of the energy are round-off (the line search then
/// judges a step by the gradient).
const ENERGY_ROUNDOFF: f64 = 1e-13;

/// The energy "no longer moves" (a stalled iteration) when it fell by at most this share.
const ENERGY_STALL: f64 = 1e-12;

/// How a Newton solve stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NewtonStop {
    /// `‖∇E‖ ≤ rel_tol · g₀`.
    Converged,
    /// `‖∇E‖` stopped decreasing at the round-off floor before reaching the tolerance.
    RoundoffFloor,
    /// The iteration cap was reached.
    MaxIterations,
    /// `‖∇E‖` stopped decreasing far above the tolerance.
    Stalled,
    /// No step reduced the energy or the gradient: the solve failed.
    LineSearchFailed,
    /// The energy or gradient became non-finite.
    NonFinite,
    /// A relaxation from near an equilibrium ([`Equilibrium::relax_near`]) met an indefinite
    /// Hessian (a saddle on the way) and stopped there.
    Saddle,
}

impl std::fmt::Display for NewtonStop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NewtonStop::Converged => "converged",
            NewtonStop::RoundoffFloor => "converged to round-off",
            NewtonStop::MaxIterations => "iteration limit reached",
            NewtonStop::Stalled => "stalled",
            NewtonStop::LineSearchFailed => "no step reduced the energy",
            NewtonStop::NonFinite => "non-finite energy",
            NewtonStop::Saddle => "stopped at a saddle",
        })
    }
}

/// What a Newton solve did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NewtonInfo {
    /// Newton iterations (accepted steps).
    pub iterations: usize,
    /// True for [`NewtonStop::Converged`] and [`NewtonStop::RoundoffFloor`].
    pub converged: bool,
    /// How it stopped.
    pub stop: NewtonStop,
    /// `‖∇E‖` at the start.
    pub grad_start: f64,
    /// `‖∇E‖` at the end.
    pub grad_end: f64,
    /// `‖∇E‖ / g₀` at the end (`g₀`: the convergence scale).
    pub grad_rel: f64,
    /// Energy at the end.
    pub energy: f64,
    /// Numeric factorizations performed (including failed and shifted ones).
    pub factorizations: usize,
    /// Iterations that reused an earlier factorization.
    pub chord_steps: usize,
    /// Iterations whose direction came from conjugate gradients preconditioned with an
    /// earlier factorization ([`Equilibrium::relax_near`]).
    #[serde(default)]
    pub krylov_steps: usize,
    /// Solves with an earlier factorization those steps took.
    #[serde(default)]
    pub krylov_solves: usize,
    /// Iterations whose direction came from the projected (convex) Hessian.
    pub projected_steps: usize,
    /// Largest diagonal shift `τ` used.
    pub max_shift: f64,
    /// Doublings of steps escaping a saddle ([`SolverTuning::escape_doublings`]).
    pub escape_doublings: usize,
}

impl NewtonInfo {
    /// What a run's record keeps of the solve.
    pub fn summary(&self) -> NewtonSummary {
        NewtonSummary {
            iterations: self.iterations,
            converged: self.converged,
            grad_rel: self.grad_rel,
            stop: self.stop,
            factorizations: self.factorizations,
            chord_steps: self.chord_steps,
        }
    }
}

/// The part of [`NewtonInfo`] that results record (`result.json`, reports).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NewtonSummary {
    /// Iterations.
    pub iterations: usize,
    /// Converged (to the tolerance or the round-off floor).
    pub converged: bool,
    /// `‖∇E‖ / g₀` at the end (`g₀`: the convergence scale, see [`crate::solve::newton`]).
    pub grad_rel: f64,
    /// How it stopped.
    pub stop: NewtonStop,
    /// Numeric factorizations it took.
    #[serde(default)]
    pub factorizations: usize,
    /// Steps that reused an earlier factorization.
    #[serde(default)]
    pub chord_steps: usize,
}

/// An equilibrium problem: a structure of an energy model, factored with `symbolic` (an
/// analysis of the model's pattern, or one restricted to a superset of the structure's
/// vertices), solved with `params` and `tuning`.
#[derive(Clone, Copy, Debug)]
pub struct Equilibrium<'a> {
    /// The network's energy.
    pub model: &'a EnergyModel,
    /// The curves of the structure.
    pub active: &'a ActiveSet,
    /// The symbolic analysis every factorization uses.
    pub symbolic: &'a Arc<SymbolicFactor>,
    /// What an equilibrium is.
    pub params: &'a NewtonParams,
    /// How the work is done.
    pub tuning: &'a SolverTuning,
}

/// A relaxed state's solve report and Hessian.
#[derive(Clone, Debug)]
pub struct Relaxed {
    /// What the solve did.
    pub info: NewtonInfo,
    /// The Hessian values at the final state (the last assembly's: the same as
    /// `model.assemble(x, active, true).hess`), for the spectrum that follows.
    pub hess: Vec<f64>,
}

impl Equilibrium<'_> {
    /// Relaxes the structure from displacements `x` (updated in place) to equilibrium.
    ///
    /// `warm`, a factorization of a nearby Hessian of the same structure (e.g. at a previous
    /// equilibrium), serves the first step; only the work changes, never the tolerance met.
    pub fn relax(&self, x: &mut [f64], warm: Option<Cholesky>) -> Relaxed {
        self.relax_with(x, warm, false)
    }

    /// Relaxes the structure from displacements `x` near its equilibrium (e.g. a nearby
    /// structure's): the first step factors the Hessian, and the later ones solve theirs by
    /// conjugate gradients preconditioned with that factorization (Krylov steps, see the
    /// module documentation). The same tolerance as [`Self::relax`]. It never walks over a
    /// saddle: where the Hessian is indefinite it stops ([`NewtonStop::Saddle`]), since a
    /// start near one equilibrium that passes a saddle may end in another.
    pub fn relax_near(&self, x: &mut [f64]) -> Relaxed {
        self.relax_with(x, None, true)
    }

    fn relax_with(&self, x: &mut [f64], warm: Option<Cholesky>, krylov: bool) -> Relaxed {
        let _timer = crate::profile::Timer::new(crate::profile::Phase::Relax);
        let mut cur = self.model.assemble(x, self.active, true);
        let mut solver = Solver::new(self, &cur, warm);
        solver.krylov = krylov;
        let Err(stop) = solver.run(x, &mut cur);
        Relaxed {
            info: solver.finish(stop),
            hess: cur.hess,
        }
    }

    /// The convergence scale `g₀`: the structure's gradient norm in the drawn state, at least
    /// its forces' natural scale ([`EnergyModel::natural_force_scale`]).
    pub fn convergence_scale(&self) -> f64 {
        let zero = vec![0.0; self.model.dofs()];
        let drawn = norm(&self.model.assemble(&zero, self.active, false).grad);
        drawn.max(self.model.natural_force_scale(self.active))
    }
}

/// `g / g₀`, 0 when `g₀` is.
fn relative(g: f64, g_ref: f64) -> f64 {
    if g_ref > 0.0 { g / g_ref } else { 0.0 }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The Newton direction `F⁻¹ g` if it is a finite descent direction (`gᵀd > 0`).
fn descent(f: &Cholesky, g: &[f64]) -> Option<Vec<f64>> {
    let mut d = g.to_vec();
    f.solve_vec(&mut d);
    let gd = dot(&d, g);
    (gd > 0.0 && gd.is_finite()).then_some(d)
}

/// A step direction `d` (the step is `x − α d`) and the factorization it came from.
struct Direction {
    d: Vec<f64>,
    factor: Cholesky,
    /// From the projected Hessian (a saddle nearby): a full step may be extended.
    projected: bool,
    /// Solved by conjugate gradients with an earlier factorization (a Krylov step).
    krylov: bool,
}

/// What a line search found: the step length, and the assembly at the new point when the
/// search already made it.
struct Accepted {
    alpha: f64,
    assembly: Option<Assembly>,
}

/// The state of one Newton solve between iterations.
struct Solver<'a> {
    eq: &'a Equilibrium<'a>,
    /// The convergence scale `g₀`.
    g_ref: f64,
    /// Mean absolute diagonal of the starting Hessian: the scale of the shifts.
    diag_scale: f64,
    info: NewtonInfo,
    /// The trial point of line searches.
    trial: Vec<f64>,
    best_grad: f64,
    stalled: usize,
    last_decrease: f64,
    /// A factorization of the Hessian at the current point (the caller's, at the start).
    fresh: Option<Cholesky>,
    /// The last factorization, for chord steps at later points.
    stale: Option<Cholesky>,
    last_projected: bool,
    /// Whether the last step reused an earlier factorization (a chord or Krylov step).
    last_chord: bool,
    /// A chord or Krylov step's line search just failed, or a Krylov step did not cut
    /// `‖∇E‖` enough: the next step factors afresh.
    retry_fresh: bool,
    /// Steps after the first are Krylov steps ([`Equilibrium::relax_near`]).
    krylov: bool,
    /// Solves the last Krylov solve took.
    last_krylov_solves: usize,
    /// `‖∇E‖` before the last step if it was a full one, and whether it was a chord step.
    full_step: Option<(f64, bool)>,
}

impl<'a> Solver<'a> {
    fn new(eq: &'a Equilibrium<'a>, cur: &Assembly, warm: Option<Cholesky>) -> Self {
        let pattern = eq.model.pattern();
        let g_start = norm(&cur.grad);
        let g_ref = eq.convergence_scale();
        let diag: f64 = pattern.diag.iter().map(|&k| cur.hess[k].abs()).sum();
        Solver {
            eq,
            g_ref,
            diag_scale: (diag / pattern.n.max(1) as f64).max(f64::MIN_POSITIVE),
            info: NewtonInfo {
                iterations: 0,
                converged: false,
                stop: NewtonStop::MaxIterations,
                grad_start: g_start,
                grad_end: g_start,
                grad_rel: relative(g_start, g_ref),
                energy: cur.energy,
                factorizations: 0,
                chord_steps: 0,
                krylov_steps: 0,
                krylov_solves: 0,
                projected_steps: 0,
                max_shift: 0.0,
                escape_doublings: 0,
            },
            trial: vec![0.0; cur.grad.len()],
            best_grad: g_start,
            stalled: 0,
            last_decrease: f64::INFINITY,
            fresh: warm,
            stale: None,
            last_projected: false,
            last_chord: false,
            retry_fresh: false,
            krylov: false,
            last_krylov_solves: 0,
            full_step: None,
        }
    }

    fn finish(mut self, stop: NewtonStop) -> NewtonInfo {
        self.info.stop = stop;
        self.info.converged = matches!(stop, NewtonStop::Converged | NewtonStop::RoundoffFloor);
        self.info
    }

    /// Newton iterations from `cur`, the assembly at `x` (it stays so), until a stop.
    fn run(&mut self, x: &mut [f64], cur: &mut Assembly) -> Result<Infallible, NewtonStop> {
        if !cur.energy.is_finite() || !self.info.grad_start.is_finite() {
            return Err(NewtonStop::NonFinite);
        }
        loop {
            let g_norm = norm(&cur.grad);
            self.info.grad_end = g_norm;
            self.info.grad_rel = relative(g_norm, self.g_ref);
            self.info.energy = cur.energy;
            self.stop_test(g_norm, cur.energy)?;
            let chord_now = self.chord_now(g_norm);
            let dir = self.direction(x, cur, g_norm, chord_now)?;
            let reused = chord_now || dir.krylov;
            if self.krylov {
                self.last_chord = dir.krylov;
            }
            if self.krylov || self.eq.tuning.chord_below > 0.0 {
                self.stale = Some(dir.factor);
            }
            match self.line_search(x, cur, &dir.d, g_norm, dir.projected) {
                None if reused => {
                    // The old factor's step found nothing: try a fresh factorization's.
                    self.retry_fresh = true;
                    self.last_chord = false;
                    self.full_step = None;
                }
                // Nothing reduces energy or gradient: at the round-off floor if already
                // close, otherwise a genuine failure.
                None if self.info.grad_rel <= self.eq.params.floor_max_rel => {
                    return Err(NewtonStop::RoundoffFloor);
                }
                None => return Err(NewtonStop::LineSearchFailed),
                Some(step) => {
                    self.accept(x, cur, step, g_norm, chord_now)?;
                    if dir.krylov
                        && (norm(&cur.grad) > KRYLOV_CUT * g_norm
                            || self.last_krylov_solves > KRYLOV_REFACTOR_AFTER)
                    {
                        self.retry_fresh = true;
                    }
                }
            }
        }
    }

    /// Stops the solve when it converged, stalled at the round-off floor or ran out of
    /// iterations.
    fn stop_test(&mut self, g_norm: f64, energy: f64) -> Result<(), NewtonStop> {
        let params = self.eq.params;
        let tol = params.rel_tol * self.g_ref;
        if g_norm <= tol || g_norm == 0.0 {
            return Err(NewtonStop::Converged);
        }
        let near = g_norm <= self.eq.tuning.floor_near * params.rel_tol * self.g_ref;
        if g_norm <= 0.5 * self.best_grad {
            self.best_grad = g_norm;
            self.stalled = 0;
        } else if (!self.last_chord || near)
            && !self.retry_fresh
            && self.info.iterations > 0
            && self.last_decrease <= ENERGY_STALL * energy.abs()
        {
            // The energy no longer moves and the gradient no longer halves: round-off floor.
            // A chord step that stalls proves it only near the tolerance, after steps that
            // showed Newton's quadratic convergence; farther away an old factor's step can
            // crawl along a soft mode where a fresh one still moves, so the next step factors
            // afresh.
            self.best_grad = self.best_grad.min(g_norm);
            self.stalled += 1;
            if self.stalled >= params.stall_iterations || near {
                return Err(if self.info.grad_rel <= params.floor_max_rel {
                    NewtonStop::RoundoffFloor
                } else {
                    NewtonStop::Stalled
                });
            }
        }
        if self.info.iterations >= params.max_iterations {
            return Err(NewtonStop::MaxIterations);
        }
        Ok(())
    }

    /// Whether this step reuses the last factorization ([`SolverTuning::chord_below`]), which
    /// it then takes as the current one.
    fn chord_now(&mut self, g_norm: f64) -> bool {
        if self.krylov {
            // Krylov steps subsume chord steps (a chord step is their first iterate).
            return false;
        }
        let quadratic = self.full_step.is_some_and(|(g0, chord)| {
            let cut = if chord {
                CHORD_CUT
            } else {
                CHORD_CUT * CHORD_CUT
            };
            g_norm <= cut * g0
        });
        let chord_now = self.fresh.is_none()
            && quadratic
            && !self.retry_fresh
            && self.stale.is_some()
            && g_norm <= self.eq.tuning.chord_below * self.g_ref;
        self.retry_fresh = false;
        self.last_chord = chord_now;
        let stale = self.stale.take();
        if chord_now {
            self.fresh = stale;
        }
        chord_now
    }

    /// The step's direction: from the current factorization if it gives a descent direction,
    /// else from the exact Hessian if it is positive definite, else from the projected one.
    fn direction(
        &mut self,
        x: &[f64],
        cur: &Assembly,
        g_norm: f64,
        chord_now: bool,
    ) -> Result<Direction, NewtonStop> {
        if let Some((d, factor)) = self
            .fresh
            .take()
            .and_then(|f| descent(&f, &cur.grad).map(|d| (d, f)))
        {
            if chord_now {
                self.info.chord_steps += 1;
            }
            return Ok(Direction {
                d,
                factor,
                projected: false,
                krylov: false,
            });
        }
        if self.krylov
            && !std::mem::take(&mut self.retry_fresh)
            && let Some(factor) = self.stale.take()
            && let Some(d) = self.krylov_direction(cur, g_norm, &factor)
        {
            return Ok(Direction {
                d,
                factor,
                projected: false,
                krylov: true,
            });
        }
        // After a projected step the exact Hessian is usually still indefinite: try it again
        // only every few iterations, or once the gradient has come down.
        let try_exact = !self.last_projected
            || self.info.iterations.is_multiple_of(4)
            || g_norm <= 1e-3 * self.g_ref;
        let exact = if try_exact {
            self.info.factorizations += 1;
            self.factorize(&cur.hess, 0.0)
                .and_then(|f| descent(&f, &cur.grad).map(|d| (d, f)))
        } else {
            None
        };
        self.last_projected = exact.is_none();
        match exact {
            Some((d, factor)) => Ok(Direction {
                d,
                factor,
                projected: false,
                krylov: false,
            }),
            // A relaxation from near an equilibrium is kept only if it never meets a saddle
            // (see `relax_near`): the rest of its path would be wasted.
            None if self.krylov => Err(NewtonStop::Saddle),
            None => self.projected_direction(x, cur),
        }
    }

    /// The Newton direction of the current Hessian by conjugate gradients preconditioned
    /// with `factor` (an earlier factorization), to the forcing tolerance; `None` when the
    /// solve fails (see [`pcg::solve`]) or the direction is not one of descent.
    fn krylov_direction(
        &mut self,
        cur: &Assembly,
        g_norm: f64,
        factor: &Cholesky,
    ) -> Option<Vec<f64>> {
        let eta = KRYLOV_ETA.min(relative(g_norm, self.g_ref).sqrt());
        let target = (eta * g_norm).max(0.5 * self.eq.params.rel_tol * self.g_ref);
        let pattern = self.eq.model.pattern();
        let schedule = if self.eq.symbolic.factor_nnz() > self.eq.tuning.split_solves_above {
            Schedule::Subtrees
        } else {
            Schedule::Groups(1)
        };
        let found = pcg::solve(
            pattern,
            &cur.hess,
            factor,
            &cur.grad,
            target,
            KRYLOV_MAX_SOLVES,
            schedule,
        );
        self.info.krylov_solves += found.solves;
        self.last_krylov_solves = found.solves;
        let d = found.x?;
        let gd = dot(&d, &cur.grad);
        (gd > 0.0 && gd.is_finite()).then(|| {
            self.info.krylov_steps += 1;
            d
        })
    }

    /// The direction from the Hessian with every term's local Hessian projected to be
    /// positive semidefinite (always a descent direction), shifted only if even that is
    /// singular.
    fn projected_direction(&mut self, x: &[f64], cur: &Assembly) -> Result<Direction, NewtonStop> {
        let Equilibrium { model, active, .. } = *self.eq;
        self.info.projected_steps += 1;
        let locals = model.local_hessians(x, Terms::ProjectedOf(active));
        let mut hp = Vec::new();
        model.hessian_from_locals(&locals, active, &mut hp);
        let mut shift = 0.0;
        for attempt in 0.. {
            self.info.factorizations += 1;
            if let Some(factor) = self.factorize(&hp, shift)
                && let Some(d) = descent(&factor, &cur.grad)
            {
                return Ok(Direction {
                    d,
                    factor,
                    projected: true,
                    krylov: false,
                });
            }
            if attempt == MAX_SHIFTS {
                break;
            }
            shift = if shift == 0.0 {
                1e-12 * self.diag_scale
            } else {
                shift * 10.0
            };
            self.info.max_shift = self.info.max_shift.max(shift);
        }
        Err(NewtonStop::LineSearchFailed)
    }

    fn factorize(&self, hess: &[f64], shift: f64) -> Option<Cholesky> {
        let eq = self.eq;
        Cholesky::factorize(eq.symbolic, eq.model.pattern(), hess, shift, None).ok()
    }

    /// Backtracking (Armijo) line search on `x − α d`; once energy differences are below
    /// round-off, a step is accepted if it reduces `‖∇E‖`. A full step from the projected
    /// Hessian is extended while the energy keeps falling ([`Self::escape`]).
    fn line_search(
        &mut self,
        x: &[f64],
        cur: &Assembly,
        d: &[f64],
        g_norm: f64,
        projected: bool,
    ) -> Option<Accepted> {
        let Equilibrium {
            model,
            active,
            params,
            ..
        } = *self.eq;
        let gd = dot(d, &cur.grad);
        let e0 = cur.energy;
        let roundoff = ENERGY_ROUNDOFF * e0.abs().max(f64::MIN_POSITIVE);
        let mut alpha = 1.0;
        for _ in 0..=params.max_backtracks {
            set_step(&mut self.trial, x, d, alpha);
            let e = model.energy(&self.trial, active);
            if e.is_finite() {
                if e <= e0 - params.armijo * alpha * gd {
                    if projected && alpha == 1.0 {
                        alpha = self.escape(x, d, e);
                    }
                    return Some(Accepted {
                        alpha,
                        assembly: None,
                    });
                }
                if (e - e0).abs() <= roundoff {
                    // Energy differences are below round-off: judge the step by the gradient.
                    let a = model.assemble(&self.trial, active, true);
                    if norm(&a.grad) < g_norm {
                        return Some(Accepted {
                            alpha,
                            assembly: Some(a),
                        });
                    }
                }
            }
            alpha *= 0.5;
        }
        None
    }

    /// Escaping a saddle: doubles the full step `x − d` (energy `e`, in `trial`) while the
    /// energy keeps falling; returns the step length, the step left in `trial`.
    fn escape(&mut self, x: &[f64], d: &[f64], e: f64) -> f64 {
        let Equilibrium { model, active, .. } = *self.eq;
        let mut alpha = 1.0;
        let mut best = e;
        let mut longer = self.trial.clone();
        for _ in 0..self.eq.tuning.escape_doublings {
            let a = 2.0 * alpha;
            set_step(&mut longer, x, d, a);
            let el = model.energy(&longer, active);
            if !(el.is_finite() && el < best) {
                break;
            }
            best = el;
            alpha = a;
            self.trial.copy_from_slice(&longer);
        }
        self.info.escape_doublings += alpha.log2().round() as usize;
        alpha
    }

    /// Moves to the accepted step (left in `trial`).
    fn accept(
        &mut self,
        x: &mut [f64],
        cur: &mut Assembly,
        step: Accepted,
        g_norm: f64,
        chord_now: bool,
    ) -> Result<(), NewtonStop> {
        let Equilibrium { model, active, .. } = *self.eq;
        self.full_step = (step.alpha == 1.0).then_some((g_norm, chord_now));
        x.copy_from_slice(&self.trial);
        self.info.iterations += 1;
        let e0 = cur.energy;
        *cur = step
            .assembly
            .unwrap_or_else(|| model.assemble(x, active, true));
        self.last_decrease = e0 - cur.energy;
        if !cur.energy.is_finite() || !norm(&cur.grad).is_finite() {
            return Err(NewtonStop::NonFinite);
        }
        Ok(())
    }
}

/// `out = x − α d`.
fn set_step(out: &mut [f64], x: &[f64], d: &[f64], alpha: f64) {
    for ((t, xi), di) in out.iter_mut().zip(x).zip(d) {
        *t = xi - alpha * di;
    }
}

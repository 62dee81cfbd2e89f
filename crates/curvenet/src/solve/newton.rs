//! Equilibrium by Newton's method (SPEC §4).
//!
//! Each step solves `(H + τI) d = ∇E` with the shared symbolic factorization; `τ = 0` unless the
//! factorization fails or `−d` is not a descent direction, in which case `τ` grows geometrically
//! from a small multiple of the diagonal's scale. A backtracking (Armijo) line search follows;
//! once energy differences are below round-off, a step is accepted if it reduces `‖∇E‖`. Where
//! the Hessian is indefinite (a saddle on the way), the step comes from the Hessian with every
//! term projected to be positive semidefinite, and a full such step is doubled while the
//! energy keeps falling ([`NewtonParams::escape_doublings`]).
//! Converged when `‖∇E‖ ≤ rel_tol · ‖∇E(x_start)‖`, or when `‖∇E‖` stops decreasing at the
//! round-off floor; every way of stopping is reported, never hidden. In the quadratic phase
//! (relative gradient below [`NewtonParams::chord_below`]) a step reuses the last
//! factorization: an old factor cuts the residual there nearly as well as a fresh one.

use super::factor::{Cholesky, SymbolicFactor};
use crate::rod::{ActiveSet, EnergyModel};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Newton parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NewtonParams {
    /// Relative gradient tolerance (SPEC: `1e-10`).
    pub rel_tol: f64,
    /// Iteration cap. Structures near a mechanism relax by long walks along their soft mode:
    /// the bunny's final three curves take 390 steps (1.4 s), and stopped at 200 they sat
    /// 1,700 units (half the model's size) short of their equilibrium.
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
    /// Within this factor of the tolerance, one iteration that neither halves `‖∇E‖` nor
    /// moves the energy beyond round-off ends the solve at the round-off floor (Newton's
    /// quadratic convergence would have passed the tolerance); farther away it takes
    /// `stall_iterations` of them.
    #[serde(default = "default_floor_near")]
    pub floor_near: f64,
    /// Reuse the last factorization for a step ("chord" step) and keep it when the step cuts
    /// `‖∇E‖` by at least this factor; 0 (the default) disables reuse. On the paper's
    /// examples a fresh factorization per step is faster: a rejected chord step costs an
    /// assembly, and warm-started solves need few steps (docs/benchmarks.md).
    pub chord_ratio: f64,
    /// Below this relative gradient `‖∇E‖ / ‖∇E(x_start)‖`, steps reuse the last
    /// factorization instead of a fresh one ("chord" steps, judged by the same line search
    /// and round-off floor test as any step); 0 never. Newton is then in its quadratic
    /// phase: the Hessian has moved by the last step's length, so the old factor's error
    /// shrinks the residual nearly as much as a fresh one (arched shell: 1e-6 → 1e-8 →
    /// 4e-10 either way), and near the round-off floor a fresh factorization would be spent
    /// on the step that finds the floor. Only after a full step that cut `‖∇E‖`
    /// sixteenfold (fourfold for a chord step): along a soft mode Newton's full steps do not,
    /// and an old factor's steps wander there (the bunny's late relaxations). A chord step
    /// that stalls declares the round-off floor only within `floor_near` × the tolerance;
    /// farther away, and after a failed line search, the next step factors afresh.
    #[serde(default = "default_chord_below")]
    pub chord_below: f64,
    /// Conjugate-gradient iterations allowed per Newton system when an earlier factorization
    /// preconditions it; 0 (the default) always refactors. Off by default for the same
    /// reason: sixteen preconditioned iterations cost about as much as a factorization.
    #[serde(default = "default_krylov_iterations")]
    pub krylov_iterations: usize,
    /// Relative residual the conjugate gradients must reach.
    #[serde(default = "default_krylov_tol")]
    pub krylov_tol: f64,
    /// Near a saddle (the Hessian indefinite, the step from the projected Hessian) a full step
    /// that lowers the energy is doubled up to this many times while the energy keeps
    /// falling: the projected model's curvature along the escape direction is far above the
    /// true (negative) one, so its steps creep away from the saddle (bunny: eighty steps
    /// growing 8% each). 0 never extends a step; steps from the exact Hessian never are.
    #[serde(default = "default_escape_doublings")]
    pub escape_doublings: usize,
}

fn default_escape_doublings() -> usize {
    30
}

fn default_chord_below() -> f64 {
    1e-6
}

fn default_floor_near() -> f64 {
    100.0
}

fn default_krylov_iterations() -> usize {
    0
}

fn default_krylov_tol() -> f64 {
    1e-4
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
            floor_near: default_floor_near(),
            chord_ratio: 0.0,
            chord_below: default_chord_below(),
            krylov_iterations: default_krylov_iterations(),
            krylov_tol: default_krylov_tol(),
            escape_doublings: default_escape_doublings(),
        }
    }
}

impl NewtonParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.rel_tol > 0.0 && self.rel_tol < 1.0) {
            return Err(format!(
                "Newton tolerance must lie in (0, 1), got {}",
                self.rel_tol
            ));
        }
        if !(self.chord_below >= 0.0 && self.chord_below < 1.0) {
            return Err(format!(
                "Newton's chord_below must lie in [0, 1), got {}",
                self.chord_below
            ));
        }
        if !(self.floor_near >= 1.0 && self.floor_near.is_finite()) {
            return Err(format!(
                "Newton's floor_near must be a finite factor of at least 1, got {}",
                self.floor_near
            ));
        }
        if self.max_iterations == 0 {
            return Err("Newton needs at least one iteration".into());
        }
        if !(self.armijo > 0.0 && self.armijo < 0.5) {
            return Err(format!(
                "Armijo constant must lie in (0, 0.5), got {}",
                self.armijo
            ));
        }
        Ok(())
    }
}

/// A chord step in the quadratic phase must cut `‖∇E‖` by this factor, or the next step
/// factors afresh ([`NewtonParams::chord_below`]).
const CHORD_CUT: f64 = 0.25;

/// How a Newton solve stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NewtonStop {
    /// `‖∇E‖ ≤ rel_tol · ‖∇E(x_start)‖`.
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
}

/// What a Newton solve did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NewtonInfo {
    /// Newton iterations (factorizations of an accepted step).
    pub iterations: usize,
    /// True for [`NewtonStop::Converged`] and [`NewtonStop::RoundoffFloor`].
    pub converged: bool,
    /// How it stopped.
    pub stop: NewtonStop,
    /// `‖∇E‖` at the start.
    pub grad_start: f64,
    /// `‖∇E‖` at the end.
    pub grad_end: f64,
    /// `‖∇E‖ / ‖∇E(x_start)‖` at the end.
    pub grad_rel: f64,
    /// Energy at the end.
    pub energy: f64,
    /// Numeric factorizations performed (including failed and shifted ones).
    pub factorizations: usize,
    /// Iterations that reused an earlier factorization.
    pub chord_steps: usize,
    /// Iterations whose direction came from the projected (convex) Hessian.
    pub projected_steps: usize,
    /// Iterations whose Newton system was solved by preconditioned conjugate gradients.
    pub krylov_steps: usize,
    /// Largest diagonal shift `τ` used.
    pub max_shift: f64,
    /// Doublings of steps escaping a saddle ([`NewtonParams::escape_doublings`]).
    #[serde(default)]
    pub escape_doublings: usize,
}

/// Conjugate gradients for `H d = g` (`H` symmetric, upper triangle `hess` in `pattern`),
/// preconditioned by the factorization `f` of a nearby matrix. `None` when `H` shows
/// non-positive curvature or the relative residual does not reach `tol` within `max_it`.
fn pcg(
    pattern: &crate::sparse::Pattern,
    hess: &[f64],
    g: &[f64],
    f: &Cholesky,
    tol: f64,
    max_it: usize,
) -> Option<Vec<f64>> {
    if max_it == 0 {
        return None;
    }
    let n = g.len();
    let g_norm = norm(g);
    let mut x = vec![0.0; n];
    let mut r = g.to_vec();
    let mut z = r.clone();
    f.solve_vec(&mut z);
    let mut p = z.clone();
    let mut rz: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
    let mut q = vec![0.0; n];
    for _ in 0..max_it {
        pattern.sym_matvec(hess, &p, &mut q);
        let pq: f64 = p.iter().zip(&q).map(|(a, b)| a * b).sum();
        if !(pq > 0.0 && pq.is_finite()) {
            return None;
        }
        let alpha = rz / pq;
        for i in 0..n {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
        }
        if norm(&r) <= tol * g_norm {
            return Some(x);
        }
        z.copy_from_slice(&r);
        f.solve_vec(&mut z);
        let rz_new: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..n {
            p[i] = z[i] + beta * p[i];
        }
    }
    None
}

/// The Newton direction `F⁻¹ g` if it is a finite descent direction (`gᵀd > 0`).
fn descent(f: &Cholesky, g: &[f64]) -> Option<Vec<f64>> {
    let mut d = g.to_vec();
    f.solve_vec(&mut d);
    let gd: f64 = d.iter().zip(g).map(|(a, b)| a * b).sum();
    (gd > 0.0 && gd.is_finite()).then_some(d)
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Relaxes the structure `active` of `model` from displacements `x` (updated in place) to
/// equilibrium.
///
/// `grad_reference` overrides `‖∇E(x_start)‖` in the relative test (pass the drawn state's
/// gradient norm when warm-starting from a previous equilibrium, so the tolerance means the
/// same thing for every solve).
pub fn relax(
    model: &EnergyModel,
    active: &ActiveSet,
    symbolic: &Arc<SymbolicFactor>,
    x: &mut [f64],
    grad_reference: Option<f64>,
    params: &NewtonParams,
) -> NewtonInfo {
    relax_assembled(model, active, symbolic, x, grad_reference, params, None).0
}

/// [`relax`] starting with `initial`, a factorization of a nearby Hessian (e.g. the
/// structure's Hessian at a previous equilibrium), for the first steps (the result meets the
/// same tolerance; only the work changes), and handing out the Hessian values at the final
/// `x` (the last assembly's, the same as `model.assemble(x, active, true).hess`): the
/// spectrum that follows a relaxation needs no assembly of its own.
pub fn relax_assembled(
    model: &EnergyModel,
    active: &ActiveSet,
    symbolic: &Arc<SymbolicFactor>,
    x: &mut [f64],
    grad_reference: Option<f64>,
    params: &NewtonParams,
    initial: Option<Cholesky>,
) -> (NewtonInfo, Vec<f64>) {
    let _timer = crate::profile::Timer::new(crate::profile::Phase::Relax);
    let mut cur = model.assemble(x, active, true);
    let info = newton_loop(
        model,
        active,
        symbolic,
        x,
        grad_reference,
        params,
        initial,
        &mut cur,
    );
    (info, cur.hess)
}

/// The Newton iteration of [`relax_assembled`] from `cur`, the assembly at `x`; `cur` stays
/// the assembly at `x` throughout.
#[allow(clippy::too_many_arguments)]
fn newton_loop(
    model: &EnergyModel,
    active: &ActiveSet,
    symbolic: &Arc<SymbolicFactor>,
    x: &mut [f64],
    grad_reference: Option<f64>,
    params: &NewtonParams,
    initial: Option<Cholesky>,
    cur: &mut crate::rod::model::Assembly,
) -> NewtonInfo {
    let pattern = model.pattern();
    let g_start = norm(&cur.grad);
    let g_ref = grad_reference.unwrap_or(g_start);
    let mut info = NewtonInfo {
        iterations: 0,
        converged: false,
        stop: NewtonStop::MaxIterations,
        grad_start: g_start,
        grad_end: g_start,
        grad_rel: if g_ref > 0.0 { g_start / g_ref } else { 0.0 },
        energy: cur.energy,
        factorizations: 0,
        chord_steps: 0,
        projected_steps: 0,
        krylov_steps: 0,
        max_shift: 0.0,
        escape_doublings: 0,
    };
    if !cur.energy.is_finite() || !g_start.is_finite() {
        info.stop = NewtonStop::NonFinite;
        return info;
    }
    // Diagonal scale for shifts.
    let diag_scale = {
        let d: f64 = pattern.diag.iter().map(|&k| cur.hess[k].abs()).sum();
        (d / pattern.n.max(1) as f64).max(f64::MIN_POSITIVE)
    };
    let mut trial = vec![0.0; x.len()];
    let mut best_grad = g_start;
    let mut stalled = 0;
    let mut last_decrease = f64::INFINITY;
    // `fresh`: a factorization of the Hessian at the current point (the caller's, at the
    // start); `stale`: the last factorization, for chord steps at later points.
    let mut fresh: Option<Cholesky> = initial;
    let mut stale: Option<Cholesky> = None;
    let mut last_projected = false;
    // Whether the last step was a chord step, and whether a chord step's line search just
    // failed (the step is retried with a fresh factorization).
    let mut last_chord = false;
    let mut retry_fresh = false;
    // `‖∇E‖` before the last step if it was a full one, and whether it was a chord step.
    let mut full_step: Option<(f64, bool)> = None;
    loop {
        let g_norm = norm(&cur.grad);
        info.grad_end = g_norm;
        info.grad_rel = if g_ref > 0.0 { g_norm / g_ref } else { 0.0 };
        info.energy = cur.energy;
        if g_norm <= params.rel_tol * g_ref || g_norm == 0.0 {
            info.converged = true;
            info.stop = NewtonStop::Converged;
            return info;
        }
        if g_norm <= 0.5 * best_grad {
            best_grad = g_norm;
            stalled = 0;
        } else if (!last_chord || g_norm <= params.floor_near * params.rel_tol * g_ref)
            && !retry_fresh
            && info.iterations > 0
            && last_decrease <= 1e-12 * cur.energy.abs()
        {
            // The energy no longer moves and the gradient no longer halves: round-off floor.
            // A chord step that stalls proves it only near the tolerance, after steps that
            // showed Newton's quadratic convergence; farther away an old factor's step can
            // crawl along a soft mode where a fresh one still moves, so the next step factors
            // afresh.
            best_grad = best_grad.min(g_norm);
            stalled += 1;
            let near = g_norm <= params.floor_near * params.rel_tol * g_ref;
            if stalled >= params.stall_iterations || near {
                info.converged = info.grad_rel <= params.floor_max_rel;
                info.stop = if info.converged {
                    NewtonStop::RoundoffFloor
                } else {
                    NewtonStop::Stalled
                };
                return info;
            }
        }
        if info.iterations >= params.max_iterations {
            info.stop = NewtonStop::MaxIterations;
            return info;
        }

        // In the quadratic phase the last factorization serves the step: when the last full
        // step cut `‖∇E‖` sixteenfold (a fresh factorization's) or fourfold (a chord step's).
        // Along a soft mode full steps do not cut that much, and old factors' steps wander.
        let quadratic = full_step.is_some_and(|(g0, chord)| {
            let cut = if chord {
                CHORD_CUT
            } else {
                CHORD_CUT * CHORD_CUT
            };
            g_norm <= cut * g0
        });
        let chord_now = fresh.is_none()
            && quadratic
            && !retry_fresh
            && stale.is_some()
            && g_norm <= params.chord_below * g_ref;
        retry_fresh = false;
        if chord_now {
            fresh = stale.take();
        }
        last_chord = chord_now;
        // A chord step with an earlier factorization, kept when it cuts the gradient enough.
        let mut krylov: Option<Cholesky> = None;
        if let Some(f) = stale.take().filter(|_| fresh.is_none()) {
            if params.chord_ratio > 0.0
                && let Some(d) = descent(&f, &cur.grad)
            {
                let gd: f64 = d.iter().zip(&cur.grad).map(|(a, b)| a * b).sum();
                for ((t, xi), di) in trial.iter_mut().zip(x.iter()).zip(&d) {
                    *t = xi - di;
                }
                let a = model.assemble(&trial, active, true);
                let roundoff = 1e-13 * cur.energy.abs().max(f64::MIN_POSITIVE);
                let decreases = a.energy <= cur.energy - params.armijo * gd
                    || (a.energy - cur.energy).abs() <= roundoff;
                if a.energy.is_finite() && decreases && norm(&a.grad) <= params.chord_ratio * g_norm
                {
                    last_decrease = cur.energy - a.energy;
                    x.copy_from_slice(&trial);
                    *cur = a;
                    info.iterations += 1;
                    info.chord_steps += 1;
                    stale = Some(f);
                    continue;
                }
            }
            if params.krylov_iterations > 0 {
                krylov = Some(f);
            }
        }

        // Direction: the exact Hessian if it is positive definite, else the Hessian with every
        // term's local Hessian projected to be positive semidefinite (a convex model that
        // always gives a descent direction), shifted only if even that is singular.
        // Next best to a factorization: the Newton system solved by conjugate gradients
        // preconditioned with the earlier factorization (a nearby Hessian), when it converges
        // in a few iterations.
        let reuse = fresh
            .take()
            .and_then(|f| descent(&f, &cur.grad).map(|d| (d, f)))
            .inspect(|_| {
                if chord_now {
                    info.chord_steps += 1;
                }
            })
            .or_else(|| {
                let f = krylov.take()?;
                let d = pcg(
                    pattern,
                    &cur.hess,
                    &cur.grad,
                    &f,
                    params.krylov_tol,
                    params.krylov_iterations,
                )?;
                let gd: f64 = d.iter().zip(&cur.grad).map(|(a, b)| a * b).sum();
                (gd > 0.0 && gd.is_finite()).then(|| {
                    info.krylov_steps += 1;
                    (d, f)
                })
            });
        let mut projected_now = false;
        let (d, f) = match reuse {
            Some(pair) => pair,
            None => {
                // After a projected step the exact Hessian is usually still indefinite: try it
                // again only every few iterations, or once the gradient has come down.
                let try_exact =
                    !last_projected || info.iterations % 4 == 0 || g_norm <= 1e-3 * g_ref;
                let exact = if try_exact {
                    info.factorizations += 1;
                    Cholesky::factorize(symbolic, pattern, &cur.hess, 0.0)
                        .ok()
                        .and_then(|f| descent(&f, &cur.grad).map(|d| (d, f)))
                } else {
                    None
                };
                last_projected = exact.is_none();
                match exact {
                    Some(pair) => pair,
                    None => {
                        info.projected_steps += 1;
                        projected_now = true;
                        let locals = model.local_hessians_projected(x, active);
                        let mut hp = Vec::new();
                        model.hessian_from_locals(&locals, active, &mut hp);
                        let mut shift = 0.0;
                        let mut tries = 0;
                        loop {
                            tries += 1;
                            info.factorizations += 1;
                            if let Ok(f) = Cholesky::factorize(symbolic, pattern, &hp, shift) {
                                if let Some(d) = descent(&f, &cur.grad) {
                                    break (d, f);
                                }
                            }
                            if tries > 40 {
                                info.stop = NewtonStop::LineSearchFailed;
                                return info;
                            }
                            shift = if shift == 0.0 {
                                1e-12 * diag_scale
                            } else {
                                shift * 10.0
                            };
                            info.max_shift = info.max_shift.max(shift);
                        }
                    }
                }
            }
        };
        if params.chord_ratio > 0.0 || params.krylov_iterations > 0 || params.chord_below > 0.0 {
            stale = Some(f);
        }
        let gd: f64 = d.iter().zip(&cur.grad).map(|(a, b)| a * b).sum();

        // Backtracking line search on x − α d.
        let e0 = cur.energy;
        let roundoff = 1e-13 * e0.abs().max(f64::MIN_POSITIVE);
        let mut alpha = 1.0;
        let mut accepted = None;
        for _ in 0..=params.max_backtracks {
            for ((t, xi), di) in trial.iter_mut().zip(x.iter()).zip(&d) {
                *t = xi - alpha * di;
            }
            let e = model.energy(&trial, active);
            if e.is_finite() {
                if e <= e0 - params.armijo * alpha * gd {
                    accepted = Some(None);
                    if projected_now && alpha == 1.0 {
                        // Escaping a saddle: extend the step while the energy keeps falling.
                        let mut best = e;
                        let mut longer = trial.clone();
                        for _ in 0..params.escape_doublings {
                            let a = 2.0 * alpha;
                            for ((t, xi), di) in longer.iter_mut().zip(x.iter()).zip(&d) {
                                *t = xi - a * di;
                            }
                            let el = model.energy(&longer, active);
                            if !(el.is_finite() && el < best) {
                                break;
                            }
                            best = el;
                            alpha = a;
                            trial.copy_from_slice(&longer);
                        }
                        info.escape_doublings += alpha.log2().round() as usize;
                    }
                    break;
                }
                if (e - e0).abs() <= roundoff {
                    // Energy differences are below round-off: judge the step by the gradient.
                    let a = model.assemble(&trial, active, true);
                    if norm(&a.grad) < g_norm {
                        accepted = Some(Some(a));
                        break;
                    }
                }
            }
            alpha *= 0.5;
        }
        match accepted {
            None if chord_now => {
                // The old factor's step found nothing: try a fresh factorization's.
                retry_fresh = true;
                last_chord = false;
                full_step = None;
            }
            None => {
                // Nothing reduces energy or gradient: at the round-off floor if already close,
                // otherwise a genuine failure.
                info.stop = if info.grad_rel <= params.floor_max_rel {
                    info.converged = true;
                    NewtonStop::RoundoffFloor
                } else {
                    NewtonStop::LineSearchFailed
                };
                return info;
            }
            Some(pre) => {
                full_step = (alpha == 1.0).then_some((g_norm, chord_now));
                x.copy_from_slice(&trial);
                info.iterations += 1;
                *cur = pre.unwrap_or_else(|| model.assemble(x, active, true));
                last_decrease = e0 - cur.energy;
                if !cur.energy.is_finite() || !norm(&cur.grad).is_finite() {
                    info.stop = NewtonStop::NonFinite;
                    return info;
                }
            }
        }
    }
}

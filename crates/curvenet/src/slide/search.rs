//! The search over the moves' coefficients: a deterministic pattern search without
//! derivatives. A first sweep probes each coordinate alone at `probe` levels each side
//! (`±bound·k/probe`) and takes the best, with the point combining each coordinate's best
//! improving level; then each sweep evaluates every coordinate moved by `±step` (in parallel, the
//! results taken in index order, so the outcome is the same on any number of threads); the
//! best improving candidate is taken, and the pattern point that combines every improving
//! coordinate's better direction is tried beside it. A sweep that improves nothing halves the
//! step; the search ends when the step falls below its smallest, after its evaluation budget,
//! or when cancelled (keeping the best point so far).

use crate::cancel::Cancel;
use rayon::prelude::*;
use std::collections::HashMap;

/// The search's settings.
#[derive(Clone, Debug, PartialEq)]
pub struct PatternParams {
    /// Each coordinate stays within `[-bound, bound]`.
    pub bound: f64,
    /// The first step.
    pub step: f64,
    /// The search ends once the step is below this.
    pub min_step: f64,
    /// The most evaluations, checked before each sweep (the sweep under way is finished).
    pub max_evaluations: usize,
    /// `max_evaluations` holds within a sweep too: the points of a sweep past it are not
    /// evaluated (the best so far is kept).
    pub strict: bool,
    /// An improvement must exceed this fraction of the current value's magnitude.
    pub relative_gain: f64,
    /// Levels each side of the first sweep's probe of each coordinate (0: none; the first
    /// sweep is then an ordinary one at `step`).
    pub probe: usize,
}

/// One accepted step of the search.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Step {
    /// Evaluations made when it was accepted.
    pub evaluation: usize,
    /// The step size.
    pub step: f64,
    /// The objective after it.
    pub value: f64,
}

/// What the search found.
#[derive(Clone, Debug, PartialEq)]
pub struct PatternOutcome {
    /// The best point.
    pub x: Vec<f64>,
    /// Its value.
    pub value: f64,
    /// Points evaluated (distinct).
    pub evaluations: usize,
    /// Sweeps made.
    pub sweeps: usize,
    /// The steps accepted, in order.
    pub steps: Vec<Step>,
    /// The search was cancelled.
    pub cancelled: bool,
    /// The search stopped at its most evaluations.
    pub limited: bool,
}

/// Maximises `f` (a value, `-∞` for a point not allowed) from the origin of `dimension`
/// coordinates. `progress` hears each accepted step.
pub fn pattern_search(
    dimension: usize,
    f: &(dyn Fn(&[f64]) -> f64 + Sync),
    params: &PatternParams,
    cancel: &Cancel,
    progress: &dyn Fn(&Step),
) -> PatternOutcome {
    let mut memo: HashMap<Vec<u64>, f64> = HashMap::new();
    let key = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
    let mut x = vec![0.0; dimension];
    let mut value = f(&x);
    memo.insert(key(&x), value);
    let mut out = PatternOutcome {
        x: x.clone(),
        value,
        evaluations: 1,
        sweeps: 0,
        steps: Vec::new(),
        cancelled: false,
        limited: false,
    };
    let limit = match params.strict {
        true => params.max_evaluations,
        false => usize::MAX,
    };
    let mut step = params.step;
    if params.probe > 0 && dimension > 0 {
        let levels = params.probe;
        let mut candidates: Vec<(usize, Vec<f64>)> = Vec::new();
        for i in 0..dimension {
            for k in 1..=levels {
                for sign in [1.0, -1.0] {
                    let mut y = x.clone();
                    y[i] = sign * params.bound * k as f64 / levels as f64;
                    candidates.push((i, y));
                }
            }
        }
        let values = evaluate_all(&candidates, f, &mut memo, cancel, &key, limit);
        let mut pattern = x.clone();
        let mut best: Option<(usize, f64)> = None;
        let mut per: Vec<Option<(usize, f64)>> = vec![None; dimension];
        for (k, &v) in values.iter().enumerate() {
            if v > value && best.is_none_or(|(_, b)| v > b) {
                best = Some((k, v));
            }
            let i = candidates[k].0;
            if v > value && per[i].is_none_or(|(_, b)| v > b) {
                per[i] = Some((k, v));
            }
        }
        let improving = per.iter().flatten().count();
        for (k, _) in per.iter().flatten() {
            let (i, y) = &candidates[*k];
            pattern[*i] = y[*i];
        }
        if let Some((k, v)) = best {
            let (mut nx, mut nv) = (candidates[k].1.clone(), v);
            if improving > 1 && !cancel.is_cancelled() {
                let pv =
                    evaluate_all(&[(0, pattern.clone())], f, &mut memo, cancel, &key, limit)[0];
                if pv > nv {
                    (nx, nv) = (pattern, pv);
                }
            }
            x = nx;
            value = nv;
            let s = Step {
                evaluation: memo.len(),
                step: params.bound / levels as f64,
                value,
            };
            progress(&s);
            out.steps.push(s);
        }
        out.sweeps += 1;
        step = step.min(params.bound / (2 * levels) as f64);
    }
    let better = |a: f64, b: f64| a > b + params.relative_gain * b.abs().max(f64::MIN_POSITIVE);
    while dimension > 0 && step >= params.min_step && memo.len() < params.max_evaluations {
        if cancel.is_cancelled() {
            out.cancelled = true;
            break;
        }
        out.sweeps += 1;
        let mut candidates: Vec<(usize, Vec<f64>)> = Vec::new();
        for i in 0..dimension {
            for sign in [1.0, -1.0] {
                let mut y = x.clone();
                y[i] = (y[i] + sign * step).clamp(-params.bound, params.bound);
                if y[i] != x[i] {
                    candidates.push((i, y));
                }
            }
        }
        let values = evaluate_all(&candidates, f, &mut memo, cancel, &key, limit);
        if cancel.is_cancelled() {
            out.cancelled = true;
        }
        // The best candidate (the first of equals), and each coordinate's better direction.
        let mut best: Option<(usize, f64)> = None;
        let mut pattern = x.clone();
        let mut improving = 0;
        for (k, &v) in values.iter().enumerate() {
            if better(v, value) {
                let (i, y) = &candidates[k];
                if best.is_none_or(|(_, b)| v > b) {
                    best = Some((k, v));
                }
                let other = values
                    .iter()
                    .zip(&candidates)
                    .filter(|(w, (j, _))| *j == *i && **w > v)
                    .count();
                if other == 0 {
                    pattern[*i] = y[*i];
                    improving += 1;
                }
            }
        }
        let Some((k, v)) = best else {
            if out.cancelled {
                break;
            }
            step /= 2.0;
            continue;
        };
        let (mut nx, mut nv) = (candidates[k].1.clone(), v);
        if improving > 1 && !out.cancelled {
            let pv = evaluate_all(&[(0, pattern.clone())], f, &mut memo, cancel, &key, limit)[0];
            if pv > nv {
                (nx, nv) = (pattern, pv);
            }
        }
        x = nx;
        value = nv;
        let s = Step {
            evaluation: memo.len(),
            step,
            value,
        };
        progress(&s);
        out.steps.push(s);
        if out.cancelled {
            break;
        }
    }
    out.x = x;
    out.value = value;
    out.evaluations = memo.len();
    out.limited = memo.len() >= params.max_evaluations;
    out
}

/// The values of `points` (memoised), evaluated in parallel; `-∞` for a point skipped once
/// `cancel` is set, and for the points past the first ones not yet known that bring the
/// points evaluated to `limit` (in the order given, so the same ones whatever the threads).
fn evaluate_all(
    points: &[(usize, Vec<f64>)],
    f: &(dyn Fn(&[f64]) -> f64 + Sync),
    memo: &mut HashMap<Vec<u64>, f64>,
    cancel: &Cancel,
    key: &dyn Fn(&[f64]) -> Vec<u64>,
    limit: usize,
) -> Vec<f64> {
    let mut room = limit.saturating_sub(memo.len());
    let mut seen = std::collections::HashSet::new();
    let known: Vec<Option<f64>> = points
        .iter()
        .map(|(_, y)| memo.get(&key(y)).copied())
        .collect();
    // Which unknown points fit within the limit.
    let allowed: Vec<bool> = (points.iter().zip(&known))
        .map(|((_, y), k)| {
            if k.is_some() || seen.contains(&key(y)) {
                return true;
            }
            let fits = room > 0;
            if fits {
                room -= 1;
                seen.insert(key(y));
            }
            fits
        })
        .collect();
    let fresh: Vec<Option<f64>> = points
        .par_iter()
        .zip(&known)
        .zip(&allowed)
        .map(|(((_, y), k), &allowed)| match k {
            Some(_) => None,
            None if !allowed || cancel.is_cancelled() => Some(f64::NEG_INFINITY),
            None => Some(f(y)),
        })
        .collect();
    let mut values = Vec::with_capacity(points.len());
    for ((((_, y), k), v), allowed) in points.iter().zip(known).zip(fresh).zip(allowed) {
        let v = k.or(v).unwrap_or(f64::NEG_INFINITY);
        if allowed && !cancel.is_cancelled() {
            memo.insert(key(y), v);
        }
        values.push(v);
    }
    values
}

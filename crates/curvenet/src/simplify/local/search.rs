//! One local search from one start: scans of single moves by first improvement and
//! Kernighan–Lin chains, over the moves a set allows.

use super::evaluator::{Entry, Evaluator, Memo, Stopped, best_position, improves};
use super::{LocalOutcome, LocalParams, Move, Step, Strategy, check};
use crate::cancel::Cancel;
use crate::constraints::{Constraints, UnitMove};
use crate::simplify::SimplifyError;
use crate::simplify::exhaustive::SubsetScore;
use crate::stability::Analyzer;

/// Moves evaluated together (in parallel) under first improvement; fixed, so the search does
/// not depend on the thread count.
const CHUNK: usize = 8;

/// The local search from `start` (feasible), under `constraints` when given, adding what it
/// evaluates to `memo`. The outcome's `starts`, `evaluations` and `structures` are left for
/// [`super::starts::MultiStart::finish`].
pub(super) fn search_from(
    analyzer: &Analyzer,
    params: &LocalParams,
    constraints: Option<&Constraints>,
    start: &[usize],
    cancel: &Cancel,
    memo: &mut Memo,
) -> Result<LocalOutcome, SimplifyError> {
    let (lengths, budget) = check(analyzer, params)?;
    let mut cur: Vec<usize> = start.to_vec();
    cur.sort_unstable();
    cur.dedup();
    let n = lengths.len();
    if let Some(&c) = cur.iter().chain(&params.keep).find(|&&c| c >= n) {
        return Err(SimplifyError::Params(
            format!("curve {c} does not exist ({n} curves)").into(),
        ));
    }
    let length = |s: &[usize]| -> f64 { s.iter().map(|&c| lengths[c]).sum() };
    if cur.is_empty() || length(&cur) > budget || !params.keep.iter().all(|k| cur.contains(k)) {
        return Err(SimplifyError::Params(
            "local search needs a feasible starting subset".into(),
        ));
    }
    if let Some(Err(v)) = constraints.map(|c| c.check(&cur)) {
        return Err(SimplifyError::Params(
            format!("local search needs a starting subset that meets the constraints: {v}").into(),
        ));
    }
    let mut search = Search {
        ev: Evaluator {
            analyzer,
            constraints,
            keep: params.keep.clone(),
            tolerance: params.tolerance,
            memo,
            cancel,
        },
        params,
        constraints,
        lengths: &lengths,
        budget,
        lambda: f64::NAN,
        cur,
        steps: Vec::new(),
        rounds: 0,
        chains: 0,
    };
    let (start_score, cancelled) = match search.start() {
        Ok(start) => (start, search.run().is_err()),
        Err(Stopped) => return Err(SimplifyError::Cancelled),
    };
    // A start over `--max-deviation` that no move left: its own `λ_eq`.
    let lambda = if search.lambda == f64::NEG_INFINITY {
        search
            .ev
            .memo
            .get(&search.cur)
            .map_or(f64::NAN, |e| e.lambda)
    } else {
        search.lambda
    };
    let deviation = constraints
        .filter(|c| c.params().max_deviation.is_some())
        .and_then(|_| analyzer.deviation(&analyzer.set(&search.cur)).ok());
    Ok(LocalOutcome {
        // Filled in by the multi-start run from the evaluations all its starts share.
        visited: Vec::new(),
        start: start_score,
        starts: Vec::new(),
        given_searched: false,
        deviation,
        best: SubsetScore {
            length: length(&search.cur),
            curves: search.cur,
            lambda,
        },
        steps: search.steps,
        rounds: search.rounds,
        chains: search.chains,
        evaluations: 0,
        structures: 0,
        cancelled,
    })
}

/// The state of one local search.
struct Search<'s> {
    ev: Evaluator<'s>,
    params: &'s LocalParams,
    constraints: Option<&'s Constraints>,
    lengths: &'s [f64],
    budget: f64,
    /// The current set and its rank ([`Entry::value`]: its `λ_eq` once a set within
    /// `--max-deviation` is reached).
    cur: Vec<usize>,
    lambda: f64,
    steps: Vec<Step>,
    rounds: usize,
    chains: usize,
}

impl Search<'_> {
    /// Evaluates the start (and takes its best part when it falls apart into a better one).
    fn start(&mut self) -> Result<SubsetScore, Stopped> {
        let first = self.ev.eval_all(std::slice::from_ref(&self.cur))?.remove(0);
        self.lambda = first.value;
        let start = SubsetScore {
            curves: self.cur.clone(),
            length: self.cur.iter().map(|&c| self.lengths[c]).sum(),
            lambda: first.lambda,
        };
        if let Some(p) = first.part.filter(|_| self.params.parts) {
            // The start falls apart and one of its parts alone is better.
            self.steps.push(Step {
                step: Move::Part(p.0),
                lambda: p.2,
                round: 0,
            });
            self.cur = p.1;
            self.lambda = p.2;
        }
        self.rounds = self.steps.len();
        Ok(start)
    }

    /// Rounds of single moves (and chains under variable depth) until none improves or the
    /// move cap is hit.
    fn run(&mut self) -> Result<(), Stopped> {
        while self.steps.len() < self.params.max_moves {
            let round = self.rounds;
            self.rounds += 1;
            if let Some(c) = self.scan()? {
                self.take(std::slice::from_ref(&c), round);
                continue;
            }
            if self.params.strategy != Strategy::VariableDepth {
                break;
            }
            // A local optimum of single moves: a chain from it.
            self.chains += 1;
            if !self.chain(round)? {
                break;
            }
        }
        Ok(())
    }

    /// The moves (with the sets they lead to), evaluated.
    fn candidates(&mut self, moves: &[(Move, Vec<usize>)]) -> Result<Vec<Candidate>, Stopped> {
        let sets: Vec<Vec<usize>> = moves.iter().map(|m| m.1.clone()).collect();
        let entries = self.ev.eval_all(&sets)?;
        let parts = self.params.parts;
        Ok(moves
            .iter()
            .zip(sets)
            .zip(entries)
            .map(|((m, s), e)| Candidate::new(m.0, s, e, parts))
            .collect())
    }

    /// The moves from `set` that stay feasible and move no `locked` curve, in the
    /// documented order, with the sets they lead to.
    fn moves(&self, set: &[usize], locked: Option<&[bool]>) -> Vec<(Move, Vec<usize>)> {
        match self.constraints {
            Some(c) => unit_moves(c, set, self.params, locked),
            None => neighbourhood(set, self.lengths, self.budget, self.params, locked)
                .into_iter()
                .map(|m| (m, m.apply(set)))
                .collect(),
        }
    }

    /// A scan of single moves by first improvement (under variable depth too: the descent to
    /// a local optimum before any chain): the improving move taken, if any.
    fn scan(&mut self) -> Result<Option<Candidate>, Stopped> {
        let tol = self.params.tolerance;
        let moves = self.moves(&self.cur, None);
        for part in moves.chunks(CHUNK) {
            let cands = self.candidates(part)?;
            let pick = cands
                .iter()
                .position(|c| improves(c.value(), self.lambda, tol));
            if let Some(i) = pick {
                let mut cands = cands;
                return Ok(Some(cands.swap_remove(i)));
            }
        }
        Ok(None)
    }

    /// A Kernighan–Lin chain from the current set; takes its best prefix when it improves
    /// (true), else leaves the set (false).
    fn chain(&mut self, round: usize) -> Result<bool, Stopped> {
        let (params, tol) = (self.params, self.params.tolerance);
        let n = self.lengths.len();
        let mut set = self.cur.clone();
        let mut locked = vec![false; n];
        let mut chain: Vec<Candidate> = Vec::new();
        for _ in 0..params.depth.unwrap_or(n).max(1) {
            let moves = self.moves(&set, Some(&locked));
            let mut cands = self.candidates(&moves)?;
            let values: Vec<f64> = cands.iter().map(Candidate::value).collect();
            let Some(i) = best_position(&values, tol) else {
                break;
            };
            let c = cands.swap_remove(i);
            for x in c.step.curves().into_iter().flatten() {
                match self.constraints {
                    Some(cs) => {
                        for &y in &cs.units()[cs.unit_of(x)] {
                            locked[y] = true;
                        }
                    }
                    None => locked[x] = true,
                }
            }
            set = c.end().to_vec();
            chain.push(c);
        }
        let top = chain
            .iter()
            .map(Candidate::value)
            .fold(f64::NEG_INFINITY, f64::max);
        if !improves(top, self.lambda, tol) {
            return Ok(false);
        }
        // The shortest prefix within the tolerance of the chain's best.
        let floor = top - tol * top.abs();
        let end = chain
            .iter()
            .position(|c| c.value() >= floor && improves(c.value(), self.lambda, tol))
            .expect("the chain's best improves")
            + 1;
        self.take(&chain[..end], round);
        Ok(true)
    }

    /// Takes `moves` (in order) as round `round`'s.
    fn take(&mut self, moves: &[Candidate], round: usize) {
        for c in moves {
            self.steps.extend(c.steps(round));
        }
        let last = moves.last().expect("a move");
        self.cur = last.end().to_vec();
        self.lambda = last.value();
    }
}

/// A move evaluated: the set it leads to, possibly followed by keeping its best part.
struct Candidate {
    step: Move,
    set: Vec<usize>,
    /// The set's `λ_eq`.
    lambda: f64,
    /// The set's rank ([`Entry::value`]).
    value: f64,
    part: Option<(usize, Vec<usize>, f64)>,
}

impl Candidate {
    fn new(step: Move, set: Vec<usize>, entry: Entry, parts: bool) -> Self {
        Candidate {
            step,
            set,
            lambda: entry.lambda,
            value: entry.value,
            part: entry.part.filter(|_| parts),
        }
    }

    /// The rank where it ends (`λ_eq`, or −∞ over `--max-deviation`).
    fn value(&self) -> f64 {
        self.part.as_ref().map_or(self.value, |p| p.2)
    }

    /// The set where it ends.
    fn end(&self) -> &[usize] {
        self.part.as_ref().map_or(&self.set, |p| &p.1)
    }

    /// Its steps (one or two).
    fn steps(&self, round: usize) -> Vec<Step> {
        let mut v = vec![Step {
            step: self.step,
            lambda: self.lambda,
            round,
        }];
        if let Some(p) = &self.part {
            v.push(Step {
                step: Move::Part(p.0),
                lambda: p.2,
                round,
            });
        }
        v
    }
}

/// The unit moves from `cur` under `constraints` ([`Constraints::neighbours`]), each named by
/// its units' smallest curves; a unit is locked when its curves are.
fn unit_moves(
    constraints: &Constraints,
    cur: &[usize],
    params: &LocalParams,
    locked: Option<&[bool]>,
) -> Vec<(Move, Vec<usize>)> {
    let units = constraints.units();
    let unit_locked: Option<Vec<bool>> = locked.map(|l| units.iter().map(|u| l[u[0]]).collect());
    constraints
        .neighbours(cur, params.add_back, params.drop, unit_locked.as_deref())
        .into_iter()
        .map(|(m, set)| {
            let first = |u: usize| units[u][0];
            let m = match m {
                UnitMove::Add(u) => Move::Add(first(u)),
                UnitMove::Drop(u) => Move::Drop(first(u)),
                UnitMove::Swap { out, into } => Move::Swap {
                    out: first(out),
                    into: first(into),
                },
            };
            (m, set)
        })
        .collect()
}

/// The moves from `cur` that stay feasible and move no `locked` curve, in the documented
/// order.
fn neighbourhood(
    cur: &[usize],
    lengths: &[f64],
    budget: f64,
    params: &LocalParams,
    locked: Option<&[bool]>,
) -> Vec<Move> {
    let n = lengths.len();
    let free = |c: &usize| locked.is_none_or(|l| !l[*c]);
    // Feasibility on the new set's own length (summed in ascending order, as everywhere).
    let fits = |m: &Move| m.apply(cur).iter().map(|&c| lengths[c]).sum::<f64>() <= budget;
    let outside: Vec<usize> = (0..n).filter(|c| !cur.contains(c)).filter(free).collect();
    let removable: Vec<usize> = cur
        .iter()
        .copied()
        .filter(|c| !params.keep.contains(c))
        .filter(free)
        .collect();
    let mut moves = Vec::new();
    if params.add_back {
        moves.extend(outside.iter().map(|&c| Move::Add(c)));
    }
    if params.drop && cur.len() > 1 {
        moves.extend(removable.iter().map(|&c| Move::Drop(c)));
    }
    for &out in &removable {
        moves.extend(outside.iter().map(|&into| Move::Swap { out, into }));
    }
    moves.retain(fits);
    moves
}

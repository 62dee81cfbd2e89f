//! The answer of a run: the network to build, chosen among the networks the searches of the
//! run evaluated, and the alternatives beside it.
//!
//! A network *qualifies* when it is
//! - **stable**: `λ_eq > 0` with no zero mode and no negative mode among its computed
//!   eigenvalues (a mechanism, `λ ≈ 0`, or an unstable equilibrium is never an answer);
//! - **feasible**: within the budget, holding the keep list, and meeting every constraint
//!   ([`Constraints::check`], and `--max-deviation` on its equilibrium when asked for).
//!
//! The answer is the qualifying network with the largest `λ_eq`; networks within the tie
//! tolerance (relative 1e-7) of the best go to the first offered. The caller offers, in order,
//! the greedy's final network, then the local search's, then any other search's. The
//! alternatives are the best qualifying networks after it, by decreasing `λ_eq` (ties to the
//! first offered), each *distinct* from the answer and from every alternative before it:
//! the curves in one of the two networks and not in the other must total at least
//! [`DISTINCT`] (5%) of the budget. A network that differs from a better one only by curves
//! shorter than that (adding, dropping or swapping a tiny curve) is the same design to build,
//! so it is passed over; so is a network *dominated* by a qualifying one made of some of its
//! curves with at least its `λ_eq` (within the tie tolerance: its other curves add material
//! and no stability, e.g. a separate part that is not the weakest). With none qualifying, there is no answer: the reason names what the
//! best-ranked offer lacked, and the smallest stable network of the run (any offer, within the
//! budget or not: the greedy's path records every larger network) is named with how far over
//! the budget it is.

use super::{Constraints, Margins};
use crate::words::{Message, Opt, Recorded, message};
use serde::{Deserialize, Serialize};

/// Relative tolerance under which two `λ_eq` tie.
const TIE: f64 = 1e-7;

/// Two networks are distinct designs when the curves in exactly one of them total at least
/// this fraction of the budget.
pub const DISTINCT: f64 = 0.05;

/// A network a search of the run evaluated, offered as the answer.
#[derive(Clone, Debug, PartialEq)]
pub struct Offer {
    /// Which search found it: `greedy`, `local_search`, `exhaustive`, `random`, …
    pub source: String,
    /// The greedy's iteration, for the networks of its path.
    pub iteration: Option<usize>,
    /// Curves, ascending.
    pub curves: Vec<usize>,
    /// Total rest length.
    pub length: f64,
    /// `λ_eq`.
    pub lambda: f64,
    /// Zero modes among the computed eigenvalues.
    pub zero_modes: usize,
    /// Negative modes among them.
    pub negative_modes: usize,
    /// The largest displacement of a vertex at equilibrium, when known.
    pub deviation: Option<f64>,
}

impl Offer {
    /// Stable: `λ_eq > 0`, no zero mode, no negative mode.
    pub fn is_stable(&self) -> bool {
        self.lambda > 0.0 && self.zero_modes == 0 && self.negative_modes == 0
    }
}

/// What [`Answer`] and [`StableNetwork`] say of a network: where it was found, its curves,
/// length and `λ_eq` (their first fields in `result.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Found {
    /// Which search found it.
    pub source: String,
    /// The greedy's iteration, for a network of its path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub iteration: Option<usize>,
    /// Curves, ascending.
    pub curves: Vec<usize>,
    /// Total rest length.
    pub length: f64,
    /// `λ_eq`.
    pub lambda: f64,
}

impl Found {
    fn of(offer: &Offer) -> Self {
        Found {
            source: offer.source.clone(),
            iteration: offer.iteration,
            curves: offer.curves.clone(),
            length: offer.length,
            lambda: offer.lambda,
        }
    }
}

/// The network to build (`answer` in `result.json`; each of `alternatives` too).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Answer {
    /// Where it was found, its curves, length and `λ_eq`.
    #[serde(flatten)]
    pub found: Found,
    /// Zero modes (0).
    pub zero_modes: usize,
    /// Negative modes (0).
    pub negative_modes: usize,
    /// Every constraint's margin.
    pub margins: Margins,
    /// In the physical mode, its physical figures (frequencies, deflections, stresses in a
    /// material's units), set by the run once the answer is chosen; absent in the paper's
    /// mode.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub physical: Option<crate::physics::PhysicalSummary>,
}

/// A stable network outside the budget, named when there is no answer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StableNetwork {
    /// Where it was found, its curves, length and `λ_eq`.
    #[serde(flatten)]
    pub found: Found,
    /// How far its length exceeds the budget, in percent of the budget (0 or less: within).
    pub over_budget_percent: f64,
}

/// Why there is no answer (`no_answer` in `result.json`, beside `"answer": null`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NoAnswer {
    /// What the networks found lacked.
    pub reason: Message,
    /// The smallest stable network of the run, if any.
    pub smallest_stable: Option<StableNetwork>,
}

/// The answer and the alternatives.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// The answer, or why there is none.
    pub answer: Result<Answer, NoAnswer>,
    /// Up to the number asked for, best first (the answer not included).
    pub alternatives: Vec<Answer>,
}

/// Whether the networks `a` and `b` are distinct designs: the curves in exactly one of them
/// total at least [`DISTINCT`] of the budget.
pub fn distinct(constraints: &Constraints, a: &[usize], b: &[usize]) -> bool {
    let only = |x: &[usize], y: &[usize]| -> Vec<usize> {
        x.iter().copied().filter(|c| !y.contains(c)).collect()
    };
    let differ = constraints.length(&only(a, b)) + constraints.length(&only(b, a));
    differ >= DISTINCT * constraints.budget()
}

/// Whether `p` dominates `o`: a proper subset of its curves, as stable (within the tie
/// tolerance): `o`'s other curves add material and no stability.
fn dominates(p: &Offer, o: &Offer) -> bool {
    p.curves.len() < o.curves.len()
        && p.curves.iter().all(|c| o.curves.contains(c))
        && p.lambda >= o.lambda - TIE * o.lambda.abs()
}

/// Whether `offer` qualifies as the answer or an alternative (stable and feasible; see the
/// module documentation).
pub fn qualifies(constraints: &Constraints, offer: &Offer) -> bool {
    disqualified(constraints, offer).is_none()
}

/// Why `offer` does not qualify, if it does not.
fn disqualified(constraints: &Constraints, offer: &Offer) -> Option<Message> {
    if offer.negative_modes > 0 {
        return Some(message![format!(
            "{} negative mode(s): an unstable equilibrium (λ_eq {:.6e})",
            offer.negative_modes, offer.lambda
        )]);
    }
    if offer.zero_modes > 0 || !(offer.lambda > 0.0) {
        return Some(message![format!(
            "{} zero mode(s): a mechanism, a part of it moves freely (λ_eq {:.6e})",
            offer.zero_modes.max(1),
            offer.lambda
        )]);
    }
    if let Err(v) = constraints.check(&offer.curves) {
        return Some(message![format!("it does not meet the constraints ({v})")]);
    }
    if constraints.params().max_deviation.is_some() && offer.deviation.is_none() {
        return Some(message![
            "its equilibrium's deviation from the designed shape was not measured"
        ]);
    }
    if let Some(d) = offer.deviation
        && !constraints.deviation_ok(d)
    {
        return Some(match constraints.deviation_unit() {
            None => message![
                format!(
                    "its equilibrium moves a vertex {d:.6} from its designed place, more than "
                ),
                Opt::MaxDeviation,
                " allows"
            ],
            Some(_) if !d.is_finite() => message![
                "it has no linear self-weight deflection in the physical model (not stable \
                 there), so it meets no ",
                Opt::MaxDeviation
            ],
            Some(u) => message![
                format!(
                    "bent into shape and under its own weight (the physical model) it moves a \
                     vertex {} from its designed place, more than ",
                    crate::fmt::length_in(d, Some(u))
                ),
                Opt::MaxDeviation,
                " allows"
            ],
        });
    }
    None
}

fn answer_of(constraints: &Constraints, offer: &Offer) -> Answer {
    Answer {
        found: Found::of(offer),
        zero_modes: offer.zero_modes,
        negative_modes: offer.negative_modes,
        margins: constraints.margins(&offer.curves, offer.deviation),
        physical: None,
    }
}

/// Chooses the answer and up to `alternatives` alternatives among `offers` (see the module
/// documentation).
pub fn choose(constraints: &Constraints, offers: &[Offer], alternatives: usize) -> Choice {
    let qualifying: Vec<&Offer> = offers
        .iter()
        .filter(|o| disqualified(constraints, o).is_none())
        .collect();
    // Distinct curve sets, the first offer of each; then by decreasing λ_eq, ties (within the
    // tolerance of the better) to the earlier offer.
    let mut unique: Vec<&Offer> = Vec::new();
    for o in qualifying {
        if !unique.iter().any(|d| d.curves == o.curves) {
            unique.push(o);
        }
    }
    let mut ranked: Vec<(usize, &Offer)> = unique.into_iter().enumerate().collect();
    ranked.sort_by(|a, b| {
        let (la, lb) = (a.1.lambda, b.1.lambda);
        let tie = (la - lb).abs() <= TIE * la.abs().max(lb.abs());
        if tie {
            a.0.cmp(&b.0)
        } else {
            lb.total_cmp(&la)
        }
    });
    let ranked: Vec<&Offer> = ranked.into_iter().map(|(_, o)| o).collect();
    let Some(&first) = ranked.first() else {
        return Choice {
            answer: Err(no_answer(constraints, offers)),
            alternatives: Vec::new(),
        };
    };
    let mut picked: Vec<&Offer> = vec![first];
    for &o in &ranked[1..] {
        if picked.len() > alternatives {
            break;
        }
        if picked
            .iter()
            .all(|p| distinct(constraints, &p.curves, &o.curves))
            && !ranked.iter().any(|p| dominates(p, o))
        {
            picked.push(o);
        }
    }
    let mut picked = picked.into_iter().map(|o| answer_of(constraints, o));
    Choice {
        answer: Ok(picked.next().expect("the answer")),
        alternatives: picked.collect(),
    }
}

/// Why nothing qualifies, with the smallest stable network of the run.
fn no_answer(constraints: &Constraints, offers: &[Offer]) -> NoAnswer {
    let budget = constraints.budget();
    let within: Vec<&Offer> = offers
        .iter()
        .filter(|o| o.length <= budget && !o.curves.is_empty())
        .collect();
    let reason = if within.is_empty() {
        message!["no network found meets the budget"]
    } else {
        let mut lines: Vec<Message> = Vec::new();
        for o in within.iter().take(4) {
            let what = disqualified(constraints, o).unwrap_or_default();
            let place = o
                .iteration
                .map_or_else(String::new, |k| format!(" (iteration {k})"));
            lines.push(what.prefixed([
                format!("the {}'s network{place}: ", o.source.replace('_', " ")).into(),
            ]));
        }
        if within.len() > 4 {
            lines.push(message![format!(
                "and {} other network(s) likewise",
                within.len() - 4
            )]);
        }
        message!["no stable network meets the budget and the constraints: "]
            .then(Message::join(lines, "; "))
    };
    let smallest_stable = offers
        .iter()
        .filter(|o| o.is_stable())
        .min_by(|a, b| a.length.total_cmp(&b.length))
        .map(|o| StableNetwork {
            found: Found::of(o),
            over_budget_percent: 100.0 * (o.length - budget) / budget,
        });
    NoAnswer {
        reason,
        smallest_stable,
    }
}

impl Answer {
    /// One line for summaries: where it comes from, its size, length and value (`value`
    /// names it: `λ_eq`, or `μ_min` under the frequency objective), and each constraint asked
    /// for beyond the budget with its standing (groups and orbits whole, one structure, the
    /// number of curves, the largest gap and deviation against their limits). Lengths carry
    /// `unit` when given: the physical mode's scene unit, where the largest deviation is the
    /// physical model's under self-weight.
    pub fn describe(&self, value: &str, unit: Option<&str>) -> String {
        let source = self.found.source.replace('_', " ");
        let place = match self.found.iteration {
            Some(k) => format!("the {source}'s iteration {k}"),
            None => format!("the {source}'s network"),
        };
        let m = &self.margins;
        let mut s = format!(
            "{place}, {} curves, length {} ({}% of the budget), {value} {:.6e}",
            self.found.curves.len(),
            crate::fmt::length_in(self.found.length, unit),
            crate::fmt::percent(100.0 * m.budget.value / m.budget.limit),
            self.found.lambda
        );
        if m.groups.is_some() {
            s.push_str("; groups whole");
        }
        if m.symmetry.is_some() {
            s.push_str("; symmetric (orbits whole)");
        }
        if let Some(c) = &m.connected {
            s.push_str(&if c.value == 1.0 {
                "; one connected structure".to_string()
            } else {
                format!("; {} separate structures", c.value)
            });
        }
        if let Some(k) = &m.min_curves {
            s.push_str(&format!("; {} curves (at least {})", k.value, k.limit));
        }
        let deviation = match unit {
            Some(_) => "largest deviation under self-weight (the physical model)",
            None => "largest deviation",
        };
        let named = [
            ("largest gap", m.max_gap.as_ref()),
            (deviation, m.max_deviation.as_ref()),
        ];
        for (what, margin) in named {
            if let Some(g) = margin {
                s.push_str(&format!(
                    "; {what} {} (limit {})",
                    crate::fmt::length_in(g.value, unit),
                    crate::fmt::length_in(g.limit, unit)
                ));
            }
        }
        s
    }
}

impl NoAnswer {
    /// Lines for summaries: the reason, then the smallest stable network (its value named
    /// `value`, its length in `unit`, as in [`Answer::describe`]).
    pub fn describe(&self, value: &str, unit: Option<&str>) -> String {
        let mut s = format!("no answer: {}", self.reason.render(&Recorded));
        match &self.smallest_stable {
            Some(n) => {
                let place = n.found.iteration.map_or_else(
                    || format!("the {}'s network", n.found.source),
                    |k| format!("iteration {k}"),
                );
                let budget = if n.over_budget_percent > 0.0 {
                    format!("{:.1}% over the budget", n.over_budget_percent)
                } else {
                    format!(
                        "within the budget, {}% of it",
                        crate::fmt::percent(100.0 + n.over_budget_percent)
                    )
                };
                s.push_str(&format!(
                    "\nsmallest stable network of the run: {place}, {} curves, length {} \
                     ({budget}), {value} {:.6e}",
                    n.found.curves.len(),
                    crate::fmt::length_in(n.found.length, unit),
                    n.found.lambda
                ));
            }
            None => s.push_str("\nno stable network was found in the run"),
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::testing::{network, pavilion};
    use crate::constraints::{ConstraintParams, parse_groups};

    fn offer(source: &str, curves: &[usize], lengths: &[f64], lambda: f64, zero: usize) -> Offer {
        Offer {
            source: source.into(),
            iteration: None,
            curves: curves.to_vec(),
            length: curves.iter().map(|&c| lengths[c]).sum(),
            lambda,
            zero_modes: zero,
            negative_modes: 0,
            deviation: None,
        }
    }

    #[test]
    fn the_best_stable_feasible_network_is_the_answer() {
        let net = network(&pavilion(4, false, 0.0));
        let l = net.rest_lengths();
        // The budget holds the ring with two arches, not the whole pavilion.
        let budget = (l[0] + l[1].max(l[3]) + l[2].max(l[3])) * (1.0 + 1e-9);
        assert!(budget < l.iter().sum::<f64>());
        let c = Constraints::none(&net, budget, &[]);
        let offers = vec![
            offer("greedy", &[0, 1, 2], &l, 1e-9, 0),
            offer("local_search", &[0, 1, 3], &l, 3e-9, 0),
            // Better but a mechanism, and one over the budget.
            offer("random", &[0], &l, 5e-9, 1),
            offer("exhaustive", &[0, 1, 2, 3, 4], &l, 9e-9, 0),
            // A tie with the local search's, offered later: an alternative, not the answer.
            offer("exhaustive", &[1, 2], &l, 3e-9 * (1.0 + 1e-9), 0),
            offer("exhaustive", &[0, 1, 3], &l, 3e-9, 0),
        ];
        let ch = choose(&c, &offers, 5);
        let a = ch.answer.expect("an answer");
        assert_eq!(
            (a.found.source.as_str(), a.found.curves.clone()),
            ("local_search", vec![0, 1, 3])
        );
        assert!(a.margins.all_met());
        let alt: Vec<Vec<usize>> = ch
            .alternatives
            .iter()
            .map(|x| x.found.curves.clone())
            .collect();
        // [0, 1, 2] is [1, 2] with the ring added, and less stable: dominated.
        assert_eq!(alt, vec![vec![1, 2]], "distinct, best first, undominated");
        assert_eq!(choose(&c, &offers, 1).alternatives.len(), 1);
    }

    #[test]
    fn alternatives_are_distinct_undominated_and_sorted() {
        use crate::constraints::testing::polyline;
        use crate::geom::Vec3;
        // The pavilion and a tiny straight curve (5) beside it, 20 units long.
        let mut curves = pavilion(4, false, 0.0);
        let tiny = (0..=4)
            .map(|i| Vec3::new(1500.0 + 5.0 * i as f64, 0.0, 0.0))
            .collect();
        curves.push(polyline(tiny, false));
        let net = network(&curves);
        let l = net.rest_lengths();
        assert!(l[5] < 0.05 * l[1], "the tiny curve is tiny");
        let c = Constraints::none(&net, l.iter().sum(), &[]);
        let offers = vec![
            offer("greedy", &[0, 1, 2], &l, 9e-9, 0),
            // The answer with the tiny curve added: the same design.
            offer("local_search", &[0, 1, 2, 5], &l, 8e-9, 0),
            // The answer with the tiny curve swapped in for the ring: distinct.
            offer("local_search", &[1, 2, 5], &l, 7e-9, 0),
            // Arch 4 added to a better network, [0, 1, 3], offered after it: dominated.
            offer("local_search", &[0, 1, 3, 4], &l, 6e-9 * (1.0 - 1e-9), 0),
            offer("local_search", &[0, 1, 3], &l, 6e-9, 0),
            offer("local_search", &[0, 2, 3], &l, 5e-9, 0),
            offer("local_search", &[0, 3, 4], &l, 4e-9, 0),
        ];
        let ch = choose(&c, &offers, 3);
        let a = ch.answer.expect("an answer");
        assert_eq!(a.found.curves, vec![0, 1, 2]);
        let alt: Vec<Vec<usize>> = ch
            .alternatives
            .iter()
            .map(|x| x.found.curves.clone())
            .collect();
        assert_eq!(alt, vec![vec![1, 2, 5], vec![0, 1, 3], vec![0, 2, 3]]);
        for w in ch.alternatives.windows(2) {
            assert!(w[0].found.lambda >= w[1].found.lambda);
        }
        assert!(
            ch.alternatives
                .iter()
                .all(|x| x.found.lambda <= a.found.lambda)
        );
        assert!(!distinct(&c, &[0, 1, 2], &[0, 1, 2, 5]));
        assert!(distinct(&c, &[0, 1, 2], &[1, 2, 5]));
        // More asked for than there are: the rest, no error.
        let all = choose(&c, &offers, 50).alternatives;
        assert_eq!(all.len(), 4);
        assert_eq!(all[3].found.curves, vec![0, 3, 4]);
    }

    #[test]
    fn a_mechanism_is_never_the_answer_and_the_smallest_stable_network_is_named() {
        let net = network(&pavilion(4, false, 0.0));
        let l = net.rest_lengths();
        // The budget holds the ring with one arch: only the mechanism of the path.
        let budget = (l[0] + l[1]) * (1.0 + 1e-9);
        assert!(budget < l[0] + l[1] + l[2].min(l[3]));
        let c = Constraints::none(&net, budget, &[]);
        let mut path = vec![
            offer("greedy", &[0, 1, 2, 3, 4], &l, 4e-9, 0),
            offer("greedy", &[0, 1, 2, 3], &l, 2e-9, 0),
            offer("greedy", &[0, 1], &l, -2e-15, 1),
        ];
        for (k, o) in path.iter_mut().enumerate() {
            o.iteration = Some(k);
        }
        let ch = choose(&c, &path, 3);
        let none = ch.answer.expect_err("no answer");
        assert!(
            none.reason.render(&Recorded).contains("zero mode"),
            "{}",
            none.reason
        );
        assert!(
            none.reason.render(&Recorded).contains("iteration 2"),
            "{}",
            none.reason
        );
        let s = none.smallest_stable.clone().expect("iteration 1 is stable");
        assert_eq!(s.found.iteration, Some(1));
        assert!(s.over_budget_percent > 0.0);
        assert!(
            none.describe("λ_eq", None)
                .contains("smallest stable network of the run: iteration 1")
        );
        assert!(ch.alternatives.is_empty());
    }

    #[test]
    fn constraints_and_the_deviation_disqualify() {
        let net = network(&pavilion(4, false, 0.0));
        let l = net.rest_lengths();
        let total: f64 = l.iter().sum();
        let p = ConstraintParams {
            groups: parse_groups("1 3\n", "g.txt").expect("groups"),
            max_deviation: Some(10.0),
            ..Default::default()
        };
        let c = Constraints::new(&net, None, &p, total, &[]).expect("feasible");
        let mut split = offer("greedy", &[0, 1], &l, 1e-9, 0);
        split.deviation = Some(1.0);
        let mut sags = offer("local_search", &[0, 1, 3], &l, 1e-9, 0);
        sags.deviation = Some(11.0);
        let none = choose(&c, &[split.clone(), sags.clone()], 0)
            .answer
            .expect_err("none");
        assert!(
            none.reason.render(&Recorded).contains("group"),
            "{}",
            none.reason
        );
        assert!(
            none.reason.render(&Recorded).contains("--max-deviation"),
            "{}",
            none.reason
        );
        sags.deviation = Some(9.0);
        let a = choose(&c, &[split, sags], 0)
            .answer
            .expect("now it qualifies");
        assert_eq!(a.margins.max_deviation.expect("evaluated").margin, 1.0);
        assert_eq!(a.margins.groups.expect("groups").value, 0.0);
    }
}

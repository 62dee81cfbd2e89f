//! Curves that move together: the groups and symmetry orbits of the design constraints.
//!
//! A symmetry orbit moves as one: its first curve (the *leader*) has the orbit's coefficients,
//! and every other curve of the orbit is the leader's moved curve mapped by the power of the
//! symmetry that maps the leader onto it, each point then put back on the surface (an end
//! that slides onto the boundary, an end that stays at its drawn position), so a symmetric
//! network stays symmetric. This needs the orbit to hold as many curves as the symmetry group
//! has elements: a curve the symmetry maps onto itself (a curve on a mirror plane, or across
//! it) could only take moves that are symmetric themselves, which its family does not hold,
//! so such an orbit stays where it is.
//!
//! A group (of a groups file or the curve files) moves with one set of coefficients applied
//! to each member's own family, when every member has the same family (the same functions:
//! both ends on the boundary, or the same end, or neither); the offset then runs along each
//! member's own direction across itself. A group whose members' families differ, or a unit
//! where groups and orbits meet, stays where it is.

use super::surface::Surface;
use crate::constraints::{Constraints, Symmetry};
use crate::geom::Vec3;
use crate::io::Polyline;

/// How a curve follows its leader.
#[derive(Clone, Debug, PartialEq)]
pub enum TieMap {
    /// The leader's coefficients applied to the curve's own family (a group).
    Shared,
    /// The leader's moved curve mapped by `symmetry` applied `power` times (an orbit);
    /// `reversed` when the map runs the leader's curve backwards along this one.
    Symmetry {
        /// The symmetry.
        symmetry: Symmetry,
        /// How many times it is applied.
        power: u32,
        /// The image runs from this curve's last point to its first.
        reversed: bool,
    },
}

/// A curve that moves with another.
#[derive(Clone, Debug, PartialEq)]
pub struct Tie {
    /// The curve (position among the slider's curves).
    pub curve: usize,
    /// The curve whose coefficients it takes (a position; never itself tied).
    pub leader: usize,
    /// How.
    pub map: TieMap,
}

/// The ties of the curves at `positions` (their ids in the network `constraints` was bound
/// to, in slider order) and the curves that stay because their unit cannot move as one.
/// `curves` are the drawn polylines, in slider order.
pub fn ties_of(
    constraints: &Constraints,
    ids: &[usize],
    curves: &[Polyline],
) -> (Vec<Tie>, Vec<usize>) {
    let position = |id: usize| ids.iter().position(|&i| i == id);
    let (mut ties, mut stay) = (Vec::new(), Vec::new());
    let orbits: Vec<&Vec<usize>> = constraints
        .symmetry()
        .map(|s| s.orbits.iter().filter(|o| o.len() > 1).collect())
        .unwrap_or_default();
    for unit in constraints.units().iter().filter(|u| u.len() > 1) {
        let members: Vec<usize> = unit.iter().filter_map(|&c| position(c)).collect();
        if members.len() < 2 {
            continue;
        }
        let leader = members[0];
        let orbit = orbits.iter().find(|o| o.as_slice() == unit.as_slice());
        let touches_orbit = orbits.iter().any(|o| o.iter().any(|c| unit.contains(c)));
        match (orbit, constraints.symmetry()) {
            (Some(_), Some(found)) if unit.len() == found.group_order() as usize => {
                let order = found.group_order();
                for &m in &members[1..] {
                    let (power, reversed) = best_power(
                        &found.symmetry,
                        order,
                        &curves[leader].points,
                        &curves[m].points,
                    );
                    ties.push(Tie {
                        curve: m,
                        leader,
                        map: TieMap::Symmetry {
                            symmetry: found.symmetry.clone(),
                            power,
                            reversed,
                        },
                    });
                }
            }
            _ if !touches_orbit => ties.extend(members[1..].iter().map(|&m| Tie {
                curve: m,
                leader,
                map: TieMap::Shared,
            })),
            _ => stay.extend(members),
        }
    }
    (ties, stay)
}

/// The power of `symmetry` (1 to `order − 1`) that maps `leader` closest onto `member`, and
/// whether it runs backwards along it.
fn best_power(symmetry: &Symmetry, order: u32, leader: &[Vec3], member: &[Vec3]) -> (u32, bool) {
    let (Some(&first), Some(&last)) = (leader.first(), leader.last()) else {
        return (1, false);
    };
    let (Some(&m0), Some(&m1)) = (member.first(), member.last()) else {
        return (1, false);
    };
    let mut best = (f64::INFINITY, 1, false);
    for k in 1..order.max(2) {
        let (a, b) = (symmetry.apply(first, k), symmetry.apply(last, k));
        let forward = a.dist(m0) + b.dist(m1);
        let backward = a.dist(m1) + b.dist(m0);
        let mid = leader[leader.len() / 2];
        let middle = distance_to(symmetry.apply(mid, k), member);
        for (d, reversed) in [(forward, false), (backward, true)] {
            if d + middle < best.0 {
                best = (d + middle, k, reversed);
            }
        }
    }
    (best.1, best.2)
}

/// The distance from `p` to the polyline through `points`.
fn distance_to(p: Vec3, points: &[Vec3]) -> f64 {
    if points.len() < 2 {
        return points.first().map_or(f64::INFINITY, |q| p.dist(*q));
    }
    points
        .windows(2)
        .map(|w| crate::geom::point_segment_distance(p, w[0], w[1]))
        .fold(f64::INFINITY, f64::min)
}

/// The leader's moved curve `moved` mapped onto the curve `drawn` by `map` (a
/// [`TieMap::Symmetry`]), every point put back on `surface`: an end where `slides` says onto
/// the boundary, another end at its drawn position. `None` when the surface cannot take a
/// point.
pub fn mapped(
    moved: &Polyline,
    drawn: &Polyline,
    symmetry: &Symmetry,
    power: u32,
    reversed: bool,
    slides: [bool; 2],
    surface: &Surface,
) -> Option<Polyline> {
    let mut points: Vec<Vec3> = moved
        .points
        .iter()
        .map(|&p| symmetry.apply(p, power))
        .collect();
    if reversed {
        points.reverse();
    }
    let m = points.len();
    for (i, p) in points.iter_mut().enumerate() {
        let end = !drawn.closed && (i == 0 || i + 1 == m);
        *p = if !end {
            surface.closest(*p)?.point
        } else {
            let k = usize::from(i != 0);
            if slides[k] {
                surface.closest_on_boundary(*p)?.0
            } else if k == 0 {
                *drawn.points.first()?
            } else {
                *drawn.points.last()?
            }
        };
    }
    Some(Polyline {
        points,
        closed: drawn.closed,
        origin: drawn.origin.clone(),
        label: drawn.label.clone(),
    })
}

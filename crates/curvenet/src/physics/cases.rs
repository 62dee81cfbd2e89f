//! Load cases and combinations of the physical mode, as a loads file gives them (JSON):
//!
//! ```json
//! {
//!   "cases": [
//!     {"name": "G", "self_weight": true},
//!     {"name": "S", "line": {"intensity": "0.8kN/m", "direction": [0, 0, -1], "per": "projected"}},
//!     {"name": "P", "points": [{"at": [500, 0, 300], "force": [0, 0, -2000]}]},
//!     {"name": "W", "pressure": {"intensity": "1kN/m", "axis": [0, 1, 0], "toward": "inside"}}
//!   ],
//!   "combinations": [{"name": "ULS", "factors": {"G": 1.35, "S": 1.5}}]
//! }
//! ```
//!
//! A case sums what it names: the structure's self-weight (its lumped masses times gravity),
//! a line load along the curves (an intensity with a force-per-length unit, a direction,
//! `per` `length` of curve (the default) or `projected` length across the direction, as snow
//! is given), and point loads in newtons at points of the network, each snapped to the
//! structure's nearest vertex (the snap distance is reported; a point farther than twice the
//! longest edge from the structure is refused, saying how far), and a pressure: a load per
//! length of curve normal to each curve in the plane perpendicular to `axis`, pushing
//! `toward` the `inside` of each curve (its concave side as drawn, seen along the axis) or the
//! `outside`; a straight curve's inside is to the right of its drawn direction seen from the
//! axis's tip. A combination sums cases with factors. Self-weight, line and point loads are
//! dead loads: they keep their direction as the structure deflects. A pressure is a follower
//! load: it stays normal to the curves as they deflect, a conservative load through the
//! area the curves sweep ([`crate::rod::Pressure`]), exact where each loaded curve's ends are
//! held in the plane; an end that moves in the plane also feels the pressure on the short
//! segment from its drawn position to where it is. A curve that leaves the plane is loaded by
//! the pressure on its projection onto the plane.

use super::loads::{held_vertices, self_weight};
use crate::material::Physical;
use crate::rod::{ActiveSet, Network, PressurePart};
use crate::units::parse_quantity;
use crate::words::Message;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The name of the structure's own weight as a load case of its own, which every structural
/// export carries: no case or combination of a loads file may take it.
pub const SELF_WEIGHT: &str = "self-weight";

/// Why a case or combination may not be named `name`, if it may not.
fn reserved(name: &str) -> Option<String> {
    name.trim().eq_ignore_ascii_case(SELF_WEIGHT).then(|| {
        format!(
            "the name {name} is the structure's own weight, a load case of its own in every              export; name it otherwise (a case with \"self_weight\": true is that load)"
        )
    })
}

/// How a line load's intensity is measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Per {
    /// Per length of curve.
    #[default]
    Length,
    /// Per length projected across the load's direction (snow on a roof: per plan length).
    Projected,
}

/// A line load as the file gives it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineSpec {
    /// Intensity with a force-per-length unit (`0.8kN/m`, `800N/m`).
    pub intensity: String,
    /// Direction (any length).
    pub direction: [f64; 3],
    /// What length the intensity is per.
    #[serde(default)]
    pub per: Per,
}

/// The side of each curve a pressure pushes toward.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Toward {
    /// The concave side of each curve as drawn.
    #[default]
    Inside,
    /// The convex side.
    Outside,
}

/// A pressure as the file gives it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PressureSpec {
    /// Intensity with a force-per-length unit, per length of curve (`1kN/m`).
    pub intensity: String,
    /// The axis (any length): the pressure acts in the plane perpendicular to it.
    pub axis: [f64; 3],
    /// The side it pushes toward.
    #[serde(default)]
    pub toward: Toward,
}

impl PressureSpec {
    /// The intensity in N/m.
    pub fn intensity_n_per_m(&self) -> Result<f64, Message> {
        parse_quantity(
            &self.intensity,
            crate::units::Quantity::LineLoad,
            "the pressure's \"intensity\"",
            None,
        )
    }
}

/// A point load as the file gives it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSpec {
    /// Where (scene units).
    pub at: [f64; 3],
    /// The force, N.
    pub force: [f64; 3],
}

/// A load case as the file gives it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    /// Its name.
    pub name: String,
    /// Whether it holds the structure's self-weight.
    #[serde(default)]
    pub self_weight: bool,
    /// A line load along the curves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub line: Option<LineSpec>,
    /// Point loads.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub points: Vec<PointSpec>,
    /// A pressure normal to the curves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure: Option<PressureSpec>,
}

/// A combination as the file gives it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CombinationSpec {
    /// Its name.
    pub name: String,
    /// Each case's factor.
    pub factors: BTreeMap<String, f64>,
}

/// A loads file, checked ([`Loads::parse`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Loads {
    /// The load cases.
    pub cases: Vec<CaseSpec>,
    /// The combinations.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub combinations: Vec<CombinationSpec>,
}

/// A point load snapped to the structure.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snap {
    /// The point given.
    pub at: [f64; 3],
    /// The vertex it acts on.
    pub vertex: usize,
    /// How far the vertex is from the point, scene units.
    pub distance: f64,
}

/// The line of `text` where `needle` first occurs (1 when it does not).
fn line_of(text: &str, needle: &str) -> usize {
    text.find(needle)
        .map_or(1, |at| text[..at].matches('\n').count() + 1)
}

impl Loads {
    /// Reads and checks the loads file's text (`file` names it in messages).
    ///
    /// # Errors
    ///
    /// A message naming the file and line: malformed JSON, a case without a name or with
    /// nothing in it, two cases or combinations of one name, an intensity without its unit,
    /// a zero direction, a non-finite number, a combination naming a case the file does not
    /// define.
    pub fn parse(text: &str, file: &str) -> Result<Loads, Message> {
        let loads: Loads = serde_json::from_str(text)
            .map_err(|e| Message::from(format!("{file}:{}: {e}", e.line())))?;
        let at = |needle: &str, what: String| {
            Message::from(format!("{file}:{}: {what}", line_of(text, needle)))
        };
        if loads.cases.is_empty() {
            return Err(at("cases", "the file defines no load case".into()));
        }
        let mut names: Vec<&str> = Vec::new();
        for c in &loads.cases {
            let quoted = format!("\"{}\"", c.name);
            if c.name.trim().is_empty() {
                return Err(at("\"name\"", "a load case has an empty name".into()));
            }
            if names.contains(&c.name.as_str()) {
                return Err(at(&quoted, format!("two load cases are named {}", c.name)));
            }
            if let Some(why) = reserved(&c.name) {
                return Err(at(&quoted, why));
            }
            names.push(&c.name);
            if !c.self_weight && c.line.is_none() && c.points.is_empty() && c.pressure.is_none() {
                return Err(at(
                    &quoted,
                    format!(
                        "load case {} holds no load (give \"self_weight\": true, a \"line\", \
                         \"points\" or a \"pressure\")",
                        c.name
                    ),
                ));
            }
            if let Some(l) = &c.line {
                l.intensity_n_per_m()
                    .map_err(|e| at(&l.intensity, format!("load case {}: {e}", c.name)))?;
                if !direction_ok(l.direction) {
                    return Err(at(
                        &quoted,
                        format!(
                            "load case {}: the line load's direction must be finite and not zero",
                            c.name
                        ),
                    ));
                }
            }
            if let Some(p) = &c.pressure {
                p.intensity_n_per_m()
                    .map_err(|e| at(&p.intensity, format!("load case {}: {e}", c.name)))?;
                if !direction_ok(p.axis) {
                    return Err(at(
                        &quoted,
                        format!(
                            "load case {}: the pressure's axis must be finite and not zero",
                            c.name
                        ),
                    ));
                }
            }
            for p in &c.points {
                if !p.at.iter().chain(&p.force).all(|x| x.is_finite()) {
                    return Err(at(
                        &quoted,
                        format!(
                            "load case {}: a point load's numbers must be finite",
                            c.name
                        ),
                    ));
                }
            }
        }
        let mut combined: Vec<&str> = Vec::new();
        for k in &loads.combinations {
            let quoted = format!("\"{}\"", k.name);
            if names.contains(&k.name.as_str()) || combined.contains(&k.name.as_str()) {
                return Err(at(
                    &quoted,
                    format!("the combination {} has the name of another case", k.name),
                ));
            }
            if let Some(why) = reserved(&k.name) {
                return Err(at(&quoted, why));
            }
            combined.push(&k.name);
            if k.factors.is_empty() {
                return Err(at(
                    &quoted,
                    format!("the combination {} has no factors", k.name),
                ));
            }
            for (case, f) in &k.factors {
                if !names.contains(&case.as_str()) {
                    return Err(at(
                        &quoted,
                        format!(
                            "the combination {} names load case {case}, which the file does not \
                             define (its cases: {})",
                            k.name,
                            names.join(", ")
                        ),
                    ));
                }
                if !f.is_finite() {
                    return Err(at(
                        &quoted,
                        format!("the combination {}: factors must be finite", k.name),
                    ));
                }
            }
        }
        Ok(loads)
    }

    /// Every case's forces and then every combination's, with their names and the point
    /// loads' snaps, on the structure `active` (forces on the `3·V` vertex coordinates, zero
    /// off the structure).
    ///
    /// # Errors
    ///
    /// A message naming the case for a point farther than twice the longest edge from the
    /// structure.
    pub fn forces(
        &self,
        network: &Network,
        physical: &Physical,
        active: &ActiveSet,
    ) -> Result<Vec<CaseForces>, Message> {
        let mut out: Vec<CaseForces> = Vec::new();
        for c in &self.cases {
            out.push(case_forces(c, network, physical, active)?);
        }
        for k in &self.combinations {
            let mut f = vec![0.0; 3 * network.vertex_count()];
            let mut snaps = Vec::new();
            let mut pressure = Vec::new();
            for (name, factor) in &k.factors {
                let case = out[..self.cases.len()]
                    .iter()
                    .find(|c| &c.name == name)
                    .expect("checked by parse");
                for (a, b) in f.iter_mut().zip(&case.forces) {
                    *a += factor * b;
                }
                snaps.extend(case.snaps.iter().cloned());
                pressure.extend(case.pressure.iter().map(|p| PressurePart {
                    axis: p.axis,
                    curves: p.curves.iter().map(|q| factor * q).collect(),
                }));
            }
            out.push(CaseForces {
                name: k.name.clone(),
                factors: k.factors.clone(),
                forces: f,
                snaps,
                pressure,
            });
        }
        Ok(out)
    }
}

impl LineSpec {
    /// The intensity in N/m.
    pub fn intensity_n_per_m(&self) -> Result<f64, Message> {
        parse_quantity(
            &self.intensity,
            crate::units::Quantity::LineLoad,
            "the line load's \"intensity\"",
            None,
        )
    }
}

fn direction_ok(d: [f64; 3]) -> bool {
    d.iter().all(|x| x.is_finite()) && d.iter().any(|&x| x != 0.0)
}

/// One case's or combination's forces.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseForces {
    /// Its name.
    pub name: String,
    /// A combination's factors (empty for a case).
    pub factors: BTreeMap<String, f64>,
    /// Forces on the vertex coordinates, N.
    pub forces: Vec<f64>,
    /// Where its point loads act.
    pub snaps: Vec<Snap>,
    /// Its pressures (a follower load, scaled with the forces), per curve in the model's
    /// force per length.
    pub pressure: Vec<PressurePart>,
}

fn case_forces(
    c: &CaseSpec,
    network: &Network,
    physical: &Physical,
    active: &ActiveSet,
) -> Result<CaseForces, Message> {
    let n = network.vertex_count();
    let mut f = if c.self_weight {
        self_weight(network, physical, active)
    } else {
        vec![0.0; 3 * n]
    };
    if let Some(l) = &c.line {
        let q = physical.units.line_load_to_scene(
            l.intensity_n_per_m()
                .map_err(|e| Message::from(format!("load case {}: {e}", c.name)))?,
        );
        let d = crate::geom::Vec3::from(l.direction).normalized();
        for (k, rod) in network.rods.iter().enumerate() {
            if !active.contains(k) {
                continue;
            }
            for j in 0..rod.edge_count() {
                let (a, b) = rod.edge(j);
                let e = network.positions[b as usize] - network.positions[a as usize];
                let len = match l.per {
                    Per::Length => rod.rest_lengths[j],
                    Per::Projected => (e.norm2() - e.dot(d).powi(2)).max(0.0).sqrt(),
                };
                for v in [a, b] {
                    for i in 0..3 {
                        f[3 * v as usize + i] += 0.5 * q * len * d.to_array()[i];
                    }
                }
            }
        }
    }
    let held = held_vertices(network, active);
    let longest = network.edge_length_stats().max;
    let mut snaps = Vec::new();
    for p in &c.points {
        let at = crate::geom::Vec3::from(p.at);
        let (vertex, distance) = (0..n)
            .filter(|&v| held[v])
            .map(|v| (v, (network.positions[v] - at).norm()))
            .fold((usize::MAX, f64::INFINITY), |best, x| {
                if x.1 < best.1 { x } else { best }
            });
        if vertex == usize::MAX || distance > 2.0 * longest {
            return Err(Message::from(format!(
                "load case {}: the point load at ({}, {}, {}) is {} {unit} from the \
                 structure's nearest vertex; a point load must lie on the network (within \
                 twice the longest edge, {} {unit})",
                c.name,
                p.at[0],
                p.at[1],
                p.at[2],
                crate::fmt::significant(distance, 4),
                crate::fmt::significant(2.0 * longest, 4),
                unit = physical.units.symbol()
            )));
        }
        for i in 0..3 {
            f[3 * vertex + i] += p.force[i];
        }
        snaps.push(Snap {
            at: p.at,
            vertex,
            distance,
        });
    }
    let mut pressure = Vec::new();
    if let Some(p) = &c.pressure {
        let q = physical.units.line_load_to_scene(
            p.intensity_n_per_m()
                .map_err(|e| Message::from(format!("load case {}: {e}", c.name)))?,
        );
        let axis = crate::geom::Vec3::from(p.axis).normalized();
        let curves = (network.rods.iter().enumerate())
            .map(|(k, rod)| {
                if !active.contains(k) {
                    return 0.0;
                }
                // The curve's turning seen from the axis's tip: positive turns left, whose
                // concave side is its left (pushed by a negative value).
                let edges: Vec<crate::geom::Vec3> = (0..rod.edge_count())
                    .map(|j| {
                        let (a, b) = rod.edge(j);
                        network.positions[b as usize] - network.positions[a as usize]
                    })
                    .collect();
                let turning: f64 = (edges.windows(2))
                    .map(|w| axis.dot(w[0].cross(w[1])).atan2(w[0].dot(w[1])))
                    .sum();
                let right = if turning > 1e-9 { -1.0 } else { 1.0 };
                match p.toward {
                    Toward::Inside => right * q,
                    Toward::Outside => -right * q,
                }
            })
            .collect();
        pressure.push(PressurePart { axis, curves });
    }
    Ok(CaseForces {
        name: c.name.clone(),
        factors: BTreeMap::new(),
        forces: f,
        snaps,
        pressure,
    })
}

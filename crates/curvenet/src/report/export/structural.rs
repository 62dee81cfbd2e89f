//! A recorded network of a physical run as a structural model for other finite-element tools:
//! the neutral structural JSON (`"format": "curvenet-structure"`, [`StructuralModel`]) and
//! the OpenSeesPy script built from it ([`super::opensees`]).
//!
//! What the model carries, in the scene's consistent units (length ℓ, N, s; mass N·s²/ℓ,
//! stress N/ℓ²):
//! - **nodes**: one per vertex of every kept rod, at its drawn position, so each rod has its
//!   own node at a joint (a rod crossing itself, one per pass);
//! - **ties**: the nodes of one joint share their translations and rotate freely of each
//!   other, as curvenet's joints do;
//! - **elements**: one elastic beam per rod edge, with its rod's material (`E`, `G`) and
//!   section (`A`, `I`, `J`) and a vector in its local x–z plane (`vecxz`, any: the sections
//!   are round);
//! - **supports**: an anchored vertex's nodes have the translations its supports fix fixed
//!   (some only, given per end: on the vertex's first node, the others tied to it); a
//!   clamped end's node also its rotations (the physical mode's clamp holds the end vertex and its
//!   tangent, and a pre-bent rod's twist);
//! - **skew supports**: an end held along a direction of the surface (along or across its
//!   boundary, normal to it) has a translational spring to the ground along that direction,
//!   of curvenet's own anchor stiffness (`2µ`, rigid next to the rods): the same penalty
//!   curvenet's energy carries, so the exported model is curvenet's;
//! - **spin holds**: a rod drawn straight spins about its own axis without moving a point;
//!   curvenet carries no twist for it, and a beam model would have a zero-stiffness spin:
//!   unless a clamp holds it, a rotational spring about the rod's axis at its first node
//!   (its own torsional stiffness over its length) holds the spin, which decouples from
//!   everything else;
//! - **masses**: curvenet's lumped masses (`ρ A` times half of each adjacent edge) on each
//!   node's translations, and on a twisting (pre-bent, curved) rod's rotations `ρ J` times
//!   the same half edges (curvenet's twist inertia about the axis; given about every axis,
//!   which adds a bending rotary inertia of relative size `(r/ℓ)²` that curvenet leaves out);
//! - **load cases**: self-weight, each node's mass times gravity.
//!
//! The geometry is the drawn one, which is the unloaded equilibrium of pre-bent rods: for
//! them the model is curvenet's. A rod straight at rest but drawn curved is bent into its
//! equilibrium and carries the bending prestress of the assembly; the exported beams are
//! stress-free in the drawn shape, without that prestress (and its geometric stiffness), and
//! their torsion couples with bending where curvenet's straight rods carry none.

use crate::material::{Physical, PhysicalMaterial, RestShape, Section};
use crate::rod::{ActiveSet, Network};
use crate::run_folder::schema::PhysicalModel;
use crate::words::Message;
use serde::{Deserialize, Serialize};

/// The `format` of a structural JSON file.
pub const STRUCTURE_FORMAT: &str = "curvenet-structure";

/// The version of the structural JSON format.
pub const STRUCTURE_VERSION: u32 = 1;

/// How many natural frequencies an exported model computes by default.
pub const DEFAULT_FREQUENCIES: usize = 6;

/// The model's units.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelUnits {
    /// Length (`mm`, `cm`, `m`).
    pub length: String,
    /// Force.
    pub force: String,
    /// Mass: force × time² / length.
    pub mass: String,
    /// Stress: force / length².
    pub stress: String,
    /// Time.
    pub time: String,
}

/// A node: one vertex of one rod.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// Its id (from 1).
    pub id: usize,
    /// Position.
    pub xyz: [f64; 3],
    /// The curve (rod) it belongs to.
    pub curve: usize,
    /// The network vertex it stands on.
    pub vertex: usize,
}

/// Nodes that share their translations (a joint), rotating freely of each other.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tie {
    /// The joint's vertex.
    pub vertex: usize,
    /// The nodes, the first the one the others follow.
    pub nodes: Vec<usize>,
}

/// A material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaterialRow {
    /// Its id (from 1).
    pub id: usize,
    /// Its name.
    pub name: String,
    /// Young's modulus `E`.
    pub young: f64,
    /// Shear modulus `G = E / (2 (1 + ν))`.
    pub shear: f64,
    /// Density (mass per volume).
    pub density: f64,
    /// Strength.
    pub strength: f64,
}

/// A round cross-section.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SectionRow {
    /// Its id (from 1).
    pub id: usize,
    /// In words (`solid r 10`, `tube 60 × 4`).
    pub description: String,
    /// Area `A`.
    pub area: f64,
    /// Second moment of area about either axis, `I_y = I_z`.
    pub second_moment: f64,
    /// Torsion constant `J`.
    pub torsion: f64,
    /// Distance from the axis to the outer fibre.
    pub outer_radius: f64,
}

/// An elastic beam between two nodes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Element {
    /// Its id (from 1).
    pub id: usize,
    /// Its end nodes.
    pub nodes: [usize; 2],
    /// The curve (rod) it belongs to.
    pub curve: usize,
    /// Its material's id.
    pub material: usize,
    /// Its section's id.
    pub section: usize,
    /// A vector in the element's local x–z plane, not along it.
    pub vecxz: [f64; 3],
}

/// A node's fixed degrees of freedom.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Support {
    /// The node.
    pub node: usize,
    /// Fixed (`true`) or free: translations x, y, z, then rotations about x, y, z.
    pub fixed: [bool; 6],
}

/// A support along one direction that is not a world axis (a curve end held along or across
/// the surface's boundary, or normal to the surface): a translational spring from the node to
/// the ground along `direction`, with curvenet's own anchor stiffness (rigid next to the rods).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SkewSupport {
    /// The node.
    pub node: usize,
    /// The direction it holds (unit).
    pub direction: [f64; 3],
    /// Force per length along it.
    pub stiffness: f64,
}

/// A rotational spring about a straight rod's axis, from a node to the ground.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpinHold {
    /// The node.
    pub node: usize,
    /// The rod's axis (unit).
    pub axis: [f64; 3],
    /// Moment per radian.
    pub stiffness: f64,
}

/// A node's lumped mass.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NodeMass {
    /// The node.
    pub node: usize,
    /// On each translation.
    pub translational: f64,
    /// On each rotation.
    pub rotational: f64,
}

/// A force on a node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NodalLoad {
    /// The node.
    pub node: usize,
    /// The force.
    pub force: [f64; 3],
}

/// A named load case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadCase {
    /// Its name (`self-weight`).
    pub name: String,
    /// Its nodal forces.
    pub nodal: Vec<NodalLoad>,
}

/// A structure for finite-element tools (`"format": "curvenet-structure"`; the module's
/// documentation says what it carries).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructuralModel {
    /// Always [`STRUCTURE_FORMAT`].
    pub format: String,
    /// Always [`STRUCTURE_VERSION`].
    pub version: u32,
    /// Where it came from (free text).
    pub source: String,
    /// Set when the structure is unstable: what makes it so.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unstable: Option<String>,
    /// The units of every number below.
    pub units: ModelUnits,
    /// How many natural frequencies to compute.
    pub frequencies: usize,
    /// Nodes.
    pub nodes: Vec<Node>,
    /// Joints: nodes sharing translations.
    pub ties: Vec<Tie>,
    /// Materials.
    pub materials: Vec<MaterialRow>,
    /// Sections.
    pub sections: Vec<SectionRow>,
    /// Elements.
    pub elements: Vec<Element>,
    /// Supports.
    pub supports: Vec<Support>,
    /// Supports along directions that are not world axes (springs to the ground).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub skew_supports: Vec<SkewSupport>,
    /// Spin holds of rods drawn straight.
    pub spin_holds: Vec<SpinHold>,
    /// Lumped masses.
    pub masses: Vec<NodeMass>,
    /// Load cases.
    pub load_cases: Vec<LoadCase>,
}

/// The id of `item` in `list` (from 1), added when new.
fn id_of<T: PartialEq>(list: &mut Vec<T>, item: T) -> usize {
    match list.iter().position(|x| *x == item) {
        Some(i) => i + 1,
        None => {
            list.push(item);
            list.len()
        }
    }
}

/// The name of the load case every model carries: the structure's own weight.
pub use crate::physics::cases::SELF_WEIGHT;

/// A unit vector among the axes least along `d`, for an element's local x–z plane.
fn across(d: [f64; 3]) -> [f64; 3] {
    let i = (0..3)
        .min_by(|&a, &b| d[a].abs().total_cmp(&d[b].abs()))
        .unwrap_or(2);
    let mut v = [0.0; 3];
    v[i] = 1.0;
    v
}

impl StructuralModel {
    /// The structure of `curves` of `network` (drawn positions) in the physical model
    /// `model`; `source` says where it came from, `unstable` what makes it unstable.
    pub fn new(
        network: &Network,
        curves: &[usize],
        model: &PhysicalModel,
        source: String,
        unstable: Option<String>,
    ) -> Result<StructuralModel, Message> {
        let physical = &model.physical;
        let rest = model.rest(network.rods.len());
        let p = &network.positions;
        let u = physical.units;
        let mut curves = curves.to_vec();
        curves.sort_unstable();
        curves.dedup();
        let mut nodes = Vec::new();
        let mut at_vertex: Vec<Vec<usize>> = vec![Vec::new(); network.vertex_count()];
        let (mut materials, mut sections) = (Vec::new(), Vec::new());
        let (mut elements, mut masses) = (Vec::new(), Vec::new());
        let mut spin_holds = Vec::new();
        let mut clamped = Vec::new();
        let mut anchored = vec![[false; 3]; network.vertex_count()];
        let mut skew: Vec<(usize, [f64; 3])> = Vec::new();
        let anchor_stiffness = 2.0
            * crate::rod::physical::rigid_anchor_weight(
                network,
                &crate::rod::physical::physical_rods(physical, network.rods.len(), &rest),
            );
        let mut gravity_forces = Vec::new();
        let g = physical.gravity_scene();
        for &c in &curves {
            let rod = &network.rods[c];
            if rod.vertices.len() < 2 {
                continue;
            }
            let r = physical.scene_rod(c);
            let material = id_of(&mut materials, material_row(physical, c));
            let section = id_of(&mut sections, section_row(physical.curve_section(c)));
            let twists = rest[c] == RestShape::PreBent && !rod.is_drawn_straight(p);
            let first = nodes.len() + 1;
            for &v in &rod.vertices {
                let id = nodes.len() + 1;
                nodes.push(Node {
                    id,
                    xyz: p[v as usize].to_array(),
                    curve: c,
                    vertex: v as usize,
                });
                at_vertex[v as usize].push(id);
            }
            let m = rod.vertices.len();
            let mut half_edges = vec![0.0; m];
            for j in 0..rod.edge_count() {
                let (a, b) = (j, (j + 1) % m);
                half_edges[a] += 0.5 * rod.rest_lengths[j];
                half_edges[b] += 0.5 * rod.rest_lengths[j];
                let d = (p[rod.vertices[b] as usize] - p[rod.vertices[a] as usize]).to_array();
                elements.push(Element {
                    id: elements.len() + 1,
                    nodes: [first + a, first + b],
                    curve: c,
                    material,
                    section,
                    vecxz: across(d),
                });
            }
            for (i, &h) in half_edges.iter().enumerate() {
                let mass = r.mass_per_length * h;
                masses.push(NodeMass {
                    node: first + i,
                    translational: mass,
                    rotational: if twists {
                        r.polar_mass_per_length * h
                    } else {
                        0.0
                    },
                });
                gravity_forces.push(NodalLoad {
                    node: first + i,
                    force: g.map(|gi| mass * gi),
                });
            }
            // The physical mode's clamp holds the end vertex and its tangent, not the
            // neighbour the network anchors for the paper's clamp (`rod::model`'s rule).
            let ends = [rod.vertices[0], rod.vertices[m.saturating_sub(1)]];
            let released: Vec<u32> = [(true, 1), (false, m.saturating_sub(2))]
                .into_iter()
                .filter(|&(at_start, _)| rod.is_clamped_at(at_start))
                .map(|(_, i)| rod.vertices[i])
                .filter(|v| !ends.contains(v))
                .collect();
            for &v in rod.anchors.iter().filter(|v| !released.contains(v)) {
                for (held, axis) in anchored[v as usize].iter_mut().zip(rod.anchor_axes(v)) {
                    *held |= axis;
                }
                skew.extend(rod.anchor_skew(v).into_iter().map(|d| (v as usize, d)));
            }
            let mut held = false;
            for (at_start, i) in [(true, 0), (false, m.saturating_sub(1))] {
                if rod.is_clamped_at(at_start) {
                    clamped.push(first + i);
                    held = true;
                }
            }
            if !held && !rod.closed && rod.is_drawn_straight(p) && m >= 2 {
                let d = p[rod.vertices[m - 1] as usize] - p[rod.vertices[0] as usize];
                let length: f64 = rod.rest_length();
                spin_holds.push(SpinHold {
                    node: first,
                    axis: d.normalized().to_array(),
                    stiffness: r.gj / length,
                });
            }
        }
        let mut supports = Vec::new();
        let mut ties = Vec::new();
        for (v, ids) in at_vertex.iter().enumerate() {
            // All three translations fixed: every node at the vertex is fixed, no tie needed.
            // Some only: the first node carries them and the others follow it by a tie.
            let whole = anchored[v].iter().all(|&a| a);
            for (k, &n) in ids.iter().enumerate() {
                let all = clamped.contains(&n);
                let [x, y, z] = anchored[v].map(|a| a && (whole || k == 0));
                if x || y || z || all {
                    supports.push(Support {
                        node: n,
                        fixed: [x, y, z, all, all, all],
                    });
                }
            }
            if !whole && ids.len() > 1 {
                ties.push(Tie {
                    vertex: v,
                    nodes: ids.clone(),
                });
            }
        }
        supports.sort_by_key(|s| s.node);
        // A skew support on the vertex's first node; the others share its translations (a
        // vertex with some translations free has its nodes tied above).
        let skew_supports = skew
            .into_iter()
            .filter_map(|(v, direction)| {
                Some(SkewSupport {
                    node: *at_vertex[v].first()?,
                    direction,
                    stiffness: anchor_stiffness,
                })
            })
            .collect();
        let symbol = u.symbol();
        let mut load_cases = vec![LoadCase {
            name: SELF_WEIGHT.into(),
            nodal: gravity_forces,
        }];
        // The run's load cases, each force on the first node at its vertex (the others share
        // its translations).
        if let Some(loads) = &model.loads {
            let active = ActiveSet::from_curves(network.rods.len(), &curves);
            for case in loads.forces(network, physical, &active)? {
                let forces = crate::physics::loaded::forces_at_rest(network, &case, &active);
                let nodal = (0..network.vertex_count())
                    .filter_map(|v| {
                        let f = [0, 1, 2].map(|a| forces[3 * v + a]);
                        let node = *at_vertex[v].first()?;
                        (f != [0.0; 3]).then_some(NodalLoad { node, force: f })
                    })
                    .collect();
                load_cases.push(LoadCase {
                    name: case.name,
                    nodal,
                });
            }
        }
        Ok(StructuralModel {
            format: STRUCTURE_FORMAT.into(),
            version: STRUCTURE_VERSION,
            source,
            unstable,
            units: ModelUnits {
                length: symbol.into(),
                force: "N".into(),
                mass: format!("N·s²/{symbol}"),
                stress: format!("N/{symbol}²"),
                time: "s".into(),
            },
            frequencies: DEFAULT_FREQUENCIES,
            nodes,
            ties,
            materials: materials
                .into_iter()
                .enumerate()
                .map(|(i, m)| MaterialRow { id: i + 1, ..m })
                .collect(),
            sections: sections
                .into_iter()
                .enumerate()
                .map(|(i, s)| SectionRow { id: i + 1, ..s })
                .collect(),
            elements,
            supports,
            skew_supports,
            spin_holds,
            masses,
            load_cases,
        })
    }

    /// The model as JSON text (numbers in their shortest round-trip form).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|_| "null".into()) + "\n"
    }
}

/// Curve `c`'s material in the scene's units (its id set by the caller).
fn material_row(physical: &Physical, c: usize) -> MaterialRow {
    let m: &PhysicalMaterial = physical.curve_material(c);
    let u = physical.units;
    MaterialRow {
        id: 0,
        name: m.name.clone(),
        young: u.stress_to_scene(m.young_pa),
        shear: u.stress_to_scene(m.shear_pa()),
        density: u.density_to_scene(m.density_kg_m3),
        strength: u.stress_to_scene(m.strength_pa),
    }
}

/// A section's row (its id set by the caller).
fn section_row(s: &Section) -> SectionRow {
    SectionRow {
        id: 0,
        description: s.describe(),
        area: s.area(),
        second_moment: s.second_moment(),
        torsion: s.polar_moment(),
        outer_radius: s.outer_radius(),
    }
}

//! Stresses in the equilibrium the rods were bent into.
//!
//! A rod bent to curvature `κ` has a bending stress `σ_b = E r κ` in its outer fibre (`r`
//! the distance from the axis to the outer fibre: the radius of a bar, half the outer diameter
//! of a tube), and a stretched or compressed one an axial stress `σ_a = E (|e|/ē − 1)`. At a
//! vertex the fibre on one side carries both, `|σ_a| + σ_b` (the larger of its two edges'
//! axial stresses): that over the material's strength is the *utilisation*, above 1 where
//! the rod yields or breaks when assembled. `κ` is the discrete curvature
//! `2 |κb − κ̄b'| / (ē₀ + ē₁)` measured from the rod's rest shape (`rod::terms::bend_strain`:
//! zero for a pre-bent rod where it was drawn), and at a clamped end the clamp's
//! (`rod::terms::clamp_strain` over the end edge: the moment a clamp carries); the gridshell
//! builder's check that a rod survives being bent into shape is `σ_b = E r / R` on an arc of
//! radius `R`.

use crate::geom::Vec3;
use crate::material::{Physical, RestShape};
use crate::rod::Network;
use crate::rod::terms::{bend_strain, clamp_rest, clamp_strain, rest_bend};
use crate::rod::{ActiveSet, EnergyModel};
use serde::{Deserialize, Serialize};

/// A stress at one place.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StressAt {
    /// The stress, MPa.
    pub mpa: f64,
    /// The curve.
    pub curve: usize,
    /// The vertex (for an axial stress, the edge's first vertex).
    pub vertex: usize,
}

/// One curve's largest stresses.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurveStress {
    /// The curve.
    pub curve: usize,
    /// Largest bending stress `E r κ`, MPa.
    pub bending_mpa: f64,
    /// Largest axial stress `|E ε|`, MPa.
    pub axial_mpa: f64,
    /// Largest combined outer-fibre stress `|σ_a| + σ_b`, MPa.
    pub combined_mpa: f64,
    /// Where the combined stress is largest.
    pub vertex: usize,
    /// The curve's material strength, MPa.
    pub strength_mpa: f64,
}

impl CurveStress {
    /// `combined / strength`.
    pub fn utilisation(&self) -> f64 {
        self.combined_mpa / self.strength_mpa
    }
}

/// The stresses of a structure at one state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stresses {
    /// Every curve of the structure, ascending.
    pub curves: Vec<CurveStress>,
}

impl Stresses {
    /// The largest bending stress.
    pub fn max_bending(&self) -> Option<StressAt> {
        self.largest(|c| c.bending_mpa)
    }

    /// The largest axial stress (its curve; the vertex of its largest combined stress).
    pub fn max_axial(&self) -> Option<StressAt> {
        self.largest(|c| c.axial_mpa)
    }

    /// The largest of one stress over the curves, where it occurs.
    fn largest(&self, mpa: impl Fn(&CurveStress) -> f64) -> Option<StressAt> {
        self.curves
            .iter()
            .max_by(|a, b| mpa(a).total_cmp(&mpa(b)))
            .map(|c| StressAt {
                mpa: mpa(c),
                curve: c.curve,
                vertex: c.vertex,
            })
    }

    /// The curve with the largest utilisation.
    pub fn max_utilisation(&self) -> Option<&CurveStress> {
        self.curves
            .iter()
            .max_by(|a, b| a.utilisation().total_cmp(&b.utilisation()))
    }

    /// The curves whose combined stress exceeds their strength, worst first.
    pub fn overstressed(&self) -> Vec<&CurveStress> {
        let mut over: Vec<&CurveStress> = self
            .curves
            .iter()
            .filter(|c| c.combined_mpa > c.strength_mpa)
            .collect();
        over.sort_by(|a, b| b.utilisation().total_cmp(&a.utilisation()));
        over
    }
}

/// The stresses of the curves of `active` at the unknowns `u` (displacements from the drawn
/// state, then any twists), with rest shapes `rest` (straight where shorter). With `model`
/// (the physical model `u` belongs to), a pre-bent rod with twist unknowns takes its bending
/// strains from its material frame ([`EnergyModel::frame_strains`]) and adds the shear of its
/// torsion, `τ = G r (m − m̄) / l̄` (and at its clamps the clamps' twist), as
/// `√(σ² + 3 τ²)` (von Mises) to the combined stress.
pub fn assembly_stresses(
    network: &Network,
    physical: &Physical,
    rest: &[RestShape],
    active: &ActiveSet,
    u: &[f64],
    model: Option<&EnergyModel>,
) -> Stresses {
    let x = |v: u32| -> Vec3 {
        let i = 3 * v as usize;
        network.positions[v as usize] + Vec3::new(u[i], u[i + 1], u[i + 2])
    };
    let units = physical.units;
    let mut curves = Vec::new();
    for (c, rod) in network.rods.iter().enumerate() {
        if !active.contains(c) {
            continue;
        }
        let props = physical.scene_rod(c);
        let pre_bent = rest.get(c).copied().unwrap_or_default() == RestShape::PreBent;
        let (m, ne) = (rod.vertices.len(), rod.edge_count());
        // Axial stress of every edge.
        let axial: Vec<f64> = (0..ne)
            .map(|j| {
                let (a, b) = rod.edge(j);
                let strain = x(a).dist(x(b)) / rod.rest_lengths[j] - 1.0;
                units.stress_to_mpa(props.young * strain).abs()
            })
            .collect();
        let mut out = CurveStress {
            curve: c,
            bending_mpa: 0.0,
            axial_mpa: axial.iter().copied().fold(0.0, f64::max),
            combined_mpa: 0.0,
            vertex: rod.vertices[0] as usize,
            strength_mpa: units.stress_to_mpa(props.strength),
        };
        let framed = model.map(|m| m.frame_strains(u, c)).unwrap_or_default();
        let clamp_twists = model
            .map(|m| m.clamp_twist_strains(u, c))
            .unwrap_or_default();
        // A pre-bent rod's material frame: its bending and twist at every interior vertex
        // (the energy's frame terms).
        let shear = props.young / (2.0 * (1.0 + physical.curve_material(c).poisson));
        for (i, &(v, kappa, twist)) in framed.iter().enumerate() {
            // The frame terms' centres in order: vertex `i` of a closed rod, `i + 1` of an
            // open one; the edges on either side.
            let centre = if rod.closed { i } else { i + 1 };
            let (prev, next) = ((centre + ne - 1) % ne, centre % ne);
            let bending = units.stress_to_mpa(props.young * props.outer_radius * kappa);
            let tau = units.stress_to_mpa(shear * props.outer_radius * twist.abs());
            let sigma = bending + axial[prev].max(axial[next]);
            let combined = (sigma * sigma + 3.0 * tau * tau).sqrt();
            out.bending_mpa = out.bending_mpa.max(bending);
            if combined > out.combined_mpa {
                out.combined_mpa = combined;
                out.vertex = v as usize;
            }
        }
        // Bending at every vertex with a bending term (the interior ones, or all of a closed
        // rod), the same stencils as the energy's.
        let centers = if !framed.is_empty() {
            0..0
        } else if rod.closed {
            0..m
        } else {
            1..m.saturating_sub(1)
        };
        for i in centers {
            let (prev, next) = ((i + ne - 1) % ne, i % ne);
            let (v0, v1, v2) = (
                rod.vertices[(i + m - 1) % m],
                rod.vertices[i],
                rod.vertices[(i + 1) % m],
            );
            let (r0, r1) = (rod.rest_lengths[prev], rod.rest_lengths[next]);
            let drawn = pre_bent.then(|| {
                let p = |v: u32| network.positions[v as usize];
                rest_bend(p(v1) - p(v0), p(v2) - p(v1), r0, r1)
            });
            let strain = bend_strain(x(v0), x(v1), x(v2), r0, r1, drawn.as_ref());
            let kappa = 2.0 * strain.norm() / (r0 + r1);
            let bending = units.stress_to_mpa(props.young * props.outer_radius * kappa);
            let combined = bending + axial[prev].max(axial[next]);
            out.bending_mpa = out.bending_mpa.max(bending);
            if combined > out.combined_mpa {
                out.combined_mpa = combined;
                out.vertex = v1 as usize;
            }
        }
        // Bending at a clamped end: the clamp's ghost stencil (`rod::terms::clamp`), whose
        // dual length is the end edge's.
        for at_start in [true, false] {
            if !rod.is_clamped_at(at_start) {
                continue;
            }
            let idx = |k: usize| rod.vertices[if at_start { k } else { m - 1 - k }];
            let edge = if at_start { 0 } else { ne - 1 };
            let rest = rod.rest_lengths[edge];
            let p = |v: u32| network.positions[v as usize];
            let drawn = clamp_rest(
                p(idx(0)),
                p(idx(1)),
                (m > 2).then(|| p(idx(2))),
                rest,
                pre_bent,
            );
            let kappa = clamp_strain(x(idx(0)), x(idx(1)), rest, &drawn).norm() / rest;
            let bending = units.stress_to_mpa(props.young * props.outer_radius * kappa);
            let twist = clamp_twists
                .iter()
                .find(|t| t.0 == idx(0))
                .map_or(0.0, |t| t.1);
            let tau = units.stress_to_mpa(shear * props.outer_radius * twist.abs());
            let sigma = bending + axial[edge];
            let combined = (sigma * sigma + 3.0 * tau * tau).sqrt();
            out.bending_mpa = out.bending_mpa.max(bending);
            if combined > out.combined_mpa {
                out.combined_mpa = combined;
                out.vertex = idx(0) as usize;
            }
        }
        if out.combined_mpa < out.axial_mpa {
            out.combined_mpa = out.axial_mpa;
        }
        curves.push(out);
    }
    Stresses { curves }
}

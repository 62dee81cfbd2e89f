//! The rod network as data: rods sharing vertices at their crossings, in their locked rest
//! state. [`crate::network`] builds it from curves; the energy ([`super::EnergyModel`]) is
//! built from it.

use super::Supports;
use crate::geom::Vec3;
use crate::material::{EndFrame, EndSupport};
use serde::{Deserialize, Serialize};

/// How far from its chord (relative to the chord's length) every vertex of a rod may lie for
/// the rod to be straight ([`Rod::is_drawn_straight`]): rounding of straight input, not a
/// shape.
pub const STRAIGHT_SAGITTA: f64 = 1e-9;

/// One rod: the resampled curve of the same id.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rod {
    /// Global vertex indices along the rod. A closed rod does not repeat its first vertex; a
    /// rod crossing itself lists the shared vertex twice.
    pub vertices: Vec<u32>,
    /// True for a closed curve (an edge joins the last vertex to the first).
    pub closed: bool,
    /// Rest length of each edge (`vertices.len() − 1` edges, or `vertices.len()` if closed).
    pub rest_lengths: Vec<f64>,
    /// Supported (anchored) vertices; their anchor targets are their rest positions.
    pub anchors: Vec<u32>,
    /// The supports of its start and end when they are not the network's `supports` (given
    /// per end): which translations an end's anchors fix, and (through `anchors`) whether its
    /// rotation is held.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ends: Option<[EndSupport; 2]>,
    /// The surface's directions at its start and end, where a support given per end fixes a
    /// translation along one of them ([`EndSupport::surface`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<[EndFrame; 2]>,
}

impl Rod {
    /// Number of edges.
    pub fn edge_count(&self) -> usize {
        self.rest_lengths.len()
    }

    /// The rod's rest length `L_i`: the material to cut, fixed for the whole run.
    pub fn rest_length(&self) -> f64 {
        self.rest_lengths.iter().sum()
    }

    /// Whether the rod is clamped at its first (`at_start`) or last vertex: open, and that
    /// vertex and its neighbour anchored (the paper's clamp, as the network records it).
    pub fn is_clamped_at(&self, at_start: bool) -> bool {
        let m = self.vertices.len();
        if self.closed || m < 2 {
            return false;
        }
        let (end, next) = if at_start {
            (self.vertices[0], self.vertices[1])
        } else {
            (self.vertices[m - 1], self.vertices[m - 2])
        };
        self.anchors.contains(&end) && self.anchors.contains(&next)
    }

    /// The translations (x, y, z) the anchor of vertex `v` fixes: those of the end it belongs
    /// to (the end vertex, or the neighbour a held rotation anchors), all three without per-end
    /// supports.
    pub fn anchor_axes(&self, v: u32) -> [bool; 3] {
        let Some(ends) = self.ends else {
            return [true; 3];
        };
        let m = self.vertices.len();
        let mut axes = [false; 3];
        for (s, near) in ends.iter().zip([[0, 1], [m - 1, m.saturating_sub(2)]]) {
            if near.iter().any(|&i| self.vertices.get(i) == Some(&v)) {
                for (a, f) in axes.iter_mut().zip(s.fixed) {
                    *a |= f;
                }
            }
        }
        axes
    }

    /// The weight matrix of the anchor of vertex `v`: `Σ d dᵀ` over the unit directions its
    /// end's support fixes — the world axes of [`Self::anchor_axes`] and the surface's
    /// directions ([`Self::anchor_skew`]) — so the anchor's energy `µ Δxᵀ W Δx` penalises the
    /// displacement along each fixed direction.
    pub fn anchor_weights(&self, v: u32) -> [[f64; 3]; 3] {
        let mut w = [[0.0; 3]; 3];
        for (a, fixed) in self.anchor_axes(v).into_iter().enumerate() {
            if fixed {
                w[a][a] = 1.0;
            }
        }
        for d in self.anchor_skew(v) {
            for (a, row) in w.iter_mut().enumerate() {
                for (b, x) in row.iter_mut().enumerate() {
                    *x += d[a] * d[b];
                }
            }
        }
        w
    }

    /// The surface's unit directions (along the boundary, across it, normal to the surface)
    /// along which the anchor of vertex `v` is fixed: those of the end it belongs to (the end
    /// vertex, or the neighbour a held rotation anchors).
    pub fn anchor_skew(&self, v: u32) -> Vec<[f64; 3]> {
        let (Some(ends), Some(frames)) = (self.ends, self.frames) else {
            return Vec::new();
        };
        let m = self.vertices.len();
        let mut out = Vec::new();
        for ((s, f), near) in ends
            .iter()
            .zip(&frames)
            .zip([[0, 1], [m - 1, m.saturating_sub(2)]])
        {
            if near.iter().any(|&i| self.vertices.get(i) == Some(&v)) {
                out.extend(f.fixed_directions(s));
            }
        }
        out
    }

    /// The support of its first (`at_start`) or last end (`None` when closed or a single
    /// vertex): its own when given per end, else as its anchors hold it (clamped when the end
    /// vertex and its neighbour are anchored, pinned when the end vertex alone is, free).
    pub fn end_support(&self, at_start: bool) -> Option<EndSupport> {
        let m = self.vertices.len();
        if self.closed || m < 2 {
            return None;
        }
        if let Some(e) = self.ends {
            return Some(e[usize::from(!at_start)]);
        }
        let end = self.vertices[if at_start { 0 } else { m - 1 }];
        Some(if self.is_clamped_at(at_start) {
            EndSupport::CLAMPED
        } else if self.anchors.contains(&end) {
            EndSupport::PINNED
        } else {
            EndSupport::FREE
        })
    }

    /// Whether the rod is straight as drawn in `positions`: open, and every vertex within
    /// [`STRAIGHT_SAGITTA`] of the chord's length from the chord. A pre-bent rod that is
    /// straight carries no twist unknowns: its twist decouples from its bending exactly, as a
    /// straight rod's does, and its spin about its own axis moves no point, so it is no
    /// mechanism.
    pub fn is_drawn_straight(&self, positions: &[Vec3]) -> bool {
        let m = self.vertices.len();
        if self.closed || m < 2 {
            return !self.closed;
        }
        let a = positions[self.vertices[0] as usize];
        let chord = positions[self.vertices[m - 1] as usize] - a;
        let len = chord.norm();
        if len == 0.0 {
            return false;
        }
        let dir = chord / len;
        self.vertices.iter().all(|&v| {
            let d = positions[v as usize] - a;
            (d - dir * d.dot(dir)).norm() <= STRAIGHT_SAGITTA * len
        })
    }

    /// The end vertices of edge `j`.
    pub fn edge(&self, j: usize) -> (u32, u32) {
        let n = self.vertices.len();
        (self.vertices[j], self.vertices[(j + 1) % n])
    }
}

/// A vertex shared by two or more rods (or by two passes of one rod).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Joint {
    /// The shared vertex.
    pub vertex: u32,
    /// Curves through it, ascending, without repeats.
    pub curves: Vec<u32>,
}

/// A rod network in its locked rest state (`docs/model.md`, *Network construction*).
///
/// `positions` is the drawn (resampled) state: rest lengths were measured on it and anchors
/// pull toward it. Relaxed states are separate coordinate vectors of displacements from it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Network {
    /// Rest positions of all vertices.
    pub positions: Vec<Vec3>,
    /// One rod per input curve, in input order: rod `i` is curve `i`.
    pub rods: Vec<Rod>,
    /// Shared vertices.
    pub joints: Vec<Joint>,
    /// Supports used to choose the anchored vertices.
    pub supports: Supports,
}

impl Network {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of degrees of freedom (3 per vertex).
    pub fn dofs(&self) -> usize {
        3 * self.positions.len()
    }

    /// Rest length of every curve.
    pub fn rest_lengths(&self) -> Vec<f64> {
        self.rods.iter().map(Rod::rest_length).collect()
    }

    /// Total rest length of the given curves.
    pub fn total_length(&self, curves: &[usize]) -> f64 {
        curves.iter().map(|&c| self.rods[c].rest_length()).sum()
    }

    /// The rest positions as a flat coordinate vector `[x0, y0, z0, x1, …]`.
    pub fn rest_coordinates(&self) -> Vec<f64> {
        self.positions.iter().flat_map(|p| p.to_array()).collect()
    }

    /// Minimum, median and maximum rest edge length over all rods.
    pub fn edge_length_stats(&self) -> EdgeLengthStats {
        let mut all: Vec<f64> = self
            .rods
            .iter()
            .flat_map(|r| r.rest_lengths.iter().copied())
            .collect();
        all.sort_by(f64::total_cmp);
        if all.is_empty() {
            return EdgeLengthStats {
                min: 0.0,
                median: 0.0,
                max: 0.0,
            };
        }
        let median = if all.len() % 2 == 1 {
            all[all.len() / 2]
        } else {
            0.5 * (all[all.len() / 2 - 1] + all[all.len() / 2])
        };
        EdgeLengthStats {
            min: all[0],
            median,
            max: all[all.len() - 1],
        }
    }

    /// For every vertex, the curves through it (ascending, no repeats).
    pub fn vertex_curves(&self) -> Vec<Vec<u32>> {
        let mut out = vec![Vec::new(); self.positions.len()];
        for (c, rod) in self.rods.iter().enumerate() {
            for &v in &rod.vertices {
                let list: &mut Vec<u32> = &mut out[v as usize];
                if list.last() != Some(&(c as u32)) {
                    list.push(c as u32);
                }
            }
        }
        for l in &mut out {
            l.sort_unstable();
            l.dedup();
        }
        out
    }
}

/// Edge-length range of a network.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EdgeLengthStats {
    /// Shortest rest edge.
    pub min: f64,
    /// Median rest edge.
    pub median: f64,
    /// Longest rest edge.
    pub max: f64,
}

//! Straightest geodesics shot from the boundary (the paper's Fig. 3.1; docs/model.md,
//! *Curve generation*).
//!
//! A geodesic starts at arc-length fraction `t` of a boundary loop (see
//! [`MeshTopology::point_on_loop`] for the reference's conventions), leaves at angle `θ` from
//! the boundary direction (the direction of the loop's edge at that point, which follows face
//! orientation) turning into the surface, and walks straight across triangles: at each edge
//! the next triangle is unfolded flat around the edge, so the direction keeps its angle with
//! the edge. Through an interior vertex the path continues so that the angles on its two sides
//! are equal (half the total angle around the vertex each: the *straightest* geodesic of
//! Polthier and Schmies). It stops on reaching the boundary, at an edge or at a vertex.
//!
//! The output polyline holds the start point, every edge crossing and vertex passage, and the
//! end point, all exactly on the mesh (edge points are interpolated between the edge's
//! vertices).

use super::TraceError;
use super::topology::MeshTopology;
use super::walk::{Exit, Walker, in_plane, inward_normal, straightest, vertex_fan};
use crate::io::{Origin, Polyline};
use serde::{Deserialize, Serialize};

/// Limits and tolerances of a trace.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TraceOptions {
    /// The trace fails when the curve grows longer than this multiple of the mesh's bounding
    /// box diagonal (runaway spirals, loops around a handle). Default 20.
    pub length_cap_factor: f64,
    /// The trace fails after crossing this many triangles. Default: no explicit cap beyond
    /// `max(100 000, 200 × faces)`, applied when this is `None`.
    pub max_steps: Option<usize>,
    /// A vertex whose distance to the path's line is below this fraction of the triangle's
    /// longest edge is hit: the path goes through it. Default 1e-9.
    pub vertex_snap: f64,
}

impl Default for TraceOptions {
    fn default() -> Self {
        TraceOptions {
            length_cap_factor: 20.0,
            max_steps: None,
            vertex_snap: 1e-9,
        }
    }
}

impl TraceOptions {
    /// Checks the options' domains.
    pub(crate) fn validate(&self) -> Result<(), TraceError> {
        if !(self.length_cap_factor > 0.0) || !self.length_cap_factor.is_finite() {
            return Err(TraceError::InvalidParameter {
                name: "length_cap_factor",
                value: self.length_cap_factor,
                expected: "a positive finite number",
            });
        }
        if !(self.vertex_snap >= 0.0) || !(self.vertex_snap < 0.5) {
            return Err(TraceError::InvalidParameter {
                name: "vertex_snap",
                value: self.vertex_snap,
                expected: "a fraction in [0, 0.5)",
            });
        }
        Ok(())
    }

    /// The absolute length cap on `topo`.
    pub(crate) fn length_cap(&self, topo: &MeshTopology) -> f64 {
        self.length_cap_factor * topo.bounding_diagonal()
    }

    /// The step cap on `topo`.
    pub(crate) fn step_cap(&self, topo: &MeshTopology) -> usize {
        self.max_steps
            .unwrap_or_else(|| 100_000usize.max(topo.face_count().saturating_mul(200)))
    }
}

/// How a geodesic ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeodesicEnd {
    /// It crossed this boundary edge (mesh edge index).
    BoundaryEdge(usize),
    /// It reached this boundary vertex.
    BoundaryVertex(usize),
}

/// A traced geodesic.
#[derive(Clone, Debug, PartialEq)]
pub struct GeodesicPath {
    /// The path: start, crossings, end.
    pub polyline: Polyline,
    /// Its length.
    pub length: f64,
    /// The boundary point it started from.
    pub start: super::topology::BoundaryPoint,
    /// The shooting angle.
    pub theta: f64,
    /// How it ended.
    pub end: GeodesicEnd,
    /// Number of interior vertices it passed through.
    pub vertex_passes: usize,
    /// The face of each segment (`faces[i]` holds segment `points[i]`–`points[i + 1]`).
    pub faces: Vec<usize>,
}

/// Traces the geodesic from arc-length fraction `t` of boundary loop `loop_index` at angle
/// `theta` (radians, strictly between 0 and π) from the boundary direction into the surface.
///
/// # Errors
///
/// [`TraceError::InvalidParameter`] for `theta` outside `(0, π)` or invalid options; the
/// boundary errors of [`MeshTopology::point_on_loop`]; and on the way,
/// [`TraceError::NonManifoldEdge`], [`TraceError::NonManifoldVertex`],
/// [`TraceError::DegenerateFace`], [`TraceError::LengthCap`], [`TraceError::StepCap`].
pub fn trace_geodesic(
    topo: &MeshTopology,
    loop_index: usize,
    t: f64,
    theta: f64,
    options: &TraceOptions,
) -> Result<GeodesicPath, TraceError> {
    options.validate()?;
    if !(theta > 0.0 && theta < std::f64::consts::PI) {
        return Err(TraceError::InvalidParameter {
            name: "theta",
            value: theta,
            expected: "an angle strictly between 0 and π (radians)",
        });
    }
    let start = topo.point_on_loop(loop_index, t)?;
    let face = *topo
        .edge_faces(start.edge)
        .first()
        .ok_or_else(|| TraceError::InvalidMesh("boundary edge without a face".into()))?;
    if topo.is_degenerate(face) {
        return Err(TraceError::DegenerateFace { face });
    }
    let opposite = topo
        .opposite_vertex(face, start.edge)
        .ok_or_else(|| TraceError::InvalidMesh("boundary edge not in its face".into()))?;
    let ehat = (topo.position(start.to) - topo.position(start.from)).normalized();
    let inward = inward_normal(topo, start.from, start.to, opposite);
    let dir = (ehat * theta.cos() + inward * theta.sin()).normalized();

    let cap = options.length_cap(topo);
    let mut walker = Walker::new(face, start.point, dir, start.edge, cap);
    let (end, vertex_passes) = walk_to_boundary(topo, &mut walker, options)?;
    finish(walker, start, theta, end, vertex_passes)
}

/// Walks `walker` straight across the mesh until it reaches the boundary: how it ended and
/// how many interior vertices it passed through.
pub(crate) fn walk_to_boundary(
    topo: &MeshTopology,
    walker: &mut Walker,
    options: &TraceOptions,
) -> Result<(GeodesicEnd, usize), TraceError> {
    let max_steps = options.step_cap(topo);
    let mut vertex_passes = 0;
    for _ in 0..max_steps {
        if topo.is_degenerate(walker.face) {
            return Err(TraceError::DegenerateFace { face: walker.face });
        }
        walker.dir = in_plane(topo, walker.face, walker.dir);
        match walker.exit(topo, options.vertex_snap) {
            Exit::Edge { edge, point } => {
                walker.advance(point)?;
                match topo.across(edge, walker.face)? {
                    None => return Ok((GeodesicEnd::BoundaryEdge(edge), vertex_passes)),
                    Some(next) => walker.cross(topo, edge, next),
                }
            }
            Exit::Vertex(v) => {
                walker.advance(topo.position(v))?;
                let Some(fan) = vertex_fan(topo, v, walker.face)? else {
                    return Ok((GeodesicEnd::BoundaryVertex(v), vertex_passes));
                };
                vertex_passes += 1;
                let (k, dir) = straightest(topo, v, &fan, walker.dir);
                walker.turn(v, fan.faces[k], dir);
            }
        }
    }
    Err(TraceError::StepCap { steps: max_steps })
}

/// The path the finished walk drew (an error for a path of zero length).
fn finish(
    walker: Walker,
    start: super::topology::BoundaryPoint,
    theta: f64,
    end: GeodesicEnd,
    vertex_passes: usize,
) -> Result<GeodesicPath, TraceError> {
    if walker.points.len() < 2 {
        return Err(TraceError::InvalidParameter {
            name: "theta",
            value: theta,
            expected: "an angle that enters the surface (the path has zero length)",
        });
    }
    Ok(GeodesicPath {
        polyline: Polyline {
            points: walker.points,
            closed: false,
            origin: Origin::new("<geodesic>", 0),
            label: None,
        },
        length: walker.length,
        start,
        theta,
        end,
        vertex_passes,
        faces: walker.faces,
    })
}

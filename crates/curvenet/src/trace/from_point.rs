//! A straightest geodesic from a point of the surface in a direction (what a designer draws
//! on the page: press on the surface, drag a direction): the walk of [`super::geodesic`]
//! started inside a triangle, continued until it reaches the boundary.

use super::TraceError;
use super::geodesic::{GeodesicEnd, TraceOptions, walk_to_boundary};
use super::topology::MeshTopology;
use super::walk::{Walker, in_plane};
use crate::geom::{Vec3, closest_point_on_triangle};
use crate::io::{Origin, Polyline};

/// A geodesic traced from a point of the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct PointGeodesic {
    /// The path: the point on the surface, every edge crossing and vertex passage, the end on
    /// the boundary.
    pub polyline: Polyline,
    /// Its length.
    pub length: f64,
    /// How far the given point was from the surface (it starts at the closest point).
    pub distance: f64,
    /// How it ended.
    pub end: GeodesicEnd,
}

/// Traces the straightest geodesic from the point of the mesh closest to `point`, leaving
/// along `direction` (projected onto the triangle there), until it reaches the boundary.
///
/// # Errors
///
/// [`TraceError::InvalidParameter`] for a non-finite point, a direction that is zero, not
/// finite or normal to the surface there, or one that leaves the surface at once (the path
/// has zero length); [`TraceError::InvalidMesh`] for a mesh without a usable triangle; the
/// walk's errors of [`super::trace_geodesic`].
pub fn trace_geodesic_from(
    topo: &MeshTopology,
    point: Vec3,
    direction: Vec3,
    options: &TraceOptions,
) -> Result<PointGeodesic, TraceError> {
    options.validate()?;
    if !point.is_finite() {
        return Err(TraceError::InvalidParameter {
            name: "point",
            value: f64::NAN,
            expected: "a point with finite coordinates",
        });
    }
    let bad_direction = || TraceError::InvalidParameter {
        name: "direction",
        value: direction.norm(),
        expected: "a direction along the surface (not zero, not normal to it)",
    };
    if !(direction.is_finite() && direction.norm() > 0.0) {
        return Err(bad_direction());
    }
    let (face, start, distance) = start_face(topo, point, direction)
        .ok_or_else(|| TraceError::InvalidMesh("no usable triangle".into()))?;
    let dir = in_plane(topo, face, direction);
    if !(dir.is_finite() && dir.norm() > 0.5) {
        return Err(bad_direction());
    }
    let cap = options.length_cap(topo);
    let mut walker = Walker::inside(face, start, dir, cap);
    let (end, _) = walk_to_boundary(topo, &mut walker, options)?;
    if walker.points.len() < 2 || !(walker.length > 0.0) {
        return Err(TraceError::InvalidParameter {
            name: "direction",
            value: direction.norm(),
            expected: "a direction into the surface: from this point it leaves the surface at once",
        });
    }
    Ok(PointGeodesic {
        polyline: Polyline {
            points: walker.points,
            closed: false,
            origin: Origin::new("<geodesic>", 0),
            label: None,
        },
        length: walker.length,
        distance,
        end,
    })
}

/// The triangle the walk starts in, the start point on it and the point's distance to the
/// mesh: the closest triangle, and among triangles as close (the point on an edge or a
/// vertex), the one `direction` heads into.
fn start_face(topo: &MeshTopology, point: Vec3, direction: Vec3) -> Option<(usize, Vec3, f64)> {
    let mut found: Vec<(f64, usize, Vec3)> = Vec::new();
    for f in 0..topo.face_count() {
        if topo.is_degenerate(f) {
            continue;
        }
        let [a, b, c] = topo.face_points(f);
        let q = closest_point_on_triangle(point, a, b, c);
        found.push((q.dist(point), f, q));
    }
    let best = found.iter().map(|x| x.0).fold(f64::INFINITY, f64::min);
    if !best.is_finite() {
        return None;
    }
    let tie = best + 1e-9 * topo.bounding_diagonal();
    let near: Vec<&(f64, usize, Vec3)> = found.iter().filter(|x| x.0 <= tie).collect();
    // A step along the direction (in each candidate's plane) stays closest to the triangle
    // it heads into.
    let off = |&&(_, f, q): &&(f64, usize, Vec3)| {
        let [a, b, c] = topo.face_points(f);
        let longest = a.dist(b).max(b.dist(c)).max(c.dist(a));
        let step = q + in_plane(topo, f, direction) * (1e-6 * longest);
        step.dist(closest_point_on_triangle(step, a, b, c)) / longest.max(f64::MIN_POSITIVE)
    };
    let pick = near
        .iter()
        .min_by(|x, y| off(x).total_cmp(&off(y)).then(x.1.cmp(&y.1)))?;
    Some((pick.1, pick.2, pick.0))
}

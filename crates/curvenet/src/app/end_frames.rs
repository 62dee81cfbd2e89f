//! The surface's directions at curve ends whose supports fix a translation along them
//! (`"fixed": ["boundary-normal", "surface-normal"]`): along the surface's boundary (its
//! tangent at the boundary point nearest the end), across it (in the surface's tangent plane,
//! normal to the boundary) and normal to the surface.
//!
//! The boundary is the mesh's edges that belong to one triangle. An end that uses a boundary
//! direction must lie within [`SURFACE_TOLERANCE`] of the mesh's size from the boundary; one
//! that fixes the surface's normal only, within it from the surface. At a corner of the
//! boundary (two boundary edges meeting at the nearest point) the first edge found gives the
//! tangent. The normal is that of the triangle the nearest boundary edge (or the nearest
//! point of the surface) belongs to.

use crate::geom::{Aabb, Vec3, closest};
use crate::io::TriMesh;
use crate::material::{EndFrame, EndSupport};
use std::collections::HashMap;

/// How close (relative to the mesh's bounding-box diagonal) a curve end must lie to the
/// surface's boundary (or to the surface, for its normal alone) to take its directions: a
/// curve drawn on the smooth surface ends on the smooth boundary, which the mesh's edges cut
/// as chords.
pub const SURFACE_TOLERANCE: f64 = 1e-2;

/// Why an end's surface directions could not be found (the message for its file and line).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameError(pub String);

/// The frame at `at`, an end held by `support` (which uses a surface direction), on `mesh`;
/// `which` names the end in a message (`curve 3's start`).
pub fn end_frame(
    mesh: Option<&TriMesh>,
    at: Vec3,
    support: &EndSupport,
    which: &str,
) -> Result<EndFrame, FrameError> {
    let Some(mesh) = mesh else {
        return Err(FrameError(format!(
            "{which}'s support fixes a direction of the surface ({}), but there is no surface: \
             give a mesh",
            support.name()
        )));
    };
    let triangles = mesh.finite_triangles();
    let size = Aabb::of_points(mesh.vertices.iter()).extent().norm();
    let tol = SURFACE_TOLERANCE * size;
    let boundary = support.surface_directions().any(|d| d.needs_boundary());
    let (face, tangent) = if boundary {
        let Some((d, face, a, b)) = nearest_boundary_edge(mesh, at) else {
            return Err(FrameError(format!(
                "{which}'s support ({}) is along the surface's boundary, but the surface has \
                 no boundary (every edge is shared by two triangles)",
                support.name()
            )));
        };
        if d > tol {
            return Err(FrameError(format!(
                "{which} is not on the surface's boundary: the nearest boundary point is {} \
                 away (it must lie within {}) for its support ({})",
                crate::fmt::significant(d, 4),
                crate::fmt::significant(tol, 4),
                support.name()
            )));
        }
        (face, (b - a).normalized())
    } else {
        let nearest = triangles
            .iter()
            .enumerate()
            .map(|(f, t)| {
                (
                    closest::closest_point_on_triangle(at, t[0], t[1], t[2]).dist(at),
                    f,
                )
            })
            .min_by(|x, y| x.0.total_cmp(&y.0));
        let Some((d, f)) = nearest else {
            return Err(FrameError(format!(
                "{which}'s support ({}) needs the surface, which has no triangles",
                support.name()
            )));
        };
        if d > tol {
            return Err(FrameError(format!(
                "{which} is not on the surface: the nearest point of the surface is {} away \
                 (it must lie within {}) for its support ({})",
                crate::fmt::significant(d, 4),
                crate::fmt::significant(tol, 4),
                support.name()
            )));
        }
        (face_of_finite(mesh, f), Vec3::ZERO)
    };
    let [a, b, c] = mesh.faces[face].map(|i| mesh.vertices[i as usize]);
    let n = (b - a).cross(c - a);
    if !(n.norm() > 0.0) {
        return Err(FrameError(format!(
            "{which}'s nearest triangle of the surface has no area: its normal is undefined"
        )));
    }
    let normal = n.normalized();
    let across = if boundary {
        normal.cross(tangent).normalized()
    } else {
        Vec3::ZERO
    };
    Ok(EndFrame([
        tangent.to_array(),
        across.to_array(),
        normal.to_array(),
    ]))
}

/// The index in `mesh.faces` of the `f`-th finite triangle (`TriMesh::finite_triangles`).
fn face_of_finite(mesh: &TriMesh, f: usize) -> usize {
    let n = mesh.vertices.len();
    mesh.faces
        .iter()
        .enumerate()
        .filter(|(_, t)| {
            t.iter()
                .all(|&i| (i as usize) < n && mesh.vertices[i as usize].is_finite())
        })
        .nth(f)
        .map_or(0, |(i, _)| i)
}

/// The boundary edge (one triangle's only) nearest `p`: its distance, its triangle and its
/// end points.
fn nearest_boundary_edge(mesh: &TriMesh, p: Vec3) -> Option<(f64, usize, Vec3, Vec3)> {
    let n = mesh.vertices.len();
    let mut count: HashMap<(u32, u32), (usize, usize, u32, u32)> = HashMap::new();
    for (f, t) in mesh.faces.iter().enumerate() {
        if t.iter().any(|&i| i as usize >= n) {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            count.entry(key).or_insert((0, f, a, b)).0 += 1;
        }
    }
    let mut edges: Vec<_> = count.into_values().filter(|e| e.0 == 1).collect();
    edges.sort_unstable_by_key(|e| (e.1, e.2, e.3));
    edges
        .into_iter()
        .map(|(_, f, a, b)| {
            let (x, y) = (mesh.vertices[a as usize], mesh.vertices[b as usize]);
            (closest::point_segment_distance(p, x, y), f, x, y)
        })
        .filter(|e| e.0.is_finite() && e.2 != e.3)
        .min_by(|x, y| x.0.total_cmp(&y.0))
}

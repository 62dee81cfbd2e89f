//! The surface curves slide on: closest points on a triangle mesh (through the crate's one
//! [`Bvh`]) with the normal of the triangle found, and closest points on the mesh's boundary
//! (the edges one triangle uses), where a curve end that lies on the boundary stays.

use crate::geom::{Aabb, Bvh, Vec3, closest_point_on_triangle};
use crate::io::TriMesh;
use std::collections::HashMap;

/// A triangle mesh indexed for closest-point queries on it and on its boundary.
#[derive(Clone, Debug)]
pub struct Surface {
    triangles: Vec<[Vec3; 3]>,
    normals: Vec<Vec3>,
    tree: Bvh,
    boundary: Vec<[Vec3; 2]>,
    boundary_tree: Bvh,
    diagonal: f64,
}

/// A point of the surface found for a query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The closest point.
    pub point: Vec3,
    /// The unit normal of the triangle it lies on (oriented as the triangle).
    pub normal: Vec3,
    /// The distance from the query to it.
    pub distance: f64,
}

impl Surface {
    /// Indexes `mesh` (faces with an index out of range or a non-finite corner are skipped,
    /// as every geometric query of the crate skips them). `None` for a mesh without usable
    /// triangles.
    pub fn new(mesh: &TriMesh) -> Option<Surface> {
        let n = mesh.vertices.len();
        let usable: Vec<[u32; 3]> = mesh
            .faces
            .iter()
            .copied()
            .filter(|f| {
                f.iter()
                    .all(|&i| (i as usize) < n && mesh.vertices[i as usize].is_finite())
            })
            .collect();
        if usable.is_empty() {
            return None;
        }
        let triangles: Vec<[Vec3; 3]> = usable
            .iter()
            .map(|f| f.map(|i| mesh.vertices[i as usize]))
            .collect();
        let normals = triangles
            .iter()
            .map(|[a, b, c]| (*b - *a).cross(*c - *a).normalized())
            .collect();
        // Boundary edges: used by exactly one triangle (orientation ignored).
        let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
        for f in &usable {
            for k in 0..3 {
                let (a, b) = (f[k], f[(k + 1) % 3]);
                *uses.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let mut edges: Vec<(u32, u32)> = uses
            .into_iter()
            .filter(|&(_, count)| count == 1)
            .map(|(e, _)| e)
            .collect();
        edges.sort_unstable();
        let boundary: Vec<[Vec3; 2]> = edges
            .iter()
            .map(|&(a, b)| [mesh.vertices[a as usize], mesh.vertices[b as usize]])
            .collect();
        let bounds = Aabb::of_points(triangles.iter().flatten());
        Some(Surface {
            tree: Bvh::new(triangles.iter().map(Aabb::of_points).collect()),
            boundary_tree: Bvh::new(boundary.iter().map(Aabb::of_points).collect()),
            normals,
            triangles,
            boundary,
            diagonal: bounds.extent().norm(),
        })
    }

    /// The length of the surface's bounding-box diagonal.
    pub fn diagonal(&self) -> f64 {
        self.diagonal
    }

    /// Whether the surface has a boundary.
    pub fn has_boundary(&self) -> bool {
        !self.boundary.is_empty()
    }

    /// The point of the surface closest to `p`.
    pub fn closest(&self, p: Vec3) -> Option<SurfacePoint> {
        if !p.is_finite() {
            return None;
        }
        let closest = |i: u32| {
            let [a, b, c] = self.triangles[i as usize];
            closest_point_on_triangle(p, a, b, c)
        };
        let (distance, i) = self
            .tree
            .nearest(p, f64::INFINITY, -1.0, |i| p.dist(closest(i)))?;
        Some(SurfacePoint {
            point: closest(i),
            normal: self.normals[i as usize],
            distance,
        })
    }

    /// The point of the surface's boundary closest to `p` and its distance (`None` for a
    /// closed surface).
    pub fn closest_on_boundary(&self, p: Vec3) -> Option<(Vec3, f64)> {
        if !p.is_finite() {
            return None;
        }
        let closest = |i: u32| {
            let [a, b] = self.boundary[i as usize];
            let ab = b - a;
            let t = ((p - a).dot(ab) / ab.norm2().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            a.lerp(b, t)
        };
        let (d, i) = self
            .boundary_tree
            .nearest(p, f64::INFINITY, -1.0, |i| p.dist(closest(i)))?;
        Some((closest(i), d))
    }
}

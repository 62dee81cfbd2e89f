//! How far curves lie from their surface: the distance from a point to a triangle mesh
//! ([`MeshDistance`], through the shared [`Bvh`] over the triangles, `O(log n)` per query on
//! ordinary meshes) and the curves that stray from it ([`curves_far_from_mesh`]: a wrong scale
//! or units, the mesh of another scene).

use super::{LIST_LIMIT, and_more};
use crate::geom::{Aabb, Bvh, Vec3, closest_point_on_triangle};
use crate::io::{Origin, Polyline, TriMesh};

/// Default relative distance (times the mesh's bounding-box diagonal) beyond which a curve point
/// counts as far from the mesh.
pub const FAR_FROM_MESH: f64 = 0.03;

/// Point-to-surface distance for one triangle mesh.
///
/// Faces that point to a missing vertex or hold a non-finite coordinate are skipped.
#[derive(Clone, Debug)]
pub struct MeshDistance {
    triangles: Vec<[Vec3; 3]>,
    tree: Bvh,
    bounds: Aabb,
}

impl MeshDistance {
    /// Indexes the triangles of `mesh`.
    pub fn new(mesh: &TriMesh) -> Self {
        let triangles = mesh.finite_triangles();
        let boxes: Vec<Aabb> = triangles.iter().map(Aabb::of_points).collect();
        MeshDistance {
            tree: Bvh::new(boxes),
            bounds: Aabb::of_points(triangles.iter().flatten()),
            triangles,
        }
    }

    /// Number of usable triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The distance from `p` to the surface and the nearest triangle (an index among the usable
    /// ones); `None` for a mesh without usable triangles or a non-finite `p`.
    pub fn distance(&self, p: Vec3) -> Option<(f64, usize)> {
        if !p.is_finite() {
            return None;
        }
        self.tree
            .nearest(p, f64::INFINITY, -1.0, |i| self.triangle_distance(p, i))
            .map(|(d, i)| (d, i as usize))
    }

    /// True when the surface comes within `radius` of `p` (cheaper than [`Self::distance`]: the
    /// search stops at the first triangle close enough).
    pub fn is_within(&self, p: Vec3, radius: f64) -> bool {
        p.is_finite()
            && self
                .tree
                .nearest(p, f64::INFINITY, radius, |i| self.triangle_distance(p, i))
                .is_some_and(|(d, _)| d <= radius)
    }

    fn triangle_distance(&self, p: Vec3, i: u32) -> f64 {
        let [a, b, c] = self.triangles[i as usize];
        p.dist(closest_point_on_triangle(p, a, b, c))
    }
}

/// A curve whose points stray from the mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct FarCurve {
    /// Curve id.
    pub curve: usize,
    /// Where the curve was defined.
    pub origin: Origin,
    /// Points farther than the threshold.
    pub far_points: usize,
    /// All points of the curve.
    pub points: usize,
    /// The largest distance of a point to the surface.
    pub max_distance: f64,
    /// The point (index along the curve) at that distance.
    pub worst_point: usize,
}

/// What [`curves_far_from_mesh`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct FarFromMesh {
    /// The mesh's bounding-box diagonal.
    pub diagonal: f64,
    /// The distance beyond which a point is far.
    pub threshold: f64,
    /// Curves with at least one far point, by id.
    pub curves: Vec<FarCurve>,
    /// Number of curves checked.
    pub checked: usize,
}

/// The curves with points farther from the surface of `mesh` than `relative ×` its bounding-box
/// diagonal. Nothing is reported when the mesh has no usable triangle or its diagonal is not a
/// positive finite number.
pub fn curves_far_from_mesh(curves: &[Polyline], mesh: &TriMesh, relative: f64) -> FarFromMesh {
    let index = MeshDistance::new(mesh);
    let diagonal = index.bounds.extent().norm();
    let threshold = relative * diagonal;
    let mut out = FarFromMesh {
        diagonal,
        threshold,
        curves: Vec::new(),
        checked: curves.len(),
    };
    if index.triangle_count() == 0 || !(threshold.is_finite() && threshold > 0.0) {
        return out;
    }
    for (c, curve) in curves.iter().enumerate() {
        let mut far = FarCurve {
            curve: c,
            origin: curve.origin.clone(),
            far_points: 0,
            points: curve.points.len(),
            max_distance: 0.0,
            worst_point: 0,
        };
        for (k, &p) in curve.points.iter().enumerate() {
            if index.is_within(p, threshold) {
                continue;
            }
            let d = index.distance(p).map_or(f64::INFINITY, |(d, _)| d);
            far.far_points += 1;
            if !(d <= far.max_distance) {
                far.max_distance = d;
                far.worst_point = k;
            }
        }
        if far.far_points > 0 {
            out.curves.push(far);
        }
    }
    out
}

/// The warning for the curves of [`curves_far_from_mesh`] (none when no curve is far).
/// `mesh_name` names the mesh in the message.
pub fn far_from_mesh_warning(found: &FarFromMesh, mesh_name: &str) -> Option<String> {
    if found.curves.is_empty() {
        return None;
    }
    let listed: Vec<String> = found
        .curves
        .iter()
        .take(LIST_LIMIT)
        .map(|f| {
            format!(
                "curve {} ({}: {} of {} points, up to {:.4e} away)",
                f.curve, f.origin, f.far_points, f.points, f.max_distance
            )
        })
        .collect();
    let hint = if found.curves.len() == found.checked {
        "; no curve lies on the surface: are the mesh and the curves in the same units and \
         position?"
    } else {
        ""
    };
    Some(format!(
        "{} curve(s) far from the mesh {mesh_name} (points more than {:.4e}, {}% of its \
         bounding-box diagonal {:.4e}, from the surface): {}{}{hint}",
        found.curves.len(),
        found.threshold,
        crate::fmt::percent(100.0 * found.threshold / found.diagonal),
        found.diagonal,
        listed.join(", "),
        and_more(found.curves.len()),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::checks::tests::{polyline, square_mesh};

    #[test]
    fn mesh_distance_matches_brute_force() {
        // A bumpy grid of 2·20·20 triangles.
        let n = 20;
        let mut mesh = TriMesh::default();
        for i in 0..=n {
            for j in 0..=n {
                let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
                mesh.vertices
                    .push(Vec3::new(x, y, 0.1 * (7.0 * x).sin() * (5.0 * y).cos()));
            }
        }
        let id = |i: usize, j: usize| (i * (n + 1) + j) as u32;
        for i in 0..n {
            for j in 0..n {
                mesh.faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                mesh.faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let index = MeshDistance::new(&mesh);
        let mut rng = crate::rng::SplitMix64::new(7);
        for _ in 0..200 {
            let p = Vec3::new(
                2.0 * rng.next_f64() - 0.5,
                2.0 * rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
            );
            let brute = mesh
                .faces
                .iter()
                .map(|f| {
                    let [a, b, c] = f.map(|i| mesh.vertices[i as usize]);
                    p.dist(closest_point_on_triangle(p, a, b, c))
                })
                .fold(f64::INFINITY, f64::min);
            let (d, _) = index.distance(p).unwrap();
            assert!((d - brute).abs() < 1e-12, "{d} vs {brute}");
            assert!(index.is_within(p, brute * 1.001 + 1e-12));
            assert!(brute < 1e-9 || !index.is_within(p, brute * 0.999));
        }
    }

    #[test]
    fn far_curves_are_found_and_near_ones_are_not() {
        let mesh = square_mesh();
        let curves = vec![
            polyline(&[[0.1, 0.1, 0.0], [0.9, 0.9, 0.001]]),
            polyline(&[[0.1, 0.9, 0.0], [0.5, 0.5, 0.5], [0.9, 0.1, 0.0]]),
        ];
        let found = curves_far_from_mesh(&curves, &mesh, FAR_FROM_MESH);
        assert_eq!(found.curves.len(), 1);
        let f = &found.curves[0];
        assert_eq!(
            (f.curve, f.far_points, f.points, f.worst_point),
            (1, 1, 3, 1)
        );
        assert!((f.max_distance - 0.5).abs() < 1e-12);
        let w = far_from_mesh_warning(&found, "m.obj").unwrap();
        assert!(w.contains("curve 1 (c.txt:3: 1 of 3 points"), "{w}");
        // The share of the diagonal as a person writes it, not `2.9999999999999996%`.
        assert!(w.contains(", 3.00% of its bounding-box diagonal"), "{w}");
        assert!(!w.contains("same units"), "{w}");
        // Every curve far: the hint about units.
        let far = vec![polyline(&[[10.0, 0.0, 0.0], [11.0, 0.0, 0.0]])];
        let w = far_from_mesh_warning(&curves_far_from_mesh(&far, &mesh, 0.03), "m.obj").unwrap();
        assert!(w.contains("same units"), "{w}");
        // Nothing usable: nothing reported, no panic.
        let empty = TriMesh::default();
        assert!(curves_far_from_mesh(&far, &empty, 0.03).curves.is_empty());
    }
}

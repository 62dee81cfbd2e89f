//! Connectivity and shape problems of a triangle mesh.

use super::{LIST_LIMIT, listed};
use crate::geom::Vec3;
use crate::io::TriMesh;
use std::collections::HashMap;

/// What one pass over a mesh's faces found.
#[derive(Debug, Default)]
struct FaceScan {
    /// Faces that point to a missing vertex.
    missing: Vec<usize>,
    /// Faces of zero area or with a repeated vertex.
    degenerate: Vec<usize>,
    /// Faces with the same three vertices as an earlier face: (face, earlier face).
    duplicates: Vec<(usize, usize)>,
    /// Undirected edge of the usable faces → (faces using it, faces running it from its lower
    /// to its higher vertex).
    edges: HashMap<(u32, u32), (usize, usize)>,
}

fn scan_faces(mesh: &TriMesh) -> FaceScan {
    let n = mesh.vertices.len();
    let mut scan = FaceScan::default();
    let mut seen_faces: HashMap<[u32; 3], usize> = HashMap::new();
    for (k, f) in mesh.faces.iter().enumerate() {
        if f.iter().any(|&i| i as usize >= n) {
            scan.missing.push(k);
            continue;
        }
        let [a, b, c] = f.map(|i| mesh.vertices[i as usize]);
        let repeated = f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
        if repeated || zero_area(a, b, c) {
            scan.degenerate.push(k);
            continue;
        }
        let mut key = *f;
        key.sort_unstable();
        if let Some(&first) = seen_faces.get(&key) {
            scan.duplicates.push((k, first));
            continue;
        }
        seen_faces.insert(key, k);
        for (u, v) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
            let e = scan.edges.entry((u.min(v), u.max(v))).or_insert((0, 0));
            e.0 += 1;
            if u < v {
                e.1 += 1;
            }
        }
    }
    scan
}

/// Problems of a triangle mesh's connectivity and shape, one warning per kind, each naming
/// `mesh_name` and the first offending faces (1-based, as in an OBJ file). A mesh read by
/// [`crate::io::read_mesh`] has already lost its degenerate faces (with warnings of their own).
pub fn mesh_warnings(mesh: &TriMesh, mesh_name: &str) -> Vec<String> {
    let scan = scan_faces(mesh);
    let mut warnings = Vec::new();
    let faces = |list: &[usize]| {
        let mut s: Vec<String> = list
            .iter()
            .take(LIST_LIMIT)
            .map(|k| (k + 1).to_string())
            .collect();
        if list.len() > LIST_LIMIT {
            s.push(format!("… ({} in all)", list.len()));
        }
        s.join(", ")
    };
    if !scan.missing.is_empty() {
        warnings.push(format!(
            "mesh {mesh_name}: {} face(s) point to a missing vertex and are ignored: faces {}",
            scan.missing.len(),
            faces(&scan.missing)
        ));
    }
    if !scan.degenerate.is_empty() {
        warnings.push(format!(
            "mesh {mesh_name}: {} degenerate face(s) (zero area or a repeated vertex): faces {}",
            scan.degenerate.len(),
            faces(&scan.degenerate)
        ));
    }
    let d = &scan.duplicates;
    if !d.is_empty() {
        warnings.push(format!(
            "mesh {mesh_name}: {} duplicate face(s) (the same three vertices as an earlier face): \
             faces {}",
            d.len(),
            listed(d, ", ", |(k, first)| format!("{} = {}", k + 1, first + 1))
        ));
    }
    warnings.extend(edge_warnings(&scan.edges, mesh_name));
    warnings
}

/// Edges shared by more than two faces, and edges two faces run the same way.
fn edge_warnings(edges: &HashMap<(u32, u32), (usize, usize)>, mesh_name: &str) -> Vec<String> {
    let mut non_manifold: Vec<(u32, u32, usize)> = Vec::new();
    let mut flipped: Vec<(u32, u32)> = Vec::new();
    for (&(u, v), &(count, forward)) in edges {
        if count > 2 {
            non_manifold.push((u, v, count));
        } else if count == 2 && forward != 1 {
            flipped.push((u, v));
        }
    }
    non_manifold.sort_unstable();
    flipped.sort_unstable();
    let mut warnings = Vec::new();
    if !non_manifold.is_empty() {
        warnings.push(format!(
            "mesh {mesh_name}: {} non-manifold edge(s) shared by more than two faces: vertices {}",
            non_manifold.len(),
            listed(&non_manifold, ", ", |(u, v, c)| format!(
                "{}–{} ({c} faces)",
                u + 1,
                v + 1
            ))
        ));
    }
    if !flipped.is_empty() {
        warnings.push(format!(
            "mesh {mesh_name}: {} edge(s) where two faces disagree on orientation (the faces \
             run the edge the same way): vertices {}",
            flipped.len(),
            listed(&flipped, ", ", |(u, v)| format!("{}–{}", u + 1, v + 1))
        ));
    }
    warnings
}

/// True when the triangle has (numerically) zero area against its longest edge, or a
/// non-finite vertex. Coordinates are first scaled by a power of two so that nothing overflows.
fn zero_area(a: Vec3, b: Vec3, c: Vec3) -> bool {
    let largest = [a, b, c]
        .iter()
        .flat_map(|p| p.to_array())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    if !largest.is_finite() || largest == 0.0 {
        return true;
    }
    let exponent = largest.log2().ceil().clamp(-1000.0, 1000.0) as i32;
    let s = 2f64.powi(-exponent);
    let (a, b, c) = (a * s, b * s, c * s);
    let (e1, e2, e3) = (b - a, c - a, c - b);
    let longest2 = e1.norm2().max(e2.norm2()).max(e3.norm2());
    !(e1.cross(e2).norm() > 1e-12 * longest2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::checks::tests::square_mesh;

    #[test]
    fn mesh_problems_are_named() {
        let mut mesh = square_mesh();
        mesh.vertices.push(Vec3::new(0.5, 0.5, 1.0));
        mesh.vertices.push(Vec3::new(2.0, 0.0, 0.0));
        mesh.faces.push([0, 2, 4]); // third face on edge 0–2: non-manifold
        mesh.faces.push([2, 0, 1]); // duplicate of face 1
        mesh.faces.push([0, 1, 5]); // collinear: degenerate
        mesh.faces.push([0, 1, 9]); // missing vertex
        let w = mesh_warnings(&mesh, "m.obj");
        let all = w.join("\n");
        assert!(all.contains("1 face(s) point to a missing vertex"), "{all}");
        assert!(all.contains("1 degenerate face(s)"), "{all}");
        assert!(
            all.contains("duplicate face(s)") && all.contains("4 = 1"),
            "{all}"
        );
        assert!(
            all.contains("non-manifold edge(s)") && all.contains("1–3 (3 faces)"),
            "{all}"
        );
        assert!(mesh_warnings(&square_mesh(), "m.obj").is_empty());
        let mut flipped = square_mesh();
        flipped.faces[1] = [0, 3, 2];
        let w = mesh_warnings(&flipped, "m.obj");
        assert!(
            w.len() == 1 && w[0].contains("disagree on orientation"),
            "{w:?}"
        );
    }
}

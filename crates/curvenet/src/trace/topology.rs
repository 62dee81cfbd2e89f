//! Mesh connectivity for tracing: edges and their faces, boundary loops in the reference's
//! order, vertex fans, face normals.
//!
//! [`MeshTopology::new`] accepts any triangle soup whose indices are valid: non-manifold edges
//! (three or more faces), non-manifold vertices, inconsistent orientation and degenerate faces
//! are recorded, not rejected. Tracing fails with a clear [`TraceError`] only when a curve
//! actually reaches such a place.
//!
//! # Boundary loops (the reference's convention)
//!
//! A boundary edge is an edge with exactly one face. Loops are listed in increasing order of
//! their smallest vertex index; each starts at that vertex and follows the boundary edges in
//! face orientation (the direction in which a boundary edge appears in its face). At a vertex
//! where two loops touch (two outgoing boundary edges), the unused edge with the smallest edge
//! number is taken. If the orientation is inconsistent the walk takes any unused boundary edge
//! at the current vertex, and a chain that cannot be closed is kept as an open loop
//! ([`BoundaryLoop::closed`] is false).

use super::TraceError;
use crate::geom::{Aabb, Vec3};
use crate::io::TriMesh;
use std::collections::HashMap;

/// A triangle whose doubled area is at most this fraction of its longest edge squared is
/// degenerate (the same rule as the OBJ reader).
const DEGENERATE_AREA: f64 = 1e-12;

/// One boundary loop: its vertices in order and their arc lengths.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryLoop {
    /// Vertex indices in loop order, starting at the loop's smallest vertex index. The closing
    /// edge (last vertex back to the first) is implicit.
    pub vertices: Vec<usize>,
    /// Cumulative arc length at each vertex (`arc[0] = 0`), without the closing edge.
    pub arc: Vec<f64>,
    /// Length without the closing edge: the length the parameter `t` refers to.
    pub open_length: f64,
    /// Full length, closing edge included (equal to `open_length` for an open chain).
    pub length: f64,
    /// True when the last vertex connects back to the first through a boundary edge.
    pub closed: bool,
}

impl BoundaryLoop {
    /// Number of boundary edges of the loop (the closing edge included when closed).
    pub fn edge_count(&self) -> usize {
        let n = self.vertices.len();
        if self.closed { n } else { n.saturating_sub(1) }
    }
}

/// A point on a boundary edge, found from a loop and an arc-length parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryPoint {
    /// The loop.
    pub loop_index: usize,
    /// Index in the loop of the edge's first vertex (the edge runs to the next loop vertex).
    pub loop_edge: usize,
    /// The mesh edge.
    pub edge: usize,
    /// The edge's first vertex, in loop order.
    pub from: usize,
    /// The edge's second vertex, in loop order.
    pub to: usize,
    /// The point.
    pub point: Vec3,
    /// The parameter actually used (after the reference's nudges).
    pub t: f64,
}

/// Edge–face adjacency and boundary loops of a triangle mesh.
///
/// Accessors taking a vertex, edge or face index panic when the index is out of range, like
/// slice indexing; indices read from this type (faces, edges, loops) are always valid.
#[derive(Clone, Debug)]
pub struct MeshTopology {
    vertices: Vec<Vec3>,
    faces: Vec<[usize; 3]>,
    /// Edge vertices, sorted.
    edges: Vec<[usize; 2]>,
    /// Start of each edge's faces in `edge_face_list` (CSR, `edges.len() + 1` entries).
    edge_face_start: Vec<usize>,
    edge_face_list: Vec<usize>,
    /// `face_edges[f][k]` joins local vertices `k` and `k + 1 (mod 3)`.
    face_edges: Vec<[usize; 3]>,
    /// Faces around each vertex (CSR).
    vertex_face_start: Vec<usize>,
    vertex_face_list: Vec<usize>,
    edge_index: HashMap<(usize, usize), usize>,
    normals: Vec<Vec3>,
    areas: Vec<f64>,
    degenerate: Vec<bool>,
    boundary_vertex: Vec<bool>,
    loops: Vec<BoundaryLoop>,
    /// Length of the vertices' bounding-box diagonal.
    diagonal: f64,
}

impl MeshTopology {
    /// Builds the connectivity of `mesh`.
    ///
    /// # Errors
    ///
    /// [`TraceError::InvalidMesh`] when the mesh has no faces, a face index is out of range, a
    /// face repeats a vertex or a vertex coordinate is not finite.
    pub fn new(mesh: &TriMesh) -> Result<Self, TraceError> {
        let nv = mesh.vertices.len();
        if mesh.faces.is_empty() {
            return Err(TraceError::InvalidMesh("the mesh has no faces".into()));
        }
        if let Some(i) = mesh.vertices.iter().position(|v| !v.is_finite()) {
            return Err(TraceError::InvalidMesh(format!(
                "vertex {i} has a non-finite coordinate"
            )));
        }
        let mut faces = Vec::with_capacity(mesh.faces.len());
        for (f, tri) in mesh.faces.iter().enumerate() {
            let t = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
            if let Some(&bad) = t.iter().find(|&&v| v >= nv) {
                return Err(TraceError::InvalidMesh(format!(
                    "face {f} uses vertex {bad}, but the mesh has {nv} vertices"
                )));
            }
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(TraceError::InvalidMesh(format!(
                    "face {f} repeats a vertex ({} {} {})",
                    t[0], t[1], t[2]
                )));
            }
            faces.push(t);
        }
        let vertices = mesh.vertices.clone();

        // Edges, numbered in order of first appearance (faces in order, local edges 0..3).
        let mut edge_index: HashMap<(usize, usize), usize> = HashMap::new();
        let mut edges: Vec<[usize; 2]> = Vec::new();
        let mut face_edges = Vec::with_capacity(faces.len());
        let mut edge_face_pairs: Vec<(usize, usize)> = Vec::with_capacity(3 * faces.len());
        for (f, t) in faces.iter().enumerate() {
            let mut fe = [0usize; 3];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let key = (a.min(b), a.max(b));
                let e = *edge_index.entry(key).or_insert_with(|| {
                    edges.push([key.0, key.1]);
                    edges.len() - 1
                });
                fe[k] = e;
                edge_face_pairs.push((e, f));
            }
            face_edges.push(fe);
        }
        let (edge_face_start, edge_face_list) = csr(edges.len(), &edge_face_pairs);
        let vf_pairs: Vec<(usize, usize)> = faces
            .iter()
            .enumerate()
            .flat_map(|(f, t)| t.iter().map(move |&v| (v, f)))
            .collect();
        let (vertex_face_start, vertex_face_list) = csr(nv, &vf_pairs);

        let mut normals = Vec::with_capacity(faces.len());
        let mut areas = Vec::with_capacity(faces.len());
        let mut degenerate = Vec::with_capacity(faces.len());
        for t in &faces {
            let (a, b, c) = (vertices[t[0]], vertices[t[1]], vertices[t[2]]);
            let n = (b - a).cross(c - a);
            let longest = (b - a).norm2().max((c - b).norm2()).max((a - c).norm2());
            let deg = !(n.norm() > DEGENERATE_AREA * longest) || !n.is_finite();
            degenerate.push(deg);
            areas.push(0.5 * n.norm());
            normals.push(if deg { Vec3::ZERO } else { n.normalized() });
        }

        let mut topo = MeshTopology {
            diagonal: Aabb::of_points(&vertices).extent().norm(),
            vertices,
            faces,
            edges,
            edge_face_start,
            edge_face_list,
            face_edges,
            vertex_face_start,
            vertex_face_list,
            edge_index,
            normals,
            areas,
            degenerate,
            boundary_vertex: vec![false; nv],
            loops: Vec::new(),
        };
        for e in 0..topo.edges.len() {
            if topo.is_boundary_edge(e) {
                let [a, b] = topo.edges[e];
                topo.boundary_vertex[a] = true;
                topo.boundary_vertex[b] = true;
            }
        }
        topo.loops = topo.find_loops();
        Ok(topo)
    }

    /// Walks the boundary edges into loops (see the module documentation for the order).
    fn find_loops(&self) -> Vec<BoundaryLoop> {
        let nv = self.vertices.len();
        // Boundary edges with their direction in their face.
        let mut incident: Vec<Vec<(usize, usize, bool)>> = vec![Vec::new(); nv];
        for (f, t) in self.faces.iter().enumerate() {
            for k in 0..3 {
                let e = self.face_edges[f][k];
                if self.is_boundary_edge(e) {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    // (edge, other end, oriented away from this vertex)
                    incident[a].push((e, b, true));
                    incident[b].push((e, a, false));
                }
            }
        }
        for list in &mut incident {
            list.sort_unstable();
        }
        let mut used = vec![false; self.edges.len()];
        let next_edge = |v: usize, used: &[bool]| -> Option<(usize, usize)> {
            let unused = || incident[v].iter().filter(|x| !used[x.0]);
            unused()
                .find(|x| x.2)
                .or_else(|| unused().next())
                .map(|&(e, w, _)| (e, w))
        };
        let mut loops = Vec::new();
        for start in 0..nv {
            while let Some((e0, w0)) = next_edge(start, &used) {
                used[e0] = true;
                let mut verts = vec![start];
                let mut cur = w0;
                let mut closed = false;
                loop {
                    if cur == start {
                        closed = true;
                        break;
                    }
                    verts.push(cur);
                    match next_edge(cur, &used) {
                        Some((e, w)) => {
                            used[e] = true;
                            cur = w;
                        }
                        None => break,
                    }
                }
                let mut arc = vec![0.0];
                for w in verts.windows(2) {
                    arc.push(arc[arc.len() - 1] + self.vertices[w[0]].dist(self.vertices[w[1]]));
                }
                let open_length = arc[arc.len() - 1];
                let length = match (closed, verts.first(), verts.last()) {
                    (true, Some(&a), Some(&b)) => {
                        open_length + self.vertices[a].dist(self.vertices[b])
                    }
                    _ => open_length,
                };
                loops.push(BoundaryLoop {
                    vertices: verts,
                    arc,
                    open_length,
                    length,
                    closed,
                });
            }
        }
        loops
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Number of edges.
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// Position of vertex `v` (`v` must be a vertex index).
    pub fn position(&self, v: usize) -> Vec3 {
        self.vertices[v]
    }

    /// Faces as vertex index triples.
    pub fn faces(&self) -> &[[usize; 3]] {
        &self.faces
    }

    /// The two vertices of edge `e` (sorted).
    pub fn edge(&self, e: usize) -> [usize; 2] {
        self.edges[e]
    }

    /// The faces of edge `e` (one for a boundary edge, more than two for a non-manifold one).
    pub fn edge_faces(&self, e: usize) -> &[usize] {
        &self.edge_face_list[self.edge_face_start[e]..self.edge_face_start[e + 1]]
    }

    /// The edges of face `f`: entry `k` joins the face's local vertices `k` and `k + 1 (mod 3)`.
    pub fn face_edges(&self, f: usize) -> [usize; 3] {
        self.face_edges[f]
    }

    /// The faces around vertex `v`, in increasing order.
    pub fn vertex_faces(&self, v: usize) -> &[usize] {
        &self.vertex_face_list[self.vertex_face_start[v]..self.vertex_face_start[v + 1]]
    }

    /// The edge joining `a` and `b`, if any.
    pub fn find_edge(&self, a: usize, b: usize) -> Option<usize> {
        self.edge_index.get(&(a.min(b), a.max(b))).copied()
    }

    /// True when edge `e` has exactly one face.
    pub fn is_boundary_edge(&self, e: usize) -> bool {
        self.edge_faces(e).len() == 1
    }

    /// True when vertex `v` lies on a boundary edge.
    pub fn is_boundary_vertex(&self, v: usize) -> bool {
        self.boundary_vertex[v]
    }

    /// Unit normal of face `f` in its vertex order (zero for a degenerate face).
    pub fn face_normal(&self, f: usize) -> Vec3 {
        self.normals[f]
    }

    /// Area of face `f`.
    pub fn face_area(&self, f: usize) -> f64 {
        self.areas[f]
    }

    /// True when face `f` has (numerically) zero area.
    pub fn is_degenerate(&self, f: usize) -> bool {
        self.degenerate[f]
    }

    /// Corner positions of face `f`.
    pub fn face_points(&self, f: usize) -> [Vec3; 3] {
        let t = self.faces[f];
        [
            self.vertices[t[0]],
            self.vertices[t[1]],
            self.vertices[t[2]],
        ]
    }

    /// The boundary loops (see the module documentation for their order).
    pub fn boundary_loops(&self) -> &[BoundaryLoop] {
        &self.loops
    }

    /// Length of the bounding box diagonal.
    pub fn bounding_diagonal(&self) -> f64 {
        self.diagonal
    }

    /// The face of `e` other than `f`: `Ok(None)` on a boundary edge.
    ///
    /// # Errors
    ///
    /// [`TraceError::NonManifoldEdge`] when `e` has more than two faces.
    pub fn across(&self, e: usize, f: usize) -> Result<Option<usize>, TraceError> {
        let fs = self.edge_faces(e);
        match fs.len() {
            0 | 1 => Ok(None),
            2 => Ok(Some(if fs[0] == f { fs[1] } else { fs[0] })),
            n => Err(TraceError::NonManifoldEdge {
                vertices: self.edges[e],
                faces: n,
            }),
        }
    }

    /// The point at arc-length fraction `t` of boundary loop `loop_index`, with the reference's
    /// conventions: `t` is a fraction of the loop's length *without* its closing edge;
    /// `t = 0` and `t = 1` (exactly) become 0.001 and 0.999; a point falling exactly on a loop
    /// vertex moves back along its edge by 5% of the edge's length.
    ///
    /// # Errors
    ///
    /// [`TraceError::NoBoundary`], [`TraceError::LoopOutOfRange`], and
    /// [`TraceError::InvalidParameter`] for `t` outside `[0, 1]` or a loop of zero length.
    pub fn point_on_loop(&self, loop_index: usize, t: f64) -> Result<BoundaryPoint, TraceError> {
        if self.loops.is_empty() {
            return Err(TraceError::NoBoundary);
        }
        let lp = self
            .loops
            .get(loop_index)
            .ok_or(TraceError::LoopOutOfRange {
                index: loop_index,
                count: self.loops.len(),
            })?;
        if !(0.0..=1.0).contains(&t) {
            return Err(TraceError::InvalidParameter {
                name: "t",
                value: t,
                expected: "a fraction in [0, 1]",
            });
        }
        if !(lp.open_length > 0.0) || lp.edge_count() == 0 {
            return Err(TraceError::InvalidParameter {
                name: "boundary loop length",
                value: lp.open_length,
                expected: "a loop of positive length",
            });
        }
        let t = if t == 0.0 {
            0.001
        } else if t == 1.0 {
            0.999
        } else {
            t
        };
        let n = lp.vertices.len();
        let mut target = t * lp.open_length;
        let mut cur = 0.0;
        let edges = lp.edge_count();
        let mut found = None;
        for i in 0..edges {
            let (a, b) = (lp.vertices[i], lp.vertices[(i + 1) % n]);
            let (pa, pb) = (self.vertices[a], self.vertices[b]);
            let len = pa.dist(pb);
            if cur + len == target {
                target -= 0.05 * len;
            }
            if cur + len > target || i + 1 == edges {
                let off = (target - cur).clamp(0.0, len);
                let point = if len > 0.0 {
                    pa + (pb - pa) * (off / len)
                } else {
                    pa
                };
                found = Some((i, a, b, point));
                break;
            }
            cur += len;
        }
        let (i, a, b, point) = found.ok_or(TraceError::NoBoundary)?;
        let edge = self
            .find_edge(a, b)
            .ok_or_else(|| TraceError::InvalidMesh(format!("loop edge ({a}, {b}) not found")))?;
        Ok(BoundaryPoint {
            loop_index,
            loop_edge: i,
            edge,
            from: a,
            to: b,
            point,
            t,
        })
    }

    /// Local index (0, 1, 2) of vertex `v` in face `f`, if it belongs to it.
    pub(crate) fn local_index(&self, f: usize, v: usize) -> Option<usize> {
        self.faces[f].iter().position(|&w| w == v)
    }

    /// Local index `k` of edge `e` in face `f` (the edge joins local vertices `k`, `k + 1`).
    pub(crate) fn local_edge(&self, f: usize, e: usize) -> Option<usize> {
        self.face_edges[f].iter().position(|&x| x == e)
    }

    /// The vertex of face `f` opposite edge `e` (which must belong to `f`).
    pub(crate) fn opposite_vertex(&self, f: usize, e: usize) -> Option<usize> {
        self.local_edge(f, e).map(|k| self.faces[f][(k + 2) % 3])
    }
}

/// Compressed rows from `(row, value)` pairs, rows in `0..n`, values in input order.
fn csr(n: usize, pairs: &[(usize, usize)]) -> (Vec<usize>, Vec<usize>) {
    let mut start = vec![0usize; n + 1];
    for &(r, _) in pairs {
        start[r + 1] += 1;
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut list = vec![0usize; pairs.len()];
    for &(r, v) in pairs {
        list[fill[r]] = v;
        fill[r] += 1;
    }
    (start, list)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(vertices: &[[f64; 3]], faces: &[[u32; 3]]) -> TriMesh {
        TriMesh {
            vertices: vertices.iter().map(|&a| Vec3::from(a)).collect(),
            faces: faces.to_vec(),
        }
    }

    /// A 2×2-cell grid of the unit square (vertices numbered row by row).
    fn square() -> TriMesh {
        let mut v = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                v.push([i as f64 * 0.5, j as f64 * 0.5, 0.0]);
            }
        }
        let mut f = Vec::new();
        for j in 0..2u32 {
            for i in 0..2u32 {
                let a = j * 3 + i;
                f.push([a, a + 1, a + 4]);
                f.push([a, a + 4, a + 3]);
            }
        }
        mesh(&v, &f)
    }

    #[test]
    fn square_has_one_ccw_loop_starting_at_vertex_zero() {
        let topo = MeshTopology::new(&square()).unwrap();
        assert_eq!(topo.edge_count(), 16);
        let loops = topo.boundary_loops();
        assert_eq!(loops.len(), 1);
        let lp = &loops[0];
        // Counter-clockwise faces: the boundary runs 0 → 1 → 2 → 5 → 8 → 7 → 6 → 3.
        assert_eq!(lp.vertices, vec![0, 1, 2, 5, 8, 7, 6, 3]);
        assert!(lp.closed);
        assert!((lp.open_length - 3.5).abs() < 1e-12);
        assert!((lp.length - 4.0).abs() < 1e-12);
        assert!(topo.is_boundary_vertex(0) && !topo.is_boundary_vertex(4));
    }

    #[test]
    fn reversed_orientation_reverses_the_loop() {
        let mut m = square();
        for f in &mut m.faces {
            f.swap(1, 2);
        }
        let topo = MeshTopology::new(&m).unwrap();
        assert_eq!(
            topo.boundary_loops()[0].vertices,
            vec![0, 3, 6, 7, 8, 5, 2, 1]
        );
    }

    #[test]
    fn point_on_loop_follows_the_reference_conventions() {
        let topo = MeshTopology::new(&square()).unwrap();
        // t is a fraction of 3.5 (the closing edge 3 → 0 excluded).
        let p = topo.point_on_loop(0, 0.5).unwrap();
        assert!((p.point - Vec3::new(1.0, 0.75, 0.0)).norm() < 1e-12);
        assert_eq!((p.from, p.to), (5, 8));
        // t = 0 is nudged to 0.001.
        let p = topo.point_on_loop(0, 0.0).unwrap();
        assert!((p.t - 0.001).abs() < 1e-15);
        assert!((p.point - Vec3::new(0.0035, 0.0, 0.0)).norm() < 1e-12);
        // A point exactly on a vertex (arc length 1.0 = vertex 2) moves back by 5% of its edge.
        let p = topo.point_on_loop(0, 1.0 / 3.5).unwrap();
        assert_eq!((p.from, p.to), (1, 2));
        assert!((p.point - Vec3::new(0.975, 0.0, 0.0)).norm() < 1e-12);
        assert!(matches!(
            topo.point_on_loop(1, 0.5),
            Err(TraceError::LoopOutOfRange { .. })
        ));
        assert!(topo.point_on_loop(0, f64::NAN).is_err());
        assert!(topo.point_on_loop(0, 1.5).is_err());
    }

    #[test]
    fn annulus_loops_are_ordered_by_smallest_vertex() {
        // Outer square 4..8 listed after the inner square 0..4: the inner ring is loop 0.
        let v = [
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
            [-2.0, -2.0, 0.0],
            [2.0, -2.0, 0.0],
            [2.0, 2.0, 0.0],
            [-2.0, 2.0, 0.0],
        ];
        let mut f = Vec::new();
        for i in 0..4u32 {
            let (a, b) = (i, (i + 1) % 4);
            f.push([4 + a, 4 + b, b]);
            f.push([4 + a, b, a]);
        }
        let topo = MeshTopology::new(&mesh(&v, &f)).unwrap();
        let loops = topo.boundary_loops();
        assert_eq!(loops.len(), 2);
        assert_eq!(loops[0].vertices[0], 0);
        assert_eq!(loops[1].vertices[0], 4);
        // The inner ring runs clockwise in face orientation (the surface lies to its left).
        assert_eq!(loops[0].vertices, vec![0, 3, 2, 1]);
        assert_eq!(loops[1].vertices, vec![4, 5, 6, 7]);
    }

    #[test]
    fn bad_meshes_are_clear_errors() {
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert!(matches!(
            MeshTopology::new(&mesh(&v, &[[0, 1, 3]])),
            Err(TraceError::InvalidMesh(_))
        ));
        assert!(matches!(
            MeshTopology::new(&mesh(&v, &[[0, 1, 1]])),
            Err(TraceError::InvalidMesh(_))
        ));
        assert!(MeshTopology::new(&mesh(&v, &[])).is_err());
        let nan = [[0.0, 0.0, f64::NAN], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert!(MeshTopology::new(&mesh(&nan, &[[0, 1, 2]])).is_err());
    }

    #[test]
    fn non_manifold_edges_are_recorded_not_rejected() {
        let v = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, -1.0, 0.0],
            [0.5, 0.0, 1.0],
        ];
        let topo = MeshTopology::new(&mesh(&v, &[[0, 1, 2], [1, 0, 3], [0, 1, 4]])).unwrap();
        let nm: Vec<usize> = (0..topo.edge_count())
            .filter(|&e| topo.edge_faces(e).len() > 2)
            .collect();
        assert_eq!(nm.len(), 1);
        assert_eq!(topo.edge(nm[0]), [0, 1]);
        assert!(matches!(
            topo.across(nm[0], 0),
            Err(TraceError::NonManifoldEdge { faces: 3, .. })
        ));
    }

    #[test]
    fn closed_surface_has_no_loops() {
        let v = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let topo =
            MeshTopology::new(&mesh(&v, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])).unwrap();
        assert!(topo.boundary_loops().is_empty());
        assert_eq!(topo.point_on_loop(0, 0.5), Err(TraceError::NoBoundary));
    }
}

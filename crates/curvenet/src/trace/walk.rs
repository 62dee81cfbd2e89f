//! Straight walks across triangles, shared by the geodesic tracer and the streamlines.
//!
//! A walk is a sequence of straight segments, one per triangle. In a triangle the exit is found
//! from the *signs* of the three corners' distances to the ray's line, not from intersection
//! parameters, so the decision is consistent even when the ray passes within rounding of a
//! corner: corners closer to the line than `snap ×` the triangle's longest edge count as hit,
//! and the walk goes through that vertex.
//!
//! Crossing an edge, the direction is unfolded into the next triangle: it keeps its angle with
//! the edge (the two triangles are laid flat around the edge). This does not rely on the faces'
//! orientation, so inconsistently oriented meshes are walked correctly too.

use super::TraceError;
use super::topology::MeshTopology;
use crate::geom::Vec3;

/// How the walk entered the current face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Entry {
    /// Through this edge (mesh edge index).
    Edge(usize),
    /// From this vertex (mesh vertex index).
    Vertex(usize),
    /// From a point inside the face (a walk started on the surface, not on its boundary).
    Inside,
}

/// Where the walk leaves the current face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Exit {
    /// Through an edge, at a point.
    Edge {
        /// Mesh edge index.
        edge: usize,
        /// Exit point on the edge.
        point: Vec3,
    },
    /// Through a vertex.
    Vertex(usize),
}

/// A walk under way: its face, position, direction and how it entered the face, and the
/// polyline so far (stopped once longer than `cap`).
pub(crate) struct Walker {
    pub face: usize,
    pub pos: Vec3,
    pub dir: Vec3,
    pub entry: Entry,
    pub points: Vec<Vec3>,
    /// The face each segment of `points` crosses.
    pub faces: Vec<usize>,
    pub length: f64,
    cap: f64,
}

impl Walker {
    /// A walk from `pos` on edge `edge` of `face`, heading along `dir`.
    pub fn new(face: usize, pos: Vec3, dir: Vec3, edge: usize, cap: f64) -> Self {
        Walker {
            face,
            pos,
            dir,
            entry: Entry::Edge(edge),
            points: vec![pos],
            faces: Vec::new(),
            length: 0.0,
            cap,
        }
    }

    /// A walk from `pos` inside `face`, heading along `dir`.
    pub fn inside(face: usize, pos: Vec3, dir: Vec3, cap: f64) -> Self {
        Walker {
            entry: Entry::Inside,
            ..Walker::new(face, pos, dir, 0, cap)
        }
    }

    /// Where the walk leaves its face ([`exit_face`]).
    pub fn exit(&self, topo: &MeshTopology, snap: f64) -> Exit {
        exit_face(topo, self.face, self.pos, self.dir, self.entry, snap)
    }

    /// Moves to `point` of the current face; an error past the length cap.
    pub fn advance(&mut self, point: Vec3) -> Result<(), TraceError> {
        self.length += self.pos.dist(point);
        if self.length > self.cap {
            return Err(TraceError::LengthCap { cap: self.cap });
        }
        if point != self.pos {
            self.points.push(point);
            self.faces.push(self.face);
        }
        self.pos = point;
        Ok(())
    }

    /// Crosses edge `e` into face `next`, the direction unfolded ([`unfold`]).
    pub fn cross(&mut self, topo: &MeshTopology, e: usize, next: usize) {
        self.dir = unfold(topo, self.dir, e, next);
        self.face = next;
        self.entry = Entry::Edge(e);
    }

    /// Leaves vertex `v` into face `face` along `dir`.
    pub fn turn(&mut self, v: usize, face: usize, dir: Vec3) {
        self.face = face;
        self.dir = dir;
        self.entry = Entry::Vertex(v);
    }
}

/// Component of `v` orthogonal to the unit vector `u`.
#[inline]
fn reject(v: Vec3, u: Vec3) -> Vec3 {
    v - u * v.dot(u)
}

/// Unit direction in face `f`'s plane pointing from the line of edge `a`–`b` into the face
/// (towards its third vertex `c`).
pub(crate) fn inward_normal(topo: &MeshTopology, a: usize, b: usize, c: usize) -> Vec3 {
    let (pa, pb, pc) = (topo.position(a), topo.position(b), topo.position(c));
    let e = (pb - pa).normalized();
    reject(pc - pa, e).normalized()
}

/// Projects `d` onto the plane of face `f` and normalizes it (zero if it is normal to `f`).
pub(crate) fn in_plane(topo: &MeshTopology, f: usize, d: Vec3) -> Vec3 {
    reject(d, topo.face_normal(f)).normalized()
}

/// Where a ray from `pos` (on face `f`'s boundary, entered as `entry`) along `dir` leaves `f`.
///
/// `dir` must lie in the face's plane; `snap` is the vertex-hit tolerance relative to the
/// face's longest edge.
pub(crate) fn exit_face(
    topo: &MeshTopology,
    f: usize,
    pos: Vec3,
    dir: Vec3,
    entry: Entry,
    snap: f64,
) -> Exit {
    let tri = topo.faces()[f];
    let p = topo.face_points(f);
    let n = topo.face_normal(f);
    let longest = p[0].dist(p[1]).max(p[1].dist(p[2])).max(p[2].dist(p[0]));
    let tol = snap * longest;
    // Signed distance of each corner to the ray's line (positive to the left).
    let side = |k: usize| dir.cross(p[k] - pos).dot(n);
    let edge_between = |i: usize, j: usize| -> usize {
        // Local edge k joins k and k + 1.
        let k = if (i + 1) % 3 == j { i } else { j };
        topo.face_edges(f)[k]
    };
    let cut = |i: usize, si: f64, j: usize, sj: f64| -> Exit {
        let u = if si != sj {
            (si / (si - sj)).clamp(0.0, 1.0)
        } else {
            0.5
        };
        Exit::Edge {
            edge: edge_between(i, j),
            point: p[i] + (p[j] - p[i]) * u,
        }
    };
    match entry {
        Entry::Edge(e) => {
            let k0 = topo.local_edge(f, e).unwrap_or(0);
            let (i, j, k) = (k0, (k0 + 1) % 3, (k0 + 2) % 3);
            let (si, sj, sk) = (side(i), side(j), side(k));
            if sk.abs() <= tol && (p[k] - pos).dot(dir) > 0.0 {
                return Exit::Vertex(tri[k]);
            }
            // Which side of the line is `i` on? Use the corner farther from the line, so that
            // an entry point within rounding of a corner still decides correctly.
            let i_positive = if si.abs() >= sj.abs() {
                si > 0.0
            } else {
                sj < 0.0
            };
            if (sk > 0.0) == i_positive {
                cut(k, sk, j, sj)
            } else {
                cut(i, si, k, sk)
            }
        }
        Entry::Vertex(v) => {
            let i = topo.local_index(f, v).unwrap_or(0);
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let (sj, sk) = (side(j), side(k));
            let ahead = |m: usize| (p[m] - pos).dot(dir) > 0.0;
            if sj.abs() <= tol && ahead(j) && sj.abs() <= sk.abs() {
                return Exit::Vertex(tri[j]);
            }
            if sk.abs() <= tol && ahead(k) {
                return Exit::Vertex(tri[k]);
            }
            if (sj > 0.0) == (sk > 0.0) {
                // The direction does not point into the face (rounding at a fan edge): go
                // along the nearer edge.
                return Exit::Vertex(if sj.abs() <= sk.abs() { tri[j] } else { tri[k] });
            }
            cut(j, sj, k, sk)
        }
        Entry::Inside => {
            let s = [side(0), side(1), side(2)];
            let ahead = |m: usize| (p[m] - pos).dot(dir) > 0.0;
            // A corner on the line ahead is hit.
            if let Some(m) = (0..3).find(|&m| s[m].abs() <= tol && ahead(m)) {
                return Exit::Vertex(tri[m]);
            }
            // The line crosses the two edges whose corners lie on either side of it; the walk
            // leaves through the one ahead.
            let mut best: Option<(f64, Exit)> = None;
            for i in 0..3 {
                let j = (i + 1) % 3;
                if (s[i] > 0.0) == (s[j] > 0.0) {
                    continue;
                }
                let exit = cut(i, s[i], j, s[j]);
                if let Exit::Edge { point, .. } = exit {
                    let t = (point - pos).dot(dir);
                    if best.as_ref().is_none_or(|(b, _)| t > *b) {
                        best = Some((t, exit));
                    }
                }
            }
            best.map_or(Exit::Vertex(tri[0]), |(_, e)| e)
        }
    }
}

/// Unfolds `dir` (in face `from`) across edge `e` into face `to`: the result keeps its angle
/// with the edge and points into `to`.
pub(crate) fn unfold(topo: &MeshTopology, dir: Vec3, e: usize, to: usize) -> Vec3 {
    let [a, b] = topo.edge(e);
    let c = topo.opposite_vertex(to, e).unwrap_or(a);
    let ehat = (topo.position(b) - topo.position(a)).normalized();
    let w = inward_normal(topo, a, b, c);
    let along = dir.dot(ehat).clamp(-1.0, 1.0);
    let across = (1.0 - along * along).max(0.0).sqrt();
    (ehat * along + w * across).normalized()
}

/// The faces around an interior vertex, in order.
#[derive(Clone, Debug)]
pub(crate) struct Fan {
    /// Faces `F_0 … F_{m−1}`; `F_0` is the face the fan was started from.
    pub faces: Vec<usize>,
    /// `spokes[t]` and `spokes[t + 1]` are the other vertices of face `t`, in fan order
    /// (`spokes[m] == spokes[0]`).
    pub spokes: Vec<usize>,
    /// Corner angle of each face at the vertex.
    pub angles: Vec<f64>,
}

impl Fan {
    /// Total angle around the vertex.
    pub fn total(&self) -> f64 {
        self.angles.iter().sum()
    }
}

/// Angle between two vectors, in `[0, π]`.
pub(crate) fn angle_between(a: Vec3, b: Vec3) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}

/// The fan of faces around vertex `v`, starting at face `start`: `Ok(None)` when `v` is on the
/// boundary (the fan is not closed).
///
/// # Errors
///
/// [`TraceError::NonManifoldEdge`] when a spoke has more than two faces,
/// [`TraceError::NonManifoldVertex`] when the closed fan does not hold all faces of `v`,
/// [`TraceError::DegenerateFace`] for a zero-area face in the fan.
pub(crate) fn vertex_fan(
    topo: &MeshTopology,
    v: usize,
    start: usize,
) -> Result<Option<Fan>, TraceError> {
    if topo.is_boundary_vertex(v) {
        return Ok(None);
    }
    let others = |f: usize| -> Option<[usize; 2]> {
        let i = topo.local_index(f, v)?;
        let t = topo.faces()[f];
        Some([t[(i + 1) % 3], t[(i + 2) % 3]])
    };
    let [u0, u1] = others(start).ok_or(TraceError::NonManifoldVertex { vertex: v })?;
    let total_faces = topo.vertex_faces(v).len();
    let mut faces = vec![start];
    let mut spokes = vec![u0, u1];
    let mut f = start;
    let mut last = u1;
    loop {
        let e = topo
            .find_edge(v, last)
            .ok_or(TraceError::NonManifoldVertex { vertex: v })?;
        let g = match topo.across(e, f)? {
            Some(g) => g,
            None => return Ok(None),
        };
        if g == start {
            break;
        }
        if faces.len() >= total_faces {
            return Err(TraceError::NonManifoldVertex { vertex: v });
        }
        let [a, b] = others(g).ok_or(TraceError::NonManifoldVertex { vertex: v })?;
        let next = if a == last { b } else { a };
        faces.push(g);
        spokes.push(next);
        f = g;
        last = next;
    }
    if faces.len() != total_faces || spokes.last() != spokes.first() {
        return Err(TraceError::NonManifoldVertex { vertex: v });
    }
    let pv = topo.position(v);
    let mut angles = Vec::with_capacity(faces.len());
    for (t, &f) in faces.iter().enumerate() {
        if topo.is_degenerate(f) {
            return Err(TraceError::DegenerateFace { face: f });
        }
        let a = topo.position(spokes[t]) - pv;
        let b = topo.position(spokes[t + 1]) - pv;
        angles.push(angle_between(a, b));
    }
    Ok(Some(Fan {
        faces,
        spokes,
        angles,
    }))
}

/// Unit direction in fan face `t` at angle `rho` from its first spoke, turning towards its
/// second spoke.
pub(crate) fn fan_direction(topo: &MeshTopology, v: usize, fan: &Fan, t: usize, rho: f64) -> Vec3 {
    let pv = topo.position(v);
    let e = (topo.position(fan.spokes[t]) - pv).normalized();
    let w = reject(topo.position(fan.spokes[t + 1]) - pv, e).normalized();
    (e * rho.cos() + w * rho.sin()).normalized()
}

/// Angular position (from spoke 0, along the fan) of a direction `d` lying in fan face 0.
pub(crate) fn fan_position_in_first(topo: &MeshTopology, v: usize, fan: &Fan, d: Vec3) -> f64 {
    let pv = topo.position(v);
    let e0 = topo.position(fan.spokes[0]) - pv;
    let e1 = topo.position(fan.spokes[1]) - pv;
    let a = angle_between(e0, d);
    let b = angle_between(e1, d);
    // `d` lies in the wedge: a + b ≈ α₀. Outside it (rounding), clamp to the nearer spoke.
    if a + b > fan.angles[0] + 1e-9 && b < a {
        fan.angles[0]
    } else {
        a.min(fan.angles[0])
    }
}

/// The straightest continuation through interior vertex `v` (Polthier–Schmies): the path
/// arrived along `incoming` (pointing into `v`) through fan face 0, and leaves so that the
/// angles on both of its sides are equal (half the total angle each).
///
/// Returns the fan face index to continue in and the outgoing direction.
pub(crate) fn straightest(
    topo: &MeshTopology,
    v: usize,
    fan: &Fan,
    incoming: Vec3,
) -> (usize, Vec3) {
    let back = in_plane(topo, fan.faces[0], -incoming);
    let phi_back = fan_position_in_first(topo, v, fan, back);
    let total = fan.total();
    let mut target = phi_back + 0.5 * total;
    if target >= total {
        target -= total;
    }
    let m = fan.faces.len();
    let mut cum = 0.0;
    for t in 0..m {
        if target < cum + fan.angles[t] || t + 1 == m {
            let rho = (target - cum).clamp(0.0, fan.angles[t]);
            return (t, fan_direction(topo, v, fan, t, rho));
        }
        cum += fan.angles[t];
    }
    (0, fan_direction(topo, v, fan, 0, 0.0))
}

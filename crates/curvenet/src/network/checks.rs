//! Sanity checks on a network's input: findings that do not stop a network from being built but
//! that a user should hear about (SPEC §10: such warnings go to stderr and into the output, and
//! the run goes on).
//!
//! - [`MeshDistance`]: the distance from a point to a triangle mesh, through a bounding-volume
//!   hierarchy over the triangles (`O(log n)` per query on ordinary meshes);
//!   [`curves_far_from_mesh`] uses it to find curves that do not lie on their surface (wrong
//!   scale or units, the mesh of another scene).
//! - [`mesh_warnings`]: faces that point to no vertex, degenerate and duplicate faces, edges shared
//!   by more than two faces (non-manifold) and edges that two faces run the same way
//!   (inconsistent orientation).
//! - [`overlapping_curves`]: pairs of curves that run together, within the crossing tolerance of
//!   each other, over a length where a crossing would have left them: construction then sees
//!   one crossing (one joint) where the designer drew two rods lying on each other.
//! - [`network_warnings`]: what construction found: curves that cross nothing (and closed curves
//!   that float free), curves that run together, and edges far shorter than `h` (SPEC §11).
//!
//! Every function here is total: any input, however degenerate or non-finite, gives an answer
//! and never a panic.

use super::crossings::CurveGeometry;
use super::{BuildInfo, Network};
use crate::geom::{Aabb, Vec3};
use crate::io::{Origin, Polyline, TriMesh};
use std::collections::HashMap;

/// Default relative distance (times the mesh's bounding-box diagonal) beyond which a curve point
/// counts as far from the mesh.
pub const FAR_FROM_MESH: f64 = 0.03;

/// A rest edge shorter than this fraction of the target edge length `h` earns a warning: the
/// bending stiffness grows like `1/ē³`, so such an edge ill-conditions the Hessian (SPEC §11).
pub const SHORT_EDGE: f64 = 1e-2;

/// At most this many items are listed in one warning; the rest are counted.
const LIST_LIMIT: usize = 8;

/// A bounding-volume hierarchy over axis-aligned boxes (median splits along the widest axis of
/// the box centres, four items per leaf).
#[derive(Clone, Debug)]
struct BoxTree {
    nodes: Vec<BoxNode>,
    items: Vec<u32>,
}

/// A node of [`BoxTree`]: a leaf holds `items[start..end]`, an inner node two children.
#[derive(Clone, Copy, Debug)]
struct BoxNode {
    bbox: Aabb,
    start: u32,
    end: u32,
    children: Option<(u32, u32)>,
}

impl BoxTree {
    /// Items per leaf.
    const LEAF: usize = 4;

    /// Builds the tree over `boxes` (item `i` is `boxes[i]`).
    fn build(boxes: &[Aabb]) -> BoxTree {
        let mut items: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * boxes.len() / Self::LEAF + 1);
        if !boxes.is_empty() {
            Self::build_node(boxes, &mut items, 0, boxes.len(), &mut nodes);
        }
        BoxTree { nodes, items }
    }

    fn build_node(
        boxes: &[Aabb],
        items: &mut [u32],
        start: usize,
        end: usize,
        nodes: &mut Vec<BoxNode>,
    ) -> u32 {
        let mut bbox = Aabb::EMPTY;
        let mut centres = Aabb::EMPTY;
        for &i in &items[start..end] {
            let b = boxes[i as usize];
            bbox.add(b.min);
            bbox.add(b.max);
            centres.add(b.min.lerp(b.max, 0.5));
        }
        let id = nodes.len() as u32;
        nodes.push(BoxNode {
            bbox,
            start: start as u32,
            end: end as u32,
            children: None,
        });
        if end - start <= Self::LEAF {
            return id;
        }
        let ext = centres.extent();
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = (start + end) / 2;
        let key = |i: u32| {
            let b = boxes[i as usize];
            b.min[axis] + b.max[axis]
        };
        items[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
            key(a).total_cmp(&key(b)).then(a.cmp(&b))
        });
        let left = Self::build_node(boxes, items, start, mid, nodes);
        let right = Self::build_node(boxes, items, mid, end, nodes);
        nodes[id as usize].children = Some((left, right));
        id
    }

    /// The item nearest to `p` by `dist` (a distance that is at least the distance from `p` to
    /// the item's box), among items closer than `limit`; `stop_below` ends the search at the
    /// first item found closer than it. `None` when no item is closer than `limit`.
    fn nearest(
        &self,
        p: Vec3,
        limit: f64,
        stop_below: f64,
        mut dist: impl FnMut(u32) -> f64,
    ) -> Option<(f64, u32)> {
        let mut best: Option<(f64, u32)> = None;
        let mut bound = limit;
        let mut stack: Vec<(f64, u32)> = Vec::with_capacity(64);
        if let Some(root) = self.nodes.first() {
            stack.push((box_distance(&root.bbox, p), 0));
        }
        while let Some((d, n)) = stack.pop() {
            // `!(d < bound)` also drops NaN distances.
            if !(d < bound) {
                continue;
            }
            let node = &self.nodes[n as usize];
            match node.children {
                Some((l, r)) => {
                    let (dl, dr) = (
                        box_distance(&self.nodes[l as usize].bbox, p),
                        box_distance(&self.nodes[r as usize].bbox, p),
                    );
                    // The nearer child is searched first (pushed last).
                    if dl <= dr {
                        stack.push((dr, r));
                        stack.push((dl, l));
                    } else {
                        stack.push((dl, l));
                        stack.push((dr, r));
                    }
                }
                None => {
                    for &i in &self.items[node.start as usize..node.end as usize] {
                        let di = dist(i);
                        if di < bound {
                            bound = di;
                            best = Some((di, i));
                            if di < stop_below {
                                return best;
                            }
                        }
                    }
                }
            }
        }
        best
    }

    /// Calls `f` for every item whose box holds `p`.
    fn containing(&self, boxes: &[Aabb], p: Vec3, mut f: impl FnMut(u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if !holds(&node.bbox, p) {
                continue;
            }
            match node.children {
                Some((l, r)) => {
                    stack.push(r);
                    stack.push(l);
                }
                None => {
                    for &i in &self.items[node.start as usize..node.end as usize] {
                        if holds(&boxes[i as usize], p) {
                            f(i);
                        }
                    }
                }
            }
        }
    }
}

/// True when the box holds `p` (boundary included).
fn holds(b: &Aabb, p: Vec3) -> bool {
    b.min.x <= p.x
        && p.x <= b.max.x
        && b.min.y <= p.y
        && p.y <= b.max.y
        && b.min.z <= p.z
        && p.z <= b.max.z
}

/// Distance from `p` to the box (0 inside).
fn box_distance(b: &Aabb, p: Vec3) -> f64 {
    let d = Vec3::new(
        (b.min.x - p.x).max(p.x - b.max.x).max(0.0),
        (b.min.y - p.y).max(p.y - b.max.y).max(0.0),
        (b.min.z - p.z).max(p.z - b.max.z).max(0.0),
    );
    d.norm()
}

/// Distance from `p` to the segment `[a, b]` (a point when `a = b`).
pub fn point_segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = b - a;
    let len2 = d.norm2();
    let t = if len2 > 0.0 {
        ((p - a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.dist(a + d * t)
}

/// The point of triangle `abc` closest to `p` (Ericson, *Real-Time Collision Detection*, §5.1.5,
/// by Voronoi regions). A degenerate triangle (collinear or repeated vertices) is handled as its
/// three edges.
pub fn closest_point_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let on_triangle = closest_point_regions(p, a, b, c);
    if on_triangle.is_finite() {
        return on_triangle;
    }
    // Degenerate: the nearest of the edges' nearest points.
    let mut best = a;
    let mut best_d = f64::INFINITY;
    for (u, v) in [(a, b), (b, c), (c, a)] {
        let d = v - u;
        let len2 = d.norm2();
        let t = if len2 > 0.0 {
            ((p - u).dot(d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = u + d * t;
        let dq = p.dist(q);
        if dq < best_d {
            best_d = dq;
            best = q;
        }
    }
    best
}

/// Ericson's Voronoi-region walk; non-finite for degenerate triangles.
fn closest_point_regions(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Point-to-surface distance for one triangle mesh.
///
/// Faces that point to a missing vertex or hold a non-finite coordinate are skipped.
#[derive(Clone, Debug)]
pub struct MeshDistance {
    triangles: Vec<[Vec3; 3]>,
    tree: BoxTree,
    bounds: Aabb,
}

impl MeshDistance {
    /// Indexes the triangles of `mesh`.
    pub fn new(mesh: &TriMesh) -> Self {
        let triangles: Vec<[Vec3; 3]> = mesh
            .faces
            .iter()
            .filter_map(|f| {
                let get = |i: u32| mesh.vertices.get(i as usize).copied();
                let t = [get(f[0])?, get(f[1])?, get(f[2])?];
                t.iter().all(|p| p.is_finite()).then_some(t)
            })
            .collect();
        let boxes: Vec<Aabb> = triangles.iter().map(Aabb::of_points).collect();
        let mut bounds = Aabb::EMPTY;
        for b in &boxes {
            bounds.add(b.min);
            bounds.add(b.max);
        }
        MeshDistance {
            tree: BoxTree::build(&boxes),
            triangles,
            bounds,
        }
    }

    /// Number of usable triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Length of the diagonal of the usable triangles' bounding box (0 without triangles).
    pub fn diagonal(&self) -> f64 {
        self.bounds.extent().norm()
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
    let diagonal = index.diagonal();
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
    let more = found.curves.len().saturating_sub(LIST_LIMIT);
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
        100.0 * found.threshold / found.diagonal,
        found.diagonal,
        listed.join(", "),
        if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        },
    ))
}

/// Problems of a triangle mesh's connectivity and shape, one warning per kind, each naming
/// `mesh_name` and the first offending faces (1-based, as in an OBJ file). A mesh read by
/// [`crate::io::read_mesh`] has already lost its degenerate faces (with warnings of their own).
pub fn mesh_warnings(mesh: &TriMesh, mesh_name: &str) -> Vec<String> {
    let mut warnings = Vec::new();
    let n = mesh.vertices.len();
    let mut missing = Vec::new();
    let mut degenerate = Vec::new();
    let mut seen_faces: HashMap<[u32; 3], usize> = HashMap::new();
    let mut duplicates = Vec::new();
    // Undirected edge → (faces using it, faces running it from its lower to its higher vertex).
    let mut edges: HashMap<(u32, u32), (usize, usize)> = HashMap::new();
    for (k, f) in mesh.faces.iter().enumerate() {
        if f.iter().any(|&i| i as usize >= n) {
            missing.push(k);
            continue;
        }
        let [a, b, c] = f.map(|i| mesh.vertices[i as usize]);
        let repeated = f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
        if repeated || zero_area(a, b, c) {
            degenerate.push(k);
            continue;
        }
        let mut key = *f;
        key.sort_unstable();
        if let Some(&first) = seen_faces.get(&key) {
            duplicates.push((k, first));
            continue;
        }
        seen_faces.insert(key, k);
        for (u, v) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
            let e = edges.entry((u.min(v), u.max(v))).or_insert((0, 0));
            e.0 += 1;
            if u < v {
                e.1 += 1;
            }
        }
    }
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
    if !missing.is_empty() {
        warnings.push(format!(
            "mesh {mesh_name}: {} face(s) point to a missing vertex and are ignored: faces {}",
            missing.len(),
            faces(&missing)
        ));
    }
    if !degenerate.is_empty() {
        warnings.push(format!(
            "mesh {mesh_name}: {} degenerate face(s) (zero area or a repeated vertex): faces {}",
            degenerate.len(),
            faces(&degenerate)
        ));
    }
    if !duplicates.is_empty() {
        let pairs: Vec<String> = duplicates
            .iter()
            .take(LIST_LIMIT)
            .map(|(k, first)| format!("{} = {}", k + 1, first + 1))
            .collect();
        warnings.push(format!(
            "mesh {mesh_name}: {} duplicate face(s) (the same three vertices as an earlier face): \
             faces {}{}",
            duplicates.len(),
            pairs.join(", "),
            if duplicates.len() > LIST_LIMIT {
                " …"
            } else {
                ""
            }
        ));
    }
    let mut non_manifold: Vec<(u32, u32, usize)> = Vec::new();
    let mut flipped: Vec<(u32, u32)> = Vec::new();
    for (&(u, v), &(count, forward)) in &edges {
        if count > 2 {
            non_manifold.push((u, v, count));
        } else if count == 2 && forward != 1 {
            flipped.push((u, v));
        }
    }
    non_manifold.sort_unstable();
    flipped.sort_unstable();
    if !non_manifold.is_empty() {
        let list: Vec<String> = non_manifold
            .iter()
            .take(LIST_LIMIT)
            .map(|(u, v, c)| format!("{}–{} ({c} faces)", u + 1, v + 1))
            .collect();
        warnings.push(format!(
            "mesh {mesh_name}: {} non-manifold edge(s) shared by more than two faces: vertices {}{}",
            non_manifold.len(),
            list.join(", "),
            if non_manifold.len() > LIST_LIMIT {
                " …"
            } else {
                ""
            }
        ));
    }
    if !flipped.is_empty() {
        let list: Vec<String> = flipped
            .iter()
            .take(LIST_LIMIT)
            .map(|(u, v)| format!("{}–{}", u + 1, v + 1))
            .collect();
        warnings.push(format!(
            "mesh {mesh_name}: {} edge(s) where two faces disagree on orientation (the faces \
             run the edge the same way): vertices {}{}",
            flipped.len(),
            list.join(", "),
            if flipped.len() > LIST_LIMIT {
                " …"
            } else {
                ""
            }
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
    if !largest.is_finite() {
        return true;
    }
    if largest == 0.0 {
        return true;
    }
    let exponent = largest.log2().ceil().clamp(-1000.0, 1000.0) as i32;
    let s = 2f64.powi(-exponent);
    let (a, b, c) = (a * s, b * s, c * s);
    let (e1, e2, e3) = (b - a, c - a, c - b);
    let longest2 = e1.norm2().max(e2.norm2()).max(e3.norm2());
    !(e1.cross(e2).norm() > 1e-12 * longest2)
}

/// Two curves that run together.
#[derive(Clone, Debug, PartialEq)]
pub struct Overlap {
    /// The lower curve id.
    pub a: usize,
    /// The higher curve id.
    pub b: usize,
    /// Length along `a` over which `b` stays within the crossing tolerance.
    pub length: f64,
    /// Where the overlap starts on `a`.
    pub start: Vec3,
}

/// Pairs of distinct curves that stay within the crossing tolerance of each other
/// (`factor ×` the larger median segment, as in crossing detection) over at least a quarter of
/// the larger of their median segment lengths (sampled every quarter of a median segment). A
/// crossing at an angle `θ` keeps the curves that close only over about `2 · tol / θ`, so with
/// the default `factor = 1e-3` this flags curves that are tangent within about 0.5° or lie on
/// each other. Sorted by curve pair; one entry (the longest run) per pair.
pub fn overlapping_curves(curves: &[Polyline], factor: f64) -> Vec<Overlap> {
    let geo: Vec<CurveGeometry> = curves
        .iter()
        .map(|c| CurveGeometry::new(c.points.clone(), c.closed))
        .collect();
    overlaps_of(&geo, factor)
}

/// [`overlapping_curves`] on prepared geometry.
fn overlaps_of(geo: &[CurveGeometry], factor: f64) -> Vec<Overlap> {
    // Segments with boxes inflated by the largest tolerance any pair can use with them.
    let usable = |g: &CurveGeometry| {
        g.points.len() >= 2
            && g.points.iter().all(|p| p.is_finite())
            && g.length().is_finite()
            && g.median_segment > 0.0
    };
    let tol_max = geo
        .iter()
        .filter(|g| usable(g))
        .map(|g| g.tolerance(factor))
        .fold(0.0, f64::max);
    if !(tol_max.is_finite() && tol_max > 0.0) || geo.len() < 2 {
        return Vec::new();
    }
    let mut segs: Vec<(u32, u32)> = Vec::new();
    let mut boxes: Vec<Aabb> = Vec::new();
    for (c, g) in geo.iter().enumerate() {
        if !usable(g) {
            continue;
        }
        for k in 0..g.segment_count() {
            let (p, q) = g.segment(k);
            let mut b = Aabb::of_points([&p, &q]);
            let pad = Vec3::new(tol_max, tol_max, tol_max);
            b.min -= pad;
            b.max += pad;
            segs.push((c as u32, k as u32));
            boxes.push(b);
        }
    }
    let tree = BoxTree::build(&boxes);
    let mut best: HashMap<(usize, usize), Overlap> = HashMap::new();
    for (a, ga) in geo.iter().enumerate() {
        if !usable(ga) {
            continue;
        }
        // Runs in progress: other curve → (arc length where the run started, its position,
        // arc length of the latest sample near it).
        let mut runs: HashMap<usize, (f64, Vec3, f64)> = HashMap::new();
        let step = ga.median_segment / 4.0;
        let mut near: Vec<usize> = Vec::new();
        let close_run = |b: usize, run: (f64, Vec3, f64), best: &mut HashMap<_, Overlap>| {
            let length = run.2 - run.0;
            let needed = 0.25 * ga.median_segment.max(geo[b].median_segment);
            if length >= needed {
                let key = (a.min(b), a.max(b));
                let entry = Overlap {
                    a: key.0,
                    b: key.1,
                    length,
                    start: run.1,
                };
                match best.get(&key) {
                    Some(o) if o.length >= length => {}
                    _ => {
                        best.insert(key, entry);
                    }
                }
            }
        };
        for k in 0..ga.segment_count() {
            let len = ga.segment_length(k);
            let samples = ((len / step).ceil() as usize).clamp(1, 16);
            let last = k + 1 == ga.segment_count();
            let (p0, p1) = ga.segment(k);
            for j in 0..samples + usize::from(last) {
                let t = j as f64 / samples as f64;
                let p = p0.lerp(p1, t);
                let s = ga.arc[k] + t * len;
                near.clear();
                tree.containing(&boxes, p, |i| {
                    let (b, kb) = segs[i as usize];
                    let b = b as usize;
                    if b == a || near.contains(&b) {
                        return;
                    }
                    let gb = &geo[b];
                    let tol = ga.tolerance(factor).max(gb.tolerance(factor));
                    let (q0, q1) = gb.segment(kb as usize);
                    if point_segment_distance(p, q0, q1) < tol {
                        near.push(b);
                    }
                });
                for &b in &near {
                    runs.entry(b).and_modify(|r| r.2 = s).or_insert((s, p, s));
                }
                let ended: Vec<usize> =
                    runs.keys().copied().filter(|b| !near.contains(b)).collect();
                for b in ended {
                    if let Some(run) = runs.remove(&b) {
                        close_run(b, run, &mut best);
                    }
                }
            }
        }
        let mut open: Vec<(usize, (f64, Vec3, f64))> = runs.into_iter().collect();
        open.sort_by_key(|(b, _)| *b);
        for (b, run) in open {
            close_run(b, run, &mut best);
        }
    }
    let mut out: Vec<Overlap> = best.into_values().collect();
    out.sort_by_key(|o| (o.a, o.b));
    out
}

/// The warnings of a freshly built network: curves that cross nothing (closed ones float
/// free), curves that run together, and rest edges shorter than [`SHORT_EDGE`]` × h`.
/// `curves` are the input curves (for their origins), `geo` the same curves prepared for crossing
/// detection, `h` the target edge length and `factor` the relative crossing tolerance.
pub fn network_warnings(
    network: &Network,
    info: &BuildInfo,
    curves: &[Polyline],
    geo: &[CurveGeometry],
    h: f64,
    factor: f64,
) -> Vec<String> {
    let mut warnings = Vec::new();
    let at = |c: usize| {
        curves
            .get(c)
            .map_or_else(String::new, |p| format!(" ({})", p.origin))
    };
    if !info.isolated_curves.is_empty() && network.rods.len() > 1 {
        let list: Vec<String> = info
            .isolated_curves
            .iter()
            .take(LIST_LIMIT)
            .map(|&c| format!("{c}{}", at(c)))
            .collect();
        warnings.push(format!(
            "{} curve(s) cross no other curve and stand on their supports alone: {}{}",
            info.isolated_curves.len(),
            list.join(", "),
            if info.isolated_curves.len() > LIST_LIMIT {
                format!(" and {} more", info.isolated_curves.len() - LIST_LIMIT)
            } else {
                String::new()
            }
        ));
    }
    let floating: Vec<String> = info
        .isolated_curves
        .iter()
        .filter(|&&c| network.rods.get(c).is_some_and(|r| r.closed))
        .filter(|&&c| {
            !network
                .joints
                .iter()
                .any(|j| j.curves.contains(&(c as u32)))
        })
        .take(LIST_LIMIT)
        .map(|&c| format!("{c}{}", at(c)))
        .collect();
    if !floating.is_empty() {
        warnings.push(format!(
            "closed curve(s) without supports or crossings float free: nothing holds them \
             (six rigid-body zero modes each): {}",
            floating.join(", ")
        ));
    }
    let overlaps = overlaps_of(geo, factor);
    if !overlaps.is_empty() {
        let list: Vec<String> = overlaps
            .iter()
            .take(LIST_LIMIT)
            .map(|o| {
                format!(
                    "{} and {} over {:.4e} from ({:.4e}, {:.4e}, {:.4e})",
                    o.a, o.b, o.length, o.start.x, o.start.y, o.start.z
                )
            })
            .collect();
        warnings.push(format!(
            "{} pair(s) of curves run together (within the crossing tolerance of each other, \
             not crossing): curves {}{}; construction joins each such pair at one point, not \
             along its length",
            overlaps.len(),
            list.join("; "),
            if overlaps.len() > LIST_LIMIT {
                " …"
            } else {
                ""
            }
        ));
    }
    let mut shortest: Option<(f64, usize)> = None;
    for (c, rod) in network.rods.iter().enumerate() {
        for &l in &rod.rest_lengths {
            if shortest.is_none_or(|(s, _)| l < s) {
                shortest = Some((l, c));
            }
        }
    }
    if let Some((l, c)) = shortest {
        if l < SHORT_EDGE * h {
            warnings.push(format!(
                "the shortest rest edge, on curve {c}{}, is {l:.4e}: {:.2e} × the edge length \
                 h = {h:.4e}; two joints nearly coincide along it (or a joint and the curve's \
                 end), and the Hessian's condition grows like (h/ē)³ (consider --merge-joints)",
                at(c),
                l / h
            ));
        }
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_mesh() -> TriMesh {
        TriMesh {
            vertices: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            faces: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    fn polyline(points: &[[f64; 3]]) -> Polyline {
        Polyline {
            points: points.iter().map(|&p| Vec3::from(p)).collect(),
            closed: false,
            origin: Origin::new("c.txt", 3),
            label: None,
        }
    }

    #[test]
    fn closest_points_on_a_triangle_by_region() {
        let (a, b, c) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        );
        let cases = [
            (Vec3::new(0.5, 0.5, 3.0), Vec3::new(0.5, 0.5, 0.0)),
            (Vec3::new(-1.0, -1.0, 0.0), a),
            (Vec3::new(3.0, -1.0, 0.0), b),
            (Vec3::new(-1.0, 3.0, 1.0), c),
            (Vec3::new(1.0, -2.0, 0.0), Vec3::new(1.0, 0.0, 0.0)),
            (Vec3::new(2.0, 2.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
        ];
        for (p, want) in cases {
            let got = closest_point_on_triangle(p, a, b, c);
            assert!(got.dist(want) < 1e-12, "{p:?}: {got:?} != {want:?}");
        }
        // Degenerate triangles: collinear and a single point.
        let got =
            closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), a, b, Vec3::new(1.0, 0.0, 0.0));
        assert!(got.dist(Vec3::new(1.0, 0.0, 0.0)) < 1e-12, "{got:?}");
        let got = closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), a, a, a);
        assert_eq!(got, a);
    }

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
        assert!(!w.contains("same units"), "{w}");
        // Every curve far: the hint about units.
        let far = vec![polyline(&[[10.0, 0.0, 0.0], [11.0, 0.0, 0.0]])];
        let w = far_from_mesh_warning(&curves_far_from_mesh(&far, &mesh, 0.03), "m.obj").unwrap();
        assert!(w.contains("same units"), "{w}");
        // Nothing usable: nothing reported, no panic.
        let empty = TriMesh::default();
        assert!(curves_far_from_mesh(&far, &empty, 0.03).curves.is_empty());
    }

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

    #[test]
    fn overlapping_curves_are_found_but_crossings_are_not() {
        let curves = vec![
            polyline(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]),
            polyline(&[[1.0, -1.0, 0.0], [1.0, 1.0, 0.0]]),
            polyline(&[[0.5, 0.0, 0.0], [1.5, 0.0, 0.0], [2.5, 0.0, 0.0]]),
            polyline(&[[0.0, 1.0, 0.0], [2.0, 1.0001, 0.0]]),
        ];
        let o = overlapping_curves(&curves, 1e-3);
        assert_eq!(o.len(), 1, "{o:?}");
        assert_eq!((o[0].a, o[0].b), (0, 2));
        assert!((o[0].length - 1.5).abs() < 1e-9, "{o:?}");
        // Nearly tangent lines at a 1e-5 angle overlap too; at 5° they cross.
        let tangent = vec![
            polyline(&[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]),
            polyline(&[[0.0, 0.0, 0.0], [10.0, 1e-4, 0.0]]),
        ];
        assert_eq!(overlapping_curves(&tangent, 1e-3).len(), 1);
        let crossing = vec![
            polyline(&[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]),
            polyline(&[[0.0, -0.4, 0.0], [10.0, 0.47, 0.0]]),
        ];
        assert!(overlapping_curves(&crossing, 1e-3).is_empty());
    }
}

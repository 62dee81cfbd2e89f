//! Tests of the tracing module on meshes built here and on the reference meshes.

use super::*;
use crate::geom::{Vec3, segment_closest_points};
use crate::io::{TriMesh, read_mesh};
use crate::rng::SplitMix64;
use proptest::prelude::*;
use std::f64::consts::PI;
use std::path::PathBuf;

// ---------------------------------------------------------------------------------------------
// Meshes made for the tests.

/// The unit square as an `n × n` grid with alternating diagonals; interior vertices moved by
/// up to `jitter` of a cell (deterministically).
fn square(n: usize, jitter: f64) -> TriMesh {
    let mut rng = SplitMix64::new(7);
    let h = 1.0 / n as f64;
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let mut p = Vec3::new(i as f64 * h, j as f64 * h, 0.0);
            if i > 0 && i < n && j > 0 && j < n {
                p.x += jitter * h * rng.uniform(-1.0, 1.0);
                p.y += jitter * h * rng.uniform(-1.0, 1.0);
            }
            vertices.push(p);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                faces.push([a, b, c]);
                faces.push([a, c, d]);
            } else {
                faces.push([a, b, d]);
                faces.push([b, c, d]);
            }
        }
    }
    TriMesh { vertices, faces }
}

/// A prism approximating a cylinder of radius `r`, height `h`: `n` sides, `m` levels; the
/// bottom ring comes first (boundary loop 0).
fn cylinder(n: usize, m: usize, r: f64, h: f64) -> TriMesh {
    let mut vertices = Vec::new();
    for j in 0..=m {
        for i in 0..n {
            let a = 2.0 * PI * i as f64 / n as f64;
            vertices.push(Vec3::new(r * a.cos(), r * a.sin(), h * j as f64 / m as f64));
        }
    }
    let id = |i: usize, j: usize| (j * n + i % n) as u32;
    let mut faces = Vec::new();
    for j in 0..m {
        for i in 0..n {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    TriMesh { vertices, faces }
}

/// A sphere cap of radius `r` (centre at the origin) from the north pole (vertex 0) down to
/// polar angle `max_polar`: `n` meridians, `m` rings; each quad between rings gets a centre
/// vertex (4 triangles), so every mid-meridian plane is a mirror symmetry of the mesh.
fn sphere_cap(n: usize, m: usize, r: f64, max_polar: f64) -> TriMesh {
    let point = |polar: f64, lon: f64| {
        Vec3::new(
            r * polar.sin() * lon.cos(),
            r * polar.sin() * lon.sin(),
            r * polar.cos(),
        )
    };
    let mut vertices = vec![Vec3::new(0.0, 0.0, r)];
    for j in 1..=m {
        for i in 0..n {
            vertices.push(point(
                max_polar * j as f64 / m as f64,
                2.0 * PI * i as f64 / n as f64,
            ));
        }
    }
    let ring = |i: usize, j: usize| 1 + (j - 1) * n + i % n;
    let mut faces = Vec::new();
    for i in 0..n {
        faces.push([0, ring(i, 1) as u32, ring(i + 1, 1) as u32]);
    }
    for j in 1..m {
        for i in 0..n {
            let c = vertices.len();
            let polar = max_polar * (j as f64 + 0.5) / m as f64;
            vertices.push(point(polar, 2.0 * PI * (i as f64 + 0.5) / n as f64));
            let (a, b, cc, d) = (
                ring(i, j),
                ring(i + 1, j),
                ring(i + 1, j + 1),
                ring(i, j + 1),
            );
            for (p, q) in [(a, d), (d, cc), (cc, b), (b, a)] {
                faces.push([c as u32, p as u32, q as u32]);
            }
        }
    }
    // Make the orientation outward.
    let mesh = TriMesh { vertices, faces };
    let topo = MeshTopology::new(&mesh).unwrap();
    let f0 = topo.face_points(0);
    if topo.face_normal(0).dot(f0[0]) < 0.0 {
        let mut m2 = mesh;
        for f in &mut m2.faces {
            f.swap(1, 2);
        }
        return m2;
    }
    mesh
}

/// A pyramid (cone) with `n` sides: apex at height `h` over the centre of a regular polygon
/// of radius 1, the polygon's edges being the boundary.
fn cone(n: usize, h: f64) -> TriMesh {
    let mut vertices = vec![Vec3::new(0.0, 0.0, h)];
    for i in 0..n {
        let a = 2.0 * PI * i as f64 / n as f64;
        vertices.push(Vec3::new(a.cos(), a.sin(), 0.0));
    }
    let faces = (0..n)
        .map(|i| [0, 1 + i as u32, 1 + ((i + 1) % n) as u32])
        .collect();
    TriMesh { vertices, faces }
}

/// A wavy height field over `[0, 1]²` (for property tests).
fn wavy(n: usize) -> TriMesh {
    let mut m = square(n, 0.3);
    for v in &mut m.vertices {
        v.z = 0.15 * (5.0 * v.x).sin() * (4.0 * v.y + 0.5).cos();
    }
    m
}

// ---------------------------------------------------------------------------------------------
// Checks shared by the tests.

/// Distance from `p` to triangle `f`'s plane and whether it lies inside the triangle (with
/// relative tolerance).
fn on_face(topo: &MeshTopology, f: usize, p: Vec3, tol: f64) -> bool {
    let [a, b, c] = topo.face_points(f);
    let n = topo.face_normal(f);
    if (p - a).dot(n).abs() > tol {
        return false;
    }
    // Barycentric signs (areas) with a tolerance scaled to the triangle.
    let area = |x: Vec3, y: Vec3, z: Vec3| (y - x).cross(z - x).dot(n);
    let total = area(a, b, c);
    let l = a.dist(b).max(b.dist(c)).max(c.dist(a));
    [area(p, b, c), area(a, p, c), area(a, b, p)]
        .iter()
        .all(|&w| w >= -tol * l * total.abs() / (l * l))
}

/// The standard checks of a geodesic: consecutive points on their recorded faces, the last
/// point on the boundary, the angle with every crossed edge kept, no retraced segment.
fn check_path(topo: &MeshTopology, path: &GeodesicPath) {
    let pts = &path.polyline.points;
    let scale = topo.bounding_diagonal();
    let tol = 1e-9 * scale;
    assert!(pts.len() >= 2);
    assert_eq!(path.faces.len(), pts.len() - 1);
    for (i, &f) in path.faces.iter().enumerate() {
        assert!(on_face(topo, f, pts[i], tol), "point {i} off face {f}");
        assert!(
            on_face(topo, f, pts[i + 1], tol),
            "point {} off face {f}",
            i + 1
        );
    }
    // Start and end on boundary edges (or at a boundary vertex).
    let on_boundary = |p: Vec3| {
        (0..topo.edge_count()).any(|e| {
            topo.is_boundary_edge(e) && {
                let [a, b] = topo.edge(e);
                segment_closest_points(p, p, topo.position(a), topo.position(b)).2 <= tol
            }
        })
    };
    assert!(on_boundary(pts[0]), "start off the boundary");
    assert!(on_boundary(*pts.last().unwrap()), "end off the boundary");
    // Length as reported.
    let len: f64 = pts.windows(2).map(|w| w[0].dist(w[1])).sum();
    assert!((len - path.length).abs() <= 1e-9 * len.max(1.0));
    // Edge unfolding keeps the angle with each crossed edge.
    for i in 1..pts.len() - 1 {
        let (f, g) = (path.faces[i - 1], path.faces[i]);
        if f == g {
            continue;
        }
        let shared: Vec<usize> = topo.faces()[f]
            .iter()
            .copied()
            .filter(|v| topo.faces()[g].contains(v))
            .collect();
        if shared.len() != 2 || shared.iter().any(|&v| topo.position(v) == pts[i]) {
            continue; // a vertex passage
        }
        let e = (topo.position(shared[1]) - topo.position(shared[0])).normalized();
        let a_in = (pts[i] - pts[i - 1]).normalized().dot(e);
        let a_out = (pts[i + 1] - pts[i]).normalized().dot(e);
        let short = pts[i].dist(pts[i - 1]).min(pts[i].dist(pts[i + 1]));
        if short > 1e-6 * scale {
            assert!(
                (a_in - a_out).abs() < 1e-7,
                "angle changed at {i}: {a_in} vs {a_out}"
            );
        }
    }
    // Through an interior vertex, the angles on both sides of the path are equal.
    for i in 1..pts.len() - 1 {
        let f_in = path.faces[i - 1];
        let Some(&v) = topo.faces()[f_in]
            .iter()
            .find(|&&v| topo.position(v) == pts[i])
        else {
            continue;
        };
        let Some(fan) = super::walk::vertex_fan(topo, v, f_in).unwrap() else {
            continue;
        };
        let position = |face: usize, d: Vec3| {
            let t = fan
                .faces
                .iter()
                .position(|&g| g == face)
                .expect("face in the fan");
            let spoke = topo.position(fan.spokes[t]) - pts[i];
            fan.angles[..t].iter().sum::<f64>() + super::walk::angle_between(spoke, d)
        };
        let back = position(f_in, pts[i - 1] - pts[i]);
        let out = position(path.faces[i], pts[i + 1] - pts[i]);
        let total = fan.total();
        let one_side = (out - back).rem_euclid(total);
        assert!(
            (one_side - 0.5 * total).abs() < 1e-9,
            "unequal angles at vertex {v}: {one_side} of {total}"
        );
    }
    // No retraced segment: non-adjacent segments that touch are not parallel.
    let segs: Vec<(Vec3, Vec3)> = pts.windows(2).map(|w| (w[0], w[1])).collect();
    for i in 0..segs.len() {
        for j in i + 2..segs.len() {
            let (p0, p1) = segs[i];
            let (q0, q1) = segs[j];
            let d = segment_closest_points(p0, p1, q0, q1).2;
            if d <= tol {
                let c = (p1 - p0).normalized().cross((q1 - q0).normalized()).norm();
                assert!(c > 1e-6, "segments {i} and {j} overlap");
            }
        }
    }
}

/// Largest distance of `points` from the line through `a` along `d`.
fn line_deviation(points: &[Vec3], a: Vec3, d: Vec3) -> f64 {
    let d = d.normalized();
    points
        .iter()
        .map(|&p| (p - a - d * (p - a).dot(d)).norm())
        .fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------------------------
// Geodesics.

#[test]
fn flat_geodesic_is_a_straight_line_to_the_predicted_exit() {
    let mesh = square(12, 0.35);
    let topo = MeshTopology::new(&mesh).unwrap();
    let opts = TraceOptions::default();
    let mut count = 0;
    for (t, theta) in [
        (0.1, 1.0),
        (0.05, 0.4),
        (0.2, 2.5),
        (0.6, 1.2),
        (0.9, PI / 2.0),
    ] {
        let path = trace_geodesic(&topo, 0, t, theta, &opts).unwrap();
        check_path(&topo, &path);
        let pts = &path.polyline.points;
        let start = pts[0];
        // Start direction: θ from the loop direction, turned into the square.
        let bp = topo.point_on_loop(0, t).unwrap();
        let e = (topo.position(bp.to) - topo.position(bp.from)).normalized();
        let inward = Vec3::new(-e.y, e.x, 0.0); // faces are counter-clockwise
        let d = e * theta.cos() + inward * theta.sin();
        assert!(line_deviation(pts, start, d) < 1e-12, "not straight");
        // Predicted exit: first hit of the ray with the square's sides.
        let mut best = f64::INFINITY;
        for (k, lim) in [(0, 0.0), (0, 1.0), (1, 0.0), (1, 1.0)] {
            let (p, v) = if k == 0 {
                (start.x, d.x)
            } else {
                (start.y, d.y)
            };
            if v.abs() > 1e-12 {
                let s = (lim - p) / v;
                if s > 1e-9 {
                    best = best.min(s);
                }
            }
        }
        let exit = start + d * best;
        assert!(pts.last().unwrap().dist(exit) < 1e-12, "exit {exit:?}");
        assert!((path.length - best).abs() < 1e-12);
        count += 1;
    }
    assert_eq!(count, 5);
}

#[test]
fn flat_geodesic_through_vertices_stays_straight() {
    // 4 × 4 cells of 0.25: from (0.125, 0) towards (0.25, 0.25), the line passes through the
    // grid vertices (0.25, 0.25) and (0.5, 0.75).
    let mesh = square(4, 0.0);
    let topo = MeshTopology::new(&mesh).unwrap();
    let t = 0.125 / topo.boundary_loops()[0].open_length;
    let theta = 2f64.atan();
    let path = trace_geodesic(&topo, 0, t, theta, &TraceOptions::default()).unwrap();
    check_path(&topo, &path);
    assert_eq!(path.vertex_passes, 2);
    let pts = &path.polyline.points;
    assert!(line_deviation(pts, pts[0], Vec3::new(0.125, 0.25, 0.0)) < 1e-12);
    assert!(pts.last().unwrap().dist(Vec3::new(0.625, 1.0, 0.0)) < 1e-12);
}

#[test]
fn cylinder_geodesic_is_a_helix_of_the_predicted_pitch() {
    let (n, r, h) = (24, 1.0, 3.0);
    let mesh = cylinder(n, 30, r, h);
    let topo = MeshTopology::new(&mesh).unwrap();
    assert_eq!(topo.boundary_loops().len(), 2);
    assert_eq!(topo.boundary_loops()[0].vertices[0], 0);
    let theta = 0.3;
    let path = trace_geodesic(&topo, 0, 0.3, theta, &TraceOptions::default()).unwrap();
    check_path(&topo, &path);
    let pts = &path.polyline.points;
    // Unrolled, the prism is a plane: z = s tan θ with s the horizontal distance travelled.
    let mut s = 0.0;
    for w in pts.windows(2) {
        let dxy = Vec3::new(w[1].x - w[0].x, w[1].y - w[0].y, 0.0).norm();
        s += dxy;
        assert!(
            (w[1].z - s * theta.tan()).abs() < 1e-9,
            "z {} vs {}",
            w[1].z,
            s * theta.tan()
        );
    }
    assert!(
        (pts.last().unwrap().z - h).abs() < 1e-12,
        "must end on the top ring"
    );
    // Pitch: one turn (the prism's perimeter) rises by perimeter · tan θ.
    let perimeter = n as f64 * 2.0 * r * (PI / n as f64).sin();
    let turns = s / perimeter;
    assert!((turns - h / (perimeter * theta.tan())).abs() < 1e-9);
    assert!(turns > 1.5, "a real helix: {turns} turns");
    // The angle around the axis advances monotonically, in the loop's direction.
    let lp = &topo.boundary_loops()[0];
    let p0 = topo.position(lp.vertices[0]);
    let p1 = topo.position(lp.vertices[1]);
    let sense = p0.cross(p1).z.signum();
    for w in pts.windows(2) {
        assert!(w[0].cross(w[1]).z * sense >= -1e-12);
    }
}

#[test]
fn sphere_geodesic_through_the_pole_is_an_exact_great_circle() {
    // Mirror-symmetric cap: the path from a boundary edge's midpoint at θ = π/2 stays in the
    // symmetry plane, through quad centres (vertex passages) and the pole.
    let (n, m, r) = (16, 12, 2.0);
    let mesh = sphere_cap(n, m, r, 0.75 * PI);
    let topo = MeshTopology::new(&mesh).unwrap();
    let lp = &topo.boundary_loops()[0];
    let k = 5;
    let t = 0.5 * (lp.arc[k] + lp.arc[k + 1]) / lp.open_length;
    let path = trace_geodesic(&topo, 0, t, PI / 2.0, &TraceOptions::default()).unwrap();
    check_path(&topo, &path);
    let pts = &path.polyline.points;
    let normal = pts[0].cross(Vec3::new(0.0, 0.0, 1.0)).normalized();
    let dev = pts.iter().map(|p| p.dot(normal).abs()).fold(0.0, f64::max);
    assert!(dev < 1e-9 * r, "off the great circle plane by {dev}");
    assert!(
        path.vertex_passes >= 2 * (m - 1),
        "{} passages",
        path.vertex_passes
    );
    assert!(
        pts.iter().any(|p| p.dist(Vec3::new(0.0, 0.0, r)) < 1e-12),
        "misses the pole"
    );
    // It ends on the far side: the antipodal boundary edge midpoint.
    let end = *pts.last().unwrap();
    assert!((end.x + pts[0].x).abs() < 1e-9 && (end.y + pts[0].y).abs() < 1e-9);
}

#[test]
fn sphere_geodesic_approaches_a_great_circle_as_the_mesh_refines() {
    // A generic shot: the deviation from the great circle's plane shrinks with the mesh.
    let deviation = |n: usize, m: usize| {
        let mesh = sphere_cap(n, m, 1.0, 0.7 * PI);
        let topo = MeshTopology::new(&mesh).unwrap();
        let path = trace_geodesic(&topo, 0, 0.37, 1.1, &TraceOptions::default()).unwrap();
        check_path(&topo, &path);
        let pts = &path.polyline.points;
        // Plane through the centre containing the start point and the first step.
        let normal = pts[0].cross(pts[1] - pts[0]).normalized();
        pts.iter().map(|p| p.dot(normal).abs()).fold(0.0, f64::max)
    };
    let coarse = deviation(24, 12);
    let fine = deviation(96, 48);
    eprintln!("sphere great-circle deviation: coarse {coarse:.2e}, fine {fine:.2e}");
    assert!(fine < 0.02, "fine mesh deviation {fine}");
    assert!(fine < 0.5 * coarse, "no convergence: {coarse} → {fine}");
}

#[test]
fn cone_apex_is_crossed_with_equal_angles() {
    // Even cone: from an edge midpoint straight to the apex, out to the opposite midpoint.
    let mesh = cone(6, 0.8);
    let topo = MeshTopology::new(&mesh).unwrap();
    let lp = &topo.boundary_loops()[0];
    let t = 0.5 * (lp.arc[1] + lp.arc[2]) / lp.open_length;
    let path = trace_geodesic(&topo, 0, t, PI / 2.0, &TraceOptions::default()).unwrap();
    check_path(&topo, &path);
    assert_eq!(path.vertex_passes, 1);
    let pts = &path.polyline.points;
    assert_eq!(pts.len(), 3);
    assert!(pts[1].dist(Vec3::new(0.0, 0.0, 0.8)) < 1e-12);
    assert!((pts[2] + pts[0]).z.abs() < 1e-12 && (pts[2].x + pts[0].x).abs() < 1e-12);
    // Odd cone: the straightest continuation runs along the spoke to the opposite vertex.
    let mesh = cone(5, 0.5);
    let topo = MeshTopology::new(&mesh).unwrap();
    let lp = &topo.boundary_loops()[0];
    let t = 0.5 * (lp.arc[0] + lp.arc[1]) / lp.open_length;
    let path = trace_geodesic(&topo, 0, t, PI / 2.0, &TraceOptions::default()).unwrap();
    assert!(
        matches!(path.end, GeodesicEnd::BoundaryVertex(_)),
        "{:?}",
        path.end
    );
    let end = *path.polyline.points.last().unwrap();
    let start = path.polyline.points[0];
    // Opposite vertex: the start's direction reversed in the xy-plane.
    let dir = Vec3::new(-start.x, -start.y, 0.0).normalized();
    assert!((end - dir).norm() < 1e-9, "end {end:?}");
    // A generic cone: aim at the apex from several boundary points; the path goes through
    // it (equal angles, checked by `check_path`) and on to the far side.
    let mesh = cone(7, 0.6);
    let topo = MeshTopology::new(&mesh).unwrap();
    let apex = topo.position(0);
    for t in [0.13, 0.41, 0.77] {
        let bp = topo.point_on_loop(0, t).unwrap();
        let e = (topo.position(bp.to) - topo.position(bp.from)).normalized();
        let theta = super::walk::angle_between(e, apex - bp.point);
        let path = trace_geodesic(&topo, 0, t, theta, &TraceOptions::default()).unwrap();
        check_path(&topo, &path);
        assert_eq!(path.vertex_passes, 1);
        assert_eq!(path.polyline.points[1], apex);
        // The total angle is below 2π, so the path turns: it does not leave straight ahead.
        let pts = &path.polyline.points;
        let bend = super::walk::angle_between(pts[1] - pts[0], pts[2] - pts[1]);
        assert!(bend > 1e-3, "no bend at a cone apex");
    }
}

#[test]
fn geodesic_errors_are_clear() {
    let mesh = square(4, 0.0);
    let topo = MeshTopology::new(&mesh).unwrap();
    let o = TraceOptions::default();
    assert!(matches!(
        trace_geodesic(&topo, 0, 0.5, 0.0, &o),
        Err(TraceError::InvalidParameter { name: "theta", .. })
    ));
    assert!(trace_geodesic(&topo, 0, 0.5, PI, &o).is_err());
    assert!(trace_geodesic(&topo, 0, 0.5, f64::NAN, &o).is_err());
    assert!(matches!(
        trace_geodesic(&topo, 3, 0.5, 1.0, &o),
        Err(TraceError::LoopOutOfRange { index: 3, count: 1 })
    ));
    let bad = TraceOptions {
        length_cap_factor: -1.0,
        ..o
    };
    assert!(trace_geodesic(&topo, 0, 0.5, 1.0, &bad).is_err());
    // A tiny length cap stops the curve.
    let short = TraceOptions {
        length_cap_factor: 0.01,
        ..o
    };
    assert!(matches!(
        trace_geodesic(&topo, 0, 0.5, 1.0, &short),
        Err(TraceError::LengthCap { .. })
    ));
    // A geodesic spiralling up a long cylinder at a shallow angle hits the cap.
    let cyl = cylinder(16, 40, 1.0, 40.0);
    let topo = MeshTopology::new(&cyl).unwrap();
    assert!(matches!(
        trace_geodesic(&topo, 0, 0.2, 0.01, &o),
        Err(TraceError::LengthCap { .. })
    ));
    // A step cap.
    let steps = TraceOptions {
        max_steps: Some(3),
        ..o
    };
    assert!(matches!(
        trace_geodesic(&topo, 0, 0.2, 0.5, &steps),
        Err(TraceError::StepCap { steps: 3 })
    ));
}

#[test]
fn non_manifold_edge_on_the_path_is_an_error() {
    // Square 2 × 1 of two triangles each side, plus a fin on the middle edge.
    let vertices = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(2.0, 1.0, 0.0),
        Vec3::new(1.0, 0.5, 1.0),
    ];
    let faces = vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [1, 4, 6]];
    let mesh = TriMesh { vertices, faces };
    let topo = MeshTopology::new(&mesh).unwrap();
    let non_manifold = (0..topo.edge_count()).filter(|&e| topo.edge_faces(e).len() > 2);
    assert_eq!(non_manifold.count(), 1);
    // From the bottom-left edge towards the right: must cross edge 1–4.
    let r = trace_geodesic(&topo, 0, 0.02, 0.6, &TraceOptions::default());
    assert!(
        matches!(
            r,
            Err(TraceError::NonManifoldEdge {
                vertices: [1, 4],
                faces: 3
            })
        ),
        "{r:?}"
    );
}

#[test]
fn degenerate_face_on_the_path_is_an_error() {
    // A zero-area sliver (collinear vertices) in the middle of a strip.
    let vertices = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.5, 1.0, 0.0),
    ];
    // Faces: (0,1,4) and (0,4,2), (1,3,4) and the sliver (4,3,2) is collinear along y = 1.
    let faces = vec![[0, 1, 4], [0, 4, 2], [1, 3, 4], [2, 4, 3]];
    let mesh = TriMesh { vertices, faces };
    let topo = MeshTopology::new(&mesh).unwrap();
    assert!(topo.is_degenerate(3));
    let mut saw = false;
    for i in 1..20 {
        let r = trace_geodesic(
            &topo,
            0,
            i as f64 / 20.0,
            PI / 2.0,
            &TraceOptions::default(),
        );
        match r {
            Err(TraceError::DegenerateFace { face: 3 }) => saw = true,
            Ok(p) => check_path(&topo, &p),
            Err(e) => panic!("unexpected {e}"),
        }
    }
    assert!(saw);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    #[test]
    fn geodesics_on_a_wavy_mesh_stay_on_it(t in 0.0f64..=1.0, theta in 0.05f64..3.09) {
        let mesh = wavy(10);
        let topo = MeshTopology::new(&mesh).unwrap();
        match trace_geodesic(&topo, 0, t, theta, &TraceOptions::default()) {
            Ok(path) => check_path(&topo, &path),
            Err(e) => prop_assert!(matches!(e, TraceError::LengthCap { .. }), "{e}"),
        }
    }

    #[test]
    fn topology_never_panics_on_random_soups(
        faces in proptest::collection::vec(proptest::array::uniform3(0u32..8), 1..12),
        t in 0.0f64..=1.0,
        theta in 0.01f64..3.13,
    ) {
        let mut rng = SplitMix64::new(faces.len() as u64);
        let vertices: Vec<Vec3> = (0..7)
            .map(|_| Vec3::new(rng.next_f64(), rng.next_f64(), 0.3 * rng.next_f64()))
            .collect();
        let mesh = TriMesh { vertices, faces };
        if let Ok(topo) = MeshTopology::new(&mesh) {
            for k in 0..topo.boundary_loops().len() {
                let _ = trace_geodesic(&topo, k, t, theta, &TraceOptions::default());
            }
            let _ = smooth_field(&topo, &FieldOptions::default())
                .and_then(|f| trace_streamlines(&topo, &f, &StreamlineOptions::default()));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Fields and streamlines.

#[test]
fn boundary_aligned_cross_field_on_a_square_gives_a_straight_grid() {
    for jitter in [0.0, 0.3] {
        let mesh = square(10, jitter);
        let topo = MeshTopology::new(&mesh).unwrap();
        let field = smooth_field(&topo, &FieldOptions::default()).unwrap();
        assert!(field.singular_vertices().is_empty());
        let opts = StreamlineOptions {
            seeds: 16,
            ..StreamlineOptions::default()
        };
        let lines = trace_streamlines(&topo, &field, &opts).unwrap();
        assert_eq!(lines.started, 16);
        assert_eq!(lines.duplicates, 8, "each line is seeded at both ends");
        assert_eq!(lines.curves.len(), 8);
        let (mut vertical, mut horizontal) = (Vec::new(), Vec::new());
        for c in &lines.curves {
            let p = &c.points;
            let (a, b) = (p[0], *p.last().unwrap());
            let dx = p.iter().map(|q| (q.x - a.x).abs()).fold(0.0, f64::max);
            let dy = p.iter().map(|q| (q.y - a.y).abs()).fold(0.0, f64::max);
            if dx < 1e-6 {
                vertical.push(a.x);
                assert!((a.y - b.y).abs() > 1.0 - 1e-9, "spans the square");
            } else {
                assert!(dy < 1e-6, "neither vertical nor horizontal: {dx} {dy}");
                horizontal.push(a.y);
                assert!((a.x - b.x).abs() > 1.0 - 1e-9);
            }
        }
        vertical.sort_by(f64::total_cmp);
        horizontal.sort_by(f64::total_cmp);
        let expected = [0.125, 0.375, 0.625, 0.875];
        for (got, want) in vertical.iter().zip(expected) {
            assert!((got - want).abs() < 1e-9);
        }
        for (got, want) in horizontal.iter().zip(expected) {
            assert!((got - want).abs() < 1e-9);
        }
        assert_eq!((vertical.len(), horizontal.len()), (4, 4));
    }
}

#[test]
fn field_singularities_on_a_disk_sum_to_the_euler_characteristic() {
    let mesh = surfaces::builtin_surface("dome").unwrap();
    let topo = MeshTopology::new(&mesh).unwrap();
    for degree in [4u32, 6] {
        let field = smooth_field(
            &topo,
            &FieldOptions {
                degree,
                ..FieldOptions::default()
            },
        )
        .unwrap();
        let total: i64 = field.singular_vertices().iter().map(|s| s.1).sum();
        assert_eq!(total, degree as i64, "indices must sum to χ(disk) = 1");
        assert!(!field.singular_vertices().is_empty());
        // Boundary faces follow the boundary.
        let lines = trace_streamlines(
            &topo,
            &field,
            &StreamlineOptions {
                seeds: 30,
                ..StreamlineOptions::default()
            },
        )
        .unwrap();
        eprintln!(
            "dome degree {degree}: {} singular vertices, {} streamlines kept of {} (singular {}, \
             stalled {}, too long {}, duplicates {})",
            field.singular_vertices().len(),
            lines.curves.len(),
            lines.started,
            lines.singular,
            lines.stalled,
            lines.too_long,
            lines.duplicates
        );
        assert!(!lines.curves.is_empty());
        assert_eq!(
            lines.started,
            lines.curves.len()
                + lines.singular
                + lines.stalled
                + lines.too_long
                + lines.duplicates
                + lines.failed
        );
        let scale = topo.bounding_diagonal();
        for c in &lines.curves {
            let z0 = c.points[0].z;
            let z1 = c.points.last().unwrap().z;
            // The dome's boundary is its base circle at z ≈ 0.
            assert!(z0.abs() < 1e-6 * scale && z1.abs() < 1e-6 * scale);
        }
    }
}

#[test]
fn six_direction_field_streamlines_leave_at_sixty_degrees() {
    let mesh = square(10, 0.2);
    let topo = MeshTopology::new(&mesh).unwrap();
    let field = smooth_field(
        &topo,
        &FieldOptions {
            degree: 6,
            ..FieldOptions::default()
        },
    )
    .unwrap();
    let lines = trace_streamlines(
        &topo,
        &field,
        &StreamlineOptions {
            seeds: 12,
            ..StreamlineOptions::default()
        },
    )
    .unwrap();
    for r in &lines.records {
        let deg = r.theta.to_degrees();
        assert!(
            (deg - 60.0).abs() < 1e-6 || (deg - 120.0).abs() < 1e-6,
            "{deg}"
        );
    }
    assert!(!lines.records.is_empty());
}

#[test]
fn field_errors_are_clear() {
    let mesh = square(3, 0.0);
    let topo = MeshTopology::new(&mesh).unwrap();
    assert!(
        smooth_field(
            &topo,
            &FieldOptions {
                degree: 0,
                ..FieldOptions::default()
            }
        )
        .is_err()
    );
    assert!(
        smooth_field(
            &topo,
            &FieldOptions {
                degree: 13,
                ..FieldOptions::default()
            }
        )
        .is_err()
    );
    let f = smooth_field(&topo, &FieldOptions::default()).unwrap();
    let zero = StreamlineOptions {
        seeds: 0,
        ..StreamlineOptions::default()
    };
    assert!(trace_streamlines(&topo, &f, &zero).is_err());
    // A field of another mesh.
    let other = MeshTopology::new(&square(4, 0.0)).unwrap();
    assert!(matches!(
        trace_streamlines(&other, &f, &StreamlineOptions::default()),
        Err(TraceError::InvalidMesh(_))
    ));
    // A closed surface has no boundary to align with.
    let tet = TriMesh {
        vertices: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ],
        faces: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
    };
    let topo = MeshTopology::new(&tet).unwrap();
    assert_eq!(
        smooth_field(&topo, &FieldOptions::default()).unwrap_err(),
        TraceError::NoBoundary
    );
}

#[test]
fn field_is_independent_of_face_orientation() {
    // Flip half of the faces: the tracer and the field orient internally.
    let mut mesh = square(8, 0.25);
    for (i, f) in mesh.faces.iter_mut().enumerate() {
        if i % 3 == 0 {
            f.swap(1, 2);
        }
    }
    let topo = MeshTopology::new(&mesh).unwrap();
    let field = smooth_field(&topo, &FieldOptions::default()).unwrap();
    assert!(field.singular_vertices().is_empty());
    let lines = trace_streamlines(
        &topo,
        &field,
        &StreamlineOptions {
            seeds: 8,
            ..StreamlineOptions::default()
        },
    )
    .unwrap();
    assert_eq!(lines.curves.len(), 4);
    for c in &lines.curves {
        let a = c.points[0];
        let straight = c
            .points
            .iter()
            .all(|q| (q.x - a.x).abs() < 1e-6 || (q.y - a.y).abs() < 1e-6);
        assert!(straight);
    }
}

// ---------------------------------------------------------------------------------------------
// Generators.

#[test]
fn generators_are_deterministic_and_follow_the_draw_order() {
    let mesh = surfaces::builtin_surface("wave").unwrap();
    let g = Generator::Random { count: 5, seed: 3 };
    let a = generate(&mesh, &g).unwrap();
    let b = generate(&mesh, &g).unwrap();
    assert_eq!(a, b);
    // The records carry the draws: t then θ per curve, from srand(3).
    let mut rng = crate::rng::MsvcRand::new(3);
    for r in &a.records {
        let t = rng.uniform(0.0, 1.0);
        let th = rng.uniform(PI / 6.0, 5.0 * PI / 6.0);
        assert_eq!((r.t, r.theta), (t, th));
    }
    // Hill: one draw per curve, fixed t.
    let h = generate(&mesh, &Generator::Hill { count: 4, seed: 2 }).unwrap();
    let mut rng = crate::rng::MsvcRand::new(2);
    for (i, r) in h.records.iter().enumerate() {
        assert_eq!(r.t, i as f64 / 4.0 + 1.0 / 8.0);
        assert_eq!(r.theta, rng.uniform(PI / 4.0, 3.0 * PI / 4.0));
        assert_eq!(r.loop_index, 0);
    }
    // Stadium needs two loops.
    assert!(matches!(
        generate(&mesh, &Generator::Stadium { count: 4, seed: 4 }),
        Err(TraceError::LoopOutOfRange { .. })
    ));
    let stadium = surfaces::builtin_surface("stadium").unwrap();
    let s = generate(&stadium, &Generator::Stadium { count: 6, seed: 4 }).unwrap();
    let loops: Vec<usize> = s.records.iter().map(|r| r.loop_index).collect();
    assert_eq!(loops, vec![0, 1, 0, 1, 0, 1]);
    // Tent on the built-in tent: the whole border is on the ground, nothing is rejected.
    let tent = surfaces::builtin_surface("tent").unwrap();
    let g = Generator::Tent {
        count: 5,
        seed: 2,
        ground_tolerance: 1e-6,
        max_attempts: 100,
    };
    let t = generate(&tent, &g).unwrap();
    assert_eq!((t.curves.len(), t.rejected), (5, 0));
    // A tent on a surface whose border is not on the ground runs out of attempts.
    let g = Generator::Tent {
        count: 2,
        seed: 2,
        ground_tolerance: 1e-6,
        max_attempts: 7,
    };
    assert!(matches!(
        generate(&surfaces::builtin_surface("saddle").unwrap(), &g),
        Err(TraceError::GeneratorExhausted {
            accepted: 0,
            wanted: 2,
            attempts: 7
        })
    ));
    // Streamlines as a generator.
    let sl = generate(
        &tent,
        &Generator::Streamlines {
            degree: 4,
            seeds: 20,
        },
    )
    .unwrap();
    assert!(!sl.curves.is_empty());
    assert_eq!(sl.curves.len(), sl.records.len());
}

#[test]
fn builtin_surfaces_carry_random_geodesics() {
    for name in SURFACE_NAMES {
        let mesh = builtin_surface(name).unwrap();
        let g = generate(&mesh, &Generator::Random { count: 12, seed: 2 }).unwrap();
        let topo = MeshTopology::new(&mesh).unwrap();
        assert_eq!(g.curves.len() + g.failed, 12, "{name}");
        assert_eq!(g.failed, 0, "{name}: {:?}", g.failures);
        for c in &g.curves {
            assert!(c.points.len() >= 2);
            assert!(c.length() <= 20.0 * topo.bounding_diagonal());
        }
    }
}

/// The paper's meshes shipped in this crate (`data/paper/meshes`), or `$CURVENET_DATA/meshes`.
fn reference_meshes() -> Option<PathBuf> {
    if let Some(d) = std::env::var_os("CURVENET_DATA") {
        let p = PathBuf::from(d).join("meshes");
        if p.is_dir() {
            return Some(p);
        }
    }
    Some(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/paper/meshes"))
}

#[test]
fn paper_generators_on_the_reference_meshes() {
    let Some(dir) = reference_meshes() else {
        eprintln!("SKIPPED: reference meshes not found (set CURVENET_DATA)");
        return;
    };
    let cases = [
        ("hill", "hill.obj", 70),
        ("stadium", "stadium.obj", 100),
        ("bunny", "bunny_modified.obj", 75),
        ("tent", "tent.obj", 66),
    ];
    for (name, file, count) in cases {
        let mesh = read_mesh(&dir.join(file)).unwrap().mesh;
        let topo = MeshTopology::new(&mesh).unwrap();
        let generator = Generator::paper(name).unwrap();
        let out = generate(&mesh, &generator).unwrap();
        let total: f64 = out.curves.iter().map(|c| c.length()).sum();
        let points: usize = out.curves.iter().map(|c| c.points.len()).sum();
        let longest = out.curves.iter().map(|c| c.length()).fold(0.0, f64::max);
        eprintln!(
            "{name}: {} curves ({} attempts, {} rejected, {} failed), total length {total:.3}, \
             longest {longest:.3}, {points} points, mesh diagonal {:.3}, loops {:?}",
            out.curves.len(),
            out.attempts,
            out.rejected,
            out.failed,
            topo.bounding_diagonal(),
            topo.boundary_loops()
                .iter()
                .map(|l| l.vertices.len())
                .collect::<Vec<_>>(),
        );
        for f in &out.failures {
            eprintln!("  {name} failure: {f}");
        }
        assert_eq!(out.curves.len(), count, "{name}");
        assert_eq!(out.failed, 0, "{name}: {:?}", out.failures);
        let tol = 1e-9 * topo.bounding_diagonal();
        let on_boundary = |p: Vec3| {
            (0..topo.edge_count()).any(|e| {
                topo.is_boundary_edge(e) && {
                    let [a, b] = topo.edge(e);
                    segment_closest_points(p, p, topo.position(a), topo.position(b)).2 <= tol
                }
            })
        };
        for (i, c) in out.curves.iter().enumerate() {
            assert!(
                on_boundary(c.points[0]),
                "{name} curve {i} starts off the boundary"
            );
            assert!(
                on_boundary(*c.points.last().unwrap()),
                "{name} curve {i} ends off it"
            );
        }
        if name == "tent" {
            for c in &out.curves {
                assert!(c.points[0].z.abs() <= 5e-3 && c.points.last().unwrap().z.abs() <= 5e-3);
            }
        }
        if name == "stadium" {
            // Loop 0 is the inner ring (the shorter one).
            let l = topo.boundary_loops();
            assert_eq!(l.len(), 2);
            assert!(l[0].length < l[1].length, "loop 0 should be the inner ring");
        }
    }
}

#[test]
fn generators_and_options_round_trip_through_json() {
    let g = Generator::paper("tent").unwrap();
    let text = serde_json::to_string(&g).unwrap();
    assert!(
        text.starts_with(r#"{"kind":"tent","count":66,"seed":2"#),
        "{text}"
    );
    assert_eq!(serde_json::from_str::<Generator>(&text).unwrap(), g);
    let o: TraceOptions = serde_json::from_str(r#"{"length_cap_factor": 5.0}"#).unwrap();
    assert_eq!(o.length_cap_factor, 5.0);
    assert_eq!(o.vertex_snap, TraceOptions::default().vertex_snap);
    assert!(serde_json::from_str::<TraceOptions>(r#"{"cap": 5.0}"#).is_err());
    assert!(Generator::paper("roof").is_none());
}

// ---------------------------------------------------------------------------------------------
// Geodesics from a point of the surface.

#[test]
fn geodesic_from_a_point_is_a_straight_line_to_the_side_it_heads_for() {
    let mesh = square(10, 0.3);
    let topo = MeshTopology::new(&mesh).unwrap();
    let opts = TraceOptions::default();
    for (start, d) in [
        (Vec3::new(0.31, 0.47, 0.0), Vec3::new(1.0, 0.2, 0.0)),
        (Vec3::new(0.5, 0.5, 0.0), Vec3::new(-0.3, -1.0, 0.0)),
        // Above the surface and heading partly out of its plane: the closest point, the
        // direction projected.
        (Vec3::new(0.2, 0.8, 0.05), Vec3::new(1.0, -1.0, 0.5)),
        // On a grid line.
        (Vec3::new(0.4, 0.3, 0.0), Vec3::new(0.0, 1.0, 0.0)),
    ] {
        let path = trace_geodesic_from(&topo, start, d, &opts).unwrap();
        let on = Vec3::new(start.x, start.y, 0.0);
        assert!((path.distance - start.z).abs() < 1e-12);
        let flat = Vec3::new(d.x, d.y, 0.0).normalized();
        let pts = &path.polyline.points;
        assert!(pts[0].dist(on) < 1e-12);
        assert!(line_deviation(pts, on, flat) < 1e-12, "not straight");
        let exit = *pts.last().unwrap();
        let side = |v: f64| v.abs() < 1e-12 || (v - 1.0).abs() < 1e-12;
        assert!(
            side(exit.x) || side(exit.y),
            "ends on the boundary: {exit:?}"
        );
        assert!((exit - on).dot(flat) > 0.0, "heads the way it was sent");
        assert!((path.length - exit.dist(on)).abs() < 1e-12);
    }
}

#[test]
fn geodesic_from_a_point_refuses_what_cannot_be_traced() {
    let mesh = square(6, 0.0);
    let topo = MeshTopology::new(&mesh).unwrap();
    let opts = TraceOptions::default();
    let p = Vec3::new(0.5, 0.5, 0.0);
    for d in [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(f64::NAN, 0.0, 0.0),
    ] {
        let e = trace_geodesic_from(&topo, p, d, &opts).unwrap_err();
        assert!(e.to_string().contains("direction"), "{e}");
    }
    // From the boundary, heading out: it leaves at once.
    let e = trace_geodesic_from(
        &topo,
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(-1.0, 0.1, 0.0),
        &opts,
    )
    .unwrap_err();
    assert!(e.to_string().contains("leaves the surface at once"), "{e}");
    // From the boundary, heading in: across the square.
    let path = trace_geodesic_from(
        &topo,
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        &opts,
    )
    .unwrap();
    assert!((path.length - 1.0).abs() < 1e-12);
}

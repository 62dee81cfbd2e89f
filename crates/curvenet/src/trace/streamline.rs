//! Streamlines of a direction field, seeded along the boundary (paper §5).
//!
//! Seeds are spread evenly by arc length over all boundary loops together (loops taken closed,
//! in loop order): seed `i` of `n` sits at arc length `(i + ½) L / n` with `L` the total
//! boundary length. From each seed, one streamline leaves along every field direction that
//! enters the surface at more than [`StreamlineOptions::min_inward_angle`] from the boundary
//! (one for a boundary-aligned cross field, two for a 6-direction field).
//!
//! The field is constant on each face, so a streamline is integrated exactly: straight across
//! the face along the field direction closest to the direction it arrived with (unfolded
//! across the edge it crossed), then on to the next face. Through a vertex it continues along
//! the straightest direction and then the closest field direction in the face that contains
//! it. It stops on reaching the boundary.
//!
//! A streamline is dropped when it enters a singular face ([`DirectionField::is_singular`]),
//! when the field turns back across the edge it just crossed, when it exceeds the length cap
//! (it spirals or circles) and, with [`StreamlineOptions::deduplicate`], when it retraces an
//! accepted streamline (the same line traced from its other end: both ends and its middle
//! within a quarter of the seed spacing of that streamline).

use super::TraceError;
use super::field::DirectionField;
use super::geodesic::TraceOptions;
use super::topology::MeshTopology;
use super::walk::{
    Entry, Exit, Walker, angle_between, in_plane, inward_normal, straightest, vertex_fan,
};
use crate::geom::{Vec3, segment_closest_points};
use crate::io::{Origin, Polyline};
use serde::{Deserialize, Serialize};

/// Parameters of [`trace_streamlines`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StreamlineOptions {
    /// Number of seeds along the boundary.
    pub seeds: usize,
    /// A field direction leaves a seed only if it makes at least this angle (radians) with
    /// the boundary edge. Default 15°.
    pub min_inward_angle: f64,
    /// Drop streamlines that retrace an accepted one from its other end. Default true.
    pub deduplicate: bool,
    /// Length cap, step cap and vertex snapping, as for geodesics.
    pub trace: TraceOptions,
}

impl Default for StreamlineOptions {
    fn default() -> Self {
        StreamlineOptions {
            seeds: 40,
            min_inward_angle: 15f64.to_radians(),
            deduplicate: true,
            trace: TraceOptions::default(),
        }
    }
}

/// Where an accepted streamline started.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StreamlineRecord {
    /// Seed number (`0..seeds`).
    pub seed: usize,
    /// Boundary loop of the seed.
    pub loop_index: usize,
    /// Arc-length fraction of the seed along its loop, over the loop's *full* length (closing
    /// edge included; unlike the geodesics' `t`).
    pub loop_fraction: f64,
    /// Angle (radians, in `(0, π)`) between the loop direction and the streamline's first
    /// direction.
    pub theta: f64,
    /// The seed point.
    pub point: Vec3,
}

/// The result of [`trace_streamlines`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Streamlines {
    /// Accepted streamlines, in seed order.
    pub curves: Vec<Polyline>,
    /// Where each accepted streamline started.
    pub records: Vec<StreamlineRecord>,
    /// Streamlines started (seeds × inward directions).
    pub started: usize,
    /// Dropped at a field singularity.
    pub singular: usize,
    /// Dropped because the field turned back.
    pub stalled: usize,
    /// Dropped at the length or step cap.
    pub too_long: usize,
    /// Dropped as retracing an accepted streamline.
    pub duplicates: usize,
    /// Dropped for another reason (a non-manifold or degenerate element on the path).
    pub failed: usize,
}

/// Traces the streamlines of `field` (computed on `topo`) from seeds spread along the
/// boundary.
///
/// # Errors
///
/// [`TraceError::NoBoundary`] without boundary, [`TraceError::InvalidParameter`] for zero
/// seeds or invalid options, [`TraceError::InvalidMesh`] when the field was computed on
/// another mesh. Individual streamlines never fail the call: they are dropped and counted.
pub fn trace_streamlines(
    topo: &MeshTopology,
    field: &DirectionField,
    options: &StreamlineOptions,
) -> Result<Streamlines, TraceError> {
    options.trace.validate()?;
    if options.seeds == 0 {
        return Err(TraceError::InvalidParameter {
            name: "seeds",
            value: 0.0,
            expected: "at least one seed",
        });
    }
    if !(options.min_inward_angle >= 0.0 && options.min_inward_angle < std::f64::consts::FRAC_PI_2)
    {
        return Err(TraceError::InvalidParameter {
            name: "min_inward_angle",
            value: options.min_inward_angle,
            expected: "an angle in [0, π/2)",
        });
    }
    if field.face_count() != topo.face_count() {
        return Err(TraceError::InvalidMesh(format!(
            "the field has {} faces, the mesh {}",
            field.face_count(),
            topo.face_count()
        )));
    }
    let loops = topo.boundary_loops();
    let total: f64 = loops.iter().map(|l| l.length).sum();
    if loops.is_empty() || !(total > 0.0) {
        return Err(TraceError::NoBoundary);
    }
    let spacing = total / options.seeds as f64;
    let mut out = Streamlines::default();
    let min_sin = options.min_inward_angle.sin();
    for seed in 0..options.seeds {
        let Some(sp) = seed_point(topo, (seed as f64 + 0.5) * spacing) else {
            continue;
        };
        let face = topo.edge_faces(sp.edge)[0];
        let Some(opposite) = topo.opposite_vertex(face, sp.edge) else {
            continue;
        };
        let inward = inward_normal(topo, sp.from, sp.to, opposite);
        let along = (topo.position(sp.to) - topo.position(sp.from)).normalized();
        for d in field.directions(face) {
            if d.dot(inward) < min_sin.max(1e-9) {
                continue;
            }
            out.started += 1;
            match trace_one(topo, field, face, sp.point, d, sp.edge, &options.trace) {
                Ok(points) => {
                    let curve = Polyline {
                        points,
                        closed: false,
                        origin: Origin::new("<streamline>", 0),
                        label: Some(format!("streamline {}", out.curves.len())),
                    };
                    if options.deduplicate && retraces(&curve, &out.curves, 0.25 * spacing) {
                        out.duplicates += 1;
                        continue;
                    }
                    out.curves.push(curve);
                    out.records.push(StreamlineRecord {
                        seed,
                        loop_index: sp.loop_index,
                        loop_fraction: sp.fraction,
                        theta: angle_between(along, d),
                        point: sp.point,
                    });
                }
                Err(TraceError::Singularity { .. }) => out.singular += 1,
                Err(TraceError::Stalled { .. }) => out.stalled += 1,
                Err(TraceError::LengthCap { .. } | TraceError::StepCap { .. }) => out.too_long += 1,
                Err(_) => out.failed += 1,
            }
        }
    }
    Ok(out)
}

/// A seed on the boundary.
struct SeedPoint {
    loop_index: usize,
    fraction: f64,
    edge: usize,
    from: usize,
    to: usize,
    point: Vec3,
}

/// The point at arc length `s` along all loops together (each taken closed).
fn seed_point(topo: &MeshTopology, mut s: f64) -> Option<SeedPoint> {
    let loops = topo.boundary_loops();
    for (li, lp) in loops.iter().enumerate() {
        let n = lp.vertices.len();
        let edges = lp.edge_count();
        if s > lp.length && li + 1 < loops.len() {
            s -= lp.length;
            continue;
        }
        let fraction = if lp.length > 0.0 { s / lp.length } else { 0.0 };
        let mut cur = 0.0;
        for i in 0..edges {
            let (a, b) = (lp.vertices[i], lp.vertices[(i + 1) % n]);
            let (pa, pb) = (topo.position(a), topo.position(b));
            let len = pa.dist(pb);
            if s <= cur + len || i + 1 == edges {
                let u = if len > 0.0 {
                    ((s - cur) / len).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                return Some(SeedPoint {
                    loop_index: li,
                    fraction,
                    edge: topo.find_edge(a, b)?,
                    from: a,
                    to: b,
                    point: pa + (pb - pa) * u,
                });
            }
            cur += len;
        }
        return None;
    }
    None
}

/// Integrates one streamline from `pos` on boundary edge `edge` of `face` along `dir`.
fn trace_one(
    topo: &MeshTopology,
    field: &DirectionField,
    face: usize,
    pos: Vec3,
    dir: Vec3,
    edge: usize,
    options: &TraceOptions,
) -> Result<Vec<Vec3>, TraceError> {
    let max_steps = options.step_cap(topo);
    let mut w = Walker::new(face, pos, dir, edge, options.length_cap(topo));
    for _ in 0..max_steps {
        let face = w.face;
        if field.is_singular(face) {
            return Err(TraceError::Singularity { face });
        }
        if topo.is_degenerate(face) {
            return Err(TraceError::DegenerateFace { face });
        }
        if let Entry::Edge(e) = w.entry {
            let fd = field
                .best_direction(face, in_plane(topo, face, w.dir))
                .ok_or(TraceError::Singularity { face })?;
            let [a, b] = topo.edge(e);
            let c = topo
                .opposite_vertex(face, e)
                .ok_or(TraceError::Stalled { face })?;
            if fd.dot(inward_normal(topo, a, b, c)) <= 1e-12 {
                return Err(TraceError::Stalled { face });
            }
            w.dir = fd;
        }
        match w.exit(topo, options.vertex_snap) {
            Exit::Edge { edge, point } => {
                w.advance(point)?;
                match topo.across(edge, face)? {
                    None => return finish(w.points),
                    Some(next) => w.cross(topo, edge, next),
                }
            }
            Exit::Vertex(v) => {
                w.advance(topo.position(v))?;
                let Some(fan) = vertex_fan(topo, v, face)? else {
                    return finish(w.points);
                };
                let (k, straight) = straightest(topo, v, &fan, w.dir);
                let m = fan.faces.len();
                // Try the face holding the straight continuation first, then its neighbours.
                let mut chosen = None;
                for off in 0..m {
                    let t = if off % 2 == 0 {
                        (k + off / 2) % m
                    } else {
                        (k + m - off.div_ceil(2)) % m
                    };
                    let g = fan.faces[t];
                    if field.is_singular(g) {
                        continue;
                    }
                    let Some(fd) = field.best_direction(g, in_plane(topo, g, straight)) else {
                        continue;
                    };
                    let pv = topo.position(v);
                    let e0 = topo.position(fan.spokes[t]) - pv;
                    let e1 = topo.position(fan.spokes[t + 1]) - pv;
                    let inside = (angle_between(e0, fd) + angle_between(e1, fd) - fan.angles[t])
                        .abs()
                        <= 1e-9;
                    if inside && fd.dot(straight) > 0.0 {
                        chosen = Some((g, fd));
                        break;
                    }
                }
                let (g, fd) = chosen.ok_or(TraceError::Stalled { face })?;
                w.turn(v, g, fd);
            }
        }
    }
    Err(TraceError::StepCap { steps: max_steps })
}

/// A finished streamline's points (at least two distinct points).
fn finish(points: Vec<Vec3>) -> Result<Vec<Vec3>, TraceError> {
    if points.len() < 2 {
        Err(TraceError::Stalled { face: 0 })
    } else {
        Ok(points)
    }
}

/// Distance from `p` to polyline `curve`.
fn distance_to(p: Vec3, curve: &Polyline) -> f64 {
    curve
        .points
        .windows(2)
        .map(|w| segment_closest_points(p, p, w[0], w[1]).2)
        .fold(f64::INFINITY, f64::min)
}

/// The point at half the arc length of `points`.
fn midpoint(points: &[Vec3]) -> Vec3 {
    let total: f64 = points.windows(2).map(|w| w[0].dist(w[1])).sum();
    let mut acc = 0.0;
    for w in points.windows(2) {
        let l = w[0].dist(w[1]);
        if acc + l >= 0.5 * total && l > 0.0 {
            return w[0].lerp(w[1], (0.5 * total - acc) / l);
        }
        acc += l;
    }
    points.first().copied().unwrap_or(Vec3::ZERO)
}

/// True when `curve` retraces one of `accepted`: its ends and middle lie within `tol` of it,
/// with its start near that curve's end or its start (the same line from either end).
fn retraces(curve: &Polyline, accepted: &[Polyline], tol: f64) -> bool {
    let (Some(&s), Some(&e)) = (curve.points.first(), curve.points.last()) else {
        return false;
    };
    let mid = midpoint(&curve.points);
    accepted.iter().any(|a| {
        let (Some(&sa), Some(&ea)) = (a.points.first(), a.points.last()) else {
            return false;
        };
        let ends =
            (s.dist(ea) <= tol && e.dist(sa) <= tol) || (s.dist(sa) <= tol && e.dist(ea) <= tol);
        ends && distance_to(mid, a) <= tol
    })
}

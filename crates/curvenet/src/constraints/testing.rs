//! Small networks for the constraint tests: pavilions with a known symmetry.

use crate::geom::Vec3;
use crate::io::{Origin, Polyline, TriMesh};
use crate::network::{BuildParams, Network, build_network};

/// A polyline made in a test.
pub fn polyline(points: Vec<Vec3>, closed: bool) -> Polyline {
    Polyline {
        points,
        closed,
        origin: Origin::new("<test>", 0),
        label: None,
    }
}

/// A pavilion of radius `r` and height `h`: curve 0 a ring at half height, curves `1..=k` half
/// arches from the ground (at angles `2πi/k + φ`) to the apex, and, with `second`, curves
/// `k+1..=2k` shorter arches between them (angles offset by `π/k`) that cross the ring and stop
/// below the apex. Rotations of order `k` about the z axis (through the origin) map it onto
/// itself, and so do mirrors in vertical planes through an arch.
pub fn pavilion(k: usize, second: bool, phi: f64) -> Vec<Polyline> {
    let (r, h) = (1000.0, 600.0);
    let samples = 60;
    let arch = |angle: f64, reach: f64| {
        let (c, s) = (angle.cos(), angle.sin());
        let points = (0..=samples)
            .map(|i| {
                let t = reach * i as f64 / samples as f64;
                let rho = r * (1.0 - t);
                Vec3::new(
                    rho * c,
                    rho * s,
                    h * (std::f64::consts::FRAC_PI_2 * t).sin(),
                )
            })
            .collect();
        polyline(points, false)
    };
    // The arches cross z = h/2 at t = 1/3, radius 2r/3.
    let ring = (0..90)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 90.0;
            Vec3::new(2.0 * r / 3.0 * t.cos(), 2.0 * r / 3.0 * t.sin(), 0.5 * h)
        })
        .collect();
    let mut curves = vec![polyline(ring, true)];
    let step = std::f64::consts::TAU / k as f64;
    for i in 0..k {
        curves.push(arch(phi + step * i as f64, 1.0));
    }
    if second {
        for i in 0..k {
            curves.push(arch(phi + step * (i as f64 + 0.5), 0.7));
        }
    }
    curves
}

/// The network of `curves` at `h = 50`.
pub fn network(curves: &[Polyline]) -> Network {
    build_network(
        curves,
        &BuildParams {
            edge_length: 50.0,
            ..BuildParams::default()
        },
    )
    .expect("the test network builds")
    .0
}

/// `curves` moved rigidly: rotated by `angle` about the unit `axis` through the origin, then
/// shifted by `shift`; mirrored first in the plane `x = 0` when `mirror`.
pub fn moved(
    curves: &[Polyline],
    axis: Vec3,
    angle: f64,
    shift: Vec3,
    mirror: bool,
) -> Vec<Polyline> {
    let axis = axis.normalized();
    let (c, s) = (angle.cos(), angle.sin());
    let map = |p: Vec3| {
        let p = if mirror { Vec3::new(-p.x, p.y, p.z) } else { p };
        p * c + axis.cross(p) * s + axis * (axis.dot(p) * (1.0 - c)) + shift
    };
    curves
        .iter()
        .map(|pl| polyline(pl.points.iter().map(|&p| map(p)).collect(), pl.closed))
        .collect()
}

/// A flat square mesh `[-a, a]²` at `z` in `m × m` cells.
pub fn square_mesh(a: f64, z: f64, m: usize) -> TriMesh {
    let mut vertices = Vec::new();
    for i in 0..=m {
        for j in 0..=m {
            let x = -a + 2.0 * a * i as f64 / m as f64;
            let y = -a + 2.0 * a * j as f64 / m as f64;
            vertices.push(Vec3::new(x, y, z));
        }
    }
    let id = |i: usize, j: usize| (i * (m + 1) + j) as u32;
    let mut faces = Vec::new();
    for i in 0..m {
        for j in 0..m {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    TriMesh { vertices, faces }
}

/// A grid of straight curves over `[-a, a]²` at height 0: `m` along x (ids `0..m`) at
/// `y = -a + (i + ½)·2a/m`, then `m` along y (ids `m..2m`), all crossing.
pub fn grid(a: f64, m: usize) -> Vec<Polyline> {
    let mut curves = Vec::new();
    let line = |p: Vec3, q: Vec3| {
        polyline(
            (0..=40).map(|i| p.lerp(q, i as f64 / 40.0)).collect(),
            false,
        )
    };
    for i in 0..m {
        let y = -a + (i as f64 + 0.5) * 2.0 * a / m as f64;
        curves.push(line(Vec3::new(-a, y, 0.0), Vec3::new(a, y, 0.0)));
    }
    for i in 0..m {
        let x = -a + (i as f64 + 0.5) * 2.0 * a / m as f64;
        curves.push(line(Vec3::new(x, -a, 0.0), Vec3::new(x, a, 0.0)));
    }
    curves
}

//! Scenes made in code with known geometry, for tests and examples.
//!
//! [`dome_arcs`]: a spherical dome and arcs over it in several directions (vertical plane
//! sections of the sphere), crossing each other like a gridshell. Scene units match the
//! paper's examples (a few thousand across) so the default material is sensible. (Curves
//! traced on surfaces live in [`crate::trace`]; `curvenet demo` uses those.)

use crate::geom::Vec3;
use crate::io::{Origin, Polyline, TriMesh};

/// A built-in scene: surface, curves and the edge length that suits them.
#[derive(Clone, Debug)]
pub struct BuiltinScene {
    /// Scene name.
    pub name: &'static str,
    /// The surface.
    pub mesh: TriMesh,
    /// The curves, in id order.
    pub curves: Vec<Polyline>,
    /// Suggested edge length `h`.
    pub edge_length: f64,
}

/// A spherical cap of base radius `base` and height `height` (z up, base on z = 0), with
/// `families` directions of arcs, `per_family` arcs each, evenly spread over the base.
pub fn dome_arcs(base: f64, height: f64, families: usize, per_family: usize) -> BuiltinScene {
    // Sphere through the base circle and the apex: R = (b² + h²) / 2h, centre at z = h − R.
    let r = (base * base + height * height) / (2.0 * height);
    let cz = height - r;
    let surface = |x: f64, y: f64| cz + (r * r - x * x - y * y).max(0.0).sqrt();

    // Mesh: polar grid over the base disc.
    let (rings, sectors) = (24usize, 72usize);
    let mut vertices = vec![Vec3::new(0.0, 0.0, surface(0.0, 0.0))];
    for i in 1..=rings {
        let rho = base * i as f64 / rings as f64;
        for j in 0..sectors {
            let t = std::f64::consts::TAU * j as f64 / sectors as f64;
            let (x, y) = (rho * t.cos(), rho * t.sin());
            vertices.push(Vec3::new(x, y, surface(x, y)));
        }
    }
    let idx = |i: usize, j: usize| (1 + (i - 1) * sectors + j % sectors) as u32;
    let mut faces = Vec::new();
    for j in 0..sectors {
        faces.push([0, idx(1, j), idx(1, j + 1)]);
    }
    for i in 1..rings {
        for j in 0..sectors {
            let (a, b, c, d) = (idx(i, j), idx(i, j + 1), idx(i + 1, j), idx(i + 1, j + 1));
            faces.push([a, c, d]);
            faces.push([a, d, b]);
        }
    }

    // Arcs: sections of the sphere by vertical planes n·(x, y) = d.
    let mut curves = Vec::new();
    // Fine sampling: chords of a polyline sag below the sphere by s²/8R; at this density the
    // sag stays below the crossing tolerance (1e-3 of a segment), so every pair of arcs meets.
    let samples = 600;
    for f in 0..families {
        let theta = std::f64::consts::PI * f as f64 / families as f64 + 0.1;
        let (n, t) = (
            Vec3::new(theta.cos(), theta.sin(), 0.0),
            Vec3::new(-theta.sin(), theta.cos(), 0.0),
        );
        for k in 0..per_family {
            let d = base * 0.75 * (2.0 * (k as f64 + 0.5) / per_family as f64 - 1.0);
            let half = (base * base - d * d).sqrt();
            let points: Vec<Vec3> = (0..=samples)
                .map(|i| {
                    let s = -half + 2.0 * half * i as f64 / samples as f64;
                    let p = n * d + t * s;
                    Vec3::new(p.x, p.y, surface(p.x, p.y))
                })
                .collect();
            curves.push(Polyline {
                points,
                closed: false,
                origin: Origin::new("<builtin:dome>", 0),
                label: Some(format!("family {f} arc {k}")),
            });
        }
    }
    BuiltinScene {
        name: "dome",
        mesh: TriMesh { vertices, faces },
        curves,
        edge_length: 50.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dome_arcs_lie_on_the_dome_and_end_on_the_ground() {
        let s = dome_arcs(2000.0, 700.0, 3, 5);
        assert_eq!(s.curves.len(), 15);
        for c in &s.curves {
            let (a, b) = (c.points[0], *c.points.last().expect("points"));
            assert!(
                a.z.abs() < 1e-6 && b.z.abs() < 1e-6,
                "arc ends on the ground"
            );
            assert!(c.points.iter().all(|p| p.z >= -1e-9 && p.z <= 700.0 + 1e-9));
        }
        assert!(s.mesh.faces.len() > 1000);
    }
}

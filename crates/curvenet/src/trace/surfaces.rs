//! Built-in surfaces made in code, for scenes that need no input file.
//!
//! Each is an open triangle mesh of a few thousand faces, z up, at the scale of the paper's
//! scenes (largest extent about 4000 units), with normals pointing up (or outwards):
//!
//! | name | shape | boundary loops |
//! |---|---|---|
//! | `hill` | a Gaussian bump on a 4000 × 3000 rectangle | 1 |
//! | `tent` | `z = H cos(πx/a) cos(πy/a)` on a square, the whole border on the ground (`z = 0`) | 1 |
//! | `stadium` | an elliptic grandstand ring rising outwards; loop 0 is the inner ring | 2 |
//! | `shell` | a barrel vault with open ends, its long sides on the ground | 1 |
//! | `dome` | a spherical cap over a disk of radius 2000 | 1 |
//! | `saddle` | a hyperbolic paraboloid over a disk | 1 |
//! | `wave` | a sine wave over a 4000 × 3000 rectangle | 1 |

use crate::geom::{Aabb, Vec3};
use crate::io::{self, InputError, TriMesh};
use crate::words::Message;
use std::f64::consts::PI;
use std::path::Path;

/// Names of the built-in surfaces, for [`builtin_surface`].
pub const SURFACE_NAMES: [&str; 7] = ["hill", "tent", "stadium", "shell", "dome", "saddle", "wave"];

/// The built-in surface `name` (one of [`SURFACE_NAMES`]), or `None` for an unknown name.
pub fn builtin_surface(name: &str) -> Option<TriMesh> {
    let mesh = match name {
        "hill" => grid(50, 38, |u, v| {
            let (x, y) = (4000.0 * u - 2000.0, 3000.0 * v - 1500.0);
            let bump = 1000.0 * (-(x / 1100.0).powi(2) - (y / 850.0).powi(2)).exp();
            Vec3::new(x, y, bump + 60.0 * (1.0 + (x / 2000.0)))
        }),
        "tent" => grid(44, 44, |u, v| {
            let (x, y) = (4000.0 * u - 2000.0, 4000.0 * v - 2000.0);
            // Exactly zero on the border: cos(±π/2) rounds to 6e-17, so clamp.
            let h = 1200.0 * (PI * x / 4000.0).cos() * (PI * y / 4000.0).cos();
            let on_border = u == 0.0 || u == 1.0 || v == 0.0 || v == 1.0;
            Vec3::new(x, y, if on_border { 0.0 } else { h.max(0.0) })
        }),
        "stadium" => annulus(96, 16, |s, phi| {
            let (a, b) = (1300.0 + 700.0 * s, 900.0 + 800.0 * s);
            let z = (700.0 + 150.0 * (2.0 * phi).cos()) * s.powf(1.3);
            Vec3::new(a * phi.cos(), b * phi.sin(), z)
        }),
        "shell" => grid(48, 36, |u, v| {
            let x = 4000.0 * u - 2000.0;
            let r = 1400.0 * (1.0 + 0.15 * (PI * x / 2000.0).cos());
            let psi0 = 70f64.to_radians();
            let psi = psi0 * (2.0 * v - 1.0);
            Vec3::new(x, r * psi.sin(), r * (psi.cos() - psi0.cos()))
        }),
        "dome" => disk(25, |x, y| {
            // Sphere through the base circle (radius 2000) and the apex (height 1000).
            let (base, height) = (2000.0, 1000.0);
            let r = (base * base + height * height) / (2.0 * height);
            let z = (height - r) + (r * r - (x * x + y * y) * base * base).max(0.0).sqrt();
            Vec3::new(x * base, y * base, z)
        }),
        "saddle" => disk(25, |x, y| {
            Vec3::new(2000.0 * x, 2000.0 * y, 600.0 * (x * x - y * y) + 600.0)
        }),
        "wave" => grid(50, 38, |u, v| {
            let (x, y) = (4000.0 * u - 2000.0, 3000.0 * v - 1500.0);
            let z = 350.0 * (2.0 * PI * x / 2000.0).sin() * (PI * y / 3000.0).cos() + 350.0;
            Vec3::new(x, y, z)
        }),
        _ => return None,
    };
    Some(orient_up(mesh))
}

/// Why a surface named by a user could not be read.
#[derive(Debug, thiserror::Error)]
pub enum SurfaceError {
    /// The OBJ file is unreadable or malformed (naming the file and line).
    #[error(transparent)]
    Input(#[from] InputError),
    /// No such file, and no built-in surface of that name.
    #[error("{0}: no such file, and not a built-in surface (built-in: {names})", names = SURFACE_NAMES.join(", "))]
    Unknown(String),
}

/// The surface `arg` names as a user names one: an OBJ file or, when no such file exists, a
/// built-in surface (`builtin:NAME` or a bare `NAME`). Returns the mesh, its name for messages
/// and records (the path, or `builtin:NAME`) and the reader's warnings.
pub fn read_surface(arg: &Path) -> Result<(TriMesh, String, Vec<String>), SurfaceError> {
    let text = arg.to_string_lossy();
    let name = text.strip_prefix("builtin:");
    if name.is_none() && arg.exists() {
        let file = io::read_mesh(arg)?;
        let warnings = file.warnings.iter().map(|w| w.to_string()).collect();
        return Ok((file.mesh, arg.display().to_string(), warnings));
    }
    let name = name.unwrap_or(&text);
    match builtin_surface(name) {
        Some(mesh) => Ok((mesh, format!("builtin:{name}"), Vec::new())),
        None => Err(SurfaceError::Unknown(text.into_owned())),
    }
}

/// The largest extent a mesh is scaled to ([`scale_to_extent`]).
pub const MAX_EXTENT: f64 = 1e15;

/// The smallest extent a mesh is scaled to.
pub const MIN_EXTENT: f64 = 1e-12;

/// Checks an extent to scale a mesh to: 0 (the mesh kept at its size) or within
/// [[`MIN_EXTENT`], [`MAX_EXTENT`]].
pub fn check_extent(extent: f64) -> Result<(), Message> {
    if extent == 0.0 || (MIN_EXTENT..=MAX_EXTENT).contains(&extent) {
        Ok(())
    } else {
        Err(format!(
            "an extent is 0 (keep the mesh's size) or lies in [{MIN_EXTENT:e}, {MAX_EXTENT:e}]"
        )
        .into())
    }
}

/// Scales `mesh` about the origin so that its largest bounding-box side becomes `extent`;
/// returns the scaled mesh and the factor used. The reference scales command-line scenes this
/// way to a largest extent of 4000.
///
/// A mesh without positive finite extent (no vertices, all at one point) or a non-positive or
/// non-finite `extent` cannot be scaled meaningfully: the mesh is returned unchanged with
/// factor 1.
pub fn scale_to_extent(mesh: &TriMesh, extent: f64) -> (TriMesh, f64) {
    let largest = Aabb::of_points(&mesh.vertices).largest_extent();
    if !(largest > 0.0) || !largest.is_finite() || !(extent > 0.0) || !extent.is_finite() {
        return (mesh.clone(), 1.0);
    }
    let s = extent / largest;
    let scaled = TriMesh {
        vertices: mesh.vertices.iter().map(|&v| v * s).collect(),
        faces: mesh.faces.clone(),
    };
    (scaled, s)
}

/// Flips every face when the area-weighted normal points down, so that normals point up.
fn orient_up(mut mesh: TriMesh) -> TriMesh {
    let mut up = 0.0;
    for f in &mesh.faces {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.vertices[f[k] as usize]);
        up += (b - a).cross(c - a).z;
    }
    if up < 0.0 {
        for f in &mut mesh.faces {
            f.swap(1, 2);
        }
    }
    mesh
}

/// Pushes a triangle of vertex indices.
fn tri(faces: &mut Vec<[u32; 3]>, a: usize, b: usize, c: usize) {
    faces.push([a as u32, b as u32, c as u32]);
}

/// A `nx × ny`-cell grid over `(u, v) ∈ [0, 1]²`, mapped by `f`, each cell split along
/// alternating diagonals (a symmetric "union jack" pattern).
fn grid(nx: usize, ny: usize, f: impl Fn(f64, f64) -> Vec3) -> TriMesh {
    let mut vertices = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            vertices.push(f(i as f64 / nx as f64, j as f64 / ny as f64));
        }
    }
    let faces = cells(nx, ny, false, |i, j| j * (nx + 1) + i);
    TriMesh { vertices, faces }
}

/// A ring: `nphi` cells around, `ns` across, `f(s, φ)` with `s ∈ [0, 1]` from the inner to the
/// outer boundary. The inner ring's vertices come first, so it is boundary loop 0.
fn annulus(nphi: usize, ns: usize, f: impl Fn(f64, f64) -> Vec3) -> TriMesh {
    let mut vertices = Vec::with_capacity(nphi * (ns + 1));
    for j in 0..=ns {
        for i in 0..nphi {
            vertices.push(f(j as f64 / ns as f64, 2.0 * PI * i as f64 / nphi as f64));
        }
    }
    let faces = cells(nphi, ns, true, |i, j| j * nphi + (i % nphi));
    TriMesh { vertices, faces }
}

/// The triangles of `nx × ny` cells, cell `(i, j)` having corners `id(i, j)`, `id(i + 1, j)`,
/// `id(i + 1, j + 1)`, `id(i, j + 1)`, split along alternating diagonals; `flip` reverses
/// their orientation.
fn cells(nx: usize, ny: usize, flip: bool, id: impl Fn(usize, usize) -> usize) -> Vec<[u32; 3]> {
    let mut faces = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            let pair = if (i + j) % 2 == 0 {
                [[a, b, c], [a, c, d]]
            } else {
                [[a, b, d], [b, c, d]]
            };
            for [x, y, z] in pair {
                let (y, z) = if flip { (z, y) } else { (y, z) };
                tri(&mut faces, x, y, z);
            }
        }
    }
    faces
}

/// A disk of `rings` rings (ring `k` has `6k` vertices) over the unit disk, mapped by
/// `f(x, y)`. The centre is vertex 0.
fn disk(rings: usize, f: impl Fn(f64, f64) -> Vec3) -> TriMesh {
    let mut vertices = vec![f(0.0, 0.0)];
    let mut ring_ids: Vec<Vec<usize>> = vec![vec![0]];
    for k in 1..=rings {
        let n = 6 * k;
        let r = k as f64 / rings as f64;
        let mut ids = Vec::with_capacity(n);
        for j in 0..n {
            let phi = 2.0 * PI * j as f64 / n as f64;
            ids.push(vertices.len());
            vertices.push(f(r * phi.cos(), r * phi.sin()));
        }
        ring_ids.push(ids);
    }
    let mut faces = Vec::new();
    for k in 1..=rings {
        let (inner, outer) = (&ring_ids[k - 1], &ring_ids[k]);
        let (a, b) = (inner.len(), outer.len());
        if a == 1 {
            for j in 0..b {
                tri(&mut faces, inner[0], outer[j], outer[(j + 1) % b]);
            }
            continue;
        }
        // Merge the two rings by angle.
        let (mut i, mut j) = (0usize, 0usize);
        while i < a || j < b {
            let next_outer = (j + 1) as f64 / b as f64;
            let next_inner = (i + 1) as f64 / a as f64;
            if j < b && (i == a || next_outer <= next_inner) {
                tri(&mut faces, inner[i % a], outer[j], outer[(j + 1) % b]);
                j += 1;
            } else {
                tri(&mut faces, inner[i % a], outer[j % b], inner[(i + 1) % a]);
                i += 1;
            }
        }
    }
    TriMesh { vertices, faces }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::topology::MeshTopology;

    #[test]
    fn every_builtin_surface_is_a_clean_open_mesh_of_the_right_size() {
        for name in SURFACE_NAMES {
            let mesh = builtin_surface(name).unwrap();
            let topo = MeshTopology::new(&mesh).unwrap();
            let nf = topo.face_count();
            assert!((2000..=8000).contains(&nf), "{name}: {nf} faces");
            let ext = Aabb::of_points(&mesh.vertices).largest_extent();
            assert!((3500.0..=4500.0).contains(&ext), "{name}: extent {ext}");
            assert!(
                (0..topo.edge_count()).all(|e| topo.edge_faces(e).len() <= 2),
                "{name}"
            );
            assert!(
                (0..nf).all(|f| !topo.is_degenerate(f)),
                "{name}: degenerate face"
            );
            let loops = topo.boundary_loops();
            let want = if name == "stadium" { 2 } else { 1 };
            assert_eq!(loops.len(), want, "{name}");
            assert!(loops.iter().all(|l| l.closed), "{name}");
            // Euler characteristic: a disk (1) or an annulus (0).
            let chi = topo.vertex_count() as i64 - topo.edge_count() as i64 + nf as i64;
            assert_eq!(chi, 2 - want as i64, "{name}");
            // Normals up on average.
            let up: f64 = (0..nf)
                .map(|f| topo.face_normal(f).z * topo.face_area(f))
                .sum();
            assert!(up > 0.0, "{name}");
        }
        assert!(builtin_surface("nope").is_none());
    }

    #[test]
    fn stadium_inner_ring_is_loop_zero_and_tent_border_is_on_the_ground() {
        let topo = MeshTopology::new(&builtin_surface("stadium").unwrap()).unwrap();
        let loops = topo.boundary_loops();
        assert!(loops[0].length < loops[1].length);
        let tent = builtin_surface("tent").unwrap();
        let topo = MeshTopology::new(&tent).unwrap();
        for &v in &topo.boundary_loops()[0].vertices {
            assert_eq!(tent.vertices[v].z, 0.0);
        }
    }

    #[test]
    fn scaling_to_an_extent() {
        let mesh = builtin_surface("dome").unwrap();
        let (scaled, s) = scale_to_extent(&mesh, 1.0);
        let e = Aabb::of_points(&scaled.vertices).largest_extent();
        assert!((e - 1.0).abs() < 1e-12);
        assert!((s * Aabb::of_points(&mesh.vertices).largest_extent() - 1.0).abs() < 1e-12);
        let empty = TriMesh::default();
        assert_eq!(scale_to_extent(&empty, 4000.0).1, 1.0);
        assert_eq!(scale_to_extent(&mesh, f64::NAN).1, 1.0);
    }
}

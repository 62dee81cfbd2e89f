//! OBJ triangle meshes: `v` and `f` records.
//!
//! Faces accept `i`, `i/t`, `i//n` and `i/t/n` references with positive (1-based) or negative
//! (relative) indices; polygons are split into triangle fans. Everything else (`l`, `vn`, `vt`,
//! `o`, `g`, `usemtl`, comments, …) is ignored.

use super::obj_lexer::{
    VertexRef, parse_vertex, plural, push_vertices, records, resolve, vertex_suffix,
};
use super::{InputError, InputWarning, MeshFile, TriMesh};
use crate::geom::Vec3;

/// A triangle whose doubled area is at most this fraction of its longest edge squared counts as
/// having zero area (its vertices are collinear up to rounding).
const DEGENERATE_AREA: f64 = 1e-12;

/// An `f` record as read: its line and its vertex references with their lines.
struct FaceRecord {
    line: usize,
    refs: Vec<(VertexRef, usize)>,
}

/// Parses an OBJ triangle mesh. `file` names the input in messages.
///
/// Degenerate triangles (a repeated vertex, or zero area up to rounding) are left out with a
/// warning.
///
/// # Errors
///
/// [`InputError::Parse`], at the offending line, for a malformed or non-finite vertex coordinate,
/// a vertex with fewer than 3 or more than 4 numbers (6, `x y z r g b`, is accepted too), a
/// malformed face reference or one that points to no vertex, a face with fewer than 3 vertices,
/// a face using a vertex beyond the 2³² that [`TriMesh`] can index, and a file without usable
/// faces.
pub fn parse_obj_mesh(text: &str, file: &str) -> Result<MeshFile, InputError> {
    let mut vertices: Vec<Vec3> = Vec::new();
    let mut face_records: Vec<FaceRecord> = Vec::new();
    for record in records(text) {
        match record.keyword {
            "v" => vertices.push(parse_vertex(&record, file)?),
            "f" => {
                let refs = record.vertex_refs(vertices.len(), file)?;
                if refs.len() < 3 {
                    return Err(InputError::parse(
                        file,
                        record.line,
                        format!("a face needs at least 3 vertices, found {}", refs.len()),
                    ));
                }
                face_records.push(FaceRecord {
                    line: record.line,
                    refs,
                });
            }
            _ => {}
        }
    }
    if face_records.is_empty() {
        return Err(InputError::parse(
            file,
            1,
            format!(
                "no faces: the file has no `f` records ({} vert{})",
                vertices.len(),
                vertex_suffix(vertices.len())
            ),
        ));
    }

    let mut warnings = Vec::new();
    let mut faces = Vec::with_capacity(face_records.len());
    for face in &face_records {
        let idx = face
            .refs
            .iter()
            .map(|&(r, line)| resolve(r, line, vertices.len(), file))
            .collect::<Result<Vec<_>, _>>()?;
        for k in 1..idx.len() - 1 {
            let tri = [idx[0], idx[k], idx[k + 1]];
            if let Some(problem) = degeneracy(&vertices, tri) {
                warnings.push(InputWarning::new(
                    file,
                    face.line,
                    format!(
                        "degenerate face ({problem}, vertices {} {} {}) left out",
                        tri[0] + 1,
                        tri[1] + 1,
                        tri[2] + 1
                    ),
                ));
            } else {
                let [a, b, c] = tri.map(|i| to_u32(i, face.line, file));
                faces.push([a?, b?, c?]);
            }
        }
    }
    if faces.is_empty() {
        return Err(InputError::parse(
            file,
            face_records.first().map_or(1, |f| f.line),
            format!(
                "no usable faces: all {} triangle{} are degenerate",
                warnings.len(),
                plural(warnings.len())
            ),
        ));
    }
    Ok(MeshFile {
        mesh: TriMesh { vertices, faces },
        warnings,
    })
}

/// A vertex index as stored in [`TriMesh::faces`].
fn to_u32(i: usize, line: usize, file: &str) -> Result<u32, InputError> {
    u32::try_from(i).map_err(|_| {
        InputError::parse(
            file,
            line,
            format!(
                "vertex index {} is beyond the supported {} vertices",
                i as u128 + 1,
                u64::from(u32::MAX) + 1
            ),
        )
    })
}

/// Why the triangle `tri` is degenerate, or `None` if it is fine.
fn degeneracy(vertices: &[Vec3], tri: [usize; 3]) -> Option<&'static str> {
    let [a, b, c] = tri;
    if a == b || b == c || a == c {
        return Some("repeated vertex");
    }
    let (pa, pb, pc) = (vertices[a], vertices[b], vertices[c]);
    // Scale by a power of two (exact) so that no coordinate exceeds 1: edges, their squares and
    // the cross product then stay finite whatever the input's magnitude.
    let largest = [pa, pb, pc]
        .iter()
        .flat_map(|p| p.to_array())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    if largest == 0.0 {
        return Some("zero area");
    }
    let exponent = largest.log2().ceil().clamp(-1000.0, 1000.0) as i32;
    let scale = 2f64.powi(-exponent);
    let (pa, pb, pc) = (pa * scale, pb * scale, pc * scale);
    let (e1, e2, e3) = (pb - pa, pc - pa, pc - pb);
    let longest2 = e1.norm2().max(e2.norm2()).max(e3.norm2());
    let area2 = e1.cross(e2).norm();
    if area2 <= DEGENERATE_AREA * longest2 {
        return Some("zero area");
    }
    None
}

/// Writes a mesh as OBJ: a comment with the counts, the `v` records, then one `f` record per
/// triangle (1-based indices).
pub fn mesh_to_obj(mesh: &TriMesh) -> String {
    let mut out = format!(
        "# curvenet mesh: {} vert{}, {} face{}\n",
        mesh.vertices.len(),
        vertex_suffix(mesh.vertices.len()),
        mesh.faces.len(),
        plural(mesh.faces.len())
    );
    push_vertices(&mut out, &mesh.vertices);
    for f in &mesh.faces {
        out.push('f');
        for i in f {
            out.push(' ');
            out.push_str(&(u64::from(*i) + 1).to_string());
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::tests::{assert_input_error, reference_file};
    use super::*;

    fn assert_err(text: &str, line: usize, phrase: &str) {
        assert_input_error(parse_obj_mesh(text, "mesh.obj"), "mesh.obj", line, phrase);
    }

    const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

    #[test]
    fn parses_all_reference_forms() {
        let text = format!(
            "# c\n\n{QUAD}vt 0 0\nvn 0 0 1\no x\ng y\nusemtl m\ns 1\nl 1 2\n\
             f 1 2 3\nf 1/1 3/1 4/1\nf 1//1 2//1 3//1\nf 1/1/1 2/1/1 3/1/1\nf -4 -3 -2\n"
        );
        let m = parse_obj_mesh(&text, "m.obj").unwrap();
        assert_eq!(m.mesh.vertices.len(), 4);
        assert_eq!(
            m.mesh.faces,
            vec![[0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 1, 2], [0, 1, 2]]
        );
        assert!(m.warnings.is_empty());
    }

    #[test]
    fn polygons_become_fans() {
        let text = format!("{QUAD}v 0.5 1.5 0\nf 1 2 3 5 4\n");
        let m = parse_obj_mesh(&text, "m.obj").unwrap();
        assert_eq!(m.mesh.faces, vec![[0, 1, 2], [0, 2, 4], [0, 4, 3]]);
    }

    #[test]
    fn degenerate_faces_warn_and_are_left_out() {
        let text = format!("{QUAD}v 2 0 0\nf 1 2 3\nf 1 1 2\nf 1 2 5\n");
        let m = parse_obj_mesh(&text, "m.obj").unwrap();
        assert_eq!(m.mesh.faces, vec![[0, 1, 2]]);
        assert_eq!(m.warnings.len(), 2);
        assert_eq!(m.warnings[0].origin.line, 7);
        assert!(m.warnings[0].message.contains("repeated vertex"));
        assert_eq!(m.warnings[1].origin.line, 8);
        assert!(m.warnings[1].message.contains("zero area"));
    }

    #[test]
    fn extreme_magnitudes_are_judged_by_shape() {
        let text = "v 1e300 0 0\nv 0 1e300 0\nv -1e300 -1e300 0\n\
                    v 1e-300 0 0\nv 0 1e-300 0\nv 0 0 1e-300\n\
                    v 1 0 0\nv 1 0 1e-14\n\
                    f 1 2 3\nf 4 5 6\nf 1 2 7\nf 4 7 8\n";
        let m = parse_obj_mesh(text, "m.obj").unwrap();
        // The last face is a needle: 1e-14 wide, 1 long.
        assert_eq!(m.mesh.faces, vec![[0, 1, 2], [3, 4, 5], [0, 1, 6]]);
        assert_eq!(m.warnings.len(), 1);
        assert!(m.warnings[0].message.contains("zero area"));
    }

    #[test]
    fn only_degenerate_faces_is_an_error() {
        assert_err(&format!("{QUAD}\nf 1 1 2\n"), 6, "no usable faces");
    }

    #[test]
    fn malformed_number() {
        assert_err("v 0 0 0\nv 1.0 abc 3\n", 2, "malformed number `abc`");
    }

    #[test]
    fn truncated_vertex() {
        assert_err(&format!("{QUAD}v 1 2\nf 1 2 3\n"), 5, "truncated vertex");
    }

    #[test]
    fn nan_and_infinite_coordinates() {
        assert_err("v 0 0 0\nv NaN 0 0\n", 2, "not a finite number");
        assert_err("v 0 0 0\n\nv 0 0 inf\n", 3, "not a finite number");
    }

    #[test]
    fn empty_file() {
        assert_err("", 1, "no faces");
        assert_err(QUAD, 1, "no `f` records (4 vertices)");
    }

    #[test]
    fn faces_need_three_vertices() {
        assert_err(&format!("{QUAD}f 1 2\n"), 5, "at least 3 vertices, found 2");
    }

    #[test]
    fn faces_referencing_missing_vertices() {
        assert_err(
            &format!("{QUAD}f 1 2 3\nf 1 2 7\n"),
            6,
            "vertex index 7 refers to a missing",
        );
        assert_err(&format!("{QUAD}f 1 2 -9\n"), 5, "before the first vertex");
        assert_err(&format!("{QUAD}f 0 1 2\n"), 5, "index 0 is invalid");
        assert_err(
            &format!("{QUAD}f 1 2 a/b\n"),
            5,
            "malformed vertex reference",
        );
        assert_err(
            &format!("{QUAD}f 1 2 3/x/1\n"),
            5,
            "malformed vertex reference",
        );
    }

    #[test]
    fn round_trip() {
        let mesh = TriMesh {
            vertices: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 1e-7, 0.0),
                Vec3::new(0.1 + 0.2, 1.0, -3.5),
                Vec3::new(-2.0, 1.0, 1e3),
            ],
            faces: vec![[0, 1, 2], [0, 2, 3]],
        };
        let text = mesh_to_obj(&mesh);
        let back = parse_obj_mesh(&text, "rt.obj").unwrap();
        assert_eq!(back.mesh, mesh);
        assert!(back.warnings.is_empty());
    }

    #[test]
    fn reference_meshes_counts() {
        for (name, vertices, faces) in [
            ("roof.obj", 809, 1528),
            ("stadium.obj", 1348, 2568),
            ("tower.obj", 1745, 3456),
        ] {
            let Some(path) = reference_file("meshes", name) else {
                return;
            };
            let m = super::super::read_mesh(&path).unwrap();
            assert_eq!(m.mesh.vertices.len(), vertices, "{name}");
            assert_eq!(m.mesh.faces.len(), faces, "{name}");
            assert!(m.warnings.is_empty(), "{name}: {:?}", m.warnings.first());
        }
    }
}

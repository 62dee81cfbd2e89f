//! OBJ polylines (`.obj`), as Rhino exports curves.
//!
//! ```text
//! v 0 0 0
//! v 1 0 0
//! v 1 1 0
//! o ring
//! l 1 2 3 1
//! ```
//!
//! Each `l` record is one curve over the `v` records; it is closed when its first index equals
//! its last (or the points coincide). The name of the latest `o` record is the label of the
//! curves that follow it (a bare `o` clears it). Other records are ignored, except that `f`
//! records earn a warning (the file is a mesh) and free-form geometry is an error.

use super::checks::{Closure, RawCurve, finish_curve, one_line_label};
use super::obj_lexer::{
    VertexRef, parse_vertex, plural, push_vertices, records, resolve, vertex_suffix,
};
use super::{CurveFile, InputError, InputWarning, Polyline};
use crate::geom::Vec3;

/// Records of OBJ free-form geometry, which this reader refuses.
const FREE_FORM: &[&str] = &[
    "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp",
    "end", "con", "vp", "ctech", "stech",
];

/// An `l` record as read: its line, the label in force, and its vertex references with their
/// lines.
struct LineRecord {
    line: usize,
    label: Option<String>,
    refs: Vec<(VertexRef, usize)>,
}

/// Parses the polylines of an OBJ file. `file` names the input in messages.
///
/// # Errors
///
/// [`InputError::Parse`], at the offending line, for a malformed or non-finite vertex coordinate,
/// a vertex with fewer than 3 or more than 4 numbers (6, `x y z r g b`, is accepted too), a
/// malformed vertex reference or one that points to no vertex, free-form geometry (`cstype`,
/// `curv`, …), an `l` record without vertices or with fewer than 2 distinct points (3 when
/// closed), and a file without `l` records.
pub fn parse_obj_polylines(text: &str, file: &str) -> Result<CurveFile, InputError> {
    let mut vertices: Vec<Vec3> = Vec::new();
    let mut lines: Vec<LineRecord> = Vec::new();
    let mut label: Option<String> = None;
    let mut faces: Option<(usize, usize)> = None; // (line of the first `f`, count)
    for record in records(text) {
        match record.keyword {
            "v" => vertices.push(parse_vertex(&record, file)?),
            "l" => lines.push(LineRecord {
                line: record.line,
                label: label.clone(),
                refs: record.vertex_refs(vertices.len(), file)?,
            }),
            "o" => label = one_line_label(&record.rest),
            "f" => {
                let (_, count) = faces.get_or_insert((record.line, 0));
                *count += 1;
            }
            k if FREE_FORM.contains(&k) => {
                return Err(InputError::parse(
                    file,
                    record.line,
                    format!("free-form curves are not supported; export polylines (found `{k}`)"),
                ));
            }
            _ => {}
        }
    }
    if lines.is_empty() {
        let hint = if faces.is_some() {
            " (it has `f` faces: it is a mesh, not curves)"
        } else {
            ""
        };
        return Err(InputError::parse(
            file,
            1,
            format!("no curves: the file has no `l` (polyline) records{hint}"),
        ));
    }
    let mut warnings = Vec::new();
    if let Some((line, count)) = faces {
        warnings.push(InputWarning::new(
            file,
            line,
            format!(
                "ignored {count} `f` (face) record{}: faces belong to a mesh, not to curves",
                plural(count)
            ),
        ));
    }
    let mut curves = Vec::with_capacity(lines.len());
    for (index, l) in lines.into_iter().enumerate() {
        let mut points = Vec::with_capacity(l.refs.len());
        let mut indices = Vec::with_capacity(l.refs.len());
        for (r, line) in l.refs {
            let i = resolve(r, line, vertices.len(), file)?;
            indices.push(i);
            points.push((vertices[i], line));
        }
        let closure = if indices.len() >= 2 && indices.first() == indices.last() {
            Closure::Closed
        } else {
            Closure::Detect
        };
        let raw = RawCurve {
            index,
            line: l.line,
            label: l.label,
            closure,
            points,
        };
        curves.push(finish_curve(raw, file, &mut warnings)?);
    }
    Ok(CurveFile::plain(curves, warnings))
}

/// An `o` name for a label: one line, without `#` (a comment) or a trailing backslash (a
/// continuation). `None` when nothing is left.
fn object_name(label: &str) -> Option<String> {
    let cleaned = one_line_label(label)?.replace('#', " ");
    one_line_label(cleaned.trim_end_matches(['\\', ' ']))
}

/// Writes curves as OBJ polylines: all `v` records, then per curve an `o <label>` record (a bare
/// `o` for an unlabeled curve that follows a labeled one) and one `l` record. A closed curve's
/// `l` record repeats its first index at the end. Labels lose line breaks, `#` and trailing
/// backslashes, which OBJ cannot hold.
pub fn curves_to_obj(curves: &[Polyline]) -> String {
    let total: usize = curves.iter().map(|c| c.points.len()).sum();
    let mut out = format!(
        "# curvenet curves: {} curve{}, {total} vert{}\n",
        curves.len(),
        plural(curves.len()),
        vertex_suffix(total)
    );
    push_vertices(&mut out, curves.iter().flat_map(|c| &c.points));
    let mut first_index = 1usize;
    let mut named = false;
    for curve in curves {
        match curve.label.as_deref().and_then(object_name) {
            Some(name) => {
                out.push_str("o ");
                out.push_str(&name);
                out.push('\n');
                named = true;
            }
            None if named => {
                out.push_str("o\n");
                named = false;
            }
            None => {}
        }
        let n = curve.points.len();
        out.push('l');
        let closing = (curve.closed && n > 0).then_some(first_index);
        for i in (first_index..first_index + n).chain(closing) {
            out.push(' ');
            out.push_str(&i.to_string());
        }
        out.push('\n');
        first_index += n;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::Origin;
    use super::super::tests::{assert_input_error, assert_same_curves, sample_curves};
    use super::*;

    fn assert_err(text: &str, line: usize, phrase: &str) {
        assert_input_error(
            parse_obj_polylines(text, "curves.obj"),
            "curves.obj",
            line,
            phrase,
        );
    }

    const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

    #[test]
    fn parses_open_and_closed_polylines() {
        let text = format!(
            "# Rhino\n{SQUARE}g group\nusemtl m\ns off\nvn 0 0 1\nvt 0 0\n\
             l 1 2 3\nl 1/1 2/2 3/3 4/4 1/1\nl -1 -2 -3 -4\n"
        );
        let f = parse_obj_polylines(&text, "c.obj").unwrap();
        assert_eq!(f.curves.len(), 3);
        assert!(!f.curves[0].closed);
        assert_eq!(f.curves[0].points.len(), 3);
        assert_eq!(f.curves[0].origin, Origin::new("c.obj", 11));
        assert!(f.curves[1].closed);
        assert_eq!(f.curves[1].points.len(), 4);
        assert_eq!(f.curves[2].points[0], Vec3::new(0.0, 1.0, 0.0));
        assert!(f.warnings.is_empty());
    }

    #[test]
    fn coinciding_end_points_close_a_curve() {
        let text = format!("{SQUARE}v 0 0 0\nl 1 2 3 4 5\n");
        let f = parse_obj_polylines(&text, "c.obj").unwrap();
        assert!(f.curves[0].closed);
        assert_eq!(f.curves[0].points.len(), 4);
    }

    #[test]
    fn weights_continuations_and_forward_references() {
        let text = "l 1 2 \\\n 3\nv 0 0 0 1\nv 1 0 0 1\nv 1 1 0 1\n";
        let f = parse_obj_polylines(text, "c.obj").unwrap();
        assert_eq!(f.curves[0].points.len(), 3);
    }

    #[test]
    fn object_names_become_labels() {
        let text = format!("{SQUARE}o first one\nl 1 2\nl 2 3\no\nl 3 4\n");
        let f = parse_obj_polylines(&text, "c.obj").unwrap();
        assert_eq!(f.curves[0].label.as_deref(), Some("first one"));
        assert_eq!(f.curves[1].label.as_deref(), Some("first one"));
        assert_eq!(f.curves[2].label, None);
    }

    #[test]
    fn faces_are_ignored_with_one_warning() {
        let text = format!("{SQUARE}f 1 2 3\nl 1 2\nf 1 3 4\n");
        let f = parse_obj_polylines(&text, "c.obj").unwrap();
        assert_eq!(f.curves.len(), 1);
        assert_eq!(f.warnings.len(), 1);
        assert_eq!(f.warnings[0].origin.line, 5);
        assert!(f.warnings[0].message.contains("ignored 2 `f`"));
    }

    #[test]
    fn malformed_number() {
        assert_err("v 0 0 0\nv 1.0 abc 3\nl 1 2\n", 2, "malformed number `abc`");
    }

    #[test]
    fn truncated_vertex() {
        assert_err("v 0 0 0\nv 1.0 2.0\nl 1 2\n", 2, "truncated vertex");
        assert_err("v 0 0 0\nv 1 2 3 4 5\nl 1 2\n", 2, "too many numbers");
    }

    #[test]
    fn nan_and_infinite_coordinates() {
        assert_err("v 0 0 0\nv nan 0 0\nl 1 2\n", 2, "not a finite number");
        assert_err("v 0 0 0\nv 0 -inf 0\nl 1 2\n", 2, "not a finite number");
        assert_err("v 0 0 0\nv 0 0 0 inf\nl 1 2\n", 2, "not a finite number");
    }

    #[test]
    fn empty_file() {
        assert_err("", 1, "no curves");
        assert_err("# only a comment\n\n", 1, "no curves");
    }

    #[test]
    fn file_without_polylines() {
        assert_err(SQUARE, 1, "no `l` (polyline) records");
        assert_err(&format!("{SQUARE}f 1 2 3\n"), 1, "it is a mesh");
    }

    #[test]
    fn free_form_curves() {
        assert_err(
            "v 0 0 0\ncstype bspline\ndeg 3\n",
            2,
            "free-form curves are not supported; export polylines",
        );
        assert_err(
            &format!("{SQUARE}curv 0 1 1 2 3 4\n"),
            5,
            "free-form curves",
        );
    }

    #[test]
    fn malformed_and_missing_indices() {
        assert_err(
            &format!("{SQUARE}l 1 x 3\n"),
            5,
            "malformed vertex reference `x`",
        );
        assert_err(
            &format!("{SQUARE}l 1 2 9\n"),
            5,
            "vertex index 9 refers to a missing vertex",
        );
        assert_err(&format!("{SQUARE}l 1 \\\n 0\n"), 6, "index 0 is invalid");
        assert_err(&format!("{SQUARE}l -5 1\n"), 5, "before the first vertex");
    }

    #[test]
    fn curve_with_one_point() {
        assert_err(
            &format!("{SQUARE}l 1 2\nl 3\n"),
            6,
            "curve 1 has 1 distinct point",
        );
    }

    #[test]
    fn curve_with_one_repeated_point() {
        assert_err(
            &format!("{SQUARE}v 0 0 0\nl 1 5 1\n"),
            6,
            "curve 0 has 1 distinct point; a curve needs at least 2",
        );
    }

    #[test]
    fn closed_curve_with_two_distinct_points() {
        assert_err(
            &format!("{SQUARE}l 1 2 1\n"),
            5,
            "closed curve 0 has 2 distinct points",
        );
    }

    #[test]
    fn empty_polyline_record() {
        assert_err(&format!("{SQUARE}l 1 2\nl\n"), 6, "curve 1 has no points");
    }

    #[test]
    fn duplicate_points_warn_at_the_index_line() {
        let text = format!("{SQUARE}l 1 \\\n1 2\n");
        let f = parse_obj_polylines(&text, "c.obj").unwrap();
        assert_eq!(f.curves[0].points.len(), 2);
        assert_eq!(f.warnings.len(), 1);
        assert_eq!(f.warnings[0].origin.line, 6);
    }

    #[test]
    fn round_trip() {
        let curves = sample_curves();
        let text = curves_to_obj(&curves);
        assert!(text.contains("\nl 4 5 6 7 4\n"), "{text}");
        let back = parse_obj_polylines(&text, "rt.obj").unwrap();
        assert!(back.warnings.is_empty(), "{:?}", back.warnings);
        assert_same_curves(&curves, &back.curves);
    }

    #[test]
    fn labels_that_obj_cannot_hold_are_cleaned() {
        let mut curves = sample_curves();
        curves[0].label = Some("a # b\nc \\".to_owned());
        let back = parse_obj_polylines(&curves_to_obj(&curves), "rt.obj").unwrap();
        assert_eq!(back.curves[0].label.as_deref(), Some("a   b c"));
        assert_eq!(object_name("#\\"), None);
    }

    #[test]
    fn empty_input_writes_a_header_only() {
        assert_eq!(
            curves_to_obj(&[]),
            "# curvenet curves: 0 curves, 0 vertices\n"
        );
    }
}

//! curvenet's JSON curve format (`.json`).
//!
//! ```json
//! {
//!   "format": "curvenet-curves",
//!   "version": 1,
//!   "units": "m",
//!   "curves": [
//!     {"label": "ring", "closed": true, "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
//!     {"points": [[0, 0, 0], [2, 0, 1], [4, 0, 0]],
//!      "material": "aluminium", "section": {"outer_diameter": 60, "wall": 4},
//!      "rest": "pre-bent"},
//!     {"label": "arch 1", "group": "arches", "points": [[0, 0, 0], [0, 1, 1], [0, 2, 0]]}
//!   ]
//! }
//! ```
//!
//! `units`, `label`, `closed` and `group` are optional; without `closed` the curve is closed when
//! its last point repeats its first. Curves with the same `group` (a name, or an integer) are kept
//! or removed together by the searches ([`CurveFile::groups`]). Unknown fields are errors (a
//! misspelt `"close"` must not pass silently). `units` (`mm`, `cm` or `m`) is the scene's length
//! unit when the command line does not give one. A curve's optional `material`, `section` and
//! `rest` set its material, its cross-section and its rest shape (`straight`, the default, or
//! `pre-bent`); their forms are in [`crate::material::spec`].
//!
//! `serde_json` validates the document and reports syntax and type errors with their line and
//! column, and reads every coordinate exactly (its `float_roundtrip` parser): values written by
//! [`curves_to_json`] come back bit for bit. The lines of the curves and points, for the
//! messages of the curve checks, come from the pieces of text it hands back for them.

use super::checks::{Closure, RawCurve, finish_curve, push_number, shorten};
use super::{CurveFile, InputError, Polyline};
use crate::geom::Vec3;
use crate::material::CurveSpec;
use serde::Deserialize;
use serde::de::IgnoredAny;
use serde_json::value::RawValue;
use std::fmt::Write as _;

/// The value of the `format` field.
const FORMAT: &str = "curvenet-curves";
/// The only version this module reads and writes.
const VERSION: u64 = 1;

/// The fields checked before the document proper, so that a file of another kind is told so
/// rather than drowned in field errors.
#[derive(Deserialize)]
#[serde(expecting = "a JSON object with \"format\": \"curvenet-curves\"")]
struct Header {
    format: Option<serde_json::Value>,
    version: Option<serde_json::Value>,
}

/// The whole document, as `serde_json` checks it.
#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a curvenet-curves object with \"format\", \"version\" and \"curves\""
)]
struct Document {
    #[serde(rename = "format")]
    _format: IgnoredAny,
    #[serde(rename = "version")]
    _version: IgnoredAny,
    #[serde(default)]
    units: Option<String>,
    #[serde(default)]
    edge_length: Option<f64>,
    curves: Vec<JsonCurve>,
}

/// One curve, as `serde_json` checks it.
#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a curve object with \"points\" and optional \"label\", \"closed\", \"group\", \"material\", \"section\", \"rest\" and \"supports\""
)]
struct JsonCurve {
    #[serde(default)]
    label: Option<String>,
    points: Vec<[f64; 3]>,
    #[serde(default)]
    closed: Option<bool>,
    #[serde(default)]
    material: Option<serde_json::Value>,
    #[serde(default)]
    section: Option<serde_json::Value>,
    #[serde(default)]
    rest: Option<serde_json::Value>,
    #[serde(default)]
    supports: Option<serde_json::Value>,
    #[serde(default)]
    group: Option<GroupTag>,
}

/// A curve's `"group"`: a name, or an integer (kept as its decimal text).
struct GroupTag(String);

impl<'de> Deserialize<'de> for GroupTag {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit;
        impl serde::de::Visitor<'_> for Visit {
            type Value = GroupTag;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a group name (a string or an integer)")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<GroupTag, E> {
                Ok(GroupTag(v.to_owned()))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<GroupTag, E> {
                Ok(GroupTag(v.to_string()))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<GroupTag, E> {
                Ok(GroupTag(v.to_string()))
            }
        }
        d.deserialize_any(Visit)
    }
}

/// Parses curvenet's JSON curve format. `file` names the input in messages.
///
/// # Errors
///
/// [`InputError::Parse`] for invalid JSON or a wrongly typed or unknown field (`serde_json`'s line
/// and column in the message), a document that is not an object, a wrong `format`, an unsupported
/// `version`, a key given twice in one object ([`super::duplicate_key`]), an empty `curves`
/// list, and the curve checks shared by all formats (no points,
/// fewer than 2 distinct points, 3 when closed), which name `curve <index>` and the line of that
/// curve's opening brace.
pub fn parse_json_curves(text: &str, file: &str) -> Result<CurveFile, InputError> {
    let json_error = |e: serde_json::Error| {
        InputError::parse(file, e.line(), format!("invalid curvenet-curves JSON: {e}"))
    };
    let fail = |line: usize, message: String| Err(InputError::parse(file, line.max(1), message));
    // The format is one object; say so before serde does (it also builds structs from arrays,
    // and would then complain about "trailing characters").
    let body = text.trim_start();
    let line = 1 + text[..text.len() - body.len()].matches('\n').count();
    if body.is_empty() {
        return fail(
            line,
            format!("the file is empty; expected a JSON object with \"format\": \"{FORMAT}\""),
        );
    }
    if !body.starts_with('{') {
        let found = match body.as_bytes()[0] {
            b'[' => "an array",
            b'"' => "a string",
            b'-' | b'0'..=b'9' => "a number",
            _ => "something else",
        };
        return fail(
            line,
            format!(
                "expected a JSON object with \"format\": \"{FORMAT}\" and \"curves\", found \
                 {found}"
            ),
        );
    }
    let header: Header = serde_json::from_str(text).map_err(json_error)?;
    // serde_json keeps the last of a key given twice: refused, naming it.
    if let Some(d) = super::duplicate_key(text) {
        return fail(d.line, d.describe());
    }
    let located = locate(text).unwrap_or_default();
    match header.format {
        Some(serde_json::Value::String(f)) if f == FORMAT => {}
        Some(other) => {
            return fail(
                located.format_line,
                format!(
                    "not a curvenet curves file: \"format\" is {}, expected \"{FORMAT}\"",
                    shorten(&other.to_string())
                ),
            );
        }
        None => {
            return fail(
                1,
                format!("not a curvenet curves file: no \"format\" field (expected \"{FORMAT}\")"),
            );
        }
    }
    match header.version {
        Some(v) if v.as_u64() == Some(VERSION) => {}
        Some(v) => {
            return fail(
                located.version_line,
                format!(
                    "unsupported \"version\" {}; this reader supports version {VERSION}",
                    shorten(&v.to_string())
                ),
            );
        }
        None => return fail(1, format!("no \"version\" field (expected {VERSION})")),
    }
    let document: Document = serde_json::from_str(text).map_err(json_error)?;
    if document.curves.is_empty() {
        return fail(located.curves_line, "no curves: \"curves\" is empty".into());
    }
    if let Some(h) = document.edge_length
        && !(h.is_finite() && h > 0.0)
    {
        let line =
            (text.find("\"edge_length\"")).map_or(1, |i| text[..i].matches('\n').count() + 1);
        return fail(
            line,
            format!("\"edge_length\" must be a positive length (scene units), got {h}"),
        );
    }

    let mut warnings = Vec::new();
    let mut curves = Vec::with_capacity(document.curves.len());
    let mut specs = Vec::with_capacity(document.curves.len());
    let mut groups = Vec::with_capacity(document.curves.len());
    for (index, curve) in document.curves.into_iter().enumerate() {
        groups.push(curve.group.map(|g| g.0));
        let (curve_line, point_lines) = located
            .curves
            .get(index)
            .map_or((0, &[][..]), |c| (c.0, &c.1[..]));
        let spec = CurveSpec::from_json(
            curve.material.as_ref(),
            curve.section.as_ref(),
            curve.rest.as_ref(),
            curve.supports.as_ref(),
        )
        .map_err(|e| InputError::parse(file, curve_line.max(1), format!("curve {index}: {e}")))?;
        specs.push(spec);
        let points = curve
            .points
            .iter()
            .enumerate()
            .map(|(j, &p)| {
                (
                    Vec3::from(p),
                    point_lines.get(j).copied().unwrap_or(curve_line),
                )
            })
            .collect();
        let raw = RawCurve {
            index,
            line: curve_line,
            label: curve.label,
            closure: Closure::declared(curve.closed),
            points,
        };
        curves.push(finish_curve(raw, file, &mut warnings)?);
    }
    if specs.iter().all(CurveSpec::is_empty) {
        specs.clear();
    }
    Ok(CurveFile {
        curves,
        warnings,
        specs,
        groups,
        units: document.units,
        edge_length: document.edge_length,
    })
}

/// Writes curves in curvenet's JSON format, pretty-printed with one point per line. Every curve
/// states `closed`; `label` appears when the curve has one. Coordinates use the shortest
/// round-trip form; a non-finite coordinate (which no reader produces) is written as `null`,
/// which the reader rejects.
pub fn curves_to_json(curves: &[Polyline]) -> String {
    curves_to_json_with(curves, &FileExtras::default())
}

/// What a curve file may say beside the curves' points: the scene's unit, the edge length,
/// and per curve its other fields (`material`, `section`, `rest`, `supports`, `group`).
#[derive(Clone, Debug, Default)]
pub struct FileExtras {
    /// `"units"`.
    pub units: Option<String>,
    /// `"edge_length"` (scene units).
    pub edge_length: Option<f64>,
    /// Each curve's further fields, in the order written (aligned with the curves, or
    /// shorter: the curves past its end have none).
    pub fields: Vec<Vec<(&'static str, serde_json::Value)>>,
}

/// [`curves_to_json`] with the file's `units` and `edge_length` and each curve's further
/// fields (what [`parse_json_curves`] reads back).
pub fn curves_to_json_with(curves: &[Polyline], extras: &FileExtras) -> String {
    let curves = curves.iter().enumerate().map(|(i, curve)| {
        let points = curve.points.iter().map(|p| {
            let number = |v: f64| {
                let mut out = String::new();
                if v.is_finite() {
                    push_number(&mut out, v);
                } else {
                    out.push_str("null");
                }
                out
            };
            format!("[{}, {}, {}]", number(p.x), number(p.y), number(p.z))
        });
        let label = curve.label.as_deref().map_or_else(String::new, |l| {
            format!("      \"label\": {},\n", json_string(l))
        });
        let mut more = String::new();
        for (key, value) in extras.fields.get(i).into_iter().flatten() {
            let _ = writeln!(more, "      \"{key}\": {value},");
        }
        format!(
            "{{\n{label}{more}      \"closed\": {},\n      \"points\": {}\n    }}",
            curve.closed,
            json_list(points, "      ")
        )
    });
    let mut head = String::new();
    if let Some(u) = &extras.units {
        let _ = write!(head, "\n  \"units\": {},", json_string(u));
    }
    if let Some(h) = extras.edge_length {
        let mut n = String::new();
        push_number(&mut n, h);
        let _ = write!(head, "\n  \"edge_length\": {n},");
    }
    format!(
        "{{\n  \"format\": {},\n  \"version\": {VERSION},{head}\n  \"curves\": {}\n}}\n",
        json_string(FORMAT),
        json_list(curves, "  ")
    )
}

/// A JSON list of `items`, one a line, its closing bracket indented by `indent`; `[]` when
/// empty.
fn json_list(items: impl Iterator<Item = String>, indent: &str) -> String {
    let lines: Vec<String> = items.map(|i| format!("\n{indent}  {i}")).collect();
    if lines.is_empty() {
        return "[]".into();
    }
    format!("[{}\n{indent}]", lines.join(","))
}

/// `s` as a JSON string literal.
fn json_string(s: &str) -> String {
    let mut out = String::from('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if u32::from(c) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", u32::from(c));
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Where things are in a curvenet-curves document: 1-based lines, 0 where not found.
#[derive(Default)]
struct Located {
    format_line: usize,
    version_line: usize,
    curves_line: usize,
    /// Each curve's line (its opening brace) and its points' lines.
    curves: Vec<(usize, Vec<usize>)>,
}

/// Records where the parts of a document that `serde_json` accepted are, from the pieces of
/// the text it hands back for them ([`RawValue`]). `None` when the document does not have the
/// shape (it then only costs the line numbers).
fn locate(text: &str) -> Option<Located> {
    #[derive(Deserialize)]
    struct Root<'a> {
        #[serde(borrow)]
        format: Option<&'a RawValue>,
        #[serde(borrow)]
        version: Option<&'a RawValue>,
        #[serde(borrow)]
        curves: Option<&'a RawValue>,
    }
    #[derive(Deserialize)]
    struct Curve<'a> {
        #[serde(borrow, default)]
        points: Vec<&'a RawValue>,
    }
    let newlines: Vec<usize> = text.match_indices('\n').map(|(i, _)| i).collect();
    // Every piece is a slice of `text`: its line is 1 + the newlines before it.
    let line = |piece: &RawValue| {
        let offset = piece.get().as_ptr() as usize - text.as_ptr() as usize;
        1 + newlines.partition_point(|&n| n < offset)
    };
    let root: Root<'_> = serde_json::from_str(text).ok()?;
    let curves: Vec<&RawValue> = root
        .curves
        .and_then(|c| serde_json::from_str(c.get()).ok())
        .unwrap_or_default();
    Some(Located {
        format_line: root.format.map_or(0, line),
        version_line: root.version.map_or(0, line),
        curves_line: root.curves.map_or(0, line),
        curves: curves
            .into_iter()
            .map(|c| {
                let points = serde_json::from_str::<Curve<'_>>(c.get())
                    .map_or_else(|_| Vec::new(), |c| c.points.into_iter().map(line).collect());
                (line(c), points)
            })
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::super::Origin;
    use super::super::tests::{assert_input_error, assert_same_curves, sample_curves};
    use super::*;

    fn assert_err(text: &str, line: usize, phrase: &str) {
        assert_input_error(
            parse_json_curves(text, "curves.json"),
            "curves.json",
            line,
            phrase,
        );
    }

    /// A document around the given curve objects, one per line from line 5 on.
    fn doc(curves: &[&str]) -> String {
        format!(
            "{{\n  \"format\": \"curvenet-curves\",\n  \"version\": 1,\n  \"curves\": [\n{}\n  ]\n}}\n",
            curves.join(",\n")
        )
    }

    const GOOD: &str = r#"{"points": [[0, 0, 0], [1, 0, 0]]}"#;

    #[test]
    fn parses_a_document() {
        let text = doc(&[
            r#"{"label": "a", "points": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 0, 0]]}"#,
            r#"{"points": [[0, 0, 0], [1, 0, 0], [1, 1, 0]], "closed": true}"#,
            r#"{"points": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 0, 0]], "closed": false}"#,
            r#"{"label": null, "points": [[0, 0, 0], [1e-3, 2.5E2, -0.0]], "closed": null}"#,
        ]);
        let f = parse_json_curves(&text, "c.json").unwrap();
        assert_eq!(f.curves.len(), 4);
        assert_eq!(f.curves[0].label.as_deref(), Some("a"));
        assert!(f.curves[0].closed);
        assert_eq!(f.curves[0].points.len(), 3);
        assert_eq!(f.curves[0].origin, Origin::new("c.json", 5));
        assert!(f.curves[1].closed);
        assert_eq!(f.curves[1].points.len(), 3);
        assert!(!f.curves[2].closed);
        assert_eq!(f.curves[2].points.len(), 4);
        assert_eq!(f.curves[3].points[1], Vec3::new(1e-3, 250.0, 0.0));
        assert_eq!(f.curves[3].origin.line, 8);
    }

    #[test]
    fn an_edge_length_is_read_and_a_bad_one_refused_at_its_line() {
        let text = doc(&[GOOD]).replacen(
            "\"version\": 1,",
            "\"version\": 1,\n  \"edge_length\": 2.5,",
            1,
        );
        assert_eq!(
            parse_json_curves(&text, "c.json").unwrap().edge_length,
            Some(2.5)
        );
        for bad in ["0", "-1"] {
            let text = text.replace("2.5", bad);
            let e = parse_json_curves(&text, "c.json").unwrap_err().to_string();
            assert!(
                e.starts_with("c.json:4:") && e.contains("edge_length"),
                "{e}"
            );
        }
    }

    #[test]
    fn groups_are_read_per_curve() {
        let text = doc(&[
            r#"{"group": "arches", "points": [[0, 0, 0], [1, 0, 0]]}"#,
            GOOD,
            r#"{"group": 7, "points": [[0, 0, 0], [1, 0, 0]]}"#,
            r#"{"points": [[0, 0, 0], [1, 0, 0]], "group": "arches"}"#,
        ]);
        let f = parse_json_curves(&text, "c.json").unwrap();
        assert_eq!(
            f.groups,
            vec![
                Some("arches".into()),
                None,
                Some("7".into()),
                Some("arches".into())
            ]
        );
        let f = parse_json_curves(&doc(&[GOOD]), "c.json").unwrap();
        assert_eq!(f.groups, vec![None]);
        let text = doc(&[GOOD, r#"{"group": [1], "points": [[0, 0, 0], [1, 0, 0]]}"#]);
        assert_err(&text, 6, "a group name (a string or an integer)");
        let text = doc(&[GOOD, r#"{"group": 1.5, "points": [[0, 0, 0], [1, 0, 0]]}"#]);
        assert_err(&text, 6, "a group name");
        let text = doc(&[r#"{"groups": "a", "points": [[0, 0, 0], [1, 0, 0]]}"#]);
        assert_err(&text, 5, "unknown field `groups`");
    }

    #[test]
    fn units_are_accepted_and_fields_may_be_escaped() {
        let text = r#"{"units": "mm", "format": "curvenet-curves", "version": 1,
            "cur\u0076es": [{"points": [[0, 0, 0], [1, 0, 0]]}]}"#;
        let f = parse_json_curves(text, "c.json").unwrap();
        assert_eq!(f.curves[0].origin.line, 2);
    }

    #[test]
    fn syntax_errors_carry_serde_line_and_column() {
        assert_err(
            "{\n  \"format\": \"curvenet-curves\",\n  oops\n}",
            3,
            "column",
        );
        assert_err(
            "{\"format\": \"curvenet-curves\"} trailing",
            1,
            "trailing characters",
        );
    }

    #[test]
    fn malformed_number() {
        let text = doc(&[GOOD, r#"{"points": [[0, 0, 0], [1.0, abc, 3]]}"#]);
        assert_err(&text, 6, "invalid curvenet-curves JSON");
        let text = doc(&[GOOD, r#"{"points": [[0, 0, 0], [1.0, "abc", 3]]}"#]);
        assert_err(&text, 6, "invalid type: string \"abc\"");
    }

    #[test]
    fn truncated_point() {
        let text = doc(&[GOOD, "{\"points\": [[0, 0, 0],\n[1.0, 2.0]]}"]);
        assert_err(&text, 7, "invalid length 2");
        let text = doc(&[GOOD, "{\"points\": [[0, 0, 0],\n[1.0, 2.0, 3, 4]]}"]);
        assert_err(&text, 7, "trailing");
    }

    #[test]
    fn nan_and_infinite_coordinates() {
        let text = doc(&[GOOD, r#"{"points": [[0, 0, 0], [NaN, 0, 0]]}"#]);
        assert_err(&text, 6, "invalid curvenet-curves JSON");
        let text = doc(&[GOOD, r#"{"points": [[0, 0, 0], [1e999, 0, 0]]}"#]);
        assert_err(&text, 6, "number out of range");
        let text = doc(&[GOOD, r#"{"points": [[0, 0, 0], [null, 0, 0]]}"#]);
        assert_err(&text, 6, "invalid type: null");
    }

    #[test]
    fn empty_file() {
        assert_err("", 1, "the file is empty");
        assert_err("\n\n  ", 3, "the file is empty");
    }

    #[test]
    fn no_curves() {
        assert_err(&doc(&[]), 4, "no curves");
        assert_err(
            "{\"format\": \"curvenet-curves\", \"version\": 1}",
            1,
            "missing field `curves`",
        );
    }

    #[test]
    fn wrong_format_or_version() {
        assert_err(
            "{\"type\": \"FeatureCollection\"}",
            1,
            "not a curvenet curves file",
        );
        assert_err(
            "{\n\"format\": \"geojson\", \"version\": 1, \"curves\": []}",
            2,
            "\"format\" is \"geojson\"",
        );
        assert_err(
            "{\"format\": \"curvenet-curves\",\n\n \"version\": 2, \"curves\": []}",
            3,
            "unsupported \"version\" 2",
        );
        assert_err(
            "{\"format\": \"curvenet-curves\", \"version\": \"1\"}",
            1,
            "unsupported \"version\"",
        );
        assert_err("{\"format\": \"curvenet-curves\"}", 1, "no \"version\"");
        let long = format!("{{\"format\": \"{}\"}}", "x".repeat(10_000));
        let e = parse_json_curves(&long, "c.json").unwrap_err();
        assert!(e.to_string().len() < 200, "{e}");
        assert_err("\n[1, 2]", 2, "expected a JSON object");
        assert_err("[\"curvenet-curves\", 1]", 1, "expected a JSON object");
        // Not "trailing characters": an array of any length is named for what it is.
        assert_err("[1,2,3]", 1, "found an array");
        assert_err("3", 1, "found a number");
    }

    #[test]
    fn unknown_fields_are_errors() {
        let text = doc(&[GOOD, r#"{"points": [[0, 0, 0], [1, 0, 0]], "close": true}"#]);
        assert_err(&text, 6, "unknown field `close`");
    }

    #[test]
    fn curve_with_one_point() {
        let text = doc(&[GOOD, GOOD, r#"{"points": [[5, 5, 5]]}"#]);
        assert_err(
            &text,
            7,
            "curve 2 has 1 distinct point; a curve needs at least 2",
        );
    }

    #[test]
    fn curve_with_one_repeated_point() {
        let text = doc(&[GOOD, "{\n\"points\": [[5, 5, 5], [5, 5, 5]]}"]);
        assert_err(&text, 6, "curve 1 has 1 distinct point");
    }

    #[test]
    fn closed_curve_with_two_distinct_points() {
        let text = doc(&[r#"{"points": [[0, 0, 0], [1, 0, 0]], "closed": true}"#]);
        assert_err(&text, 5, "closed curve 0 has 2 distinct points");
    }

    #[test]
    fn empty_curve() {
        let text = doc(&[GOOD, r#"{"label": "x", "points": []}"#]);
        assert_err(&text, 6, "curve 1 has no points");
    }

    #[test]
    fn warnings_point_at_the_point_line() {
        let text = doc(&["{\"points\": [\n[0, 0, 0],\n[0, 0, 0],\n[1, 0, 0]]}"]);
        let f = parse_json_curves(&text, "c.json").unwrap();
        assert_eq!(f.warnings.len(), 1);
        assert_eq!(f.warnings[0].origin.line, 7);
    }

    #[test]
    fn round_trip() {
        let curves = sample_curves();
        let text = curves_to_json(&curves);
        let back = parse_json_curves(&text, "rt.json").unwrap();
        assert!(back.warnings.is_empty(), "{:?}", back.warnings);
        assert_same_curves(&curves, &back.curves);
        // The writer's layout: the first curve object opens on line 5.
        assert_eq!(back.curves[0].origin.line, 5);
    }

    #[test]
    fn coordinates_come_back_bit_for_bit() {
        // serde_json alone reads these one unit in the last place off.
        let values = [
            4.520346745820636e-24,
            9.466426603509888e-32,
            2.670316890914642e-16,
        ];
        let curves = vec![Polyline {
            points: vec![Vec3::from(values), Vec3::new(1.0, 2.0, 3.0)],
            closed: false,
            origin: Origin::new("x", 0),
            label: Some("tricky \"quotes\" \\ \u{1} é".to_owned()),
        }];
        let back = parse_json_curves(&curves_to_json(&curves), "rt.json").unwrap();
        assert_eq!(back.curves[0].points, curves[0].points);
        assert_eq!(back.curves[0].label, curves[0].label);
    }

    #[test]
    fn writer_output_is_valid_json_even_when_empty() {
        let v: serde_json::Value = serde_json::from_str(&curves_to_json(&[])).unwrap();
        assert_eq!(v["format"], FORMAT);
        let mut curves = sample_curves();
        curves[0].points.clear();
        curves[1].points[0].x = f64::NAN;
        let v: serde_json::Value = serde_json::from_str(&curves_to_json(&curves)).unwrap();
        assert!(v["curves"][1]["points"][0][0].is_null());
    }

    #[test]
    fn locating_gives_up_quietly() {
        assert!(locate("{\"a\": ").is_none());
        assert!(locate("{\"a\" 1}").is_none());
        assert!(locate("\"unterminated").is_none());
        assert!(locate(&"[".repeat(1000)).is_none());
        assert!(locate("[1, 2").is_none());
    }
}

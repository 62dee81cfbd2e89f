//! Per-curve material, section and rest shape in curvenet's JSON curve format: what a file
//! says arrives with the curves, files without it read as before, and bad values are errors
//! naming the file, the line of the curve and the field.

use curvenet::io::{InputError, parse_json_curves};
use curvenet::material::spec::Length;
use curvenet::material::{MaterialSpec, RestShape, SectionSpec};

fn doc(curves: &str) -> String {
    format!(
        "{{\n  \"format\": \"curvenet-curves\",\n  \"version\": 1,\n  \"units\": \"mm\",\n  \
         \"curves\": [\n{curves}\n  ]\n}}\n"
    )
}

const PLAIN: &str = r#"    {"points": [[0, 0, 0], [1, 0, 0]]}"#;

#[test]
fn specs_arrive_with_the_curves() {
    let text = doc(&format!(
        "{PLAIN},\n    {}\n",
        r#"{"points": [[0, 0, 0], [1, 1, 0]], "material": {"preset": "aluminium", "strength": "200MPa"}, "section": {"outer_diameter": 60, "wall": "4mm"}, "rest": "pre-bent"}"#
    ));
    let f = parse_json_curves(&text, "a.json").unwrap();
    assert_eq!(f.units.as_deref(), Some("mm"));
    assert_eq!(f.specs.len(), 2);
    assert!(f.specs[0].is_empty());
    let s = &f.specs[1];
    assert_eq!(s.rest, Some(RestShape::PreBent));
    assert_eq!(
        s.material,
        Some(MaterialSpec {
            preset: Some("aluminium".into()),
            strength_pa: Some(200e6),
            ..MaterialSpec::default()
        })
    );
    assert_eq!(
        s.section,
        Some(SectionSpec::Tube {
            outer_diameter: Length::Scene(60.0),
            wall: Length::Metres(0.004)
        })
    );
}

#[test]
fn files_without_specs_read_as_before() {
    let f = parse_json_curves(&doc(PLAIN), "a.json").unwrap();
    assert!(f.specs.is_empty());
    assert_eq!(f.curves.len(), 1);
}

#[test]
fn bad_specs_name_the_file_the_line_and_the_field() {
    let cases = [
        (r#""material": "unobtainium""#, "unknown material"),
        (r#""material": {"young": "7850kg/m3"}"#, "density"),
        (r#""material": {"density": 7850}"#, "with its unit"),
        (r#""section": {"radius": "10GPa"}"#, "stress"),
        (r#""section": {"wall": 2}"#, "either"),
        (r#""rest": "curly""#, "unknown rest shape"),
    ];
    for (field, needle) in cases {
        let text = doc(&format!(
            "{PLAIN},\n    {{\"points\": [[0, 0, 0], [1, 0, 0]], {field}}}"
        ));
        match parse_json_curves(&text, "bad.json") {
            Err(e @ InputError::Parse { .. }) => {
                let msg = e.to_string();
                assert!(msg.starts_with("bad.json:7:"), "{field}: {msg}");
                assert!(
                    msg.contains("curve 1") && msg.contains(needle),
                    "{field}: {msg}"
                );
            }
            other => panic!("{field}: expected a parse error, got {other:?}"),
        }
    }
    // A misspelt field is still an error.
    let text = doc(r#"    {"points": [[0, 0, 0], [1, 0, 0]], "materal": "steel"}"#);
    assert!(parse_json_curves(&text, "bad.json").is_err());
}

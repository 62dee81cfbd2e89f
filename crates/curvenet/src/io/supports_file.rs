//! The supports file: how chosen curve ends are held, overriding the run's supports.
//!
//! ```json
//! {"format": "curvenet-supports", "version": 1,
//!  "supports": [
//!    {"at": [0, 0, 0], "support": "clamped"},
//!    {"at": [1000, 0, 0], "support": {"fixed": "yz", "rotation": "free"}},
//!    {"curve": 3, "end": "start", "support": "free"}
//!  ]}
//! ```
//!
//! An entry names its end by a point (`at`, in the curve files' coordinates: every open
//! curve end at that point, within the reader's tolerance, takes the support) or by curve id
//! and end (`"start"` or `"end"`). A support is written as in a curve file's `"supports"`
//! ([`crate::material::support`]). Where an entry lies in the file (its line) travels with it,
//! so an entry that names no curve end is reported at its line.

use super::InputError;
use crate::material::EndSupport;
use serde::Deserialize;
use serde_json::value::RawValue;

/// The `format` a supports file declares.
pub const SUPPORTS_FORMAT: &str = "curvenet-supports";

/// Which end an entry names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EndPlace {
    /// Every open curve end at this point (curve-file coordinates, before any scale).
    Point([f64; 3]),
    /// One end of one curve.
    CurveEnd {
        /// The curve's id.
        curve: usize,
        /// Its start (true) or its end.
        at_start: bool,
    },
}

/// One entry of a supports file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SupportEntry {
    /// The end it names.
    pub place: EndPlace,
    /// How that end is held.
    pub support: EndSupport,
    /// Its line in the file (1-based).
    pub line: usize,
}

/// Reads a supports file's text (`file` names it in errors).
///
/// # Errors
///
/// The file and line of malformed JSON, a key given twice, a wrong format or version, an
/// entry without a place or a support, an unknown key, a support that does not read.
pub fn parse_supports_file(text: &str, file: &str) -> Result<Vec<SupportEntry>, InputError> {
    #[derive(Deserialize)]
    struct Root<'a> {
        format: Option<String>,
        version: Option<u32>,
        #[serde(borrow)]
        supports: Option<Vec<&'a RawValue>>,
    }
    let fail = |line: usize, m: String| InputError::parse(file, line.max(1), m);
    let root: Root<'_> = serde_json::from_str(text)
        .map_err(|e| fail(e.line(), format!("not a supports file: {e}")))?;
    if let Some(d) = super::duplicate_key(text) {
        return Err(fail(d.line, d.describe()));
    }
    if root.format.as_deref() != Some(SUPPORTS_FORMAT) {
        return Err(fail(
            1,
            format!("expected \"format\": \"{SUPPORTS_FORMAT}\" (a supports file)"),
        ));
    }
    if root.version != Some(1) {
        return Err(fail(1, "expected \"version\": 1".into()));
    }
    let Some(entries) = root.supports else {
        return Err(fail(1, "no \"supports\" list".into()));
    };
    let newlines: Vec<usize> = text.match_indices('\n').map(|(i, _)| i).collect();
    entries
        .into_iter()
        .enumerate()
        .map(|(k, raw)| {
            let offset = raw.get().as_ptr() as usize - text.as_ptr() as usize;
            let line = 1 + newlines.partition_point(|&n| n < offset);
            entry(raw.get())
                .map(|(place, support)| SupportEntry {
                    place,
                    support,
                    line,
                })
                .map_err(|m| fail(line, format!("support {k}: {m}")))
        })
        .collect()
}

/// One entry's place and support, or what is wrong with it.
fn entry(text: &str) -> Result<(EndPlace, EndSupport), String> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
    let serde_json::Value::Object(map) = value else {
        return Err(
            "an entry is an object with \"at\" (or \"curve\" and \"end\") and \"support\"".into(),
        );
    };
    if let Some(k) = map
        .keys()
        .find(|k| !["at", "curve", "end", "support"].contains(&k.as_str()))
    {
        return Err(format!(
            "unknown key \"{k}\" (expected \"at\", or \"curve\" and \"end\", and \"support\")"
        ));
    }
    let support = EndSupport::from_json(map.get("support").ok_or("no \"support\"")?)
        .map_err(|e| format!("\"support\": {e}"))?;
    let place = match (map.get("at"), map.get("curve"), map.get("end")) {
        (Some(at), None, None) => {
            let p: [f64; 3] = serde_json::from_value(at.clone())
                .map_err(|_| "\"at\" must be a point [x, y, z]".to_string())?;
            if p.iter().any(|c| !c.is_finite()) {
                return Err("\"at\" must be a finite point".into());
            }
            EndPlace::Point(p)
        }
        (None, Some(c), Some(e)) => {
            let curve = c.as_u64().ok_or("\"curve\" must be a curve id (0, 1, …)")?;
            let at_start = match e.as_str() {
                Some("start") => true,
                Some("end") => false,
                _ => return Err("\"end\" must be \"start\" or \"end\"".into()),
            };
            EndPlace::CurveEnd {
                curve: usize::try_from(curve).map_err(|_| "\"curve\" is out of range")?,
                at_start,
            }
        }
        _ => {
            return Err(
                "name the end by \"at\": [x, y, z], or by \"curve\" and \"end\" (not both)".into(),
            );
        }
    };
    Ok((place, support))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_carry_their_lines() {
        let text = r#"{"format": "curvenet-supports", "version": 1,
 "supports": [
   {"at": [0, 0, 0], "support": "clamped"},
   {"curve": 3, "end": "end",
    "support": {"fixed": "yz"}}
 ]}"#;
        let e = parse_supports_file(text, "s.json").unwrap();
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].place, EndPlace::Point([0.0; 3]));
        assert_eq!(e[0].support, EndSupport::CLAMPED);
        assert_eq!(e[0].line, 3);
        assert_eq!(
            e[1].place,
            EndPlace::CurveEnd {
                curve: 3,
                at_start: false
            }
        );
        assert_eq!(e[1].line, 4);
    }

    #[test]
    fn mistakes_name_the_line() {
        for (entry, phrase) in [
            (
                r#"{"at": [0, 0], "support": "pinned"}"#,
                "a point [x, y, z]",
            ),
            (r#"{"at": [0, 0, 0]}"#, "no \"support\""),
            (
                r#"{"at": [0, 0, 0], "support": "hinged"}"#,
                "unknown support",
            ),
            (r#"{"curve": 1, "support": "free"}"#, "name the end"),
            (
                r#"{"curve": 1, "end": "middle", "support": "free"}"#,
                "\"start\" or \"end\"",
            ),
            (
                r#"{"at": [0, 0, 0], "support": "free", "fixed": "x"}"#,
                "unknown key",
            ),
        ] {
            let text = format!(
                "{{\"format\": \"curvenet-supports\", \"version\": 1,\n\"supports\": [\n{entry}]}}"
            );
            let e = parse_supports_file(&text, "s.json")
                .unwrap_err()
                .to_string();
            assert!(e.contains("s.json:3") && e.contains(phrase), "{e}");
        }
        let e = parse_supports_file(r#"{"format": "curvenet-curves", "version": 1}"#, "s.json")
            .unwrap_err()
            .to_string();
        assert!(e.contains("curvenet-supports"), "{e}");
    }
}

//! How one end of a curve is held: which of its translations are fixed (along the scene's x,
//! y and z axes) and whether its rotation is held (a clamp) or free (a pin). A curve file gives
//! them per curve end (`"supports": {"start": …, "end": …}`) and a supports file by point or by
//! curve end; without them every open end has the run's supports (`clamped` or `pinned`).
//!
//! Written forms: `"clamped"` (x, y and z fixed, rotation held), `"pinned"` (x, y and z fixed,
//! rotation free), `"free"` (nothing held), or an object `{"fixed": "yz", "rotation": "held"}`:
//! `fixed` names the fixed translations (any of `x`, `y`, `z`, or `""` for none), `rotation`
//! is `held` or `free` (default `free`). An end whose rotation is held and whose translations
//! are all free keeps its tangent and may move anywhere (a guided end).

use serde::{Deserialize, Serialize};

/// How one curve end is held.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EndSupport {
    /// Fixed translations along x, y and z.
    pub fixed: [bool; 3],
    /// Whether the end's rotation (its tangent, and a pre-bent rod's twist) is held.
    pub rotation_held: bool,
}

impl EndSupport {
    /// Every translation fixed and the rotation held.
    pub const CLAMPED: EndSupport = EndSupport {
        fixed: [true; 3],
        rotation_held: true,
    };
    /// Every translation fixed, the rotation free.
    pub const PINNED: EndSupport = EndSupport {
        fixed: [true; 3],
        rotation_held: false,
    };
    /// Nothing held.
    pub const FREE: EndSupport = EndSupport {
        fixed: [false; 3],
        rotation_held: false,
    };

    /// Whether the end is held at all (a free end is not a support).
    pub fn is_support(&self) -> bool {
        self.rotation_held || self.fixed.iter().any(|&f| f)
    }

    /// The fixed translations as written (`"xyz"`, `"yz"`, `""`).
    pub fn fixed_axes(&self) -> String {
        ["x", "y", "z"]
            .iter()
            .zip(self.fixed)
            .filter(|(_, f)| *f)
            .map(|(a, _)| *a)
            .collect()
    }

    /// Its short name: `clamped`, `pinned`, `free`, or e.g. `yz fixed; rotation held` (no
    /// comma: it stands in tables' cells).
    pub fn name(&self) -> String {
        match *self {
            EndSupport::CLAMPED => "clamped".into(),
            EndSupport::PINNED => "pinned".into(),
            EndSupport::FREE => "free".into(),
            _ => {
                let axes = self.fixed_axes();
                let fixed = if axes.is_empty() {
                    "no translation fixed".to_string()
                } else {
                    format!("{axes} fixed")
                };
                let rotation = if self.rotation_held { "held" } else { "free" };
                format!("{fixed}; rotation {rotation}")
            }
        }
    }

    /// Reads one end's support from its JSON value (a name or an object).
    ///
    /// # Errors
    ///
    /// A message saying what is wrong (an unknown name, an axis other than x, y, z, an
    /// unknown key or rotation).
    pub fn from_json(v: &serde_json::Value) -> Result<EndSupport, SupportError> {
        match v {
            serde_json::Value::String(s) => match s.as_str() {
                "clamped" => Ok(EndSupport::CLAMPED),
                "pinned" => Ok(EndSupport::PINNED),
                "free" => Ok(EndSupport::FREE),
                _ => Err(SupportError(format!(
                    "unknown support \"{s}\" (expected clamped, pinned, free or an object \
                     {{\"fixed\": \"xyz\", \"rotation\": \"held\"}})"
                ))),
            },
            serde_json::Value::Object(map) => {
                let mut out = EndSupport::FREE;
                for (k, val) in map {
                    match (k.as_str(), val) {
                        ("fixed", serde_json::Value::String(axes)) => {
                            out.fixed = parse_axes(axes)?;
                        }
                        ("rotation", serde_json::Value::String(r)) => {
                            out.rotation_held = match r.as_str() {
                                "held" => true,
                                "free" => false,
                                _ => {
                                    return Err(SupportError(format!(
                                        "unknown rotation \"{r}\" (expected held or free)"
                                    )));
                                }
                            };
                        }
                        ("fixed" | "rotation", _) => {
                            return Err(SupportError(format!("\"{k}\" must be a string")));
                        }
                        _ => {
                            return Err(SupportError(format!(
                                "unknown key \"{k}\" in a support (expected \"fixed\" and \
                                 \"rotation\")"
                            )));
                        }
                    }
                }
                Ok(out)
            }
            _ => Err(SupportError(
                "a support is a name (clamped, pinned, free) or an object {\"fixed\": \"xyz\", \
                 \"rotation\": \"held\"}"
                    .into(),
            )),
        }
    }

    /// The JSON value [`Self::from_json`] reads back.
    pub fn to_json(&self) -> serde_json::Value {
        match *self {
            EndSupport::CLAMPED | EndSupport::PINNED | EndSupport::FREE => {
                serde_json::Value::String(self.name())
            }
            _ => serde_json::json!({
                "fixed": self.fixed_axes(),
                "rotation": if self.rotation_held { "held" } else { "free" },
            }),
        }
    }
}

/// The axes named in `s` (`"xz"`), each at most once.
fn parse_axes(s: &str) -> Result<[bool; 3], SupportError> {
    let mut out = [false; 3];
    for c in s.chars() {
        let i = match c {
            'x' | 'X' => 0,
            'y' | 'Y' => 1,
            'z' | 'Z' => 2,
            _ => {
                return Err(SupportError(format!(
                    "\"fixed\": \"{s}\" names '{c}', not an axis (expected any of x, y, z)"
                )));
            }
        };
        if out[i] {
            return Err(SupportError(format!(
                "\"fixed\": \"{s}\" names '{c}' twice"
            )));
        }
        out[i] = true;
    }
    Ok(out)
}

impl Serialize for EndSupport {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.to_json().serialize(s)
    }
}

impl<'de> Deserialize<'de> for EndSupport {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        EndSupport::from_json(&v).map_err(serde::de::Error::custom)
    }
}

/// Reads a curve's `"supports"` field: `{"start": …, "end": …}` (an end left out has the
/// run's supports: `None`), or one support for both ends.
///
/// # Errors
///
/// What is wrong with it.
pub fn ends_from_json(v: &serde_json::Value) -> Result<[Option<EndSupport>; 2], SupportError> {
    match v {
        serde_json::Value::Object(map) if map.keys().all(|k| k == "start" || k == "end") => {
            let mut out = [None; 2];
            for (k, val) in map {
                let i = usize::from(k == "end");
                out[i] = Some(
                    EndSupport::from_json(val)
                        .map_err(|e| SupportError(format!("\"{k}\": {}", e.0)))?,
                );
            }
            Ok(out)
        }
        _ => {
            let one = EndSupport::from_json(v)?;
            Ok([Some(one); 2])
        }
    }
}

/// What is wrong with a written support.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct SupportError(pub String);

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn names_and_objects_round_trip() {
        for s in [
            EndSupport::CLAMPED,
            EndSupport::PINNED,
            EndSupport::FREE,
            EndSupport {
                fixed: [false, true, true],
                rotation_held: true,
            },
            EndSupport {
                fixed: [false; 3],
                rotation_held: true,
            },
        ] {
            assert_eq!(EndSupport::from_json(&s.to_json()).unwrap(), s);
        }
        assert_eq!(
            EndSupport::from_json(&json!({"fixed": "zy"})).unwrap(),
            EndSupport {
                fixed: [false, true, true],
                rotation_held: false
            }
        );
        let ends = ends_from_json(&json!({"end": "free"})).unwrap();
        assert_eq!(ends, [None, Some(EndSupport::FREE)]);
        assert_eq!(
            ends_from_json(&json!("pinned")).unwrap(),
            [Some(EndSupport::PINNED); 2]
        );
    }

    #[test]
    fn mistakes_are_named() {
        for (v, phrase) in [
            (json!("hinged"), "unknown support \"hinged\""),
            (json!({"fixed": "xw"}), "'w', not an axis"),
            (json!({"fixed": "xx"}), "'x' twice"),
            (json!({"rotation": "locked"}), "unknown rotation"),
            (json!({"fix": "x"}), "unknown key \"fix\""),
            (json!(3), "a name"),
        ] {
            let e = EndSupport::from_json(&v).unwrap_err();
            assert!(e.0.contains(phrase), "{v}: {e}");
        }
        let e = ends_from_json(&json!({"start": "hinged"})).unwrap_err();
        assert!(e.0.starts_with("\"start\": unknown support"), "{e}");
    }
}

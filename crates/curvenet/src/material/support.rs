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
//!
//! `fixed` may also be a list of directions, world axes and directions taken from the surface
//! at the end ([`SurfaceDirection`]): `{"fixed": ["boundary-normal", "surface-normal"]}` holds
//! an end on the surface's boundary and lets it slide along it. The surface's directions are
//! resolved against the mesh when the network is built (`app::ends`).

use serde::{Deserialize, Serialize};

/// A direction taken from the surface at a curve end, in which a support may fix the end's
/// translation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SurfaceDirection {
    /// Along the surface's boundary: its tangent at the boundary point nearest the end.
    BoundaryTangent,
    /// Across the boundary: in the surface's tangent plane, normal to the boundary.
    BoundaryNormal,
    /// Normal to the surface.
    SurfaceNormal,
}

impl SurfaceDirection {
    /// The three, in the order of [`EndSupport::surface`].
    pub const ALL: [SurfaceDirection; 3] = [
        SurfaceDirection::BoundaryTangent,
        SurfaceDirection::BoundaryNormal,
        SurfaceDirection::SurfaceNormal,
    ];

    /// As written in a `fixed` list.
    pub fn name(self) -> &'static str {
        match self {
            SurfaceDirection::BoundaryTangent => "boundary-tangent",
            SurfaceDirection::BoundaryNormal => "boundary-normal",
            SurfaceDirection::SurfaceNormal => "surface-normal",
        }
    }

    /// Whether the direction needs the end on the surface's boundary.
    pub fn needs_boundary(self) -> bool {
        self != SurfaceDirection::SurfaceNormal
    }
}

/// The surface's directions at one curve end (unit vectors, in the order of
/// [`SurfaceDirection::ALL`]: along the boundary, across it in the surface's tangent plane,
/// normal to the surface), resolved against the mesh by `app::ends`; a direction the end's
/// support does not use may be zero.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EndFrame(pub [[f64; 3]; 3]);

impl EndFrame {
    /// The unit vectors of the directions `support` fixes.
    pub fn fixed_directions(&self, support: &EndSupport) -> Vec<[f64; 3]> {
        (0..3)
            .filter(|&i| support.surface[i])
            .map(|i| self.0[i])
            .collect()
    }
}

/// How one curve end is held.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EndSupport {
    /// Fixed translations along x, y and z.
    pub fixed: [bool; 3],
    /// Fixed translations along the surface's directions at the end, in the order of
    /// [`SurfaceDirection::ALL`] (along the boundary, across it, normal to the surface).
    pub surface: [bool; 3],
    /// Whether the end's rotation (its tangent, and a pre-bent rod's twist) is held.
    pub rotation_held: bool,
}

impl EndSupport {
    /// Every translation fixed and the rotation held.
    pub const CLAMPED: EndSupport = EndSupport {
        fixed: [true; 3],
        surface: [false; 3],
        rotation_held: true,
    };
    /// Every translation fixed, the rotation free.
    pub const PINNED: EndSupport = EndSupport {
        fixed: [true; 3],
        surface: [false; 3],
        rotation_held: false,
    };
    /// Nothing held.
    pub const FREE: EndSupport = EndSupport {
        fixed: [false; 3],
        surface: [false; 3],
        rotation_held: false,
    };

    /// Whether the end is held at all (a free end is not a support).
    pub fn is_support(&self) -> bool {
        self.rotation_held || self.fixed.iter().chain(&self.surface).any(|&f| f)
    }

    /// Whether it fixes a translation along a direction of the surface (it needs the mesh).
    pub fn uses_surface(&self) -> bool {
        self.surface.iter().any(|&f| f)
    }

    /// The surface's directions it fixes.
    pub fn surface_directions(&self) -> impl Iterator<Item = SurfaceDirection> + '_ {
        SurfaceDirection::ALL
            .into_iter()
            .zip(self.surface)
            .filter(|(_, f)| *f)
            .map(|(d, _)| d)
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
                let mut axes = self.fixed_axes();
                for d in self.surface_directions() {
                    if !axes.is_empty() {
                        axes.push(' ');
                    }
                    axes.push_str(d.name());
                }
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
                        ("fixed", serde_json::Value::Array(names)) => {
                            (out.fixed, out.surface) = parse_directions(names)?;
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
                        ("fixed", _) => {
                            return Err(SupportError(
                                "\"fixed\" must be a string of axes (\"xz\") or a list of \
                                 directions ([\"x\", \"surface-normal\"])"
                                    .into(),
                            ));
                        }
                        ("rotation", _) => {
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
            _ => {
                let rotation = if self.rotation_held { "held" } else { "free" };
                if self.uses_surface() {
                    let names: Vec<&str> = ["x", "y", "z"]
                        .into_iter()
                        .zip(self.fixed)
                        .filter(|(_, f)| *f)
                        .map(|(a, _)| a)
                        .chain(self.surface_directions().map(SurfaceDirection::name))
                        .collect();
                    serde_json::json!({"fixed": names, "rotation": rotation})
                } else {
                    serde_json::json!({"fixed": self.fixed_axes(), "rotation": rotation})
                }
            }
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

/// The world axes and surface directions named in a `fixed` list, each at most once.
fn parse_directions(names: &[serde_json::Value]) -> Result<([bool; 3], [bool; 3]), SupportError> {
    let (mut axes, mut surface) = ([false; 3], [false; 3]);
    for v in names {
        let Some(name) = v.as_str() else {
            return Err(SupportError(format!(
                "\"fixed\": {v} is not a direction's name (expected x, y, z, boundary-tangent, \
                 boundary-normal or surface-normal)"
            )));
        };
        let slot = match name {
            "x" | "X" => &mut axes[0],
            "y" | "Y" => &mut axes[1],
            "z" | "Z" => &mut axes[2],
            "boundary-tangent" => &mut surface[0],
            "boundary-normal" => &mut surface[1],
            "surface-normal" => &mut surface[2],
            _ => {
                return Err(SupportError(format!(
                    "\"fixed\" names \"{name}\", not a direction (expected x, y, z, \
                     boundary-tangent, boundary-normal or surface-normal)"
                )));
            }
        };
        if *slot {
            return Err(SupportError(format!("\"fixed\" names \"{name}\" twice")));
        }
        *slot = true;
    }
    Ok((axes, surface))
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
                ..EndSupport::FREE
            },
            EndSupport {
                fixed: [false; 3],
                rotation_held: true,
                ..EndSupport::FREE
            },
            EndSupport {
                fixed: [false, false, true],
                surface: [false, true, false],
                rotation_held: false,
            },
            EndSupport {
                surface: [true, false, true],
                rotation_held: true,
                ..EndSupport::FREE
            },
        ] {
            assert_eq!(EndSupport::from_json(&s.to_json()).unwrap(), s);
        }
        assert_eq!(
            EndSupport::from_json(&json!({"fixed": "zy"})).unwrap(),
            EndSupport {
                fixed: [false, true, true],
                ..EndSupport::FREE
            }
        );
        assert_eq!(
            EndSupport::from_json(&json!({"fixed": ["boundary-normal", "surface-normal"]}))
                .unwrap(),
            EndSupport {
                surface: [false, true, true],
                ..EndSupport::FREE
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
            (json!({"fixed": ["along"]}), "\"along\", not a direction"),
            (json!({"fixed": ["x", "x"]}), "\"x\" twice"),
            (json!({"fixed": [1]}), "not a direction's name"),
            (json!({"fixed": 3}), "a list of directions"),
            (json!(3), "a name"),
        ] {
            let e = EndSupport::from_json(&v).unwrap_err();
            assert!(e.0.contains(phrase), "{v}: {e}");
        }
        let e = ends_from_json(&json!({"start": "hinged"})).unwrap_err();
        assert!(e.0.starts_with("\"start\": unknown support"), "{e}");
    }
}

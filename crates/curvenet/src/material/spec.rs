//! What a curve file or the command line says about a curve's material, section and rest
//! shape, before the scene's unit is known.
//!
//! In curvenet's JSON curve format a curve may carry
//!
//! ```json
//! {"points": [...],
//!  "material": "aluminium",                      // a preset, or
//!  "material": {"preset": "steel", "strength": "460MPa", "young": "200GPa",
//!               "density": "7900kg/m3", "poisson": 0.3},  // a preset (default: the run's) and overrides
//!  "section": {"radius": 10},                    // solid bar; numbers in scene units, or
//!  "section": {"outer_diameter": "60mm", "wall": "4mm"},   // a tube, with units
//!  "rest": "pre-bent"}                           // or "straight" (the default)
//! ```
//!
//! Moduli, densities and strengths need their unit (`"210GPa"`); Poisson's ratio is a plain
//! number; lengths are scene units unless they carry one.

use super::support::{EndSupport, ends_from_json};
use super::{PhysicalMaterial, RestShape, Section, presets};
use crate::units::{LengthUnit, Quantity, parse_quantity};
use crate::words::{Message, Piece, message};
use serde_json::Value;

/// A length as written: in scene units, or in metres (it had a unit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Length {
    /// Scene units (a bare number).
    Scene(f64),
    /// Metres (written with a unit: `10mm`).
    Metres(f64),
}

impl Length {
    /// A length given as text: a bare number is in scene units, a suffix (`mm`, `cm`, `m`)
    /// gives metres.
    ///
    /// # Errors
    ///
    /// A message naming `what` (an option or a file's field) for anything
    /// [`parse_quantity`] rejects.
    pub fn parse(text: &str, what: impl Into<Piece>) -> Result<Length, Message> {
        let (_, suffix) = crate::units::split_number(text);
        let v = parse_quantity(text, Quantity::Length, what, Some(1.0))?;
        Ok(if suffix.is_empty() {
            Length::Scene(v)
        } else {
            Length::Metres(v)
        })
    }

    /// The length in scene units.
    pub fn to_scene(self, units: LengthUnit) -> f64 {
        match self {
            Length::Scene(v) => v,
            Length::Metres(v) => v / units.metres(),
        }
    }
}

/// A section as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SectionSpec {
    /// A solid round bar.
    Solid {
        /// Radius.
        radius: Length,
    },
    /// A round tube.
    Tube {
        /// Outer diameter.
        outer_diameter: Length,
        /// Wall thickness.
        wall: Length,
    },
}

impl SectionSpec {
    /// The section in scene units.
    pub fn resolve(&self, units: LengthUnit) -> Section {
        match *self {
            SectionSpec::Solid { radius } => Section::Solid {
                radius: radius.to_scene(units),
            },
            SectionSpec::Tube {
                outer_diameter,
                wall,
            } => Section::Tube {
                outer_diameter: outer_diameter.to_scene(units),
                wall: wall.to_scene(units),
            },
        }
    }

    /// A tube written as `DxT` (outer diameter × wall), e.g. `60x4` or `60mm x 4mm`.
    ///
    /// # Errors
    ///
    /// A message naming `what` (an option or a file's field) when the text is not two
    /// lengths joined by `x` or `×`.
    pub fn parse_tube(text: &str, what: impl Into<Piece>) -> Result<SectionSpec, Message> {
        let what: Piece = what.into();
        let parts: Vec<&str> = text.split(['x', 'X', '×', '*']).collect();
        let [d, t] = parts.as_slice() else {
            return Err(message![
                what.with_value(format!("{text:?}")),
                ": expected the outer diameter and the wall joined by x, e.g. 60x4 or 60mmx4mm"
            ]);
        };
        Ok(SectionSpec::Tube {
            outer_diameter: Length::parse(d, what.clone())?,
            wall: Length::parse(t, what)?,
        })
    }
}

/// A material as written: a preset (default: the run's material) and overrides, in SI.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialSpec {
    /// Preset name.
    pub preset: Option<String>,
    /// Young's modulus, Pa.
    pub young_pa: Option<f64>,
    /// Density, kg/m³.
    pub density_kg_m3: Option<f64>,
    /// Strength, Pa.
    pub strength_pa: Option<f64>,
    /// Poisson's ratio.
    pub poisson: Option<f64>,
}

impl MaterialSpec {
    /// The material: the preset's values (or `base`'s when no preset is named) with the
    /// overrides applied; its name says when an override changed a preset.
    ///
    /// # Errors
    ///
    /// An unknown preset, or a value that is not positive.
    pub fn resolve(&self, base: &PhysicalMaterial) -> Result<PhysicalMaterial, Message> {
        let mut m = match &self.preset {
            Some(p) => presets::preset(p)?,
            None => base.clone(),
        };
        let mut changed = false;
        for (slot, v) in [
            (&mut m.young_pa, self.young_pa),
            (&mut m.density_kg_m3, self.density_kg_m3),
            (&mut m.strength_pa, self.strength_pa),
            (&mut m.poisson, self.poisson),
        ] {
            if let Some(v) = v {
                changed |= *slot != v;
                *slot = v;
            }
        }
        if changed && !m.name.ends_with("(modified)") && m.name != "custom" {
            m.name = format!("{} (modified)", m.name);
        }
        m.validate()?;
        Ok(m)
    }

    /// True when nothing is set.
    pub fn is_empty(&self) -> bool {
        *self == MaterialSpec::default()
    }
}

/// Everything a curve file says about one curve beyond its points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurveSpec {
    /// Its material.
    pub material: Option<MaterialSpec>,
    /// Its section.
    pub section: Option<SectionSpec>,
    /// Its rest shape.
    pub rest: Option<RestShape>,
    /// The supports of its start and its end (`None`: the run's supports).
    pub supports: [Option<EndSupport>; 2],
}

impl CurveSpec {
    /// True when the spec sets a material or a section (which need the physical mode).
    pub fn is_physical(&self) -> bool {
        self.material.is_some() || self.section.is_some()
    }

    /// True when nothing is set.
    pub fn is_empty(&self) -> bool {
        *self == CurveSpec::default()
    }

    /// The JSON curve fields that say this spec (`material`, `section`, `rest`, `supports`,
    /// those set), as [`Self::from_json`] reads them back: a saved design's curves.
    pub fn to_json_fields(&self) -> Vec<(&'static str, Value)> {
        let mut out = Vec::new();
        if let Some(m) = &self.material {
            out.push(("material", material_to_json(m)));
        }
        if let Some(s) = &self.section {
            let length = |l: Length| match l {
                Length::Scene(v) => serde_json::json!(v),
                Length::Metres(v) => Value::String(format!("{v}m")),
            };
            out.push((
                "section",
                match *s {
                    SectionSpec::Solid { radius } => serde_json::json!({"radius": length(radius)}),
                    SectionSpec::Tube {
                        outer_diameter,
                        wall,
                    } => serde_json::json!({
                        "outer_diameter": length(outer_diameter),
                        "wall": length(wall)
                    }),
                },
            ));
        }
        if let Some(r) = self.rest {
            let word = match r {
                RestShape::Straight => "straight",
                RestShape::PreBent => "pre-bent",
            };
            out.push(("rest", Value::String(word.into())));
        }
        match self.supports {
            [None, None] => {}
            [a, b] if a == b => out.push(("supports", a.map(|e| e.to_json()).unwrap_or_default())),
            [a, b] => {
                let mut map = serde_json::Map::new();
                for (key, end) in [("start", a), ("end", b)] {
                    if let Some(e) = end {
                        map.insert(key.into(), e.to_json());
                    }
                }
                out.push(("supports", Value::Object(map)));
            }
        }
        out
    }

    /// The spec of a JSON curve's `material`, `section`, `rest` and `supports` fields (each
    /// optional).
    ///
    /// # Errors
    ///
    /// A message naming the field for a wrong type, an unknown key, an unknown preset or rest
    /// shape, a value without its unit, or a unit that does not fit.
    pub fn from_json(
        material: Option<&Value>,
        section: Option<&Value>,
        rest: Option<&Value>,
        supports: Option<&Value>,
    ) -> Result<CurveSpec, Message> {
        Ok(CurveSpec {
            material: material.map(material_from_json).transpose()?,
            section: section.map(section_from_json).transpose()?,
            rest: rest
                .map(|v| match v {
                    Value::String(s) => {
                        s.parse::<RestShape>().map_err(|e| format!("\"rest\": {e}"))
                    }
                    other => Err(format!(
                        "\"rest\" must be \"straight\" or \"pre-bent\", got {other}"
                    )),
                })
                .transpose()?,
            supports: match supports {
                Some(v) => ends_from_json(v).map_err(|e| format!("\"supports\": {e}"))?,
                None => [None; 2],
            },
        })
    }
}

/// `m` as a `material` field: its preset's name alone, or an object of the preset and the
/// overrides, each with its unit.
fn material_to_json(m: &MaterialSpec) -> Value {
    let only_preset = MaterialSpec {
        preset: m.preset.clone(),
        ..MaterialSpec::default()
    };
    if let (Some(p), true) = (&m.preset, *m == only_preset) {
        return Value::String(p.clone());
    }
    let mut map = serde_json::Map::new();
    if let Some(p) = &m.preset {
        map.insert("preset".into(), Value::String(p.clone()));
    }
    for (key, v, unit) in [
        ("young", m.young_pa, "Pa"),
        ("density", m.density_kg_m3, "kg/m3"),
        ("strength", m.strength_pa, "Pa"),
    ] {
        if let Some(v) = v {
            map.insert(key.into(), Value::String(format!("{v}{unit}")));
        }
    }
    if let Some(nu) = m.poisson {
        map.insert("poisson".into(), serde_json::json!(nu));
    }
    Value::Object(map)
}

/// A `material` field: a preset name, or an object of `preset`, `young`, `density`,
/// `strength`, `poisson`.
fn material_from_json(v: &Value) -> Result<MaterialSpec, Message> {
    match v {
        Value::String(name) => {
            presets::preset(name).map_err(|e| format!("\"material\": {e}"))?;
            Ok(MaterialSpec {
                preset: Some(name.clone()),
                ..MaterialSpec::default()
            })
        }
        Value::Object(map) => {
            let mut spec = MaterialSpec::default();
            for (key, value) in map {
                let what = format!("\"material\".\"{key}\"");
                let quantity = |kind| -> Result<f64, Message> {
                    let Value::String(text) = value else {
                        return Err(format!(
                            "{what} must be a string with its unit (e.g. \"210GPa\"), got \
                             {value}"
                        )
                        .into());
                    };
                    parse_quantity(text, kind, what.as_str(), None)
                };
                match key.as_str() {
                    "preset" => {
                        let Value::String(name) = value else {
                            return Err(format!("{what} must be a preset name, got {value}").into());
                        };
                        presets::preset(name).map_err(|e| format!("{what}: {e}"))?;
                        spec.preset = Some(name.clone());
                    }
                    "young" => spec.young_pa = Some(quantity(Quantity::Stress)?),
                    "density" => spec.density_kg_m3 = Some(quantity(Quantity::Density)?),
                    "strength" => spec.strength_pa = Some(quantity(Quantity::Stress)?),
                    "poisson" => {
                        let Some(nu) = value.as_f64() else {
                            return Err(format!(
                                "{what} must be a number (Poisson's ratio, e.g. 0.3), got {value}"
                            )
                            .into());
                        };
                        spec.poisson = Some(nu);
                    }
                    other => {
                        return Err(format!(
                            "\"material\": unknown field \"{other}\" (expected preset, young, \
                             density, strength, poisson)"
                        )
                        .into());
                    }
                }
            }
            Ok(spec)
        }
        other => {
            Err(format!("\"material\" must be a preset name or an object, got {other}").into())
        }
    }
}

/// A `section` field: `{"radius": r}` or `{"outer_diameter": d, "wall": t}`.
fn section_from_json(v: &Value) -> Result<SectionSpec, Message> {
    let Value::Object(map) = v else {
        return Err(format!(
            "\"section\" must be an object ({{\"radius\": r}} or {{\"outer_diameter\": d, \
             \"wall\": t}}), got {v}"
        )
        .into());
    };
    let length = |key: &str| -> Result<Option<Length>, Message> {
        let what = format!("\"section\".\"{key}\"");
        match map.get(key) {
            None => Ok(None),
            Some(Value::Number(n)) => Ok(Some(Length::Scene(n.as_f64().unwrap_or(f64::NAN)))),
            Some(Value::String(s)) => Length::parse(s, what.as_str()).map(Some),
            Some(other) => Err(format!(
                "{what} must be a number (scene units) or a length with its unit, got {other}"
            )
            .into()),
        }
    };
    if let Some(k) = map
        .keys()
        .find(|k| !["radius", "outer_diameter", "wall"].contains(&k.as_str()))
    {
        return Err(format!(
            "\"section\": unknown field \"{k}\" (expected radius, or outer_diameter and wall)"
        )
        .into());
    }
    match (
        length("radius")?,
        length("outer_diameter")?,
        length("wall")?,
    ) {
        (Some(radius), None, None) => Ok(SectionSpec::Solid { radius }),
        (None, Some(outer_diameter), Some(wall)) => Ok(SectionSpec::Tube {
            outer_diameter,
            wall,
        }),
        _ => Err(
            "\"section\" needs either \"radius\" or both \"outer_diameter\" and \"wall\"".into(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::words::Opt;

    fn json(text: &str) -> Value {
        serde_json::from_str(text).unwrap()
    }

    #[test]
    fn json_specs_parse() {
        let m = json(r#"{"preset": "steel", "strength": "460MPa"}"#);
        let s = json(r#"{"outer_diameter": "60mm", "wall": 4}"#);
        let r = json(r#""pre-bent""#);
        let spec = CurveSpec::from_json(Some(&m), Some(&s), Some(&r), None).unwrap();
        assert_eq!(spec.rest, Some(RestShape::PreBent));
        assert_eq!(spec.material.as_ref().unwrap().strength_pa, Some(460e6));
        assert_eq!(
            spec.section,
            Some(SectionSpec::Tube {
                outer_diameter: Length::Metres(0.06),
                wall: Length::Scene(4.0)
            })
        );
        assert!(spec.is_physical());
        let only_rest = CurveSpec::from_json(None, None, Some(&r), None).unwrap();
        assert!(!only_rest.is_physical() && !only_rest.is_empty());
        let name = CurveSpec::from_json(Some(&json(r#""timber""#)), None, None, None).unwrap();
        assert_eq!(name.material.unwrap().preset.as_deref(), Some("timber"));
    }

    #[test]
    fn bad_json_specs_name_the_field() {
        let cases = [
            (r#""unobtainium""#, "unknown material"),
            (r#"{"young": 210}"#, "with its unit"),
            (r#"{"young": "7850kg/m3"}"#, "density"),
            (r#"{"density": "-5kg/m3"}"#, ""),
            (r#"{"colour": "red"}"#, "unknown field"),
            (r#"42"#, "preset name or an object"),
        ];
        for (text, needle) in cases {
            let v = json(text);
            match CurveSpec::from_json(Some(&v), None, None, None) {
                Err(e) => assert!(e.to_string().contains(needle), "{text}: {e}"),
                // A negative density parses; it is rejected when the material is resolved.
                Ok(spec) => {
                    let steel = presets::preset("steel").unwrap();
                    let e = spec
                        .material
                        .unwrap()
                        .resolve(&steel)
                        .unwrap_err()
                        .to_string();
                    assert!(e.contains("density"), "{text}: {e}");
                }
            }
        }
        for (text, needle) in [
            (r#"{"radius": 1, "wall": 2}"#, "either"),
            (r#"{"radius": "10kg"}"#, "unknown unit"),
            (r#"{"radius": "10GPa"}"#, "stress"),
            (r#"{"diameter": 3}"#, "unknown field"),
            (r#"[1, 2]"#, "must be an object"),
        ] {
            let e = CurveSpec::from_json(None, Some(&json(text)), None, None)
                .unwrap_err()
                .to_string();
            assert!(e.contains(needle), "{text}: {e}");
        }
        let e = CurveSpec::from_json(None, None, Some(&json("3")), None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("rest"), "{e}");
        let e = CurveSpec::from_json(None, None, Some(&json(r#""wavy""#)), None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown rest shape"), "{e}");
    }

    #[test]
    fn tubes_and_lengths_parse() {
        assert_eq!(
            SectionSpec::parse_tube("60x4", Opt::Tube),
            Ok(SectionSpec::Tube {
                outer_diameter: Length::Scene(60.0),
                wall: Length::Scene(4.0)
            })
        );
        let t = SectionSpec::parse_tube("60mm × 4mm", Opt::Tube).unwrap();
        assert_eq!(
            t.resolve(LengthUnit::Millimetre),
            Section::Tube {
                outer_diameter: 60.0,
                wall: 4.0
            }
        );
        assert!(SectionSpec::parse_tube("60", Opt::Tube).is_err());
        assert!(SectionSpec::parse_tube("60x4x2", Opt::Tube).is_err());
        let r = Length::parse("1.5cm", Opt::Radius).unwrap();
        assert!((r.to_scene(LengthUnit::Millimetre) - 15.0).abs() < 1e-12);
    }
}

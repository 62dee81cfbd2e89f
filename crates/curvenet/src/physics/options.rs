//! The physical mode's options as a user writes them (`--units`, `--material`, `--young`,
//! `--density`, `--strength`, `--radius`, `--tube`, `--load`, `--gravity`), turned into
//! [`PhysicalParams`]: one place for the command line and any other front end.

use super::analysis::PhysicalParams;
use crate::material::{
    self, CurveSpec, DENSITY_RANGE_KG_M3, LINE_LOAD_RANGE_N_PER_M, Physical, STRESS_RANGE_PA,
    SectionSpec, presets,
};
use crate::rod::Material;
use crate::units::{LengthUnit, Quantity, STANDARD_GRAVITY, parse_quantity};

/// The material of `--units` without `--material`.
pub const DEFAULT_MATERIAL: &str = "steel";

/// The physical mode's options, as text (`None`: not given). A run folder records them as
/// given (`result.json`'s `setup.physical`), and a resumed run must give the same.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhysicalOptions {
    /// `--units mm|cm|m`: the scene's length unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub units: Option<String>,
    /// `--material NAME`: a preset.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// `--young` with a stress unit (`210GPa`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub young: Option<String>,
    /// `--density` with a density unit (`7850kg/m3`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub density: Option<String>,
    /// `--strength` with a stress unit (`355MPa`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub strength: Option<String>,
    /// `--radius`: a solid round section (scene units, or with a length unit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<String>,
    /// `--tube DxT`: a round tube, outer diameter × wall.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tube: Option<String>,
    /// `--load`: the worst-case distributed load's intensity (`1kN/m`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load: Option<String>,
    /// `--gravity`: `9.81` (along −z) or `gx,gy,gz`, m/s².
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gravity: Option<String>,
}

impl PhysicalOptions {
    /// True when an option that turns on the physical mode is given (`--units` or
    /// `--material`).
    pub fn is_physical(&self) -> bool {
        self.units.is_some() || self.material.is_some()
    }

    /// The physical parameters, or `None` in the paper's mode. `file_units` is a length unit
    /// a curve file declared (used when `--units` is not given; `--units` wins), `specs` the
    /// curve files' per-curve material, section and rest shape (curve `c` at `specs[c]`).
    ///
    /// The physical mode is on when the options give `--units` or `--material`, when the
    /// curve file declares its `units`, or when a curve carries its own material or section:
    /// nothing a file says is ignored.
    ///
    /// # Errors
    ///
    /// A message naming the option for an unknown unit or material, a value without its unit
    /// or with another quantity's, a non-positive value, or a missing section; naming the
    /// curve when it sets a material or section (or a pre-bent rest shape) and no length unit
    /// is known.
    pub fn resolve(
        &self,
        file_units: Option<&str>,
        specs: &[CurveSpec],
    ) -> Result<Option<PhysicalParams>, String> {
        let file_physical = specs.iter().position(CurveSpec::is_physical);
        if !self.is_physical() && file_units.is_none() && file_physical.is_none() {
            for (name, given) in [
                ("--density", &self.density),
                ("--strength", &self.strength),
                ("--tube", &self.tube),
                ("--load", &self.load),
                ("--gravity", &self.gravity),
            ] {
                if given.is_some() {
                    return Err(format!(
                        "{name} belongs to the physical mode: give --units mm|cm|m and/or \
                         --material NAME ({})",
                        presets::names().join(", ")
                    ));
                }
            }
            if let Some(c) = specs
                .iter()
                .position(|s| s.rest == Some(material::RestShape::PreBent))
            {
                return Err(format!(
                    "curve {c} is pre-bent (\"rest\": \"pre-bent\"): rest shapes are analysed in \
                     the physical mode; give --units mm|cm|m (or the curve file's \"units\")"
                ));
            }
            return Ok(None);
        }
        let units: LengthUnit = match (&self.units, file_units) {
            (Some(u), _) => u.parse().map_err(|e| format!("--units: {e}"))?,
            (None, Some(u)) => u
                .parse()
                .map_err(|e| format!("the curve file's units: {e}"))?,
            (None, None) => {
                return Err(match (&self.material, file_physical) {
                    (None, Some(c)) => format!(
                        "curve {c} sets its own material or section, which needs the scene's \
                         length unit: give --units mm|cm|m (or the curve file's \"units\")"
                    ),
                    _ => "--material needs the scene's length unit: give --units mm|cm|m".into(),
                });
            }
        };
        let mut material = presets::preset(self.material.as_deref().unwrap_or(DEFAULT_MATERIAL))
            .map_err(|e| format!("--material: {e}"))?;
        let mut modified = false;
        for (name, given, slot) in [
            ("--young", &self.young, &mut material.young_pa),
            ("--density", &self.density, &mut material.density_kg_m3),
            ("--strength", &self.strength, &mut material.strength_pa),
        ] {
            if let Some(t) = given {
                *slot = quantity(name, t)?;
                modified = true;
            }
        }
        if modified {
            material.name = format!("{} (modified)", material.name);
        }
        let section = match (&self.radius, &self.tube) {
            (Some(_), Some(_)) => return Err("give --radius or --tube, not both".into()),
            (Some(r), None) => SectionSpec::Solid {
                radius: crate::material::spec::Length::parse(r, "--radius")?,
            },
            (None, Some(t)) => SectionSpec::parse_tube(t, "--tube")?,
            (None, None) => SectionSpec::Solid {
                radius: crate::material::spec::Length::Scene(Material::default().radius),
            },
        }
        .resolve(units);
        let section_option = if self.tube.is_some() {
            "--tube"
        } else {
            "--radius"
        };
        section
            .validate()
            .map_err(|e| format!("{section_option}: {e}"))?;
        let mut physical = Physical::uniform(units, material, section);
        if let Some(t) = &self.load {
            physical.load_n_per_m = quantity("--load", t)?;
        }
        if let Some(t) = &self.gravity {
            physical.gravity = parse_gravity(t)?;
        }
        // Validated with the curves' overrides.
        let physical = physical.with_curve_specs(specs)?;
        check_stiffness(&physical, specs, section_option)?;
        let mut params = PhysicalParams::new(physical);
        params.rest = specs.iter().map(|s| s.rest.unwrap_or_default()).collect();
        Ok(Some(params))
    }
}

/// The quantity, SI unit and accepted range of each option written with a unit
/// ([`crate::material`]'s bounds: far beyond any material, and keeping every stiffness, mass
/// and load within floating-point range).
const QUANTITIES: &[(&str, Quantity, &str, (f64, f64))] = &[
    ("--young", Quantity::Stress, "Pa", STRESS_RANGE_PA),
    ("--density", Quantity::Density, "kg/m3", DENSITY_RANGE_KG_M3),
    ("--strength", Quantity::Stress, "Pa", STRESS_RANGE_PA),
    ("--load", Quantity::LineLoad, "N/m", LINE_LOAD_RANGE_N_PER_M),
];

/// The largest gravity component accepted, m/s² (about 1000 g).
pub const MAX_GRAVITY: f64 = material::GRAVITY_RANGE.1;

/// `option`'s value (one of `--young`, `--density`, `--strength`, `--load`) in SI: a positive
/// number with its unit, within the option's range.
fn quantity(option: &str, text: &str) -> Result<f64, String> {
    let &(_, kind, si, (min, max)) = QUANTITIES
        .iter()
        .find(|q| q.0 == option)
        .expect("an option written with a unit");
    let v = parse_quantity(text, kind, option, None)?;
    if !(v > 0.0) {
        Err(format!("{option} {text:?} must be positive"))
    } else if !(min..=max).contains(&v) {
        Err(format!(
            "{option} {text:?} is {v:e} {si}, beyond any material (between {min:e} and {max:e} \
             {si})"
        ))
    } else {
        Ok(v)
    }
}

/// Refuses a section and material whose rods' stiffnesses (`E A`, `E I` in the scene's units)
/// leave [`crate::rod::STIFFNESS_RANGE`], naming the options that set them.
fn check_stiffness(physical: &Physical, specs: &[CurveSpec], section: &str) -> Result<(), String> {
    let (lo, hi) = crate::rod::STIFFNESS_RANGE;
    // The run's own rod (no override applies past the specs) and every curve's.
    for c in std::iter::once(specs.len()).chain(0..specs.len()) {
        let r = physical.scene_rod(c);
        for (name, k) in [("stretching", r.ks), ("bending", r.kb)] {
            if !(lo..=hi).contains(&k) {
                let whose = if c < specs.len() {
                    format!("curve {c}'s")
                } else {
                    format!("{section} and --young give a")
                };
                return Err(format!(
                    "{whose} {name} stiffness {k:e} (in the scene's units), out of the range \
                     the solvers handle ({lo:e} to {hi:e}): check the section's size against \
                     --units"
                ));
            }
        }
    }
    Ok(())
}

/// Checks one physical-mode option's text alone (`name` as on the command line, e.g.
/// `--density`), as [`PhysicalOptions::resolve`] reads it: a front end calls it while the
/// command line is parsed, so a bad value is refused before any work. `--young` here is the
/// physical mode's (with a unit); options this module does not know pass.
///
/// # Errors
///
/// The message [`PhysicalOptions::resolve`] would give for the value.
pub fn check_option(name: &str, text: &str) -> Result<(), String> {
    match name {
        "--units" => text
            .parse::<LengthUnit>()
            .map(|_| ())
            .map_err(|e| format!("--units: {e}")),
        "--material" => presets::preset(text)
            .map(|_| ())
            .map_err(|e| format!("--material: {e}")),
        "--tube" => SectionSpec::parse_tube(text, "--tube")?
            .resolve(LengthUnit::Metre)
            .validate()
            .map_err(|e| format!("--tube: {e}")),
        "--gravity" => parse_gravity(text).map(|_| ()),
        _ if QUANTITIES.iter().any(|q| q.0 == name) => quantity(name, text).map(|_| ()),
        _ => Ok(()),
    }
}

/// `--gravity`: one value (its magnitude along −z; 0 turns self-weight off) or three
/// (`gx,gy,gz`), m/s², bare or with `m/s2`.
fn parse_gravity(text: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = text.split(',').collect();
    let g = |t: &str| {
        let v = parse_quantity(t, Quantity::Acceleration, "--gravity", Some(1.0))?;
        if v.abs() > MAX_GRAVITY {
            return Err(format!(
                "--gravity {text:?}: {v:e} m/s2 is beyond {MAX_GRAVITY:e} m/s2 (about 1000 g)"
            ));
        }
        Ok(v)
    };
    // Gravity is off (0) or of a magnitude a structure can meet.
    let checked = |g: [f64; 3]| {
        let m = g.iter().fold(0.0_f64, |m, x| m.hypot(*x));
        let (min, _) = material::GRAVITY_RANGE;
        if m != 0.0 && m < min {
            return Err(format!(
                "--gravity {text:?}: a magnitude of {m:e} m/s2 is below {min:e} m/s2; give 0 to \
                 turn self-weight off"
            ));
        }
        Ok(g)
    };
    match parts.as_slice() {
        [one] => {
            let v = g(one)?;
            if v < 0.0 {
                return Err(format!(
                    "--gravity {text:?}: one value is the magnitude along -z (give gx,gy,gz for \
                     another direction)"
                ));
            }
            checked([0.0, 0.0, -v])
        }
        [x, y, z] => checked([g(x)?, g(y)?, g(z)?]),
        _ => Err(format!(
            "--gravity {text:?}: expected one value (along -z, default {STANDARD_GRAVITY}) or \
             three (gx,gy,gz) in m/s2"
        )),
    }
}

//! The physical mode's options as a user writes them (`--units`, `--material`, `--young`,
//! `--density`, `--strength`, `--radius`, `--tube`, `--load`, `--gravity`), turned into
//! [`PhysicalParams`]: one place for the command line and any other front end.

use super::analysis::PhysicalParams;
use crate::material::{CurveSpec, Physical, SectionSpec, presets};
use crate::rod::Material;
use crate::units::{LengthUnit, Quantity, STANDARD_GRAVITY, parse_quantity};

/// The material of `--units` without `--material`.
pub const DEFAULT_MATERIAL: &str = "steel";

/// The physical mode's options, as text (`None`: not given).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PhysicalOptions {
    /// `--units mm|cm|m`: the scene's length unit.
    pub units: Option<String>,
    /// `--material NAME`: a preset.
    pub material: Option<String>,
    /// `--young` with a stress unit (`210GPa`).
    pub young: Option<String>,
    /// `--density` with a density unit (`7850kg/m3`).
    pub density: Option<String>,
    /// `--strength` with a stress unit (`355MPa`).
    pub strength: Option<String>,
    /// `--radius`: a solid round section (scene units, or with a length unit).
    pub radius: Option<String>,
    /// `--tube DxT`: a round tube, outer diameter × wall.
    pub tube: Option<String>,
    /// `--load`: the worst-case distributed load's intensity (`1kN/m`).
    pub load: Option<String>,
    /// `--gravity`: `9.81` (along −z) or `gx,gy,gz`, m/s².
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
    /// # Errors
    ///
    /// A message naming the option for an unknown unit or material, a value without its unit
    /// or with another quantity's, a non-positive value, or a missing section.
    pub fn resolve(
        &self,
        file_units: Option<&str>,
        specs: &[CurveSpec],
    ) -> Result<Option<PhysicalParams>, String> {
        if !self.is_physical() {
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
            return Ok(None);
        }
        let units: LengthUnit = match (&self.units, file_units) {
            (Some(u), _) => u.parse().map_err(|e| format!("--units: {e}"))?,
            (None, Some(u)) => u
                .parse()
                .map_err(|e| format!("the curve file's units: {e}"))?,
            (None, None) => {
                return Err(
                    "--material needs the scene's length unit: give --units mm|cm|m".into(),
                );
            }
        };
        let mut material = presets::preset(self.material.as_deref().unwrap_or(DEFAULT_MATERIAL))
            .map_err(|e| format!("--material: {e}"))?;
        let mut modified = false;
        if let Some(t) = &self.young {
            material.young_pa = positive(
                parse_quantity(t, Quantity::Stress, "--young", None)?,
                "--young",
                t,
            )?;
            modified = true;
        }
        if let Some(t) = &self.density {
            material.density_kg_m3 = positive(
                parse_quantity(t, Quantity::Density, "--density", None)?,
                "--density",
                t,
            )?;
            modified = true;
        }
        if let Some(t) = &self.strength {
            material.strength_pa = positive(
                parse_quantity(t, Quantity::Stress, "--strength", None)?,
                "--strength",
                t,
            )?;
            modified = true;
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
        section.validate().map_err(|e| {
            format!(
                "{}: {e}",
                if self.tube.is_some() {
                    "--tube"
                } else {
                    "--radius"
                }
            )
        })?;
        let mut physical = Physical::uniform(units, material, section);
        if let Some(t) = &self.load {
            physical.load_n_per_m = positive(
                parse_quantity(t, Quantity::LineLoad, "--load", None)?,
                "--load",
                t,
            )?;
        }
        if let Some(t) = &self.gravity {
            physical.gravity = parse_gravity(t)?;
        }
        let physical = physical.with_curve_specs(specs)?;
        physical.validate()?;
        let mut params = PhysicalParams::new(physical);
        params.rest = specs.iter().map(|s| s.rest.unwrap_or_default()).collect();
        Ok(Some(params))
    }
}

/// `v` when it is positive, else a message naming the option.
fn positive(v: f64, what: &str, text: &str) -> Result<f64, String> {
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{what} {text:?} must be positive"))
    }
}

/// `--gravity`: one value (its magnitude along −z; 0 turns self-weight off) or three
/// (`gx,gy,gz`), m/s², bare or with `m/s2`.
fn parse_gravity(text: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = text.split(',').collect();
    let g = |t: &str| parse_quantity(t, Quantity::Acceleration, "--gravity", Some(1.0));
    match parts.as_slice() {
        [one] => {
            let v = g(one)?;
            if v < 0.0 {
                return Err(format!(
                    "--gravity {text:?}: one value is the magnitude along -z (give gx,gy,gz for \
                     another direction)"
                ));
            }
            Ok([0.0, 0.0, -v])
        }
        [x, y, z] => Ok([g(x)?, g(y)?, g(z)?]),
        _ => Err(format!(
            "--gravity {text:?}: expected one value (along -z, default {STANDARD_GRAVITY}) or \
             three (gx,gy,gz) in m/s2"
        )),
    }
}

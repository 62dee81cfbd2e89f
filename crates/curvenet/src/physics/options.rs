//! The physical mode's options as a user writes them (units, material, Young's modulus,
//! density, strength, radius, tube, load, gravity: [`Opt::Units`] …), turned into
//! [`PhysicalParams`]: one place for every front end, its messages naming the options by
//! [`Opt`].

use super::analysis::{DeflectionLimit, PhysicalParams};
use super::cases::Loads;
use crate::material::{
    self, CurveSpec, DENSITY_RANGE_KG_M3, LINE_LOAD_RANGE_N_PER_M, Physical, STRESS_RANGE_PA,
    SectionSpec, presets,
};
use crate::rod::Material;
use crate::units::{LengthUnit, Quantity, STANDARD_GRAVITY, parse_quantity};
use crate::words::{Message, Opt, given, message};

/// The material of the physical mode when only the units are given.
pub const DEFAULT_MATERIAL: &str = "steel";

/// The physical mode's options, as text (`None`: not given). A run folder records them as
/// given (`result.json`'s `setup.physical`), and a resumed run must give the same.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhysicalOptions {
    /// The scene's length unit: `mm`, `cm` or `m`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub units: Option<String>,
    /// A material preset's name.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Young's modulus with a stress unit (`210GPa`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub young: Option<String>,
    /// The density with a density unit (`7850kg/m3`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub density: Option<String>,
    /// The strength with a stress unit (`355MPa`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub strength: Option<String>,
    /// A solid round section's radius (scene units, or with a length unit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<String>,
    /// A round tube, `DxT`: outer diameter × wall.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tube: Option<String>,
    /// The worst-case distributed load's intensity (`1kN/m`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load: Option<String>,
    /// Gravity: `9.81` (along −z) or `gx,gy,gz`, m/s².
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gravity: Option<String>,
    /// The loads file: load cases and combinations (`physics::cases`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub loads: Option<String>,
    /// The load cases' deflection limit: `span/250`, or a length (`20mm`; a bare number in
    /// scene units).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub deflection_limit: Option<String>,
    /// The smallest acceptable critical load factor of a load case (default 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub buckling_factor: Option<String>,
}

impl PhysicalOptions {
    /// True when an option that turns on the physical mode is given (the units or the
    /// material).
    pub fn is_physical(&self) -> bool {
        self.units.is_some() || self.material.is_some()
    }

    /// The physical parameters, or `None` in the paper's mode. `file_units` is a length unit
    /// a curve file declared (used when the units are not given; given units win), `specs`
    /// the curve files' per-curve material, section and rest shape (curve `c` at `specs[c]`).
    ///
    /// The physical mode is on when the options give the units or the material, when the
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
    ) -> Result<Option<PhysicalParams>, Message> {
        let file_physical = specs.iter().position(CurveSpec::is_physical);
        let give_units = || given(Opt::Units, "mm|cm|m");
        if !self.is_physical() && file_units.is_none() && file_physical.is_none() {
            for (opt, value) in [
                (Opt::Density, &self.density),
                (Opt::Strength, &self.strength),
                (Opt::Tube, &self.tube),
                (Opt::Load, &self.load),
                (Opt::Gravity, &self.gravity),
                (Opt::Loads, &self.loads),
                (Opt::DeflectionLimit, &self.deflection_limit),
                (Opt::BucklingFactor, &self.buckling_factor),
            ] {
                if value.is_some() {
                    return Err(message![
                        opt,
                        " belongs to the physical mode: give ",
                        give_units(),
                        " and/or ",
                        given(Opt::Material, "NAME"),
                        format!(" ({})", presets::names().join(", "))
                    ]);
                }
            }
            if let Some(c) = specs
                .iter()
                .position(|s| s.rest == Some(material::RestShape::PreBent))
            {
                return Err(message![
                    format!(
                        "curve {c} is pre-bent (\"rest\": \"pre-bent\"): rest shapes are \
                         analysed in the physical mode; give "
                    ),
                    give_units(),
                    " (or the curve file's \"units\")"
                ]);
            }
            return Ok(None);
        }
        let units: LengthUnit = match (&self.units, file_units) {
            (Some(u), _) => u
                .parse()
                .map_err(|e| message![Opt::Units, format!(": {e}")])?,
            (None, Some(u)) => u
                .parse()
                .map_err(|e| message![format!("the curve file's units: {e}")])?,
            (None, None) => {
                return Err(match (&self.material, file_physical) {
                    (None, Some(c)) => message![
                        format!(
                            "curve {c} sets its own material or section, which needs the \
                             scene's length unit: give "
                        ),
                        give_units(),
                        " (or the curve file's \"units\")"
                    ],
                    _ => message![
                        Opt::Material,
                        " needs the scene's length unit: give ",
                        give_units()
                    ],
                });
            }
        };
        let mut material = presets::preset(self.material.as_deref().unwrap_or(DEFAULT_MATERIAL))
            .map_err(|e| e.prefixed([Opt::Material.into(), ": ".into()]))?;
        let mut modified = false;
        for (opt, value, slot) in [
            (Opt::Young, &self.young, &mut material.young_pa),
            (Opt::Density, &self.density, &mut material.density_kg_m3),
            (Opt::Strength, &self.strength, &mut material.strength_pa),
        ] {
            if let Some(t) = value {
                *slot = quantity(opt, t)?;
                modified = true;
            }
        }
        if modified {
            material.name = format!("{} (modified)", material.name);
        }
        let section = match (&self.radius, &self.tube) {
            (Some(_), Some(_)) => {
                return Err(message![
                    "give ",
                    Opt::Radius,
                    " or ",
                    Opt::Tube,
                    ", not both"
                ]);
            }
            (Some(r), None) => SectionSpec::Solid {
                radius: crate::material::spec::Length::parse(r, Opt::Radius)?,
            },
            (None, Some(t)) => SectionSpec::parse_tube(t, Opt::Tube)?,
            (None, None) => SectionSpec::Solid {
                radius: crate::material::spec::Length::Scene(Material::default().radius),
            },
        }
        .resolve(units);
        let section_option = if self.tube.is_some() {
            Opt::Tube
        } else {
            Opt::Radius
        };
        section
            .validate()
            .map_err(|e| e.prefixed([section_option.into(), ": ".into()]))?;
        let mut physical = Physical::uniform(units, material, section);
        if let Some(t) = &self.load {
            physical.load_n_per_m = quantity(Opt::Load, t)?;
        }
        if let Some(t) = &self.gravity {
            physical.gravity = parse_gravity(t)?;
        }
        // Validated with the curves' overrides.
        let physical = physical.with_curve_specs(specs)?;
        check_stiffness(&physical, specs, section_option)?;
        let mut params = PhysicalParams::new(physical);
        params.rest = specs.iter().map(|s| s.rest.unwrap_or_default()).collect();
        if let Some(path) = &self.loads {
            let text = std::fs::read_to_string(path)
                .map_err(|e| message![Opt::Loads, format!(": {path}: {e}")])?;
            params.loads = Some(Loads::parse(&text, path)?);
        }
        if let Some(t) = &self.deflection_limit {
            params.deflection_limit = Some(parse_deflection_limit(t, units)?);
        }
        if let Some(t) = &self.buckling_factor {
            params.buckling_factor = parse_buckling_factor(t)?;
        }
        Ok(Some(params))
    }
}

/// The deflection limit as written: `span/N` (N a positive number) or a length with its unit
/// (`20mm`), a bare number in scene units.
fn parse_deflection_limit(text: &str, units: LengthUnit) -> Result<DeflectionLimit, Message> {
    let value = given(Opt::DeflectionLimit, format!("{text:?}"));
    let bad = || message![value.clone(), " must be span/N or a positive length (20mm)"];
    if let Some(n) = text.trim().strip_prefix("span/") {
        let n: f64 = n.trim().parse().map_err(|_| bad())?;
        return if n.is_finite() && n > 0.0 {
            Ok(DeflectionLimit::SpanOver(n))
        } else {
            Err(bad())
        };
    }
    let metres = parse_quantity(
        text,
        Quantity::Length,
        Opt::DeflectionLimit,
        Some(units.metres()),
    )?;
    let scene = metres / units.metres();
    if scene.is_finite() && scene > 0.0 {
        Ok(DeflectionLimit::Length(scene))
    } else {
        Err(bad())
    }
}

/// The smallest acceptable critical load factor as written: a positive number.
fn parse_buckling_factor(text: &str) -> Result<f64, Message> {
    match text.trim().parse::<f64>() {
        Ok(f) if f.is_finite() && f > 0.0 => Ok(f),
        _ => Err(message![
            given(Opt::BucklingFactor, format!("{text:?}")),
            " must be a positive number"
        ]),
    }
}

/// The quantity, SI unit and accepted range of each option written with a unit
/// ([`crate::material`]'s bounds: far beyond any material, and keeping every stiffness, mass
/// and load within floating-point range).
const QUANTITIES: &[(Opt, Quantity, &str, (f64, f64))] = &[
    (Opt::Young, Quantity::Stress, "Pa", STRESS_RANGE_PA),
    (
        Opt::Density,
        Quantity::Density,
        "kg/m3",
        DENSITY_RANGE_KG_M3,
    ),
    (Opt::Strength, Quantity::Stress, "Pa", STRESS_RANGE_PA),
    (
        Opt::Load,
        Quantity::LineLoad,
        "N/m",
        LINE_LOAD_RANGE_N_PER_M,
    ),
];

/// The largest gravity component accepted, m/s² (about 1000 g).
pub const MAX_GRAVITY: f64 = material::GRAVITY_RANGE.1;

/// `option`'s value (Young's modulus, the density, the strength or the load) in SI: a
/// positive number with its unit, within the option's range.
fn quantity(option: Opt, text: &str) -> Result<f64, Message> {
    let &(_, kind, si, (min, max)) = QUANTITIES
        .iter()
        .find(|q| q.0 == option)
        .expect("an option written with a unit");
    let v = parse_quantity(text, kind, option, None)?;
    let value = given(option, format!("{text:?}"));
    if !(v > 0.0) {
        Err(message![value, " must be positive"])
    } else if !(min..=max).contains(&v) {
        Err(message![
            value,
            format!(" is {v:e} {si}, beyond any material (between {min:e} and {max:e} {si})")
        ])
    } else {
        Ok(v)
    }
}

/// Refuses a section and material whose rods' stiffnesses (`E A`, `E I` in the scene's units)
/// leave [`crate::rod::STIFFNESS_RANGE`], naming the options that set them.
fn check_stiffness(physical: &Physical, specs: &[CurveSpec], section: Opt) -> Result<(), Message> {
    let (lo, hi) = crate::rod::STIFFNESS_RANGE;
    // The run's own rod (no override applies past the specs) and every curve's.
    for c in std::iter::once(specs.len()).chain(0..specs.len()) {
        let r = physical.scene_rod(c);
        for (name, k) in [("stretching", r.ks), ("bending", r.kb)] {
            if !(lo..=hi).contains(&k) {
                let whose = if c < specs.len() {
                    message![format!("curve {c}'s")]
                } else {
                    message![section, " and ", Opt::Young, " give a"]
                };
                return Err(whose.then([
                    format!(
                        " {name} stiffness {k:e} (in the scene's units), out of the range the \
                         solvers handle ({lo:e} to {hi:e}): check the section's size against "
                    )
                    .into(),
                    Opt::Units.into(),
                ]));
            }
        }
    }
    Ok(())
}

/// Checks one physical-mode option's text alone (`option`: the units, the material, Young's
/// modulus, the density, the strength, the tube, the load or gravity), as
/// [`PhysicalOptions::resolve`] reads it: a front end calls it while its arguments are read,
/// so a bad value is refused before any work. Young's modulus here is the physical mode's
/// (with a unit); options this module does not know pass.
///
/// # Errors
///
/// The message [`PhysicalOptions::resolve`] would give for the value.
pub fn check_option(option: Opt, text: &str) -> Result<(), Message> {
    match option {
        Opt::Units => text
            .parse::<LengthUnit>()
            .map(|_| ())
            .map_err(|e| message![Opt::Units, format!(": {e}")]),
        Opt::Material => presets::preset(text)
            .map(|_| ())
            .map_err(|e| e.prefixed([Opt::Material.into(), ": ".into()])),
        Opt::Tube => SectionSpec::parse_tube(text, Opt::Tube)?
            .resolve(LengthUnit::Metre)
            .validate()
            .map_err(|e| e.prefixed([Opt::Tube.into(), ": ".into()])),
        Opt::Gravity => parse_gravity(text).map(|_| ()),
        _ if QUANTITIES.iter().any(|q| q.0 == option) => quantity(option, text).map(|_| ()),
        _ => Ok(()),
    }
}

/// Gravity: one value (its magnitude along −z; 0 turns self-weight off) or three
/// (`gx,gy,gz`), m/s², bare or with `m/s2`.
fn parse_gravity(text: &str) -> Result<[f64; 3], Message> {
    let parts: Vec<&str> = text.split(',').collect();
    let value = || given(Opt::Gravity, format!("{text:?}"));
    let g = |t: &str| {
        let v = parse_quantity(t, Quantity::Acceleration, Opt::Gravity, Some(1.0))?;
        if v.abs() > MAX_GRAVITY {
            return Err(message![
                value(),
                format!(": {v:e} m/s2 is beyond {MAX_GRAVITY:e} m/s2 (about 1000 g)")
            ]);
        }
        Ok(v)
    };
    // Gravity is off (0) or of a magnitude a structure can meet.
    let checked = |g: [f64; 3]| {
        let m = g.iter().fold(0.0_f64, |m, x| m.hypot(*x));
        let (min, _) = material::GRAVITY_RANGE;
        if m != 0.0 && m < min {
            return Err(message![
                value(),
                format!(
                    ": a magnitude of {m:e} m/s2 is below {min:e} m/s2; give 0 to turn \
                     self-weight off"
                )
            ]);
        }
        Ok(g)
    };
    match parts.as_slice() {
        [one] => {
            let v = g(one)?;
            if v < 0.0 {
                return Err(message![
                    value(),
                    ": one value is the magnitude along -z (give gx,gy,gz for another direction)"
                ]);
            }
            checked([0.0, 0.0, -v])
        }
        [x, y, z] => checked([g(x)?, g(y)?, g(z)?]),
        _ => Err(message![
            value(),
            format!(
                ": expected one value (along -z, default {STANDARD_GRAVITY}) or three \
                 (gx,gy,gz) in m/s2"
            )
        ]),
    }
}

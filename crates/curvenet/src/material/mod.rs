//! Materials, cross-sections and rest shapes of the physical mode.
//!
//! The paper's model works in scene units with `E = 1`, `r = 2` ([`crate::rod::Material`]).
//! Declaring the scene's length unit or a material turns on the *physical mode*, described by
//! a [`Physical`]: the unit ([`crate::units::LengthUnit`]), a material
//! ([`PhysicalMaterial`]: Young's modulus, density, strength, in SI; [`presets`]) and a
//! cross-section ([`Section`], scene units) for every curve, with per-curve overrides from
//! the curve file ([`spec`]), and the loads (gravity, a line load). [`Physical::scene_rod`]
//! turns one curve's description into the numbers the energy and the mass matrix use, in the
//! scene's consistent unit system (N, ℓ, s; see [`crate::units`]): `k_s = E A`, `k_b = E I`,
//! mass per length `ρ A`.
//!
//! The rest shape of a curve ([`RestShape`]: straight, as in the paper, or pre-bent to its
//! drawn shape) is independent of the mode.

pub mod presets;
pub mod section;
pub mod spec;
pub mod support;

pub use section::Section;
pub use spec::{CurveSpec, MaterialSpec, SectionSpec};
pub use support::{EndFrame, EndSupport, SurfaceDirection};

use crate::units::{LengthUnit, STANDARD_GRAVITY};
use crate::words::Message;
use serde::{Deserialize, Serialize};

/// A material in SI units.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicalMaterial {
    /// The preset it came from (`steel`), with ` (modified)` when an override changed it, or
    /// `custom`.
    pub name: String,
    /// Young's modulus, Pa.
    pub young_pa: f64,
    /// Density, kg/m³.
    pub density_kg_m3: f64,
    /// The stress at which the material yields or breaks, Pa: what stresses are compared with.
    pub strength_pa: f64,
    /// Poisson's ratio `ν`: the shear modulus is `E / (2 (1 + ν))` (the torsion of pre-bent
    /// rods). Records made before it was recorded read 0.3, every preset's value.
    #[serde(default = "default_poisson")]
    pub poisson: f64,
}

/// The Poisson's ratio of a material recorded without one (every preset's).
fn default_poisson() -> f64 {
    0.3
}

/// The Poisson's ratios accepted: those of isotropic materials, `(−1, 0.5]`.
pub const POISSON_RANGE: (f64, f64) = (-1.0, 0.5);

/// The Young's moduli and strengths accepted, Pa: from 1 Pa (softer than any gel) to 1e13 Pa
/// (ten times diamond's modulus).
pub const STRESS_RANGE_PA: (f64, f64) = (1.0, 1e13);

/// The densities accepted, kg/m³: from 1e-3 (a thousandth of air's; the lightest aerogels
/// weigh 0.16) to 1e6 (forty times osmium's).
pub const DENSITY_RANGE_KG_M3: (f64, f64) = (1e-3, 1e6);

/// The intensities of the worst-case line load accepted, N/m: from 1e-6 (the weight of a tenth
/// of a milligram per metre) to 1e12.
pub const LINE_LOAD_RANGE_N_PER_M: (f64, f64) = (1e-6, 1e12);

/// The magnitudes of gravity accepted besides 0 (no self-weight), m/s²: from 1e-6 to 1e4
/// (about 1000 g).
pub const GRAVITY_RANGE: (f64, f64) = (1e-6, 1e4);

/// Within these bounds every stiffness, mass, load and deflection of a structure whose scene
/// is of a size the inputs accept stays within floating-point range; beyond them no material
/// exists, so a value there is a mistake (a wrong unit, a typo), refused naming it.
///
/// # Errors
///
/// `what` (with `unit`) and the range when `v` lies outside `range`, or is not a number.
pub fn check_range(what: &str, v: f64, range: (f64, f64), unit: &str) -> Result<(), Message> {
    if (range.0..=range.1).contains(&v) {
        Ok(())
    } else if !(v > 0.0) {
        Err(format!("{what} must be a positive number, got {v:e} {unit}").into())
    } else {
        Err(format!(
            "{what} is {v:e} {unit}, beyond any material (between {:e} and {:e} {unit})",
            range.0, range.1
        )
        .into())
    }
}

impl PhysicalMaterial {
    /// Checks that every value lies in its range ([`STRESS_RANGE_PA`],
    /// [`DENSITY_RANGE_KG_M3`]).
    pub fn validate(&self) -> Result<(), Message> {
        for (what, v, range, unit) in [
            ("Young's modulus", self.young_pa, STRESS_RANGE_PA, "Pa"),
            ("density", self.density_kg_m3, DENSITY_RANGE_KG_M3, "kg/m3"),
            ("strength", self.strength_pa, STRESS_RANGE_PA, "Pa"),
        ] {
            check_range(
                &format!("the {what} of material '{}'", self.name),
                v,
                range,
                unit,
            )?;
        }
        let (lo, hi) = POISSON_RANGE;
        if !(self.poisson > lo && self.poisson <= hi) {
            return Err(format!(
                "the Poisson's ratio of material '{}' is {}, outside ({lo}, {hi}]",
                self.name, self.poisson
            )
            .into());
        }
        Ok(())
    }

    /// The shear modulus `G = E / (2 (1 + ν))`, Pa.
    pub fn shear_pa(&self) -> f64 {
        self.young_pa / (2.0 * (1.0 + self.poisson))
    }
}

/// The rest shape of a rod.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum RestShape {
    /// Straight at rest and bent into its drawn shape (the paper's model): the drawn network
    /// is not in equilibrium.
    #[default]
    #[serde(rename = "straight")]
    Straight,
    /// Made in its drawn shape (rest curvature = the drawn curvature): in equilibrium where it
    /// was drawn, stiff against leaving it, twisting with `G J` in the physical analysis. See
    /// `rod::frame` (and `rod::terms::bend_rest`, the twist-free term).
    #[serde(rename = "pre-bent")]
    PreBent,
}

impl RestShape {
    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            RestShape::Straight => "straight",
            RestShape::PreBent => "pre-bent",
        }
    }
}

impl std::str::FromStr for RestShape {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "straight" => Ok(RestShape::Straight),
            "pre-bent" | "prebent" | "pre_bent" => Ok(RestShape::PreBent),
            other => Err(format!(
                "unknown rest shape '{other}' (expected straight or pre-bent)"
            )),
        }
    }
}

/// One curve's material or section, where it differs from the run's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveOverride {
    /// Curve id.
    pub curve: usize,
    /// Its material, when not the run's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<PhysicalMaterial>,
    /// Its section (scene units), when not the run's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<Section>,
}

/// The physical mode of a run: units, materials, sections and loads.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Physical {
    /// The scene's length unit.
    pub units: LengthUnit,
    /// Every curve's material, unless overridden.
    pub material: PhysicalMaterial,
    /// Every curve's section (scene units), unless overridden.
    pub section: Section,
    /// Per-curve overrides, ascending by curve.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub curves: Vec<CurveOverride>,
    /// Gravity, m/s² (default 9.81 along −z).
    pub gravity: [f64; 3],
    /// Intensity of the distributed load of the worst-case deflection, N/m.
    pub load_n_per_m: f64,
}

/// One rod's numbers in the scene's unit system (N, ℓ, s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneRod {
    /// Stretching stiffness `k_s = E A`, N.
    pub ks: f64,
    /// Bending stiffness `k_b = E I`, N·ℓ².
    pub kb: f64,
    /// Mass per length `ρ A`, (N·s²/ℓ)/ℓ.
    pub mass_per_length: f64,
    /// Torsional stiffness `G J`, N·ℓ² (`G = E / (2 (1 + ν))`, `J` the section's torsion
    /// constant).
    pub gj: f64,
    /// Rotational inertia per length about the axis, `ρ J`, (N·s²/ℓ)·ℓ.
    pub polar_mass_per_length: f64,
    /// Young's modulus, N/ℓ².
    pub young: f64,
    /// Distance from the axis to the outer fibre, ℓ.
    pub outer_radius: f64,
    /// Strength, N/ℓ².
    pub strength: f64,
}

/// Default intensity of the worst-case distributed load, N/m (1 kN/m).
pub const DEFAULT_LOAD_N_PER_M: f64 = 1000.0;

impl Physical {
    /// The physical mode with one material and section for every curve, standard gravity
    /// along −z and the default line load.
    pub fn uniform(units: LengthUnit, material: PhysicalMaterial, section: Section) -> Self {
        Physical {
            units,
            material,
            section,
            curves: Vec::new(),
            gravity: [0.0, 0.0, -STANDARD_GRAVITY],
            load_n_per_m: DEFAULT_LOAD_N_PER_M,
        }
    }

    /// Checks every material and section, the gravity and the load.
    pub fn validate(&self) -> Result<(), Message> {
        self.material.validate()?;
        self.section.validate()?;
        for o in &self.curves {
            if let Some(m) = &o.material {
                m.validate().map_err(|e| curve_message(o.curve, e))?;
            }
            if let Some(s) = &o.section {
                s.validate().map_err(|e| curve_message(o.curve, e))?;
            }
        }
        if self.curves.windows(2).any(|w| w[0].curve >= w[1].curve) {
            return Err("per-curve overrides must be in ascending curve order".into());
        }
        let g = self.gravity.iter().fold(0.0_f64, |m, g| m.hypot(*g));
        if g != 0.0 {
            check_range("gravity's magnitude", g, GRAVITY_RANGE, "m/s2")?;
        }
        check_range(
            "the distributed load",
            self.load_n_per_m,
            LINE_LOAD_RANGE_N_PER_M,
            "N/m",
        )
    }

    fn override_of(&self, curve: usize) -> Option<&CurveOverride> {
        self.curves
            .binary_search_by_key(&curve, |o| o.curve)
            .ok()
            .map(|i| &self.curves[i])
    }

    /// The overrides of the network made of the curves `ids`, in that order: curve `i` of
    /// the new network takes curve `ids[i]`'s material and section.
    pub fn overrides_for(&self, ids: &[usize]) -> Vec<CurveOverride> {
        (ids.iter().enumerate())
            .filter_map(|(i, &id)| {
                let own = self.curves.iter().find(|o| o.curve == id)?;
                Some(CurveOverride {
                    curve: i,
                    ..own.clone()
                })
            })
            .collect()
    }

    /// Curve `curve`'s material.
    pub fn curve_material(&self, curve: usize) -> &PhysicalMaterial {
        self.override_of(curve)
            .and_then(|o| o.material.as_ref())
            .unwrap_or(&self.material)
    }

    /// Curve `curve`'s section (scene units).
    pub fn curve_section(&self, curve: usize) -> &Section {
        self.override_of(curve)
            .and_then(|o| o.section.as_ref())
            .unwrap_or(&self.section)
    }

    /// Curve `curve`'s numbers in the scene's unit system.
    pub fn scene_rod(&self, curve: usize) -> SceneRod {
        let m = self.curve_material(curve);
        let s = self.curve_section(curve);
        let u = self.units;
        let young = u.stress_to_scene(m.young_pa);
        SceneRod {
            ks: young * s.area(),
            kb: young * s.second_moment(),
            mass_per_length: u.density_to_scene(m.density_kg_m3) * s.area(),
            gj: u.stress_to_scene(m.shear_pa()) * s.polar_moment(),
            polar_mass_per_length: u.density_to_scene(m.density_kg_m3) * s.polar_moment(),
            young,
            outer_radius: s.outer_radius(),
            strength: u.stress_to_scene(m.strength_pa),
        }
    }

    /// Gravity in the scene's ℓ/s².
    pub fn gravity_scene(&self) -> [f64; 3] {
        self.gravity.map(|g| self.units.acceleration_to_scene(g))
    }

    /// The worst-case load's intensity in the scene's N/ℓ.
    pub fn load_scene(&self) -> f64 {
        self.units.line_load_to_scene(self.load_n_per_m)
    }

    /// Applies the per-curve specs of the curve files (`specs[c]` for curve `c`; shorter
    /// lists leave the remaining curves alone): a spec's material starts from its preset, or
    /// from the run's material, and takes its overrides; a spec's section replaces the run's.
    ///
    /// # Errors
    ///
    /// A message naming the curve for an unknown preset or an invalid value.
    pub fn with_curve_specs(mut self, specs: &[CurveSpec]) -> Result<Self, Message> {
        let mut curves = Vec::new();
        for (c, spec) in specs.iter().enumerate() {
            let material = (spec.material.as_ref())
                .map(|m| m.resolve(&self.material))
                .transpose()
                .map_err(|e| curve_message(c, e))?;
            let section = spec.section.map(|s| s.resolve(self.units));
            if material.is_some() || section.is_some() {
                curves.push(CurveOverride {
                    curve: c,
                    material,
                    section,
                });
            }
        }
        self.curves = curves;
        self.validate()?;
        Ok(self)
    }
}

/// `message` about curve `curve`: `curve 3: …`.
fn curve_message(curve: usize, message: Message) -> Message {
    message.prefixed([format!("curve {curve}: ").into()])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steel_mm() -> Physical {
        Physical::uniform(
            LengthUnit::Millimetre,
            presets::preset("steel").unwrap(),
            Section::Solid { radius: 10.0 },
        )
    }

    #[test]
    fn a_steel_rod_in_millimetres() {
        let p = steel_mm();
        assert!(p.validate().is_ok());
        let r = p.scene_rod(3);
        // E A = 210 000 N/mm² · 314.16 mm² = 6.597e7 N; E I = 210 000 · 7853.98 = 1.649e9 N mm².
        assert!((r.ks / 6.597_345e7 - 1.0).abs() < 1e-6, "{}", r.ks);
        assert!((r.kb / 1.649_336e9 - 1.0).abs() < 1e-6, "{}", r.kb);
        // ρ A = 7.85e-9 t/mm³ · 314.16 mm² = 2.466e-6 t/mm = 2.466 kg/m.
        let kg_per_m = p.units.mass_to_kg(r.mass_per_length) / p.units.metres();
        assert!((kg_per_m - 2.466_150).abs() < 1e-5, "{kg_per_m}");
        assert_eq!(r.strength, 355.0);
        assert_eq!(p.gravity_scene(), [0.0, 0.0, -9810.0]);
        assert!((p.load_scene() - 1.0).abs() < 1e-12);
        // The same rod in metres has the same physics: E I in N·m².
        let m = Physical::uniform(
            LengthUnit::Metre,
            presets::preset("steel").unwrap(),
            Section::Solid { radius: 0.01 },
        );
        let rm = m.scene_rod(0);
        assert!((rm.kb / (r.kb * 1e-6) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn per_curve_specs_override_the_run() {
        let specs = vec![
            CurveSpec::default(),
            CurveSpec {
                material: Some(MaterialSpec {
                    preset: Some("aluminium".into()),
                    ..MaterialSpec::default()
                }),
                section: Some(SectionSpec::Tube {
                    outer_diameter: spec::Length::Scene(60.0),
                    wall: spec::Length::Metres(0.004),
                }),
                rest: None,
                supports: [None; 2],
            },
            CurveSpec {
                material: Some(MaterialSpec {
                    strength_pa: Some(460e6),
                    ..MaterialSpec::default()
                }),
                ..CurveSpec::default()
            },
        ];
        let p = steel_mm().with_curve_specs(&specs).unwrap();
        assert_eq!(p.curves.len(), 2);
        assert_eq!(p.curve_material(0).name, "steel");
        assert_eq!(p.curve_material(1).name, "aluminium");
        assert_eq!(
            *p.curve_section(1),
            Section::Tube {
                outer_diameter: 60.0,
                wall: 4.0
            }
        );
        assert_eq!(p.curve_material(2).name, "steel (modified)");
        assert_eq!(p.curve_material(2).strength_pa, 460e6);
        assert_eq!(p.curve_material(2).young_pa, 210e9);
        assert_eq!(*p.curve_section(2), Section::Solid { radius: 10.0 });
        assert_eq!(p.curve_material(7).name, "steel");
        let bad = vec![CurveSpec {
            material: Some(MaterialSpec {
                density_kg_m3: Some(-1.0),
                ..MaterialSpec::default()
            }),
            ..CurveSpec::default()
        }];
        let e = steel_mm().with_curve_specs(&bad).unwrap_err().to_string();
        assert!(e.contains("curve 0") && e.contains("density"), "{e}");
    }

    #[test]
    fn rest_shapes_parse() {
        assert_eq!("pre-bent".parse::<RestShape>(), Ok(RestShape::PreBent));
        assert_eq!("straight".parse::<RestShape>(), Ok(RestShape::Straight));
        assert!("curly".parse::<RestShape>().is_err());
        assert_eq!(
            serde_json::to_string(&RestShape::PreBent).unwrap(),
            "\"pre-bent\""
        );
    }
}

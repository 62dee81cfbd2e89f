//! Material presets: the values `--material NAME` stands for, with their sources.
//!
//! Each value is a nominal design value from a standard (or, for glass fibre, from the
//! gridshells built with it); `docs/units.md` lists them with the same sources. A real product
//! differs: override any of them with `--young`, `--density`, `--strength`.
//!
//! | preset | E | ρ | strength | ν | source |
//! |---|---|---|---|---|---|
//! | `steel` | 210 GPa | 7850 kg/m³ | 355 MPa (S355 yield) | 0.3 | EN 1993-1-1 §3.2.6 (E, ν), EN 1991-1-1 Table A.4 (ρ), EN 10025-2 (S355, t ≤ 16 mm) |
//! | `aluminium` | 70 GPa | 2700 kg/m³ | 240 MPa (EN AW-6061 T6 proof stress) | 0.3 | EN 1999-1-1 §3.2.5 (E, ν, ρ), Table 3.2b (f₀) |
//! | `gfrp` | 25 GPa | 1850 kg/m³ | 400 MPa (pultruded glass-fibre tube, failure stress) | 0.3 | Douthe, Baverel & Caron 2006 (J. IASS 47(1)); du Peloux et al. 2016 (the Solidays gridshell); ν: the major Poisson's ratio of pultruded profiles, EN 13706-3 |
//! | `timber` | 11 GPa | 420 kg/m³ | 24 MPa (C24 bending strength, characteristic) | 0.3 (nominal) | EN 338:2016 Table 1 (C24: E₀,mean, ρ_mean, f_m,k) |
//!
//! The shear modulus is `G = E / (2 (1 + ν))` (the torsion of a pre-bent rod, `G J`): exact
//! for steel and aluminium; GFRP and timber are orthotropic and shear far more easily along
//! their fibres (C24's `G_mean` is 0.69 GPa, EN 338 Table 1, where `E / 2.6` gives 4.2 GPa), so
//! for them the formula overstates a pre-bent rod's torsional stiffness: set the material's
//! `"poisson"` in the curve file to match a measured `G` (`ν = E / 2G − 1`).

use super::PhysicalMaterial;
use crate::words::Message;

/// The presets: name, the other names it answers to, then Young's modulus (Pa), density
/// (kg/m³), strength (Pa) and Poisson's ratio.
type Preset = (&'static str, &'static [&'static str], f64, f64, f64, f64);

const PRESETS: &[Preset] = &[
    ("steel", &["s355"], 210e9, 7850.0, 355e6, 0.3),
    (
        "aluminium",
        &["aluminum", "al", "6061-t6"],
        70e9,
        2700.0,
        240e6,
        0.3,
    ),
    (
        "gfrp",
        &["glass-fibre", "glass-fiber", "fibreglass", "fiberglass"],
        25e9,
        1850.0,
        400e6,
        0.3,
    ),
    ("timber", &["wood", "c24"], 11e9, 420.0, 24e6, 0.3),
];

/// The preset names, for help and messages.
pub fn names() -> Vec<&'static str> {
    PRESETS.iter().map(|p| p.0).collect()
}

/// The preset called `name` (or one of its aliases, any case).
///
/// # Errors
///
/// A message listing the presets when there is none by that name.
pub fn preset(name: &str) -> Result<PhysicalMaterial, Message> {
    let key = name.trim().to_ascii_lowercase();
    PRESETS
        .iter()
        .find(|p| p.0 == key || p.1.contains(&key.as_str()))
        .map(
            |&(name, _, young_pa, density_kg_m3, strength_pa, poisson)| PhysicalMaterial {
                name: name.to_owned(),
                young_pa,
                density_kg_m3,
                strength_pa,
                poisson,
            },
        )
        .ok_or_else(|| {
            Message::from(format!(
                "unknown material '{}' (expected one of: {})",
                name.trim(),
                names().join(", ")
            ))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_found_by_name_and_alias() {
        let s = preset("steel").unwrap();
        assert_eq!(
            (s.young_pa, s.density_kg_m3, s.strength_pa),
            (210e9, 7850.0, 355e6)
        );
        assert_eq!(preset("Aluminum").unwrap().name, "aluminium");
        assert_eq!(preset("glass-fibre").unwrap().name, "gfrp");
        assert_eq!(preset(" wood ").unwrap().name, "timber");
        let e = preset("unobtainium").unwrap_err().to_string();
        assert!(e.contains("unobtainium") && e.contains("steel, aluminium, gfrp, timber"));
        for n in names() {
            assert!(preset(n).unwrap().validate().is_ok());
        }
    }
}

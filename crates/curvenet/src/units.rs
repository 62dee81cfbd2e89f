//! Physical units: the scene's length unit and quantities written with a unit suffix.
//!
//! The physical mode works in one consistent system built on the scene's length unit `ℓ`
//! (millimetre, centimetre or metre): forces in newtons, lengths in `ℓ`, time in seconds, so
//! that masses come out in `N·s²/ℓ` (for millimetres, tonnes). In it
//!
//! - a stress or modulus of `p` Pa is `p·ℓ²` N/ℓ² (steel's 210 GPa is 210 000 N/mm²);
//! - a density of `ρ` kg/m³ is `ρ·ℓ⁴` (N·s²/ℓ)/ℓ³ (steel's 7850 kg/m³ is 7.85e-9 t/mm³);
//! - an acceleration of `a` m/s² is `a/ℓ` ℓ/s², a line load of `q` N/m is `q·ℓ` N/ℓ,
//!
//! with `ℓ` in metres. Eigenvalues of `H v = μ M v` are then in s⁻² and `√μ / 2π` in hertz,
//! whatever the unit.
//!
//! Values given by the user carry their unit as a suffix (`210GPa`, `7850kg/m3`, `355MPa`,
//! `10mm`, `1kN/m`); [`parse_quantity`] converts them to SI and rejects a suffix that belongs to
//! another quantity, naming what it is.

use crate::words::{Message, Piece, message};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// The scene's length unit: what one unit of the input coordinates is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum LengthUnit {
    /// Millimetres.
    #[serde(rename = "mm")]
    Millimetre,
    /// Centimetres.
    #[serde(rename = "cm")]
    Centimetre,
    /// Metres.
    #[serde(rename = "m")]
    Metre,
}

impl LengthUnit {
    /// One scene unit in metres.
    pub fn metres(self) -> f64 {
        match self {
            LengthUnit::Millimetre => 1e-3,
            LengthUnit::Centimetre => 1e-2,
            LengthUnit::Metre => 1.0,
        }
    }

    /// The unit's symbol (`mm`, `cm`, `m`), as on the command line.
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Millimetre => "mm",
            LengthUnit::Centimetre => "cm",
            LengthUnit::Metre => "m",
        }
    }

    /// A stress in pascals, in the scene's N/ℓ².
    pub fn stress_to_scene(self, pa: f64) -> f64 {
        pa * self.metres() * self.metres()
    }

    /// A stress in the scene's N/ℓ², in megapascals.
    pub fn stress_to_mpa(self, scene: f64) -> f64 {
        scene / (self.metres() * self.metres()) * 1e-6
    }

    /// A density in kg/m³, in the scene's (N·s²/ℓ)/ℓ³.
    pub fn density_to_scene(self, kg_per_m3: f64) -> f64 {
        kg_per_m3 * self.metres().powi(4)
    }

    /// An acceleration in m/s², in the scene's ℓ/s².
    pub fn acceleration_to_scene(self, m_per_s2: f64) -> f64 {
        m_per_s2 / self.metres()
    }

    /// A line load in N/m, in the scene's N/ℓ.
    pub fn line_load_to_scene(self, n_per_m: f64) -> f64 {
        n_per_m * self.metres()
    }

    /// A mass in the scene's N·s²/ℓ, in kilograms.
    pub fn mass_to_kg(self, scene: f64) -> f64 {
        scene / self.metres()
    }
}

impl fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

impl FromStr for LengthUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "mm" | "millimetre" | "millimeter" | "millimetres" | "millimeters" => {
                Ok(LengthUnit::Millimetre)
            }
            "cm" | "centimetre" | "centimeter" | "centimetres" | "centimeters" => {
                Ok(LengthUnit::Centimetre)
            }
            "m" | "metre" | "meter" | "metres" | "meters" => Ok(LengthUnit::Metre),
            other => Err(format!(
                "unknown length unit '{other}' (expected mm, cm or m)"
            )),
        }
    }
}

/// The kinds of quantity a user writes with a unit suffix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// A stress or an elastic modulus (SI: Pa).
    Stress,
    /// A mass density (SI: kg/m³).
    Density,
    /// A length (SI: m).
    Length,
    /// A force per unit length (SI: N/m).
    LineLoad,
    /// An acceleration (SI: m/s²).
    Acceleration,
}

impl Quantity {
    /// For messages: what the quantity is (`a stress`), the suffixes it accepts, an example.
    pub fn words(self) -> [&'static str; 3] {
        match self {
            Quantity::Stress => ["a stress", "Pa, kPa, MPa, GPa, N/mm2, N/m2", "210GPa"],
            Quantity::Density => ["a density", "kg/m3, g/cm3, t/m3", "7850kg/m3"],
            Quantity::Length => ["a length", "mm, cm, m", "10mm"],
            Quantity::LineLoad => ["a line load", "N/m, kN/m, N/mm", "1kN/m"],
            Quantity::Acceleration => ["an acceleration", "m/s2", "9.81m/s2"],
        }
    }
}

/// Every known suffix (ASCII spelling; `²`, `³` and `·` are normalised first) with its
/// quantity and its factor to SI.
const SUFFIXES: &[(&str, Quantity, f64)] = &[
    ("pa", Quantity::Stress, 1.0),
    ("kpa", Quantity::Stress, 1e3),
    ("mpa", Quantity::Stress, 1e6),
    ("gpa", Quantity::Stress, 1e9),
    ("n/m2", Quantity::Stress, 1.0),
    ("n/mm2", Quantity::Stress, 1e6),
    ("kn/mm2", Quantity::Stress, 1e9),
    ("kg/m3", Quantity::Density, 1.0),
    ("g/cm3", Quantity::Density, 1e3),
    ("t/m3", Quantity::Density, 1e3),
    ("mm", Quantity::Length, 1e-3),
    ("cm", Quantity::Length, 1e-2),
    ("m", Quantity::Length, 1.0),
    ("n/m", Quantity::LineLoad, 1.0),
    ("kn/m", Quantity::LineLoad, 1e3),
    ("n/mm", Quantity::LineLoad, 1e3),
    ("kn/mm", Quantity::LineLoad, 1e6),
    ("m/s2", Quantity::Acceleration, 1.0),
];

/// Splits `text` into its number and its unit suffix (possibly empty). `1e3MPa` is `1e3` and
/// `MPa`: an `e` belongs to the number when a digit (or a sign and a digit) follows it.
pub fn split_number(text: &str) -> (&str, &str) {
    let t = text.trim();
    let b = t.as_bytes();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let number_char = c.is_ascii_digit() || c == b'.' || c == b'+' || c == b'-';
        let exponent = (c == b'e' || c == b'E')
            && i > 0
            && b[..i].iter().any(u8::is_ascii_digit)
            && match b.get(i + 1) {
                Some(d) if d.is_ascii_digit() => true,
                Some(b'+' | b'-') => b.get(i + 2).is_some_and(u8::is_ascii_digit),
                _ => false,
            };
        if exponent {
            i += 2;
            continue;
        }
        if !number_char {
            break;
        }
        i += 1;
    }
    (t[..i].trim(), t[i..].trim())
}

/// The normalised spelling of a suffix: lower case, `²`/`³` as `2`/`3`, no spaces, `^` dropped
/// (`N/mm²`, `N / mm^2` and `n/mm2` are one suffix).
fn normalise(suffix: &str) -> String {
    suffix
        .chars()
        .filter(|c| !c.is_whitespace() && *c != '^')
        .map(|c| match c {
            '²' => '2',
            '³' => '3',
            c => c.to_ascii_lowercase(),
        })
        .collect()
}

/// A value of `kind` written with a unit suffix, in SI (Pa, kg/m³, m, N/m, m/s²).
///
/// `what` names the option ([`Opt`](crate::words::Opt)) or the file's field in messages. A
/// value without a suffix is an error naming the suffixes `kind` accepts, unless `bare` gives
/// the factor to use for it (lengths in scene units, accelerations in m/s²).
///
/// # Errors
///
/// A message naming `what` for a value that is not a finite number, a suffix that belongs to
/// another quantity (saying which), an unknown suffix, or a missing one when `bare` is `None`.
pub fn parse_quantity(
    text: &str,
    kind: Quantity,
    what: impl Into<Piece>,
    bare: Option<f64>,
) -> Result<f64, Message> {
    let what: Piece = what.into();
    let given = what.with_value(format!("{text:?}"));
    let [is, suffixes, example] = kind.words();
    let (number, suffix) = split_number(text);
    let value: f64 = number.parse().map_err(|_| {
        message![
            given.clone(),
            format!(": expected a number with a unit ({suffixes}), e.g. {example}")
        ]
    })?;
    if !value.is_finite() {
        return Err(message![given, ": not a finite number"]);
    }
    if suffix.is_empty() {
        return match bare {
            Some(f) => Ok(value * f),
            None => Err(message![
                given,
                format!(" needs a unit ({suffixes}), e.g. {example}")
            ]),
        };
    }
    let norm = normalise(suffix);
    match SUFFIXES.iter().find(|(s, _, _)| *s == norm) {
        Some(&(_, k, f)) if k == kind => Ok(value * f),
        Some(&(_, k, _)) => Err(message![
            given,
            format!(
                ": {suffix} is a unit of {}, but ",
                k.words()[0]
                    .trim_start_matches("a ")
                    .trim_start_matches("an "),
            ),
            what,
            format!(" takes {is} ({suffixes})")
        ]),
        None => Err(message![
            given,
            format!(": unknown unit {suffix:?} for {is} (expected {suffixes})")
        ]),
    }
}

/// Standard gravity, m/s² (the default self-weight load).
pub const STANDARD_GRAVITY: f64 = 9.81;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_convert_to_the_scene_system() {
        let mm = LengthUnit::Millimetre;
        // 210 GPa = 210 000 N/mm², 7850 kg/m³ = 7.85e-9 t/mm³, g = 9810 mm/s².
        assert!((mm.stress_to_scene(210e9) - 210_000.0).abs() < 1e-6);
        assert!((mm.density_to_scene(7850.0) / 7.85e-9 - 1.0).abs() < 1e-12);
        assert!((mm.acceleration_to_scene(9.81) - 9810.0).abs() < 1e-9);
        assert!((mm.line_load_to_scene(1000.0) - 1.0).abs() < 1e-12);
        assert!((mm.stress_to_mpa(355.0) - 355.0).abs() < 1e-9);
        let m = LengthUnit::Metre;
        assert_eq!(m.stress_to_scene(210e9), 210e9);
        assert!((m.stress_to_mpa(355e6) - 355.0).abs() < 1e-9);
        // ρ A g is the same weight per metre in every unit: a 10 mm steel rod weighs
        // 7850 · π·0.01² · 9.81 = 24.19 N/m.
        for u in [
            LengthUnit::Millimetre,
            LengthUnit::Centimetre,
            LengthUnit::Metre,
        ] {
            let r = 0.01 / u.metres();
            let w = u.density_to_scene(7850.0)
                * std::f64::consts::PI
                * r
                * r
                * u.acceleration_to_scene(9.81);
            let per_metre = w / u.metres();
            assert!((per_metre - 24.1929).abs() < 1e-3, "{u}: {per_metre}");
        }
        assert_eq!("cm".parse::<LengthUnit>(), Ok(LengthUnit::Centimetre));
        assert!("inch".parse::<LengthUnit>().is_err());
    }

    use crate::words::{Opt, Recorded};

    #[test]
    fn suffixes_parse_to_si() {
        let p = |t, k| parse_quantity(t, k, "x", None);
        assert_eq!(p("210GPa", Quantity::Stress), Ok(210e9));
        assert_eq!(p("210 GPa", Quantity::Stress), Ok(210e9));
        assert_eq!(p("355MPa", Quantity::Stress), Ok(355e6));
        assert_eq!(p("355N/mm²", Quantity::Stress), Ok(355e6));
        assert_eq!(p("1e3MPa", Quantity::Stress), Ok(1e9));
        assert_eq!(p("2.1e+11Pa", Quantity::Stress), Ok(2.1e11));
        assert_eq!(p("7850kg/m3", Quantity::Density), Ok(7850.0));
        assert_eq!(p("7850kg/m³", Quantity::Density), Ok(7850.0));
        assert_eq!(p("7.85g/cm3", Quantity::Density), Ok(7850.0));
        assert_eq!(p("1kN/m", Quantity::LineLoad), Ok(1000.0));
        assert_eq!(p("10mm", Quantity::Length), Ok(0.01));
        assert_eq!(p("9.81m/s2", Quantity::Acceleration), Ok(9.81));
        // A bare number with a default factor.
        assert_eq!(
            parse_quantity("4", Quantity::Length, Opt::Radius, Some(1.0)),
            Ok(4.0)
        );
        assert_eq!(split_number("-3.5e-2m"), ("-3.5e-2", "m"));
        assert_eq!(split_number("2em"), ("2", "em"));
    }

    #[test]
    fn wrong_suffixes_say_what_they_are() {
        let e = parse_quantity("7850kg/m3", Quantity::Stress, Opt::Young, None)
            .unwrap_err()
            .render(&Recorded);
        assert!(e.contains("--young") && e.contains("density"), "{e}");
        let e = parse_quantity("210GPa", Quantity::Density, Opt::Density, None)
            .unwrap_err()
            .render(&Recorded);
        assert!(e.contains("stress") && e.contains("kg/m3"), "{e}");
        let e = parse_quantity("210", Quantity::Stress, Opt::Young, None)
            .unwrap_err()
            .render(&Recorded);
        assert!(e.contains("needs a unit") && e.contains("210GPa"), "{e}");
        let e = parse_quantity("210furlongs", Quantity::Stress, Opt::Young, None)
            .unwrap_err()
            .render(&Recorded);
        assert!(e.contains("unknown unit"), "{e}");
        let e = parse_quantity("GPa", Quantity::Stress, Opt::Young, None)
            .unwrap_err()
            .render(&Recorded);
        assert!(e.contains("expected a number"), "{e}");
        assert!(parse_quantity("infGPa", Quantity::Stress, Opt::Young, None).is_err());
        assert!(parse_quantity("1e999GPa", Quantity::Stress, Opt::Young, None).is_err());
    }
}

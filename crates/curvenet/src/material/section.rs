//! Cross-sections of the rods: solid round bars and round tubes, in scene units.

use crate::words::Message;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A rod's cross-section, in scene units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Section {
    /// A solid round bar of radius `radius`.
    Solid {
        /// Radius.
        radius: f64,
    },
    /// A round tube of outer diameter `outer_diameter` and wall thickness `wall`.
    Tube {
        /// Outer diameter.
        outer_diameter: f64,
        /// Wall thickness (at most half the outer diameter: a solid bar).
        wall: f64,
    },
}

impl Section {
    /// Area `A` (solid: `π r²`; tube: `π (R² − (R − t)²)`).
    pub fn area(&self) -> f64 {
        match *self {
            Section::Solid { radius } => PI * radius * radius,
            Section::Tube {
                outer_diameter,
                wall,
            } => {
                let (ro, ri) = tube_radii(outer_diameter, wall);
                PI * (ro * ro - ri * ri)
            }
        }
    }

    /// Second moment of area about a diameter, `I` (solid: `π r⁴ / 4`; tube:
    /// `π (R⁴ − (R − t)⁴) / 4`).
    pub fn second_moment(&self) -> f64 {
        match *self {
            Section::Solid { radius } => PI * radius.powi(4) / 4.0,
            Section::Tube {
                outer_diameter,
                wall,
            } => {
                let (ro, ri) = tube_radii(outer_diameter, wall);
                PI * (ro.powi(4) - ri.powi(4)) / 4.0
            }
        }
    }

    /// Torsion constant `J`, the polar moment of a round section (solid: `π r⁴ / 2`; tube:
    /// `π (D⁴ − d⁴) / 32`): twice [`Self::second_moment`].
    pub fn polar_moment(&self) -> f64 {
        2.0 * self.second_moment()
    }

    /// The distance from the axis to the outermost fibre, where bending stress is largest.
    pub fn outer_radius(&self) -> f64 {
        match *self {
            Section::Solid { radius } => radius,
            Section::Tube { outer_diameter, .. } => 0.5 * outer_diameter,
        }
    }

    /// A short description in scene units (`solid r 10`, `tube 60 × 4`).
    pub fn describe(&self) -> String {
        self.describe_in("")
    }

    /// [`Self::describe`] with each length followed by `unit` (the scene's length unit, as
    /// `"mm"`): `solid, radius 10.0 mm`.
    pub fn describe_in(&self, unit: &str) -> String {
        let u = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        match *self {
            // As given (shortest round trip: `0.01`, `1e-30`), not expanded to every zero.
            Section::Solid { radius } => format!("solid, radius {radius:?}{u}"),
            Section::Tube {
                outer_diameter,
                wall,
            } => format!("tube {outer_diameter:?}{u} × {wall:?}{u}"),
        }
    }

    /// Checks the dimensions: positive and finite, a tube's wall at most half its diameter.
    pub fn validate(&self) -> Result<(), Message> {
        match *self {
            Section::Solid { radius } => {
                if !(radius.is_finite() && radius > 0.0) {
                    return Err(format!(
                        "the section's radius must be a positive number, got {radius}"
                    )
                    .into());
                }
            }
            Section::Tube {
                outer_diameter,
                wall,
            } => {
                if !(outer_diameter.is_finite() && outer_diameter > 0.0) {
                    return Err(format!(
                        "the tube's outer diameter must be a positive number, got \
                         {outer_diameter}"
                    )
                    .into());
                }
                if !(wall.is_finite() && wall > 0.0 && wall <= 0.5 * outer_diameter) {
                    return Err(format!(
                        "the tube's wall must be positive and at most half its outer diameter \
                         ({}), got {wall}",
                        0.5 * outer_diameter
                    )
                    .into());
                }
            }
        }
        let (a, i) = (self.area(), self.second_moment());
        if !(a.is_finite() && a > f64::MIN_POSITIVE && i.is_finite() && i > f64::MIN_POSITIVE) {
            return Err(format!(
                "the section ({}) has area {a:e} and second moment {i:e}, out of floating-point \
                 range",
                self.describe()
            )
            .into());
        }
        Ok(())
    }
}

/// Outer and inner radius of a tube.
fn tube_radii(outer_diameter: f64, wall: f64) -> (f64, f64) {
    let ro = 0.5 * outer_diameter;
    (ro, (ro - wall).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn section_properties() {
        let s = Section::Solid { radius: 10.0 };
        assert!((s.area() - 314.159_265).abs() < 1e-5);
        assert!((s.second_moment() - 7_853.981_63).abs() < 1e-4);
        assert_eq!(s.outer_radius(), 10.0);
        // A 60 × 4 tube: A = π (30² − 26²) = 703.7, I = π (30⁴ − 26⁴)/4 = 277 272.
        let t = Section::Tube {
            outer_diameter: 60.0,
            wall: 4.0,
        };
        assert!((t.area() - PI * (900.0 - 676.0)).abs() < 1e-9);
        assert!((t.second_moment() - PI * (810_000.0 - 456_976.0) / 4.0).abs() < 1e-6);
        assert_eq!(t.outer_radius(), 30.0);
        // A tube whose wall is half its diameter is the solid bar.
        let full = Section::Tube {
            outer_diameter: 20.0,
            wall: 10.0,
        };
        assert!((full.second_moment() - s.second_moment()).abs() < 1e-9);
        assert!(t.validate().is_ok() && full.validate().is_ok());
        let bad = [
            Section::Solid { radius: -1.0 },
            Section::Solid { radius: f64::NAN },
            Section::Tube {
                outer_diameter: 60.0,
                wall: 31.0,
            },
            Section::Tube {
                outer_diameter: 60.0,
                wall: 0.0,
            },
            Section::Solid { radius: 1e-200 },
        ];
        for b in bad {
            assert!(b.validate().is_err(), "{b:?}");
        }
    }
}

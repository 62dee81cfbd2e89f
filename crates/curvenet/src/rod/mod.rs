//! Rod energy: the material, the supports and the discrete elastic rod terms (`docs/model.md`,
//! *Energy*).
//!
//! - [`terms`]: the local stretching, bending and anchor terms with exact derivatives (and the
//!   bending term of a pre-bent rod);
//! - [`network`]: the rod network as data (what [`crate::network`] builds from curves);
//! - [`model`]: the flat list of all terms of a network and its sparse assembly, with the
//!   ability to leave out any set of curves (a structure: `docs/model.md`, *Stability*), every
//!   rod with its own stiffnesses and rest shape ([`RodStiffness`]);
//! - [`physical`]: those stiffnesses from materials and sections, and rigid supports, in the
//!   physical mode; [`mass`]: the lumped mass matrix and the scaling to `H v = μ M v`;
//! - [`ModelRules`]: what the physical mode models beyond the paper (a clamp that holds the
//!   end itself: `clamp`; pre-bent rods with twist unknowns and a material frame: [`frame`]).

mod active;
mod clamp;
mod clamp_twist;
pub mod frame;
mod jet;
pub mod mass;
pub mod model;
pub mod network;
pub mod physical;
mod prebent;
pub mod terms;

pub use active::ActiveSet;
pub use model::{Assembly, EnergyModel, Pressure, PressurePart};
pub use network::{Joint, Network, Rod};

use crate::material::RestShape;
use crate::words::Message;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Material constants of every rod, in scene units (`docs/model.md`, *Energy*).
///
/// Results depend on the radius relative to the curves' length: the defaults are the
/// reference's (`r = 2`, `E = 1`, `µ = 500`), made for scenes a few hundred to a few thousand
/// units across.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Rod radius `r`.
    pub radius: f64,
    /// Young's modulus `E`.
    pub young: f64,
    /// Anchor weight `µ` (an anchor is a spring of stiffness `2µ`).
    pub anchor_weight: f64,
}

/// The stiffnesses (`k_s`, `k_b`, an anchor's `2µ`) the energy accepts. Within them, on scenes
/// of the sizes the inputs accept, the Hessian's entries (`k_s / h`, `k_b / h³`), its norm and
/// the products the eigen solvers form stay within floating-point range; beyond them the first
/// energy, gradient or spectrum can overflow.
pub const STIFFNESS_RANGE: (f64, f64) = (1e-100, 1e100);

impl Default for Material {
    fn default() -> Self {
        Material {
            radius: 2.0,
            young: 1.0,
            anchor_weight: 500.0,
        }
    }
}

impl Material {
    /// Stretching stiffness `k_s = E π r²`.
    pub fn ks(&self) -> f64 {
        self.young * PI * self.radius * self.radius
    }

    /// Bending stiffness `k_b = E π r⁴ / 4`.
    pub fn kb(&self) -> f64 {
        self.young * PI * self.radius.powi(4) / 4.0
    }

    /// Checks that every constant is finite and positive, and the stiffnesses `k_s`, `k_b`
    /// and `2µ` lie in [`STIFFNESS_RANGE`].
    pub fn validate(&self) -> Result<(), Message> {
        for (name, v) in [
            ("radius", self.radius),
            ("young", self.young),
            ("anchor weight", self.anchor_weight),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(
                    format!("material {name} must be a positive finite number, got {v}").into(),
                );
            }
        }
        let (lo, hi) = STIFFNESS_RANGE;
        for (name, k) in [
            ("stretching stiffness E π r²", self.ks()),
            ("bending stiffness E π r⁴ / 4", self.kb()),
        ] {
            if !(lo..=hi).contains(&k) {
                return Err(format!(
                    "radius {:e} and Young's modulus {:e} give a {name} = {k:e}, out of the \
                     range the solvers handle ({lo:e} to {hi:e}); choose scene units where \
                     the radius is nearer 1",
                    self.radius, self.young
                )
                .into());
            }
        }
        let k = 2.0 * self.anchor_weight;
        if !(lo..=hi).contains(&k) {
            return Err(format!(
                "the anchor weight {:e} gives an anchor stiffness 2µ = {k:e}, out of the range \
                 the solvers handle ({lo:e} to {hi:e})",
                self.anchor_weight
            )
            .into());
        }
        Ok(())
    }
}

/// One rod's stiffnesses and rest shape, as the energy uses them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RodStiffness {
    /// Stretching stiffness `k_s` (`E A`).
    pub ks: f64,
    /// Bending stiffness `k_b` (`E I`).
    pub kb: f64,
    /// Torsional stiffness `G J`: used by a pre-bent rod's twist under
    /// [`ModelRules::PHYSICAL`] (a straight round rod's twist decouples).
    pub gj: f64,
    /// The section's outer radius `r`: a twist unknown is the outer fibre's displacement
    /// `r θ` (`rod::frame`).
    pub arm: f64,
    /// Straight at rest (the paper) or pre-bent to its drawn shape.
    pub rest: RestShape,
}

impl From<&Material> for RodStiffness {
    /// The paper's material: `G J = E I / (1 + ν)` with `ν = 0.3` (a round section), unused
    /// by the paper's rules.
    fn from(m: &Material) -> Self {
        RodStiffness {
            ks: m.ks(),
            kb: m.kb(),
            gj: m.kb() / 1.3,
            arm: m.radius,
            rest: RestShape::Straight,
        }
    }
}

/// How a clamped end is held (`docs/model.md`, *Energy*).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ClampRule {
    /// The paper's: the first two (last two) vertices anchored, a clamp half an edge into the
    /// rod (first-order convergence).
    #[default]
    TwoVertices,
    /// The physical mode's: the end vertex anchored and its drawn tangent held by a bending
    /// term against a mirrored ghost edge (second-order convergence; `rod::terms::clamp`).
    EndTangent,
}

/// What the energy models beyond its constants: the paper's rules (the default) or the
/// physical mode's ([`ModelRules::PHYSICAL`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ModelRules {
    /// How clamped ends are held.
    pub clamp: ClampRule,
    /// Whether pre-bent rods carry a twist unknown per edge and bend and twist through a
    /// material frame (`rod::frame`); without, a pre-bent rod's bending holds its drawn
    /// orientation in the world (`rod::terms::bend_rest`).
    pub twist: bool,
}

impl ModelRules {
    /// The paper's model.
    pub const PAPER: ModelRules = ModelRules {
        clamp: ClampRule::TwoVertices,
        twist: false,
    };
    /// The physical mode's model: a clamp holds the end vertex and its tangent, and pre-bent
    /// rods carry their twist.
    pub const PHYSICAL: ModelRules = ModelRules {
        clamp: ClampRule::EndTangent,
        twist: true,
    };
    /// The physical mode's clamps without twist unknowns: pre-bent rods bend by the twist-free
    /// term (`rod::terms::bend_rest`), which resists a rigid rotation. No analysis uses it
    /// (the physical analysis and the searches' frequency objective use [`Self::PHYSICAL`]);
    /// the tests show what it got wrong.
    pub const PHYSICAL_WITHOUT_TWIST: ModelRules = ModelRules {
        clamp: ClampRule::EndTangent,
        twist: false,
    };
}

/// Which vertices of an open curve are anchored (`docs/model.md`, *Energy*). Closed curves
/// have none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Supports {
    /// The first and last vertex.
    Pinned,
    /// The first two and last two vertices (the default); in the physical mode the end
    /// vertex and its tangent ([`ClampRule::EndTangent`]).
    #[default]
    Clamped,
}

impl Supports {
    /// The name used on the command line and in outputs.
    pub fn name(self) -> &'static str {
        match self {
            Supports::Pinned => "pinned",
            Supports::Clamped => "clamped",
        }
    }

    /// Positions (indices along the curve) of the supported vertices of an open curve with
    /// `n` vertices, without repeats, in increasing order.
    pub fn anchored_indices(self, n: usize) -> Vec<usize> {
        let mut idx = match self {
            Supports::Pinned => vec![0, n.saturating_sub(1)],
            Supports::Clamped => {
                vec![
                    0,
                    1.min(n.saturating_sub(1)),
                    n.saturating_sub(2),
                    n.saturating_sub(1),
                ]
            }
        };
        idx.sort_unstable();
        idx.dedup();
        idx
    }
}

impl std::str::FromStr for Supports {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "pinned" => Ok(Supports::Pinned),
            "clamped" => Ok(Supports::Clamped),
            _ => Err(format!(
                "unknown supports '{s}' (expected pinned or clamped)"
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_constants() {
        let m = Material::default();
        assert!((m.ks() - 4.0 * PI).abs() < 1e-12);
        assert!((m.kb() - 4.0 * PI).abs() < 1e-12);
        assert!(m.validate().is_ok());
        assert!(Material { radius: -1.0, ..m }.validate().is_err());
        assert!(
            Material {
                young: f64::NAN,
                ..m
            }
            .validate()
            .is_err()
        );
    }

    #[test]
    fn supported_vertices() {
        assert_eq!(Supports::Pinned.anchored_indices(10), vec![0, 9]);
        assert_eq!(Supports::Clamped.anchored_indices(10), vec![0, 1, 8, 9]);
        assert_eq!(Supports::Clamped.anchored_indices(3), vec![0, 1, 2]);
        assert_eq!(Supports::Clamped.anchored_indices(2), vec![0, 1]);
    }
}

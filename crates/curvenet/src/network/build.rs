//! From input polylines to a locked rod network (`docs/model.md`, *Network construction*):
//!
//! 1. crossings by closest approach ([`super::crossings`]);
//! 2. joints from crossings (`super::joints`); a joint within the tolerance of an open
//!    curve's end becomes that end;
//! 3. resampling and locking (`super::resample`).

use super::crossings::{CurveGeometry, find_crossings};
use super::joints::cluster_joints;
use super::resample::resample;
use super::{EdgeLengthStats, Network};
use crate::io::Polyline;
use crate::material::{EndFrame, EndSupport};
use crate::rod::Supports;
use crate::words::{Message, Opt, message};
use serde::{Deserialize, Serialize};

/// Parameters of network construction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BuildParams {
    /// Target edge length `h` in scene units.
    pub edge_length: f64,
    /// Supports of open curves.
    pub supports: Supports,
    /// Per-curve end supports that differ from `supports` (curve `i`'s start and end; `None`
    /// keeps `supports`), from the curve file or a supports file. Empty when there are none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ends: Vec<[Option<EndSupport>; 2]>,
    /// The surface's directions at each curve end whose support fixes one
    /// ([`EndSupport::surface`]), resolved against the mesh; empty when no support does.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub end_frames: Vec<[Option<EndFrame>; 2]>,
    /// Relative crossing tolerance: two curves cross where they come closer than
    /// `tolerance · ℓ`, `ℓ` the larger of their median segment lengths (the paper's `1e-3`).
    pub tolerance: f64,
    /// Optional: also merge joints closer than this fraction of `h` (in space or along a
    /// curve). Off by default so counts match the paper (tiny edges: `docs/model.md`,
    /// *Numerical hazards*).
    pub merge_joints_below: Option<f64>,
}

impl Default for BuildParams {
    fn default() -> Self {
        BuildParams {
            edge_length: 1.0,
            supports: Supports::Clamped,
            ends: Vec::new(),
            end_frames: Vec::new(),
            tolerance: 1e-3,
            merge_joints_below: None,
        }
    }
}

impl BuildParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), BuildError> {
        if !(self.edge_length.is_finite() && self.edge_length > 0.0) {
            return Err(BuildError::InvalidParams(format!(
                "edge length h must be a positive finite number, got {}",
                self.edge_length
            )));
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0 && self.tolerance < 0.5) {
            return Err(BuildError::InvalidParams(format!(
                "crossing tolerance must lie in (0, 0.5), got {}",
                self.tolerance
            )));
        }
        if let Some(f) = self.merge_joints_below
            && !(f.is_finite() && f > 0.0 && f < 1.0)
        {
            return Err(BuildError::InvalidParams(format!(
                "joint merging fraction must lie in (0, 1), got {f}"
            )));
        }
        Ok(())
    }
}

/// Why no network could be built.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// Parameters out of range.
    #[error("invalid network parameters: {0}")]
    InvalidParams(String),
    /// No curves at all.
    #[error("no curves to build a network from")]
    NoCurves,
    /// The edge length would cut the curves into more than [`MAX_VERTICES`] vertices.
    #[error("{}", self.message())]
    TooManyVertices {
        /// The target edge length.
        edge_length: f64,
        /// Total input length of the curves.
        total_length: f64,
        /// Estimated vertex count.
        vertices: f64,
    },
    /// A curve that cannot become a rod.
    #[error("{}", self.message())]
    DegenerateCurve {
        /// Source file of the curve.
        file: String,
        /// Line of the curve in its file.
        line: usize,
        /// Curve id.
        curve: usize,
        /// What is wrong.
        message: Message,
    },
}

impl BuildError {
    /// The error as a message naming the options that help, for a front end to spell
    /// (`Display` shows it neutrally).
    pub fn message(&self) -> Message {
        match self {
            BuildError::TooManyVertices {
                edge_length,
                total_length,
                vertices,
            } => message![
                format!(
                    "the edge length h = {edge_length:e} would cut the curves (total length \
                     {total_length:e}) into about {vertices:.3e} vertices, more than the \
                     {MAX_VERTICES} a network may have; give a larger "
                ),
                Opt::EdgeLength
            ],
            BuildError::DegenerateCurve {
                file,
                line,
                curve,
                message,
            } => message
                .clone()
                .prefixed([format!("{file}:{line}: curve {curve}: ").into()]),
            e => Message::from(e.to_string()),
        }
    }

    /// Curve `curve` of `curves` cannot be a rod: `message` says why.
    pub(super) fn degenerate(curves: &[Polyline], curve: usize, message: Message) -> Self {
        BuildError::DegenerateCurve {
            file: curves[curve].origin.file.clone(),
            line: curves[curve].origin.line,
            curve,
            message,
        }
    }
}

/// What construction found, for reports.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BuildInfo {
    /// Number of curves (= rods).
    pub curves: usize,
    /// Number of vertices.
    pub vertices: usize,
    /// Number of joints.
    pub joints: usize,
    /// Crossings of two different curves (after merging hits of the same pair).
    pub crossings: usize,
    /// Crossings of a curve with itself.
    pub self_crossings: usize,
    /// Largest number of curves meeting at one joint.
    pub max_curves_at_joint: usize,
    /// Curves that cross no other curve (they stand alone, held by their supports only).
    pub isolated_curves: Vec<usize>,
    /// Rest edge lengths.
    pub edge_length: EdgeLengthStats,
    /// Smallest crossing tolerance used (scene units).
    pub min_tolerance: f64,
    /// Largest crossing tolerance used (scene units).
    pub max_tolerance: f64,
    /// Findings that do not stop the build ([`super::checks::network_warnings`]): curves that
    /// cross nothing, curves that run together, edges far shorter than `h`.
    #[serde(default)]
    pub warnings: Vec<Message>,
}

/// The most vertices a network may have. The paper's largest has 25,442; far more than this
/// limit only comes from an edge length that is tiny against the curves, which would otherwise
/// exhaust memory before anything is reported.
pub const MAX_VERTICES: usize = 5_000_000;

/// The range of curve lengths and coordinate magnitudes (scene units) a network may have. The
/// bending terms scale like `1/ē³` and their Hessians faster, so far smaller scenes overflow
/// them; far larger ones lose the anchors' and the stretching terms' precision. Any physical
/// scene, in any unit, lies well inside.
pub const LENGTH_RANGE: (f64, f64) = (1e-30, 1e30);

/// Builds the rod network of `curves` (`docs/model.md`, *Network construction*).
pub fn build_network(
    curves: &[Polyline],
    params: &BuildParams,
) -> Result<(Network, BuildInfo), BuildError> {
    params.validate()?;
    if curves.is_empty() {
        return Err(BuildError::NoCurves);
    }
    let geo: Vec<CurveGeometry> = curves
        .iter()
        .map(|c| CurveGeometry::new(c.points.clone(), c.closed))
        .collect();
    for (i, g) in geo.iter().enumerate() {
        check_curve(g).map_err(|message| BuildError::degenerate(curves, i, message))?;
    }
    // Each open curve gets at least 2 edges per piece, a closed one at least 3; the estimate
    // is made in floating point so that a tiny h cannot overflow it.
    let total_length: f64 = geo.iter().map(CurveGeometry::length).sum();
    let too_many = |vertices: f64| {
        (!(vertices <= MAX_VERTICES as f64)).then_some(BuildError::TooManyVertices {
            edge_length: params.edge_length,
            total_length,
            vertices,
        })
    };
    let estimate: f64 = geo
        .iter()
        .map(|g| (g.length() / params.edge_length).max(3.0) + 1.0)
        .sum();
    if let Some(e) = too_many(estimate) {
        return Err(e);
    }
    let crossings = find_crossings(&geo, params.tolerance);
    let (joints, passes) = cluster_joints(&geo, &crossings, params);
    // Every pass through a joint splits a piece, which adds at least two edges.
    let with_joints = estimate + 2.0 * passes.iter().map(Vec::len).sum::<usize>() as f64;
    if let Some(e) = too_many(with_joints) {
        return Err(e);
    }
    let (network, mut info) = resample(&geo, &joints, &passes, params, curves)?;

    info.crossings = crossings.iter().filter(|c| c.a.curve != c.b.curve).count();
    info.self_crossings = crossings.len() - info.crossings;
    let mut touched = vec![false; curves.len()];
    for c in crossings.iter().filter(|c| c.a.curve != c.b.curve) {
        touched[c.a.curve as usize] = true;
        touched[c.b.curve as usize] = true;
    }
    info.isolated_curves = (0..curves.len()).filter(|&c| !touched[c]).collect();
    let tols: Vec<f64> = geo.iter().map(|g| g.tolerance(params.tolerance)).collect();
    info.min_tolerance = tols.iter().copied().fold(f64::INFINITY, f64::min);
    info.max_tolerance = tols.iter().copied().fold(0.0, f64::max);
    info.warnings = super::checks::network_warnings(
        &network,
        &info,
        curves,
        &geo,
        params.edge_length,
        params.tolerance,
    );
    Ok((network, info))
}

/// Why curve `g` cannot become a rod, if it cannot: too few points, non-finite points, zero
/// length, or a size outside [`LENGTH_RANGE`].
fn check_curve(g: &CurveGeometry) -> Result<(), Message> {
    if g.points.len() < 2 || (g.closed && g.points.len() < 3) {
        return Err(format!("{} points are too few for a rod", g.points.len()).into());
    }
    if let Some(p) = g.points.iter().find(|p| !p.is_finite()) {
        return Err(format!("non-finite point {p:?}").into());
    }
    if !(g.length() > 0.0) || !(g.median_segment > 0.0) {
        return Err(format!(
            "the curve has zero length{}",
            if g.points.iter().any(|p| *p != g.points[0]) {
                " (its points differ, but by so little that lengths underflow)"
            } else {
                ""
            }
        )
        .into());
    }
    let largest = g
        .points
        .iter()
        .flat_map(|p| p.to_array())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let (lo, hi) = LENGTH_RANGE;
    if !(g.length() >= lo && g.length() <= hi && largest <= hi) {
        return Err(message![
            format!(
                "the curve's length {:e} (coordinates up to {largest:e}) is outside \
                 {lo:e}..{hi:e}, the range of scene sizes the rod model computes with; \
                 rescale the scene (",
                g.length(),
            ),
            Opt::Scale,
            ")"
        ]);
    }
    Ok(())
}

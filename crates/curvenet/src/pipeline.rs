//! The pipeline's glue: curves in, analysed network out. Commands and tests call these rather
//! than wiring the stages by hand.

use crate::io::Polyline;
use crate::network::{BuildInfo, BuildParams, build_network};
use crate::physics::PhysicalParams;
use crate::report::AnalysisReport;
use crate::rod::ActiveSet;
use crate::stability::{Analysis, Analyzer, StabilityParams};
use crate::words::{Recorded, Wording};

/// Multiplies every point by `s`.
pub fn scale_curves(curves: &mut [Polyline], s: f64) {
    for c in curves {
        for p in &mut c.points {
            *p = *p * s;
        }
    }
}

/// Edges along a curve of median length that the default edge length aims at.
pub const DEFAULT_EDGES_PER_CURVE: f64 = 50.0;

/// The most edges, over all curves together, the default edge length allows.
pub const DEFAULT_MAX_EDGES: f64 = 100_000.0;

/// Networks with more vertices than this are announced before they are built: their analysis
/// takes minutes and gigabytes.
pub const LARGE_NETWORK_VERTICES: f64 = 200_000.0;

/// The default edge length `h`: the median curve length over [`DEFAULT_EDGES_PER_CURVE`], and
/// no less than the total length over [`DEFAULT_MAX_EDGES`]. It depends on the curves' lengths,
/// not on how densely they are sampled, so a curve drawn with 100,000 points does not make the
/// network explode. `None` when the curves have no length (or a length out of range).
pub fn default_edge_length(curves: &[Polyline]) -> Option<f64> {
    let mut lengths: Vec<f64> = curves.iter().map(Polyline::length).collect();
    lengths.sort_by(f64::total_cmp);
    let median = *lengths.get(lengths.len() / 2)?;
    let total: f64 = lengths.iter().sum();
    let h = (median / DEFAULT_EDGES_PER_CURVE).max(total / DEFAULT_MAX_EDGES);
    (h.is_finite() && h > 0.0).then_some(h)
}

/// About how many vertices the network of `curves` has at edge length `h`: each curve's
/// `max(2, round(L / h))` edges (3 for a closed curve), plus one vertex at the end of an open
/// curve. Joints split pieces (adding a few edges) and share vertices (removing some): the
/// estimate is close for networks whose pieces are longer than `h`, and never far below the
/// truth when `h` is small, which is when it matters.
pub fn estimated_vertices(curves: &[Polyline], h: f64) -> f64 {
    curves
        .iter()
        .map(|c| {
            let min = if c.closed { 3.0 } else { 2.0 };
            let edges = (c.length() / h).round().max(min);
            if c.closed { edges } else { edges + 1.0 }
        })
        .sum()
}

/// The estimated vertex count of the network `curves` make at edge length `h` when it is above
/// [`LARGE_NETWORK_VERTICES`] (a network to announce before it is built), else `None`.
pub fn large_network(curves: &[Polyline], h: f64) -> Option<f64> {
    let n = estimated_vertices(curves, h);
    (n > LARGE_NETWORK_VERTICES).then_some(n)
}

/// Everything `analyze` produces.
#[derive(Debug)]
pub struct AnalyzeOutput {
    /// The stability analyzer (owns the network).
    pub analyzer: Analyzer,
    /// Construction details.
    pub build: BuildInfo,
    /// The analysis of the requested structure.
    pub analysis: Analysis,
    /// The report (what `curvenet analyze` prints).
    pub report: AnalysisReport,
}

/// Why the pipeline stopped.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// Network construction failed.
    #[error(transparent)]
    Build(#[from] crate::network::build::BuildError),
    /// Bad parameters.
    #[error("invalid parameters: {0}")]
    Params(String),
    /// The stability analysis failed.
    #[error(transparent)]
    Stability(#[from] crate::stability::StabilityError),
}

/// Builds the network of `curves`, removes `removed`, relaxes and analyses what is left (the
/// report's warnings name options as a record does, [`Recorded`]).
///
/// The analysis is that of `params.objective`: the paper's `λ_eq`, or under the frequency
/// objective `μ_min` of the mass-metric problem, the number the searches maximise. With
/// `physical` (the physical mode) the frequency objective's model is the structure's own, as
/// in the searches; the report's units note then describes the physical section.
pub fn analyze(
    curves: &[Polyline],
    build: &BuildParams,
    params: &StabilityParams,
    physical: Option<&PhysicalParams>,
    removed: &[usize],
    warnings: Vec<String>,
) -> Result<AnalyzeOutput, PipelineError> {
    let (network, info) = build_network(curves, build)?;
    let mut analyzer =
        Analyzer::new(network, params.clone()).map_err(|e| PipelineError::Params(e.to_string()))?;
    if let Some(p) = physical {
        analyzer = analyzer
            .with_physical(p.clone())
            .map_err(|e| PipelineError::Params(e.to_string()))?;
    }
    analyze_built(analyzer, info, physical, removed, warnings, &Recorded)
}

/// [`analyze`] of a network already built (`info` its build's findings) in `analyzer`, the
/// report's warnings naming options as `words` spell them.
pub fn analyze_built(
    analyzer: Analyzer,
    info: BuildInfo,
    physical: Option<&PhysicalParams>,
    removed: &[usize],
    warnings: Vec<String>,
    words: &dyn Wording,
) -> Result<AnalyzeOutput, PipelineError> {
    let n = analyzer.network().rods.len();
    let mut active = ActiveSet::all(n);
    for &c in removed {
        if c >= n {
            return Err(PipelineError::Params(format!(
                "cannot remove curve {c}: no such curve"
            )));
        }
        active.remove(c);
    }
    let analysis = analyzer.analyze(&active, None)?;
    let params = analyzer.params();
    let mut report = AnalysisReport::new(
        analyzer.network(),
        &info,
        &params.material,
        &active,
        &analysis,
        warnings,
        words,
    )
    .with_objective(params.objective);
    if let Some(p) = physical {
        report.use_physical_radius(
            analyzer.network(),
            p.physical.section.outer_radius(),
            p.physical.units.symbol(),
        );
    }
    Ok(AnalyzeOutput {
        analyzer,
        build: info,
        analysis,
        report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vec3;
    use crate::io::Origin;

    fn line(points: usize, length: f64) -> Polyline {
        Polyline {
            points: (0..points)
                .map(|i| Vec3::new(length * i as f64 / (points - 1) as f64, 0.0, 0.0))
                .collect(),
            closed: false,
            origin: Origin::new("<test>", 0),
            label: None,
        }
    }

    #[test]
    fn the_default_edge_length_ignores_how_densely_curves_are_sampled() {
        let sparse = vec![line(3, 100.0), line(3, 100.0), line(3, 200.0)];
        let mut dense = sparse.clone();
        dense[1] = line(100_000, 100.0);
        assert_eq!(default_edge_length(&sparse), Some(2.0));
        assert_eq!(default_edge_length(&dense), Some(2.0));
        // Never more than about DEFAULT_MAX_EDGES edges in all: one huge curve among small ones.
        let lopsided = vec![line(3, 1.0), line(3, 1.0), line(3, 1e7)];
        let h = default_edge_length(&lopsided).unwrap();
        assert!(estimated_vertices(&lopsided, h) <= DEFAULT_MAX_EDGES + 10.0);
        assert_eq!(default_edge_length(&[]), None);
    }

    #[test]
    fn large_networks_are_announced_with_their_vertex_count() {
        let curves = vec![line(3, 1000.0); 4];
        assert_eq!(estimated_vertices(&curves, 10.0), 4.0 * 101.0);
        assert_eq!(large_network(&curves, 10.0), None);
        let n = large_network(&curves, 0.01).expect("400,000 vertices are announced");
        assert!((n - 400_004.0).abs() < 1.0, "{n}");
    }
}

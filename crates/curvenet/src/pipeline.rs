//! The pipeline's glue: curves in, analysed network out. Commands and tests call these rather
//! than wiring the stages by hand.

use crate::io::Polyline;
use crate::network::{BuildInfo, BuildParams, Network, build_network};
use crate::report::AnalysisReport;
use crate::rod::ActiveSet;
use crate::stability::{Analysis, Analyzer, StabilityParams};

/// Multiplies every point by `s`.
pub fn scale_curves(curves: &mut [Polyline], s: f64) {
    for c in curves {
        for p in &mut c.points {
            *p = *p * s;
        }
    }
}

/// Median input segment length over all curves (a default edge length that keeps the input's
/// resolution).
pub fn median_segment_length(curves: &[Polyline]) -> f64 {
    let mut lens: Vec<f64> = curves
        .iter()
        .flat_map(|c| {
            let n = c.points.len();
            let segs = if c.closed { n } else { n.saturating_sub(1) };
            (0..segs).map(move |k| c.points[k].dist(c.points[(k + 1) % n]))
        })
        .collect();
    if lens.is_empty() {
        return 1.0;
    }
    lens.sort_by(f64::total_cmp);
    lens[lens.len() / 2]
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
    /// The report of SPEC §10.
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

/// Builds the network of `curves`, removes `removed`, relaxes and analyses what is left.
pub fn analyze(
    curves: &[Polyline],
    build: &BuildParams,
    params: &StabilityParams,
    removed: &[usize],
    warnings: Vec<String>,
) -> Result<AnalyzeOutput, PipelineError> {
    let (network, info) = build_network(curves, build)?;
    let analyzer = Analyzer::new(network, params.clone()).map_err(PipelineError::Params)?;
    let mut active = ActiveSet::all(curves.len());
    for &c in removed {
        if c >= curves.len() {
            return Err(PipelineError::Params(format!(
                "cannot remove curve {c}: no such curve"
            )));
        }
        active.remove(c);
    }
    let analysis = analyzer.analyze(&active, None)?;
    let report = AnalysisReport::new(
        analyzer.network(),
        &info,
        &params.material,
        &active,
        &analysis,
        warnings,
    );
    Ok(AnalyzeOutput {
        analyzer,
        build: info,
        analysis,
        report,
    })
}

/// Convenience for tests: the network of `curves`.
pub fn network(curves: &[Polyline], build: &BuildParams) -> Result<Network, PipelineError> {
    Ok(build_network(curves, build)?.0)
}

//! One analysis of a set-up's network (or of what removing some curves leaves): the
//! equilibrium, the stability report and, in the physical mode, the physical report; what
//! `curvenet analyze`, Python's `Network.analyze` and the server's start give, with one JSON
//! form.

use super::setup::{Setup, check_curve_ids};
use crate::app::AppError;
use crate::physics::{PhysicalReport, PhysicsError, analyze_physical};
use crate::pipeline;
use crate::report::AnalysisReport;
use crate::rod::ActiveSet;
use crate::stability::{Analysis, Analyzer};
use crate::words::{Opt, Wording, message};

/// An analysis and its reports.
#[derive(Debug)]
pub struct AnalyzeOutcome {
    /// The analyzer (owns the network).
    pub analyzer: Analyzer,
    /// The analysis of the structure.
    pub analysis: Analysis,
    /// The stability report (counts, Newton, `λ`, the spectrum, warnings).
    pub report: AnalysisReport,
    /// The physical report (the physical mode only).
    pub physical: Option<PhysicalReport>,
}

/// The JSON object of an analysis: the report's fields in their order, then `physical` when
/// there is one.
#[derive(serde::Serialize)]
struct AnalysisJson<'a> {
    #[serde(flatten)]
    report: &'a AnalysisReport,
    #[serde(skip_serializing_if = "Option::is_none")]
    physical: Option<&'a PhysicalReport>,
}

impl AnalyzeOutcome {
    /// The analysis as one JSON object (`curvenet analyze --json`'s line).
    pub fn to_json(&self) -> String {
        serde_json::to_string(&AnalysisJson {
            report: &self.report,
            physical: self.physical.as_ref(),
        })
        .expect("an analysis report serialises")
    }

    /// The analysis as text for a reader.
    pub fn to_text(&self) -> String {
        let mut text = self.report.to_text();
        if let Some(p) = &self.physical {
            text.push_str(&p.to_text());
        }
        text
    }
}

/// Analyses the set-up's network without the curves `remove` (each named once or more).
/// The report's warnings are the inputs', the build's and the analysis' own, spelled by
/// `words`.
pub fn analyze(
    setup: &mut Setup,
    remove: &[usize],
    words: &dyn Wording,
) -> Result<AnalyzeOutcome, AppError> {
    let n = setup.curve_count();
    check_curve_ids(Opt::Remove, remove, n)?;
    let mut removed = remove.to_vec();
    removed.sort_unstable();
    removed.dedup();
    if removed.len() >= n {
        return Err(AppError::usage(message![
            Opt::Remove,
            " would remove every curve; nothing is left to analyse"
        ]));
    }
    let analyzer = setup.analyzer()?;
    let info = setup.built().expect("built by the analyzer").1.clone();
    let warnings = setup
        .inputs
        .warnings
        .iter()
        .map(|w| w.render(words))
        .collect();
    let physical_params = setup.model.physical.as_ref();
    let out = pipeline::analyze_built(analyzer, info, physical_params, &removed, warnings, words)
        .map_err(|e| AppError::Failed(e.to_string()))?;
    let physical = match physical_params {
        Some(p) => {
            let mut active = ActiveSet::all(n);
            for &c in &removed {
                active.remove(c);
            }
            Some(
                analyze_physical(out.analyzer.network(), p, &active).map_err(|e| match e {
                    // Parameters the network refuses (a point load off it) are the user's.
                    PhysicsError::Params(m) => AppError::Usage(m),
                    e => AppError::Failed(e.to_string()),
                })?,
            )
        }
        None => None,
    };
    let pipeline::AnalyzeOutput {
        analyzer,
        analysis,
        report,
        ..
    } = out;
    Ok(AnalyzeOutcome {
        analyzer,
        analysis,
        report,
        physical,
    })
}

//! Networks the stability module's unit tests share.

use super::{Analyzer, StabilityParams};
use crate::network::{BuildParams, build_network};
use crate::rod::Supports;

/// The 3×3 dome of arcs (clamped, h = 150) and its analyzer.
pub(crate) fn dome_analyzer() -> Analyzer {
    dome_analyzer_with(StabilityParams::default())
}

/// [`dome_analyzer`] with `params`.
pub(crate) fn dome_analyzer_with(params: StabilityParams) -> Analyzer {
    let scene = crate::builtin::dome_arcs(2000.0, 700.0, 3, 3);
    let build = BuildParams {
        edge_length: 150.0,
        supports: Supports::Clamped,
        ..Default::default()
    };
    let (net, _) = build_network(&scene.curves, &build).expect("builds");
    Analyzer::new(net, params).expect("analyzer")
}

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

/// A 3 × 3 grid of gently arched curves 2 apart crossing at nine points (curves 0–2 along
/// x at y = −1, 0, 1; curves 3–5 along y), rods of radius 0.01, h = 0.25, clamped ends.
pub(crate) fn grid_analyzer() -> Analyzer {
    use crate::geom::Vec3;
    let curves: Vec<_> = [(0, -1.0), (0, 0.0), (0, 1.0), (1, -1.0), (1, 0.0), (1, 1.0)]
        .into_iter()
        .map(|(dir, at)| {
            let points = (0..=8)
                .map(|i| {
                    let t = -2.0 + 0.5 * f64::from(i);
                    let z = 0.3 * (1.0 - t * t / 4.0);
                    if dir == 0 {
                        Vec3::new(t, at, z)
                    } else {
                        Vec3::new(at, t, z)
                    }
                })
                .collect();
            crate::constraints::testing::polyline(points, false)
        })
        .collect();
    let build = BuildParams {
        edge_length: 0.25,
        ..Default::default()
    };
    let (net, _) = build_network(&curves, &build).expect("builds");
    let mut params = StabilityParams::default();
    params.material.radius = 0.01;
    Analyzer::new(net, params).expect("analyzer")
}

//! `curvenet serve --bench`'s drawing part: the server-side time of adding a curve — the
//! edit's whole work as `POST /api/curves` does it ([`Workspace::draw`]: the curve traced, the
//! network rebuilt from the design's curves, its structure analysed) — for geodesics drawn
//! across the middle of curves chosen by a seed, each added to the design as it started.

use crate::bench::median_p90;
use crate::workspace::Workspace;
use curvenet::app::{DrawEdit, NewCurve};
use curvenet::geom::Vec3;
use curvenet::rng::SplitMix64;
use std::fmt::Write as _;
use std::time::Instant;

/// One curve added.
#[derive(Clone, Debug)]
pub struct AddRow {
    /// The curve it was drawn across.
    pub across: usize,
    /// Server-side milliseconds.
    pub ms: f64,
    /// `λ` of the new structure.
    pub lambda: f64,
    /// The new curve's joints.
    pub joints: usize,
}

/// The curves added.
#[derive(Clone, Debug)]
pub struct DrawBench {
    /// Curves in the design.
    pub curves: usize,
    /// Vertices in its network.
    pub vertices: usize,
    /// Each addition (those the tracer refused both ways left out).
    pub adds: Vec<AddRow>,
}

/// Adds `count` geodesics to `ws`'s design, one at a time, each to the design as it is now:
/// from the middle of a curve drawn by `seed`, across it (or, when that leaves the surface at
/// once, the other way). `None` when the design's curves cannot be drawn on.
pub fn run(ws: &Workspace, count: usize, seed: u64) -> Option<DrawBench> {
    let drawing = ws.drawing.as_ref()?;
    let curves = drawing.curves();
    let mut rng = SplitMix64::new(seed);
    let mut adds = Vec::new();
    for _ in 0..count {
        let c = rng.below(curves.len() as u64) as usize;
        let pts = &curves[c].points;
        let m = pts.len() / 2;
        if m + 1 >= pts.len() {
            continue;
        }
        let (p, t) = (pts[m], pts[m + 1] - pts[m]);
        let across = t.cross(Vec3::new(0.0, 0.0, 1.0));
        for direction in [across, -across] {
            let edit = DrawEdit::Add(NewCurve::Geodesic {
                point: p,
                direction,
            });
            let start = Instant::now();
            if let Ok((next, Some(id))) = ws.draw(&edit) {
                let ms = start.elapsed().as_secs_f64() * 1e3;
                let net = next.design.analyzer().network();
                adds.push(AddRow {
                    across: c,
                    ms,
                    lambda: next.design.current().summary.lambda,
                    joints: curvenet::app::draw::joints_of(net, id).len(),
                });
                break;
            }
        }
    }
    let net = ws.design.analyzer().network();
    Some(DrawBench {
        curves: curves.len(),
        vertices: net.vertex_count(),
        adds,
    })
}

impl DrawBench {
    /// Median and 90th percentile of the additions' milliseconds.
    pub fn ms(&self) -> (f64, f64) {
        median_p90(self.adds.iter().map(|a| a.ms).collect())
    }

    /// The report as text: a line per curve added, then the median.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "adding a curve (a geodesic across the middle of a curve; the network rebuilt, its \
             structure analysed from the drawn state): {} curves, {} vertices",
            self.curves, self.vertices
        );
        for a in &self.adds {
            let _ = writeln!(
                s,
                "  across curve {:>4}: {:>9.1} ms, {} joints, λ {:.6e}",
                a.across, a.ms, a.joints, a.lambda
            );
        }
        let (median, p90) = self.ms();
        let _ = writeln!(
            s,
            "adding a curve: median {median:.1} ms, p90 {p90:.1} ms over {} curves",
            self.adds.len()
        );
        s
    }
}

//! The paper's curve generators, with the reference's conventions.
//!
//! Every geodesic generator draws with [`MsvcRand`], the reference's Windows `rand()`:
//! `srand(seed)` once, then `U[a, b] = rand() / RAND_MAX · (b − a) + a` per draw. Each curve is
//! a (loop, `t`, `θ`) triple traced by [`trace_geodesic`]:
//!
//! | generator | loop | `t` | `θ` | draws per curve |
//! |---|---|---|---|---|
//! | [`Generator::Hill`], [`Generator::Bunny`] | 0 | `i/n + 1/(2n)` | `U[π/4, 3π/4]` | `θ` |
//! | [`Generator::Stadium`] | `i mod 2` (loop 0 is the inner ring) | `i/n + 1/(2n)` | `U[π/5, 4π/5]` | `θ` |
//! | [`Generator::Tent`] | 0 | `U[0, 1]` | `U[π/6, 5π/6]` | `t` then `θ`, per attempt |
//! | [`Generator::Random`] (command-line scenes) | 0 | `U[0, 1]` | `U[π/6, 5π/6]` | `t` then `θ` |
//!
//! Reading of the order of draws (as the reference's loops do): the
//! draws of curve `i` happen just before curve `i` is traced, and nothing else draws in
//! between, so the sequence of values does not depend on how traces end. A trace that fails
//! (length cap, non-manifold element…) consumes its draws, is counted in
//! [`GeneratedCurves::failed`] and leaves no curve: the fixed-count generators then return
//! fewer than `count` curves (the reference, whose tracer cannot fail this way, has no rule
//! here). The tent generator rejects a curve (draws consumed) when its first or last point is
//! more than `ground_tolerance` above or below `z = 0` (the reference's test, `|z| > 5e-3` in
//! file units) and keeps drawing until `count` curves are accepted.
//!
//! The generators trace on the mesh as given. The examples trace hill, bunny and tent in file
//! units (unscaled); the reference traces the stadium on its ×30 mesh, which gives the same
//! curves scaled (geodesics do not depend on scale; only the tent's ground tolerance does).
//! For command-line scenes scale the mesh first with
//! [`scale_to_extent`](super::scale_to_extent)`(mesh, 4000.0)`, as the reference does.
//!
//! The networks built from the regenerated curves, against the paper's counts:
//! `docs/model.md`, *The paper's examples*.

use super::TraceError;
use super::field::{FieldOptions, smooth_field};
use super::geodesic::{TraceOptions, trace_geodesic};
use super::streamline::{StreamlineOptions, trace_streamlines};
use super::topology::MeshTopology;
use crate::io::{Origin, Polyline, TriMesh};
use crate::rng::MsvcRand;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Default number of attempts of the tent generator before it gives up.
pub const DEFAULT_MAX_ATTEMPTS: usize = 100_000;

/// A way of generating curves on a mesh. Serialised as `{"kind": "hill", "count": 70, …}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Generator {
    /// The hill's geodesics: loop 0, `t = i/n + 1/(2n)`, `θ ~ U[π/4, 3π/4]`.
    Hill {
        /// Number of curves `n`.
        count: usize,
        /// `srand` seed.
        seed: u32,
    },
    /// The bunny's geodesics: the same rule as [`Generator::Hill`].
    Bunny {
        /// Number of curves `n`.
        count: usize,
        /// `srand` seed.
        seed: u32,
    },
    /// The stadium's geodesics: loops alternate 0, 1, 0, … (`i mod 2`),
    /// `t = i/n + 1/(2n)`, `θ ~ U[π/5, 4π/5]`. Needs two boundary loops.
    Stadium {
        /// Number of curves `n`.
        count: usize,
        /// `srand` seed.
        seed: u32,
    },
    /// The tent's geodesics: loop 0, per attempt `t ~ U[0, 1]` then `θ ~ U[π/6, 5π/6]`;
    /// curves whose first or last point has `|z| > ground_tolerance` are rejected, until
    /// `count` are accepted or `max_attempts` attempts are made.
    Tent {
        /// Number of curves to accept.
        count: usize,
        /// `srand` seed.
        seed: u32,
        /// Largest `|z|` of an end on the ground (the reference: 5e-3 in file units).
        ground_tolerance: f64,
        /// Attempts before giving up with [`TraceError::GeneratorExhausted`].
        max_attempts: usize,
    },
    /// Command-line scenes: loop 0, `t ~ U[0, 1]` then `θ ~ U[π/6, 5π/6]` per curve.
    Random {
        /// Number of curves.
        count: usize,
        /// `srand` seed.
        seed: u32,
    },
    /// Streamlines of the smoothest boundary-aligned `degree`-direction field, from `seeds`
    /// seeds spread evenly along the boundary (see [`trace_streamlines`]).
    Streamlines {
        /// Symmetry order: 4 (two directions) or 6 (three).
        degree: u32,
        /// Number of seeds.
        seeds: usize,
    },
}

impl Generator {
    /// The generator of a paper example: hill (70 geodesics, seed 2), stadium (100,
    /// seed 4), bunny (75, seed 9), tent (66, seed 2, ground tolerance 5e-3).
    pub fn paper(name: &str) -> Option<Generator> {
        match name {
            "hill" => Some(Generator::Hill { count: 70, seed: 2 }),
            "stadium" => Some(Generator::Stadium {
                count: 100,
                seed: 4,
            }),
            "bunny" => Some(Generator::Bunny { count: 75, seed: 9 }),
            "tent" => Some(Generator::Tent {
                count: 66,
                seed: 2,
                ground_tolerance: 5e-3,
                max_attempts: DEFAULT_MAX_ATTEMPTS,
            }),
            _ => None,
        }
    }

    /// A short name for messages and curve origins.
    pub fn name(&self) -> &'static str {
        match self {
            Generator::Hill { .. } => "hill",
            Generator::Bunny { .. } => "bunny",
            Generator::Stadium { .. } => "stadium",
            Generator::Tent { .. } => "tent",
            Generator::Random { .. } => "random",
            Generator::Streamlines { .. } => "streamlines",
        }
    }
}

/// How one generated curve was made.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurveRecord {
    /// Boundary loop it starts on.
    pub loop_index: usize,
    /// Arc-length fraction as drawn (geodesics: of the loop's length without its closing
    /// edge, before the 0/1 nudge; streamlines: of the full loop length).
    pub t: f64,
    /// Angle from the boundary direction, radians.
    pub theta: f64,
    /// Attempt number (0-based; equals the curve number for the fixed-count generators, the
    /// seed number for streamlines).
    pub attempt: usize,
}

/// Curves made by a [`Generator`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GeneratedCurves {
    /// The curves, in generation order (labelled `"<generator> <i>"`).
    pub curves: Vec<Polyline>,
    /// How each curve was made (same order).
    pub records: Vec<CurveRecord>,
    /// Attempts made (curves traced or tried).
    pub attempts: usize,
    /// Curves traced but rejected (tent: an end off the ground; streamlines: duplicates).
    pub rejected: usize,
    /// Traces that failed (geodesics) or streamlines dropped (singularity, stall, cap).
    pub failed: usize,
    /// One message per failed geodesic: `attempt i (loop, t, θ): error`.
    pub failures: Vec<String>,
}

/// Generates curves on `mesh` (see the module documentation for each generator's rule),
/// tracing each geodesic with the default [`TraceOptions`].
///
/// # Errors
///
/// Mesh errors of [`MeshTopology::new`], [`TraceError::NoBoundary`],
/// [`TraceError::LoopOutOfRange`] (stadium on a mesh with one loop),
/// [`TraceError::InvalidParameter`] for a negative ground tolerance,
/// [`TraceError::GeneratorExhausted`] when the tent runs out of attempts, and the field
/// errors of [`smooth_field`] for streamlines. Failed individual geodesics are counted, not
/// returned as errors.
pub fn generate(mesh: &TriMesh, generator: &Generator) -> Result<GeneratedCurves, TraceError> {
    let options = &TraceOptions::default();
    let topo = MeshTopology::new(mesh)?;
    if topo.boundary_loops().is_empty() {
        return Err(TraceError::NoBoundary);
    }
    let mut g = Geodesics {
        topo: &topo,
        name: generator.name(),
        options,
        out: GeneratedCurves::default(),
    };
    match *generator {
        Generator::Hill { count, seed } | Generator::Bunny { count, seed } => {
            g.evenly(count, seed, (PI / 4.0, 3.0 * PI / 4.0), 1);
        }
        Generator::Stadium { count, seed } => {
            if topo.boundary_loops().len() < 2 && count > 1 {
                return Err(TraceError::LoopOutOfRange {
                    index: 1,
                    count: topo.boundary_loops().len(),
                });
            }
            g.evenly(count, seed, (PI / 5.0, 4.0 * PI / 5.0), 2);
        }
        Generator::Tent {
            count,
            seed,
            ground_tolerance,
            max_attempts,
        } => g.tent(count, seed, ground_tolerance, max_attempts)?,
        Generator::Random { count, seed } => g.random(count, seed),
        Generator::Streamlines { degree, seeds } => {
            return streamlines(&topo, degree, seeds, options);
        }
    }
    Ok(g.out)
}

/// Geodesics traced on one mesh, filed into `out` as they are drawn.
struct Geodesics<'a> {
    topo: &'a MeshTopology,
    /// The generator's name, for labels and origins.
    name: &'static str,
    options: &'a TraceOptions,
    out: GeneratedCurves,
}

impl Geodesics<'_> {
    /// `count` curves at evenly spaced `t = i/n + 1/(2n)`, `θ ~ U[lo, hi]`, curve `i` on loop
    /// `i mod loops` (hill, bunny: one loop; stadium: two).
    fn evenly(&mut self, count: usize, seed: u32, (lo, hi): (f64, f64), loops: usize) {
        let mut rng = MsvcRand::new(seed);
        for i in 0..count {
            let theta = rng.uniform(lo, hi);
            let t = i as f64 / count as f64 + 1.0 / (2.0 * count as f64);
            self.attempt(i % loops, t, theta, None);
        }
    }

    /// The tent's curves: `t ~ U[0, 1]` then `θ ~ U[π/6, 5π/6]` per attempt, until `count`
    /// curves with both ends on the ground are accepted or `max_attempts` are made.
    fn tent(
        &mut self,
        count: usize,
        seed: u32,
        ground_tolerance: f64,
        max_attempts: usize,
    ) -> Result<(), TraceError> {
        if !(ground_tolerance >= 0.0) {
            return Err(TraceError::InvalidParameter {
                name: "ground_tolerance",
                value: ground_tolerance,
                expected: "a non-negative distance",
            });
        }
        let mut rng = MsvcRand::new(seed);
        while self.out.curves.len() < count {
            if self.out.attempts >= max_attempts {
                return Err(TraceError::GeneratorExhausted {
                    accepted: self.out.curves.len(),
                    wanted: count,
                    attempts: self.out.attempts,
                });
            }
            let t = rng.uniform(0.0, 1.0);
            let theta = rng.uniform(PI / 6.0, 5.0 * PI / 6.0);
            self.attempt(0, t, theta, Some(ground_tolerance));
        }
        Ok(())
    }

    /// Command-line scenes' curves: `t ~ U[0, 1]` then `θ ~ U[π/6, 5π/6]` per curve.
    fn random(&mut self, count: usize, seed: u32) {
        let mut rng = MsvcRand::new(seed);
        for _ in 0..count {
            let t = rng.uniform(0.0, 1.0);
            let theta = rng.uniform(PI / 6.0, 5.0 * PI / 6.0);
            self.attempt(0, t, theta, None);
        }
    }

    /// Traces one geodesic and files the result: a curve, a rejection (with `ground`, an end
    /// more than that above or below `z = 0`) or a failure.
    fn attempt(&mut self, loop_index: usize, t: f64, theta: f64, ground: Option<f64>) {
        let (name, out) = (self.name, &mut self.out);
        let index = out.attempts;
        out.attempts += 1;
        match trace_geodesic(self.topo, loop_index, t, theta, self.options) {
            Ok(path) => {
                let mut curve = path.polyline;
                if let Some(tol) = ground {
                    let on_ground =
                        |p: Option<&crate::geom::Vec3>| p.is_some_and(|p| p.z.abs() <= tol);
                    if !on_ground(curve.points.first()) || !on_ground(curve.points.last()) {
                        out.rejected += 1;
                        return;
                    }
                }
                curve.label = Some(format!("{name} {}", out.curves.len()));
                curve.origin = Origin::new(format!("<{name}>"), 0);
                out.curves.push(curve);
                out.records.push(CurveRecord {
                    loop_index,
                    t,
                    theta,
                    attempt: index,
                });
            }
            Err(e) => {
                out.failed += 1;
                out.failures.push(format!(
                    "attempt {index} (loop {loop_index}, t {t}, θ {theta}): {e}"
                ));
            }
        }
    }
}

/// Streamlines of the smoothest boundary-aligned `degree`-direction field from `seeds` seeds.
fn streamlines(
    topo: &MeshTopology,
    degree: u32,
    seeds: usize,
    options: &TraceOptions,
) -> Result<GeneratedCurves, TraceError> {
    let field = smooth_field(
        topo,
        &FieldOptions {
            degree,
            ..FieldOptions::default()
        },
    )?;
    let lines = trace_streamlines(
        topo,
        &field,
        &StreamlineOptions {
            seeds,
            trace: *options,
            ..StreamlineOptions::default()
        },
    )?;
    Ok(GeneratedCurves {
        attempts: lines.started,
        rejected: lines.duplicates,
        failed: lines.singular + lines.stalled + lines.too_long + lines.failed,
        records: lines
            .records
            .iter()
            .map(|r| CurveRecord {
                loop_index: r.loop_index,
                t: r.loop_fraction,
                theta: r.theta,
                attempt: r.seed,
            })
            .collect(),
        curves: lines.curves,
        failures: Vec::new(),
    })
}

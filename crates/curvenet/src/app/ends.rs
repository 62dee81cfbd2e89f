//! Each curve's end supports: the curve files' own (`"supports"` per curve) and a supports
//! file's, which override them, resolved to curve ends. A supports file names an end by curve
//! id or by a point: every open curve end within [`END_TOLERANCE`] of the scene's size of that
//! point (in the curve files' coordinates, times the scale) takes the support; a point near no
//! curve end is an error at its line, saying how far the nearest end is. An end whose support
//! fixes a direction of the surface gets that direction from the mesh (`end_frames`); an error
//! there names the line that gave the support.

use super::end_frames::end_frame;
use crate::app::AppError;
use crate::geom::{Aabb, Vec3};
use crate::io::{EndPlace, InputError, Polyline, SupportEntry, TriMesh};
use crate::material::{CurveSpec, EndFrame, EndSupport};
use std::path::Path;

/// How close (relative to the curves' bounding-box diagonal) a supports file's point must be
/// to a curve end to name it.
pub const END_TOLERANCE: f64 = 1e-3;

/// Each curve's end supports and, where one fixes a direction of the surface, that end's
/// directions (`BuildParams::ends`, `BuildParams::end_frames`).
pub(super) type CurveEnds = (Vec<[Option<EndSupport>; 2]>, Vec<[Option<EndFrame>; 2]>);

/// The end supports of `curves` (scaled by `scale`) from their `specs` and the supports file
/// `file`, and the surface's directions (on `mesh`, scaled) at the ends whose supports use
/// them; each empty when nothing needs it.
pub(super) fn curve_ends(
    curves: &[Polyline],
    specs: &[CurveSpec],
    file: Option<&Path>,
    scale: f64,
    mesh: Option<&TriMesh>,
) -> Result<CurveEnds, AppError> {
    let mut ends: Vec<[Option<EndSupport>; 2]> = (0..curves.len())
        .map(|c| specs.get(c).map_or([None; 2], |s| s.supports))
        .collect();
    // Where each end's support was given: its curve's record, or the supports file's line.
    let mut given: Vec<[(String, usize); 2]> = curves
        .iter()
        .map(|c| {
            [
                (c.origin.file.clone(), c.origin.line),
                (c.origin.file.clone(), c.origin.line),
            ]
        })
        .collect();
    if let Some(path) = file {
        let name = path.display().to_string();
        let entries = crate::io::read_supports_file(path)?;
        for e in &entries {
            for (c, i) in resolve(curves, e, scale, &name)? {
                ends[c][i] = Some(e.support);
                given[c][i] = (name.clone(), e.line);
            }
        }
    }
    let mut frames = vec![[None; 2]; curves.len()];
    for (c, curve) in curves.iter().enumerate() {
        for (i, at) in [curve.points.first(), curve.points.last()]
            .into_iter()
            .enumerate()
        {
            let (Some(s), Some(&at)) = (ends[c][i].filter(EndSupport::uses_surface), at) else {
                continue;
            };
            if curve.closed {
                continue;
            }
            let which = format!("curve {c}'s {}", if i == 0 { "start" } else { "end" });
            let frame = end_frame(mesh, at, &s, &which).map_err(|e| {
                let (file, line) = &given[c][i];
                InputError::parse(file, *line, e.0)
            })?;
            frames[c][i] = Some(frame);
        }
    }
    if frames.iter().all(|e| e.iter().all(Option::is_none)) {
        frames.clear();
    }
    if ends.iter().all(|e| e.iter().all(Option::is_none)) {
        ends.clear();
    }
    Ok((ends, frames))
}

/// The curve ends (curve, 0 start / 1 end) entry `e` of file `file` names.
fn resolve(
    curves: &[Polyline],
    e: &SupportEntry,
    scale: f64,
    file: &str,
) -> Result<Vec<(usize, usize)>, InputError> {
    let fail = |m: String| InputError::parse(file, e.line, m);
    match e.place {
        EndPlace::CurveEnd { curve, at_start } => {
            let Some(c) = curves.get(curve) else {
                return Err(fail(format!(
                    "curve {curve} does not exist (the curves are 0 to {})",
                    curves.len().saturating_sub(1)
                )));
            };
            if c.closed {
                return Err(fail(format!("curve {curve} is closed: it has no ends")));
            }
            Ok(vec![(curve, usize::from(!at_start))])
        }
        EndPlace::Point(p) => {
            let at = Vec3::new(p[0], p[1], p[2]) * scale;
            let mut bbox = Aabb::EMPTY;
            for c in curves {
                for &q in &c.points {
                    bbox.add(q);
                }
            }
            let tol = END_TOLERANCE * bbox.extent().norm();
            let mut hits = Vec::new();
            let mut nearest = (f64::INFINITY, 0, 0);
            for (c, curve) in curves.iter().enumerate().filter(|(_, c)| !c.closed) {
                let (Some(&first), Some(&last)) = (curve.points.first(), curve.points.last())
                else {
                    continue;
                };
                for (i, q) in [first, last].into_iter().enumerate() {
                    let d = q.dist(at);
                    if d <= tol {
                        hits.push((c, i));
                    }
                    if d < nearest.0 {
                        nearest = (d, c, i);
                    }
                }
            }
            if hits.is_empty() {
                let (d, c, i) = nearest;
                let which = if i == 0 { "start" } else { "end" };
                return Err(fail(if d.is_finite() {
                    format!(
                        "({}, {}, {}) is not a curve end: the nearest is curve {c}'s {which}, \
                         {} away (an end must lie within {})",
                        p[0],
                        p[1],
                        p[2],
                        crate::fmt::significant(d / scale, 4),
                        crate::fmt::significant(tol / scale, 4)
                    )
                } else {
                    "no curve has ends (every curve is closed)".into()
                }));
            }
            Ok(hits)
        }
    }
}

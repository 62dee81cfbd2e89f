//! Drawing: the design's curves edited on their surface, each edit giving a new set of curves
//! whose network is rebuilt (crossings become joints, open ends supports) and analysed again.
//!
//! A [`Drawing`] holds the curves as drawn (not the network's resampled rods), the surface
//! and what builds and analyses the network (the build parameters, the edge length among
//! them, kept as the design started; the model's options). An edit ([`DrawEdit`]) adds a
//! curve — a straightest geodesic from a point of the surface in a direction
//! ([`crate::trace::trace_geodesic_from`]) or a smooth curve through points ([`through`]) —
//! deletes one, or moves one by the coefficients of the slide feature's family of moves
//! ([`crate::slide::CurveMove`]: the same functions and limits, ends on the boundary sliding
//! along it). A drawn or moved curve is made to pass through the curves it crosses
//! ([`crate::slide::snap::snap_crossings`]: the design's curves lie near the mesh, not on it),
//! so each crossing becomes a joint. [`Drawing::apply`] answers the new drawing, never changing the old one, so a
//! front end keeps the old one for undo; [`Drawing::analyzer`] builds the new network's
//! analyzer. Every front end (the server's page, a script) draws through this module.

mod slide;
mod through;

pub use through::{MAX_POINTS, smooth_through};

use super::AppError;
use super::inputs::Inputs;
use super::model::ModelOptions;
use super::setup::Setup;
use crate::geom::Vec3;
use crate::io::{FileExtras, Origin, Polyline, TriMesh, curves_to_json_with};
use crate::material::EndSupport;
use crate::network::Network;
use crate::network::checks::surface::FAR_FROM_MESH;
use crate::rod::Supports;
use crate::slide::snap::snap_crossings;
use crate::slide::{CurveMove, MaxMove, ON_BOUNDARY, SlideParams, Surface};
use crate::stability::Analyzer;
use crate::trace::{MeshTopology, TraceError, TraceOptions, trace_geodesic_from};
use crate::words::{Message, Opt, message};
use std::sync::Arc;

/// How curves are drawn and moved.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawParams {
    /// The farthest a given point may lie from the surface, a fraction of the surface's
    /// bounding-box diagonal (the curve then starts or passes at the closest point of it).
    pub max_distance: f64,
    /// How far a move may carry a point (the slide feature's default).
    pub max_move: MaxMove,
    /// How many of each curve's offset functions its moves use (the slide feature's default).
    pub functions: usize,
}

impl Default for DrawParams {
    fn default() -> Self {
        DrawParams {
            max_distance: FAR_FROM_MESH,
            max_move: MaxMove::default(),
            functions: SlideParams::default().functions,
        }
    }
}

/// A curve to add.
#[derive(Clone, Debug, PartialEq)]
pub enum NewCurve {
    /// The straightest geodesic from `point` (on the surface) along `direction`, to the
    /// boundary.
    Geodesic {
        /// Where it starts.
        point: Vec3,
        /// Where it heads (projected onto the surface there).
        direction: Vec3,
    },
    /// A smooth curve on the surface through these points, in order.
    Through(Vec<Vec3>),
}

/// One edit of the design's curves.
#[derive(Clone, Debug, PartialEq)]
pub enum DrawEdit {
    /// Adds a curve (its id is the count of curves before it).
    Add(NewCurve),
    /// Deletes a curve (the curves after it move down one id).
    Delete(usize),
    /// Moves a curve by the coefficients of its family of moves.
    Move {
        /// The curve.
        curve: usize,
        /// One coefficient per function of its family ([`Drawing::move_dimension`]).
        params: Vec<f64>,
    },
    /// Puts each curve (an id) in place of the drawn one, as one edit: a slide's curves
    /// adopted ([`Drawing::slider`]). The curves are taken as they are (a slide's already
    /// pass through the curves they cross).
    Replace(Vec<(usize, Polyline)>),
}

impl DrawEdit {
    /// The ids that `kept` (curves of the drawing before the edit) have after it: a deleted
    /// curve dropped and the later ones moved down, an added curve (id `count`, the count of
    /// curves before) kept.
    pub fn carry(&self, kept: &[usize], count: usize) -> Vec<usize> {
        let mut out: Vec<usize> = match self {
            DrawEdit::Delete(d) => kept
                .iter()
                .filter(|&&c| c != *d)
                .map(|&c| if c > *d { c - 1 } else { c })
                .collect(),
            DrawEdit::Add(_) => kept.iter().copied().chain([count]).collect(),
            DrawEdit::Move { .. } | DrawEdit::Replace(_) => kept.to_vec(),
        };
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// Why a curve could not be drawn, deleted or moved. Every variant but [`DrawError::Failed`]
/// is the user's to fix.
#[derive(Debug, thiserror::Error)]
pub enum DrawError {
    /// There is no surface to draw on.
    #[error("{0}")]
    NoSurface(Message),
    /// A point given lies too far from the surface.
    #[error(
        "point {index} lies {} from the surface, more than the {} a point drawn on it may be",
        crate::fmt::length(*distance),
        crate::fmt::length(*tolerance)
    )]
    OffSurface {
        /// Which point (0 for a geodesic's start).
        index: usize,
        /// Its distance from the surface.
        distance: f64,
        /// The largest distance allowed.
        tolerance: f64,
    },
    /// A coordinate that is not a finite number.
    #[error("point {index} has a coordinate that is not a finite number")]
    NotFinite {
        /// Which point.
        index: usize,
    },
    /// The geodesic could not be traced (a direction that leaves the surface at once, one
    /// normal to it, a runaway path).
    #[error("the geodesic cannot be traced: {0}")]
    Trace(TraceError),
    /// The new curve is shorter than the network's edge length (a geodesic that leaves the
    /// surface at once, points all but on top of each other).
    #[error(
        "the curve is {} long, shorter than the edge length {}{}",
        crate::fmt::length(*length),
        crate::fmt::length(*edge_length),
        if *geodesic { ": from this point, in this direction, it leaves the surface at once" } else { ": spread the points wider" }
    )]
    TooShort {
        /// Its length.
        length: f64,
        /// The network's edge length.
        edge_length: f64,
        /// Whether it is a geodesic.
        geodesic: bool,
    },
    /// A curve through points needs at least two distinct points.
    #[error(
        "a curve through points needs at least two distinct points on the surface, got {count}"
    )]
    TooFewPoints {
        /// The distinct points given.
        count: usize,
    },
    /// Too many points.
    #[error("a curve through points takes at most {MAX_POINTS} points, got {count}")]
    TooManyPoints {
        /// The points given.
        count: usize,
    },
    /// A curve id the design does not have.
    #[error("unknown curve {curve}: the design has {count} curves (ids 0..{last})", last = .count.saturating_sub(1))]
    UnknownCurve {
        /// The id asked for.
        curve: usize,
        /// The curves of the design.
        count: usize,
    },
    /// Deleting the last curve.
    #[error("the design's last curve cannot be deleted: draw another first")]
    LastCurve,
    /// A move with the wrong number of coefficients.
    #[error("curve {curve}'s moves have {expected} coefficients, got {got}")]
    MoveParams {
        /// The curve.
        curve: usize,
        /// Its family's dimension.
        expected: usize,
        /// The coefficients given.
        got: usize,
    },
    /// A move beyond the limits: a point carried farther than the largest move, a kink, a
    /// fold, or off the surface.
    #[error(
        "this move of curve {curve} goes beyond its limits (a point moved more than {}, a kink, a fold, or off the surface): make it smaller",
        crate::fmt::length(*max_move)
    )]
    MoveBeyond {
        /// The curve.
        curve: usize,
        /// The largest move.
        max_move: f64,
    },
    /// The structure cannot be slid (no curve kept, the physical mode, a bad largest move).
    #[error("{0}")]
    Slide(Message),
    /// The new network could not be built or its model resolved (the user's to fix).
    #[error("{0}")]
    Build(Message),
    /// Something failed that the user cannot fix.
    #[error("{0}")]
    Failed(String),
}

impl DrawError {
    /// Whether the user can fix it (a bad request), not a failure of the computation.
    pub fn is_input(&self) -> bool {
        !matches!(self, DrawError::Failed(_))
    }

    /// The error as a message naming options for a front end to spell.
    pub fn message(&self) -> Message {
        match self {
            DrawError::NoSurface(m) | DrawError::Build(m) | DrawError::Slide(m) => m.clone(),
            e => Message::from(e.to_string()),
        }
    }
}

impl From<AppError> for DrawError {
    fn from(e: AppError) -> Self {
        match e {
            AppError::Usage(m) => DrawError::Build(m),
            e => DrawError::Failed(e.to_string()),
        }
    }
}

/// The design's curves on their surface, and what builds and analyses their network.
#[derive(Clone, Debug)]
pub struct Drawing {
    /// The curves and how they are built (the surface taken out: it is `mesh`).
    inputs: Inputs,
    options: ModelOptions,
    mesh: Arc<TriMesh>,
    surface: Arc<Surface>,
    topology: Arc<MeshTopology>,
    params: DrawParams,
}

/// The drawing an edit gave and the curve it drew or moved.
#[derive(Clone, Debug)]
pub struct Drawn {
    /// The drawing after the edit.
    pub drawing: Drawing,
    /// The curve added or moved (`None` for a deletion).
    pub curve: Option<usize>,
}

impl Drawing {
    /// The drawing of `setup`'s curves on its surface, analysed in the model of `options`.
    ///
    /// # Errors
    ///
    /// [`DrawError::NoSurface`] when the set-up has no surface, or one no curve can be traced
    /// on (no usable triangle, not a manifold).
    pub fn new(setup: &Setup, options: &ModelOptions) -> Result<Drawing, DrawError> {
        let no_surface = |why: &str| {
            DrawError::NoSurface(message![
                format!("drawing needs the surface the curves lie on{why}: give the mesh ("),
                Opt::Mesh,
                ")"
            ])
        };
        let mut inputs = setup.inputs.clone();
        let mesh = inputs.mesh.take().ok_or_else(|| no_surface(""))?;
        let surface =
            Surface::new(&mesh).ok_or_else(|| no_surface(" (it has no usable triangle)"))?;
        let topology = MeshTopology::new(&mesh)
            .map_err(|e| no_surface(&format!(" (this one cannot be traced on: {e})")))?;
        inputs.warnings.clear();
        Ok(Drawing {
            inputs,
            options: options.clone(),
            mesh: Arc::new(mesh),
            surface: Arc::new(surface),
            topology: Arc::new(topology),
            params: DrawParams::default(),
        })
    }

    /// With `params`.
    pub fn with_params(mut self, params: DrawParams) -> Self {
        self.params = params;
        self
    }

    /// The curves as drawn, in id order.
    pub fn curves(&self) -> &[Polyline] {
        &self.inputs.curves
    }

    /// The surface.
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// The edge length the network is built with.
    pub fn edge_length(&self) -> f64 {
        self.inputs.build.edge_length
    }

    /// The curves as a curve file (curvenet's JSON format), `only` of them when given: what
    /// `--curves` reads back into the same network and analysis with the same surface. The
    /// file carries the scene's unit, the edge length, and each curve's material, section,
    /// rest shape, group and end supports (those of the curve files and of a supports file,
    /// and the run's pinned supports when the run's supports are pinned). The model's other
    /// options (the run's material, radius, loads) are the command line's to give again.
    pub fn curves_json(&self, only: Option<&[usize]>) -> String {
        let i = &self.inputs;
        let ids: Vec<usize> = match only {
            Some(ids) => ids
                .iter()
                .copied()
                .filter(|&c| c < i.curves.len())
                .collect(),
            None => (0..i.curves.len()).collect(),
        };
        let curves: Vec<Polyline> = ids.iter().map(|&c| i.curves[c].clone()).collect();
        let run_end = match i.build.supports {
            Supports::Pinned => Some(EndSupport::PINNED),
            Supports::Clamped => None,
        };
        let fields = ids
            .iter()
            .map(|&c| {
                let mut spec = i.specs.get(c).cloned().unwrap_or_default();
                spec.supports = if i.curves[c].closed {
                    [None, None]
                } else {
                    let ends = i.build.ends.get(c).copied().unwrap_or([None, None]);
                    ends.map(|e| e.or(run_end))
                };
                let mut fields = spec.to_json_fields();
                if let Some(g) = i.groups.iter().find(|g| g.curves.contains(&c)) {
                    fields.push(("group", serde_json::Value::String(g.name.clone())));
                }
                fields
            })
            .collect();
        let extras = FileExtras {
            units: self
                .options
                .physical
                .units
                .clone()
                .or_else(|| i.file_units.clone()),
            edge_length: Some(self.edge_length()),
            fields,
        };
        curves_to_json_with(&curves, &extras)
    }

    /// The curve `edit` would add, or the moved curve (a preview: nothing is built).
    ///
    /// # Errors
    ///
    /// As [`Self::apply`], but for a deletion, which previews nothing
    /// ([`DrawError::UnknownCurve`] when the curve is unknown, else an empty curve).
    pub fn preview(&self, edit: &DrawEdit) -> Result<Polyline, DrawError> {
        match edit {
            DrawEdit::Add(NewCurve::Geodesic { point, direction }) => {
                self.geodesic(*point, *direction)
            }
            DrawEdit::Add(NewCurve::Through(points)) => self.through(points),
            DrawEdit::Move { curve, params } => self.moved(*curve, params),
            DrawEdit::Replace(curves) => {
                for (c, _) in curves {
                    self.check_id(*c)?;
                }
                Ok(curves.first().map(|(_, p)| p.clone()).unwrap_or(Polyline {
                    points: Vec::new(),
                    closed: false,
                    origin: Origin::new("<replaced>", 0),
                    label: None,
                }))
            }
            DrawEdit::Delete(c) => {
                self.check_id(*c)?;
                Ok(Polyline {
                    points: Vec::new(),
                    closed: false,
                    origin: Origin::new("<deleted>", 0),
                    label: None,
                })
            }
        }
    }

    /// The drawing after `edit` (this one unchanged).
    ///
    /// # Errors
    ///
    /// A point off the surface (saying how far), a direction that leaves the surface at once,
    /// fewer than two points, an unknown curve, the last curve deleted, a move with the wrong
    /// number of coefficients or beyond the limits.
    pub fn apply(&self, edit: &DrawEdit) -> Result<Drawn, DrawError> {
        let mut next = self.clone();
        let count = self.inputs.curves.len();
        let curve = match edit {
            DrawEdit::Add(new) => {
                let c = self.preview(edit)?;
                let (length, edge_length) = (c.length(), self.edge_length());
                if !(length >= edge_length) {
                    let geodesic = matches!(new, NewCurve::Geodesic { .. });
                    return Err(DrawError::TooShort {
                        length,
                        edge_length,
                        geodesic,
                    });
                }
                next.push(c);
                Some(count)
            }
            DrawEdit::Move { curve, .. } => {
                let c = self.preview(edit)?;
                next.inputs.curves[*curve] = c;
                Some(*curve)
            }
            DrawEdit::Replace(curves) => {
                self.preview(edit)?;
                for (c, p) in curves {
                    next.inputs.curves[*c] = p.clone();
                }
                None
            }
            DrawEdit::Delete(d) => {
                self.check_id(*d)?;
                if count == 1 {
                    return Err(DrawError::LastCurve);
                }
                next.delete(*d);
                None
            }
        };
        // The drawn or moved curve passes through the curves it crosses (the others lie near
        // the mesh, not on it), so that each crossing becomes a joint.
        if let Some(c) = curve {
            let mut moved = vec![false; next.inputs.curves.len()];
            moved[c] = true;
            snap_crossings(&mut next.inputs.curves, &moved, self.edge_length());
        }
        Ok(Drawn {
            drawing: next,
            curve,
        })
    }

    /// The analyzer of the drawing's network, built from its curves, and the build's
    /// warnings.
    ///
    /// # Errors
    ///
    /// The network cannot be built or the model resolved ([`DrawError::Build`]), or the
    /// analyzer failed.
    pub fn analyzer(&self) -> Result<(Analyzer, Vec<Message>), DrawError> {
        let i = &self.inputs;
        let model = self.options.resolve(i.file_units.as_deref(), &i.specs)?;
        let mut setup = Setup::from_parts(self.inputs.clone(), model);
        let analyzer = setup.analyzer()?;
        Ok((analyzer, setup.build_warnings()))
    }

    /// How many coefficients curve `curve`'s moves have.
    ///
    /// # Errors
    ///
    /// An unknown curve.
    pub fn move_dimension(&self, curve: usize) -> Result<usize, DrawError> {
        Ok(self.family(curve)?.dimension())
    }

    /// The largest move, a length.
    pub fn max_move(&self) -> f64 {
        self.params.max_move.length(self.surface.diagonal())
    }

    /// The coefficients of the move of `curve` that carries its point nearest `from` towards
    /// `to` (a designer's drag): the family's first function scaled so that the point moves
    /// by the drag across the curve, halved until the move is within the limits (all zero
    /// when none is).
    ///
    /// # Errors
    ///
    /// An unknown curve, a non-finite point.
    pub fn drag(&self, curve: usize, from: Vec3, to: Vec3) -> Result<Vec<f64>, DrawError> {
        for (index, p) in [from, to].into_iter().enumerate() {
            if !p.is_finite() {
                return Err(DrawError::NotFinite { index });
            }
        }
        let family = self.family(curve)?;
        through::drag_params(&family, &self.surface, from, to, self.max_move())
    }

    /// The family of moves of `curve`: ends on the boundary slide along it.
    fn family(&self, curve: usize) -> Result<CurveMove, DrawError> {
        self.check_id(curve)?;
        let drawn = &self.inputs.curves[curve];
        let diagonal = self.surface.diagonal();
        let on_boundary = |p: Option<&Vec3>| {
            !drawn.closed
                && p.and_then(|&p| self.surface.closest_on_boundary(p))
                    .is_some_and(|(_, d)| d <= ON_BOUNDARY * diagonal)
        };
        let slides = [
            on_boundary(drawn.points.first()),
            on_boundary(drawn.points.last()),
        ];
        let spacing = self.edge_length() / 2.0;
        Ok(CurveMove::new(
            drawn,
            &self.surface,
            spacing,
            slides,
            self.params.functions,
        ))
    }

    /// The geodesic from `point` along `direction`.
    fn geodesic(&self, point: Vec3, direction: Vec3) -> Result<Polyline, DrawError> {
        if !point.is_finite() {
            return Err(DrawError::NotFinite { index: 0 });
        }
        self.near_surface(0, point)?;
        let path = trace_geodesic_from(&self.topology, point, direction, &TraceOptions::default())
            .map_err(DrawError::Trace)?;
        Ok(Polyline {
            origin: Origin::new("<drawn geodesic>", 0),
            ..path.polyline
        })
    }

    /// The smooth curve on the surface through `points`.
    fn through(&self, points: &[Vec3]) -> Result<Polyline, DrawError> {
        if points.len() > MAX_POINTS {
            return Err(DrawError::TooManyPoints {
                count: points.len(),
            });
        }
        let mut on = Vec::with_capacity(points.len());
        for (index, &p) in points.iter().enumerate() {
            if !p.is_finite() {
                return Err(DrawError::NotFinite { index });
            }
            on.push(self.near_surface(index, p)?);
        }
        smooth_through(&on, &self.surface, self.edge_length() / 4.0)
    }

    /// `curve` moved by `params`.
    fn moved(&self, curve: usize, params: &[f64]) -> Result<Polyline, DrawError> {
        let family = self.family(curve)?;
        if params.len() != family.dimension() {
            return Err(DrawError::MoveParams {
                curve,
                expected: family.dimension(),
                got: params.len(),
            });
        }
        let max_move = self.max_move();
        let beyond = DrawError::MoveBeyond { curve, max_move };
        if params.iter().any(|a| !a.is_finite()) {
            return Err(beyond);
        }
        family.apply(params, &self.surface, max_move).ok_or(beyond)
    }

    /// The point of the surface closest to `p`, refused when farther than allowed.
    fn near_surface(&self, index: usize, p: Vec3) -> Result<Vec3, DrawError> {
        let tolerance = self.params.max_distance * self.surface.diagonal();
        let found = self
            .surface
            .closest(p)
            .ok_or(DrawError::NotFinite { index })?;
        if found.distance > tolerance {
            return Err(DrawError::OffSurface {
                index,
                distance: found.distance,
                tolerance,
            });
        }
        Ok(found.point)
    }

    /// Refuses an id the drawing does not have.
    fn check_id(&self, curve: usize) -> Result<(), DrawError> {
        let count = self.inputs.curves.len();
        if curve >= count {
            return Err(DrawError::UnknownCurve { curve, count });
        }
        Ok(())
    }

    /// Appends `curve`, with no support, spec or group of its own.
    fn push(&mut self, curve: Polyline) {
        let i = &mut self.inputs;
        if !i.build.ends.is_empty() {
            i.build.ends.push([None, None]);
        }
        if !i.specs.is_empty() {
            i.specs.push(Default::default());
        }
        i.curves.push(curve);
    }

    /// Removes curve `d`, the later ids moved down in the groups and the keep list.
    fn delete(&mut self, d: usize) {
        let i = &mut self.inputs;
        i.curves.remove(d);
        if d < i.build.ends.len() {
            i.build.ends.remove(d);
        }
        if d < i.specs.len() {
            i.specs.remove(d);
        }
        let shift = |ids: &mut Vec<usize>| {
            ids.retain(|&c| c != d);
            for c in ids.iter_mut().filter(|c| **c > d) {
                *c -= 1;
            }
        };
        for g in &mut i.groups {
            shift(&mut g.curves);
        }
        i.groups.retain(|g| !g.curves.is_empty());
        if let Some(e) = &mut i.example {
            shift(&mut e.keep);
        }
    }
}

/// The joints of `curve` in `network`: each one's point and the curves through it.
pub fn joints_of(network: &Network, curve: usize) -> Vec<(Vec3, Vec<usize>)> {
    network
        .joints
        .iter()
        .filter(|j| j.curves.contains(&(curve as u32)))
        .map(|j| {
            let p = network.positions[j.vertex as usize];
            (p, j.curves.iter().map(|&c| c as usize).collect())
        })
        .collect()
}

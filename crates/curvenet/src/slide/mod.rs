//! Sliding: the chosen curves moved *on the surface* to raise the objective (`docs/model.md`,
//! *Sliding*).
//!
//! A [`Slider`] holds a network's curves as drawn, the surface, how the network is built and
//! analysed, the budget and the constraints in force. Each curve free to move gets a small,
//! smooth family of moves ([`moves`]: a few offset functions along the curve within the
//! surface, ends on the boundary sliding along it); a point of the family is one coefficient
//! per function. [`Slider::evaluate`] moves the curves, rebuilds the network from the moved
//! curves (crossings, joints, resampling: a move may create or remove joints) and analyses it
//! cold through [`crate::stability::Analyzer`]; [`Slider::run`] searches the coefficients
//! ([`search`]: a deterministic pattern search without derivatives) and returns the best
//! network found ([`SlideOutcome`]).
//!
//! What a move may do is checked for every candidate: every point within the largest move
//! of where it was drawn (measured on the rebuilt network's vertices against the drawn
//! polyline), no kinks or folds, the total rest length within the budget (or not above the
//! start's), and the design constraints in force (connected, fewest curves, largest gap,
//! largest deviation) met by the rebuilt network.

pub mod loads;
pub mod moves;
pub mod search;
pub mod snap;
pub mod surface;
pub mod ties;

pub use moves::{Basis, CurveMove};
pub use search::{PatternOutcome, PatternParams, Step, pattern_search};
pub use surface::Surface;
pub use ties::{Tie, TieMap};

use crate::cancel::Cancel;
use crate::constraints::{ConstraintParams, Constraints, SymmetryOption};
use crate::io::{Origin, Polyline, TriMesh};
use crate::network::checks::surface::FAR_FROM_MESH;
use crate::network::{BuildParams, Network, build_network};
use crate::stability::{Analyzer, StabilityParams};
use crate::words::{Message, Opt, message};
use serde::{Deserialize, Serialize};

/// The default largest move: this fraction of the surface's bounding-box diagonal.
pub const DEFAULT_MAX_MOVE: f64 = 0.05;

/// The largest move allowed: this fraction of the surface's bounding-box diagonal.
pub const MAX_MAX_MOVE: f64 = 0.5;

/// Rebuilt polylines whose vertices moved less than this fraction of the surface's diagonal
/// are settled ([`Slider::evaluate`]).
pub const SETTLED: f64 = 1e-11;

/// The most builds of one network while it settles.
pub const MAX_REBUILDS: usize = 8;

/// A gain: more than this fraction of the objective's magnitude (smaller differences are
/// within what a rebuild reproduces; the search's steps and the choice among a run's slides
/// both count only gains).
pub const RELATIVE_GAIN: f64 = 1e-6;

/// Whether the objective `a` is a gain over `b` ([`RELATIVE_GAIN`]).
pub fn is_gain(a: f64, b: f64) -> bool {
    a > b + RELATIVE_GAIN * b.abs().max(f64::MIN_POSITIVE)
}

/// A curve end within this fraction of the surface's diagonal of the boundary lies on it.
pub const ON_BOUNDARY: f64 = 0.005;

/// How far a move may go: a length, or a fraction of the surface's bounding-box diagonal.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum MaxMove {
    /// A length in scene units.
    Length(f64),
    /// A fraction of the surface's bounding-box diagonal (`5%` is `0.05`).
    Fraction(f64),
}

impl Default for MaxMove {
    fn default() -> Self {
        MaxMove::Fraction(DEFAULT_MAX_MOVE)
    }
}

impl std::str::FromStr for MaxMove {
    type Err = Message;

    /// `5%` (of the surface's diagonal) or a length (`12.5`).
    fn from_str(s: &str) -> Result<Self, Message> {
        let t = s.trim();
        let bad = || message![format!("{s:?}: "), "expected a length or a percentage (5%)"];
        match t.strip_suffix('%') {
            Some(p) => p
                .trim()
                .parse::<f64>()
                .map(|v| MaxMove::Fraction(v / 100.0))
                .map_err(|_| bad()),
            None => t.parse::<f64>().map(MaxMove::Length).map_err(|_| bad()),
        }
    }
}

impl MaxMove {
    /// The length on a surface of bounding-box diagonal `diagonal`.
    pub fn length(self, diagonal: f64) -> f64 {
        match self {
            MaxMove::Length(l) => l,
            MaxMove::Fraction(f) => f * diagonal,
        }
    }
}

/// How sliding moves the curves and searches.
#[derive(Clone, Debug, PartialEq)]
pub struct SlideParams {
    /// How far a point may move from the curve as drawn.
    pub max_move: MaxMove,
    /// Every curve end stays where it is (else ends on the boundary slide along it).
    pub fixed_ends: bool,
    /// Curves that do not move (ids among the slider's curves).
    pub pinned: Vec<usize>,
    /// How many of each curve's offset functions the family uses (1 to 4; [`moves`]).
    pub functions: usize,
    /// The search's smallest step, as a fraction of the largest move.
    pub min_step: f64,
    /// The most networks evaluated.
    pub max_evaluations: usize,
    /// `max_evaluations` holds within a sweep of the search too (the page's slide); else it is
    /// checked between sweeps, the sweep under way finished (the command line's).
    pub strict_limit: bool,
    /// Levels each side at which the first sweep probes each coefficient alone
    /// ([`PatternParams::probe`]).
    pub probe: usize,
}

impl Default for SlideParams {
    fn default() -> Self {
        SlideParams {
            max_move: MaxMove::default(),
            fixed_ends: false,
            pinned: Vec::new(),
            functions: 3,
            min_step: 1.0 / 16.0,
            max_evaluations: 400,
            strict_limit: false,
            probe: 2,
        }
    }
}

/// Why sliding could not start.
#[derive(Debug, thiserror::Error)]
pub enum SlideError {
    /// No surface to slide on.
    #[error("{0}")]
    NoSurface(Message),
    /// A curve is not on the surface.
    #[error("{}", self.message())]
    OffSurface {
        /// The curve (its id in the input).
        curve: usize,
        /// Its largest distance from the surface.
        distance: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// Parameters out of range.
    #[error("{0}")]
    Params(Message),
    /// The starting network could not be built or analysed.
    #[error("{0}")]
    Failed(String),
}

impl SlideError {
    /// The error as a message naming options for a front end to spell.
    pub fn message(&self) -> Message {
        match self {
            SlideError::NoSurface(m) | SlideError::Params(m) => m.clone(),
            SlideError::OffSurface {
                curve,
                distance,
                tolerance,
            } => Message::from(format!(
                "curve {curve} is not on the surface: a point of it lies {} from the \
                 surface, more than the {} a curve on it may be",
                crate::fmt::length(*distance),
                crate::fmt::length(*tolerance)
            )),
            SlideError::Failed(m) => Message::from(m.clone()),
        }
    }
}

/// What sliding starts from.
#[derive(Clone, Debug)]
pub struct SlideProblem {
    /// The network's curves as drawn, in id order (ids are positions here).
    pub curves: Vec<Polyline>,
    /// The id each curve had where it came from (for messages; positions when empty).
    pub ids: Vec<usize>,
    /// Each curve as the designer drew it, which the largest move is measured from (empty:
    /// [`Self::curves`]; a network slid again after a local search gives the shapes its
    /// curves had before any slide, so moves do not add up beyond the largest move).
    pub drawn: Vec<Polyline>,
    /// How the network is built.
    pub build: BuildParams,
    /// How it is analysed (the objective included).
    pub stability: StabilityParams,
    /// The physical mode's parameters (`None`: the paper's model): each network is then
    /// analysed in the structure's own model (its rest shapes one per curve, in order).
    pub physical: Option<crate::physics::PhysicalParams>,
    /// The budget, a length.
    pub budget: f64,
    /// Curves that do not move (the keep list, and units of the constraints that cannot move
    /// as one: [`ties`]), by position.
    pub fixed: Vec<usize>,
    /// Curves that move with another ([`ties`]: the groups and symmetry orbits).
    pub ties: Vec<Tie>,
    /// The design constraints the moved network must meet (groups and symmetry are held by
    /// the ties, so they are not checked again).
    pub constraints: ConstraintParams,
}

/// One network evaluated.
#[derive(Clone, Debug)]
pub struct Evaluated {
    /// The moved curves, as the rebuilt network's rest polylines.
    pub curves: Vec<Polyline>,
    /// The network.
    pub network: Network,
    /// The objective (`λ_eq`, or `μ_min`).
    pub lambda: f64,
    /// Total rest length.
    pub length: f64,
    /// Each curve's largest distance from where it was drawn.
    pub moves: Vec<f64>,
    /// Its largest deviation from its designed place, as the largest-deviation constraint
    /// measures it (`None` when that constraint is not in force).
    pub deviation: Option<f64>,
    /// It meets the budget and every constraint.
    pub feasible: bool,
}

/// What sliding did.
#[derive(Clone, Debug)]
pub struct SlideOutcome {
    /// The network it started from (rebuilt from the drawn curves).
    pub before: Evaluated,
    /// The best network found (`before` when nothing better was).
    pub after: Evaluated,
    /// Each curve's coefficients.
    pub coefficients: Vec<Vec<f64>>,
    /// The largest move allowed (scene units).
    pub max_move: f64,
    /// Joints of `after` not in `before` (by the curves they join).
    pub joints_added: usize,
    /// Joints of `before` not in `after`.
    pub joints_removed: usize,
    /// The search.
    pub search: PatternOutcome,
}

/// A network made ready to slide.
#[derive(Debug)]
pub struct Slider {
    problem: SlideProblem,
    surface: Surface,
    mesh: TriMesh,
    moves: Vec<Option<CurveMove>>,
    /// Each curve's coefficients in the search's vector (empty for a curve that stays; a
    /// tied curve's are its leader's).
    slices: Vec<std::ops::Range<usize>>,
    /// Each tied curve's tie, and its ends' sliding.
    tied: Vec<Option<(Tie, [bool; 2])>>,
    dimension: usize,
    max_move: f64,
    params: SlideParams,
}

impl Slider {
    /// Prepares `problem` on `mesh` (`None`: no surface, an error) with `params`.
    ///
    /// # Errors
    ///
    /// No surface, a curve off it, a largest move out of range, a pinned curve out of range.
    pub fn new(
        problem: SlideProblem,
        mesh: Option<&TriMesh>,
        params: SlideParams,
    ) -> Result<Slider, SlideError> {
        let no_surface = || {
            SlideError::NoSurface(message![
                "sliding moves curves on their surface, and none is known: give the mesh (",
                Opt::Mesh,
                ") the curves lie on"
            ])
        };
        let mesh = mesh.ok_or_else(no_surface)?;
        let surface = Surface::new(mesh).ok_or_else(no_surface)?;
        let diagonal = surface.diagonal();
        let max_move = params.max_move.length(diagonal);
        if !(max_move.is_finite() && max_move > 0.0 && max_move <= MAX_MAX_MOVE * diagonal) {
            return Err(SlideError::Params(message![
                Opt::MaxMove,
                format!(
                    " is {}: it must be positive and at most {}% of the surface's \
                     bounding-box diagonal ({})",
                    crate::fmt::length(max_move),
                    MAX_MAX_MOVE * 100.0,
                    crate::fmt::length(MAX_MAX_MOVE * diagonal)
                )
            ]));
        }
        let n = problem.curves.len();
        if let Some(&c) = params.pinned.iter().find(|&&c| c >= n) {
            return Err(SlideError::Params(message![
                Opt::Pin,
                format!(" names curve {c}, but the network has {n} curves")
            ]));
        }
        if !(1..=4).contains(&params.functions) {
            return Err(SlideError::Params(Message::from(format!(
                "a curve's family of moves has 1 to 4 functions, not {}",
                params.functions
            ))));
        }
        let tolerance = FAR_FROM_MESH * diagonal;
        let id = |c: usize| problem.ids.get(c).copied().unwrap_or(c);
        for (c, curve) in problem.curves.iter().enumerate() {
            let far = curve
                .points
                .iter()
                .map(|&p| surface.closest(p).map_or(f64::INFINITY, |s| s.distance))
                .fold(0.0, f64::max);
            if far > tolerance {
                return Err(SlideError::OffSurface {
                    curve: id(c),
                    distance: far,
                    tolerance,
                });
            }
        }
        let spacing = problem.build.edge_length / 2.0;
        let on_boundary = |p: Option<&crate::geom::Vec3>| {
            !params.fixed_ends
                && p.and_then(|&p| surface.closest_on_boundary(p))
                    .is_some_and(|(_, d)| d <= ON_BOUNDARY * diagonal)
        };
        let slides: Vec<[bool; 2]> = (problem.curves.iter())
            .map(|c| [on_boundary(c.points.first()), on_boundary(c.points.last())])
            .collect();
        let stays = stays(&problem, &params.pinned, &slides, params.functions);
        let mut tied: Vec<Option<(Tie, [bool; 2])>> = vec![None; n];
        for t in problem.ties.iter().filter(|t| !stays[t.curve]) {
            tied[t.curve] = Some((t.clone(), slides[t.curve]));
        }
        let mut slices = vec![0..0; n];
        let mut dimension = 0;
        let mut moves: Vec<Option<CurveMove>> = vec![None; n];
        for c in 0..n {
            if stays[c] {
                continue;
            }
            let curve = &problem.curves[c];
            let shared = tied[c]
                .as_ref()
                .is_none_or(|(t, _)| t.map == TieMap::Shared);
            if shared {
                let m = CurveMove::new(curve, &surface, spacing, slides[c], params.functions);
                if tied[c].is_none() {
                    slices[c] = dimension..dimension + m.dimension();
                    dimension += m.dimension();
                }
                moves[c] = Some(m);
            }
        }
        for c in 0..n {
            if let Some((t, _)) = &tied[c] {
                slices[c] = slices[t.leader].clone();
            }
        }
        Ok(Slider {
            problem,
            surface,
            mesh: mesh.clone(),
            moves,
            slices,
            tied,
            dimension,
            max_move,
            params,
        })
    }

    /// The number of coefficients of the moves.
    pub fn dimension(&self) -> usize {
        self.dimension
    }

    /// The largest move, scene units.
    pub fn max_move(&self) -> f64 {
        self.max_move
    }

    /// The surface.
    pub fn surface(&self) -> &Surface {
        &self.surface
    }

    /// Each curve's family (`None` for a curve that does not move, or one that follows its
    /// orbit's leader by the symmetry).
    pub fn moves(&self) -> &[Option<CurveMove>] {
        &self.moves
    }

    /// Whether curve `c` moves (by its own coefficients or with its leader's).
    pub fn moving(&self, c: usize) -> bool {
        !self.slices[c].is_empty()
    }

    /// Each curve's coefficients in a point `x` of the search (empty for a curve that stays;
    /// a tied curve's are its leader's).
    pub fn coefficients(&self, x: &[f64]) -> Vec<Vec<f64>> {
        (self.slices.iter())
            .map(|r| x[r.clone()].to_vec())
            .collect()
    }

    /// The network moved by coefficients `x` ([`Self::dimension`] of them), rebuilt and
    /// analysed cold; `None` when a curve's move is not allowed or the network cannot be
    /// built or analysed.
    pub fn evaluate(&self, x: &[f64]) -> Option<Evaluated> {
        let mut moved = Vec::with_capacity(self.moves.len());
        let mut changed = vec![false; self.moves.len()];
        for (c, m) in self.moves.iter().enumerate() {
            let a = &x[self.slices[c].clone()];
            changed[c] = a.iter().any(|&v| v != 0.0);
            let curve = match m {
                Some(m) => m.apply(a, &self.surface, self.max_move)?,
                None => self.problem.curves[c].clone(),
            };
            moved.push(curve);
        }
        // An orbit's curves: the leader's moved curve mapped by the symmetry.
        for (c, t) in self.tied.iter().enumerate() {
            if let Some((t, slides)) = t
                && changed[c]
                && let TieMap::Symmetry {
                    symmetry,
                    power,
                    reversed,
                } = &t.map
            {
                moved[c] = ties::mapped(
                    &moved[t.leader],
                    &self.problem.curves[c],
                    symmetry,
                    *power,
                    *reversed,
                    *slides,
                    &self.surface,
                )?;
            }
        }
        snap::snap_crossings(&mut moved, &changed, self.problem.build.edge_length);
        let (curves, network) = self.settle(moved)?;
        let all: Vec<usize> = (0..network.rods.len()).collect();
        let moves: Vec<f64> = (0..self.moves.len())
            .map(|c| {
                let pts: Vec<_> = network.rods[c]
                    .vertices
                    .iter()
                    .map(|&v| network.positions[v as usize])
                    .collect();
                let drawn = self.problem.drawn.get(c);
                moves::largest_distance(&pts, drawn.unwrap_or(&self.problem.curves[c]))
            })
            .collect();
        // A curve this slide does not move keeps its polyline (one moved by an earlier slide
        // was checked then; its rebuilt vertices can shift by a hair where joints move).
        if (moves.iter().zip(&changed)).any(|(&d, &moved)| moved && d > self.max_move) {
            return None;
        }
        let length = network.total_length(&all);
        let mut feasible = length <= self.problem.budget * (1.0 + 1e-12);
        let constraints = self.constraints(&network, length);
        if let Some(c) = &constraints {
            feasible &= c.as_ref().is_ok_and(|c| c.check(&all).is_ok());
        }
        let mut analyzer = Analyzer::new(network, self.problem.stability.clone()).ok()?;
        if let Some(p) = &self.problem.physical {
            analyzer = analyzer.with_physical(p.clone()).ok()?;
        }
        let analysis = analyzer.analyze(&analyzer.all(), None).ok()?;
        // The largest deviation as the run's constraint measures it: the equilibrium's in
        // the paper's mode, under self-weight in the physical model in the physical mode.
        let deviation = self.problem.constraints.max_deviation.map(|_| {
            analyzer
                .structure_deviation(&all, &analysis.displacement)
                .unwrap_or(f64::INFINITY)
        });
        if let (Some(Ok(c)), Some(d)) = (&constraints, deviation) {
            feasible &= c.deviation_ok(d);
        }
        Some(Evaluated {
            curves,
            network: analyzer.network().clone(),
            lambda: analysis.lambda(),
            length,
            moves,
            deviation,
            feasible,
        })
    }

    /// The network of `curves`, built again from its own rest polylines until they no longer
    /// change (within [`SETTLED`] of the surface's diagonal; at most [`MAX_REBUILDS`] builds):
    /// the network recorded is then the one its exported curves build, so an analysis of
    /// those gives the objective recorded. Returns the polylines and their network.
    fn settle(&self, curves: Vec<Polyline>) -> Option<(Vec<Polyline>, Network)> {
        let (mut network, _) = build_network(&curves, &self.problem.build).ok()?;
        let mut curves = rest_polylines(&network);
        let limit = SETTLED * self.surface.diagonal();
        for _ in 1..MAX_REBUILDS {
            let (next, _) = build_network(&curves, &self.problem.build).ok()?;
            let again = rest_polylines(&next);
            let settled = again.iter().zip(&curves).all(|(a, b)| {
                a.points.len() == b.points.len()
                    && a.points
                        .iter()
                        .zip(&b.points)
                        .all(|(p, q)| p.dist(*q) <= limit)
            });
            (network, curves) = (next, again);
            if settled {
                break;
            }
        }
        Some((curves, network))
    }

    /// The constraints in force bound to `network` (`None` when none is; `Err` when the
    /// network cannot meet them).
    fn constraints(&self, network: &Network, length: f64) -> Option<Result<Constraints, ()>> {
        let params = ConstraintParams {
            groups: Vec::new(),
            symmetry: SymmetryOption::None,
            ..self.problem.constraints.clone()
        };
        if params.is_empty() {
            return None;
        }
        let budget = self.problem.budget.max(length);
        Some(Constraints::new(network, Some(&self.mesh), &params, budget, &[]).map_err(|_| ()))
    }

    /// Searches the moves from the drawn network; `progress` hears each step taken.
    ///
    /// # Errors
    ///
    /// The drawn network cannot be built or analysed.
    pub fn run(
        &self,
        cancel: &Cancel,
        progress: &dyn Fn(&Step),
    ) -> Result<SlideOutcome, SlideError> {
        let before = self.evaluate(&vec![0.0; self.dimension]).ok_or_else(|| {
            SlideError::Failed("the network to slide could not be built and analysed".into())
        })?;
        // A start over the budget (the rebuilt lengths differ slightly) may not grow.
        let cap = before.length.max(self.problem.budget);
        let value = |x: &[f64]| match self.evaluate(x) {
            Some(e) if e.feasible || (e.length <= cap && !before.feasible) => e.lambda,
            _ => f64::NEG_INFINITY,
        };
        let params = PatternParams {
            bound: self.max_move,
            step: self.max_move / 2.0,
            min_step: self.max_move * self.params.min_step,
            max_evaluations: self.params.max_evaluations,
            strict: self.params.strict_limit,
            relative_gain: RELATIVE_GAIN,
            probe: self.params.probe,
        };
        let search = pattern_search(self.dimension, &value, &params, cancel, progress);
        let after = if search.value > before.lambda {
            self.evaluate(&search.x).unwrap_or_else(|| before.clone())
        } else {
            before.clone()
        };
        let x = if search.value > before.lambda {
            search.x.clone()
        } else {
            vec![0.0; self.dimension]
        };
        let coefficients = self.coefficients(&x);
        let (joints_added, joints_removed) = joint_changes(&before.network, &after.network);
        Ok(SlideOutcome {
            before,
            after,
            coefficients,
            max_move: self.max_move,
            joints_added,
            joints_removed,
            search,
        })
    }
}

/// Each rod of `network` as a polyline through its rest positions, labelled as its curve.
pub fn rest_polylines(network: &Network) -> Vec<Polyline> {
    network
        .rods
        .iter()
        .enumerate()
        .map(|(c, r)| Polyline {
            points: r
                .vertices
                .iter()
                .map(|&v| network.positions[v as usize])
                .collect(),
            closed: r.closed,
            origin: Origin::new("slide", c + 1),
            label: None,
        })
        .collect()
}

/// How many joints (by the curves they join) `after` has that `before` lacks, and the other
/// way round.
pub fn joint_changes(before: &Network, after: &Network) -> (usize, usize) {
    let keys = |n: &Network| {
        let mut k: Vec<Vec<u32>> = n
            .joints
            .iter()
            .map(|j| {
                let mut c = j.curves.clone();
                c.sort_unstable();
                c
            })
            .collect();
        k.sort();
        k
    };
    let (a, b) = (keys(before), keys(after));
    let (mut i, mut j, mut common) = (0, 0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Equal => {
                common += 1;
                i += 1;
                j += 1;
            }
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
        }
    }
    (b.len() - common, a.len() - common)
}

/// Which curves stay: the fixed and the pinned, a tied curve's whole unit when one of it
/// stays, and a group whose members' families differ ([`ties`]).
fn stays(
    problem: &SlideProblem,
    pinned: &[usize],
    slides: &[[bool; 2]],
    functions: usize,
) -> Vec<bool> {
    let n = problem.curves.len();
    let mut stays: Vec<bool> = (0..n)
        .map(|c| problem.fixed.contains(&c) || pinned.contains(&c))
        .collect();
    let family = |c: usize| moves::Basis::of(problem.curves[c].closed, slides[c], functions);
    let mut leaders: Vec<usize> = problem.ties.iter().map(|t| t.leader).collect();
    leaders.sort_unstable();
    leaders.dedup();
    for l in leaders {
        let unit: Vec<&Tie> = problem.ties.iter().filter(|t| t.leader == l).collect();
        let held = stays[l]
            || unit.iter().any(|t| {
                stays[t.curve] || (t.map == TieMap::Shared && family(t.curve) != family(l))
            });
        if held {
            stays[l] = true;
            for t in unit {
                stays[t.curve] = true;
            }
        }
    }
    stays
}

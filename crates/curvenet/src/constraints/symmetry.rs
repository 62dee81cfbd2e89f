//! Symmetry of a network (`--symmetry rotate:N | mirror | auto | none`): the rotation about an
//! axis, or the mirror plane, that maps the network onto itself, and the curves' orbits under
//! it, which become groups so that every answer has the symmetry.
//!
//! # What is compared
//!
//! The network at rest: each rod's polyline (its vertices' rest positions, the resampled
//! curve), whether it is closed and how many anchored vertices it has (the supports follow the
//! curve's ends, so a map of curves onto curves maps supports onto supports). A transform `T`
//! is a symmetry when every curve `i` has a curve `j` with `T(i)` within the tolerance of `j`:
//! every sample of `T(i)` (up to [`SAMPLES`] of its vertices, evenly spread, ends included)
//! lies within the tolerance of `j`'s polyline and every sample of `j` within it of `T(i)`'s
//! (a symmetric Hausdorff distance over the samples). The tolerance is relative to the scene's
//! size, the diagonal of the rest positions' bounding box: [`DEFAULT_TOLERANCE`] by default
//! (the rods' chords between resampled vertices sit a sagitta `h²/8R` off the drawn curve, far
//! below it on the paper's scenes).
//!
//! # Where the axis and the plane come from
//!
//! Both pass through the network's centroid `g` (the rest edges' midpoints weighted by their
//! lengths; every symmetry fixes it). A rotation axis of order 3 or more is the principal axis
//! of the edges' inertia tensor about `g` with the distinct eigenvalue (the other two are
//! equal); one of order 2 is a principal axis too. Axes are tried in that order, then the
//! coordinate axes (scenes whose tensor is degenerate, such as a cube's). A mirror plane's
//! normal is a principal axis, or the direction from one end of a curve to the end of another
//! that the mirror swaps (for a rotationally symmetric scene, whose other principal axes are
//! arbitrary): the ends of two reference curves against every curve's ends.
//!
//! `rotate:N` takes the first axis where the rotation by `2π/N` is a symmetry; `mirror` the first
//! plane found; `auto` the axis with the largest order `N_max` (orders up to [`MAX_ORDER`] are
//! tried) and lists every order dividing it, largest first, then the mirror: the caller keeps
//! the largest whose orbits the budget allows.

use crate::geom::point_segment_distance;
use crate::geom::{Aabb, Vec3};
use crate::network::Network;
use crate::network::subnet::curve_components;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Default tolerance, relative to the scene's size (the diagonal of its bounding box).
pub const DEFAULT_TOLERANCE: f64 = 1e-3;

/// Largest rotation order tried by `auto`.
pub const MAX_ORDER: u32 = 64;

/// Samples per curve in the distance test.
pub const SAMPLES: usize = 48;

/// The coordinate axes, the last candidate axes.
const UNIT_AXES: [Vec3; 3] = [
    Vec3::new(1.0, 0.0, 0.0),
    Vec3::new(0.0, 1.0, 0.0),
    Vec3::new(0.0, 0.0, 1.0),
];

/// The `--symmetry` setting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SymmetryOption {
    /// No symmetry asked for.
    #[default]
    None,
    /// Rotation of this order (≥ 2) about the detected axis.
    Rotate(u32),
    /// A mirror plane.
    Mirror,
    /// The largest symmetry found (that the budget allows).
    Auto,
}

impl std::str::FromStr for SymmetryOption {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let bad =
            || format!("unknown symmetry `{s}`: expected rotate:N (N ≥ 2), mirror, auto or none");
        match s.trim().to_ascii_lowercase().as_str() {
            "none" => Ok(SymmetryOption::None),
            "mirror" => Ok(SymmetryOption::Mirror),
            "auto" => Ok(SymmetryOption::Auto),
            t => {
                let n = t.strip_prefix("rotate:").ok_or_else(bad)?;
                let n: u32 = n.trim().parse().map_err(|_| bad())?;
                if n < 2 {
                    return Err(format!("rotate:{n}: a rotation's order must be at least 2"));
                }
                Ok(SymmetryOption::Rotate(n))
            }
        }
    }
}

impl fmt::Display for SymmetryOption {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SymmetryOption::None => write!(f, "none"),
            SymmetryOption::Rotate(n) => write!(f, "rotate:{n}"),
            SymmetryOption::Mirror => write!(f, "mirror"),
            SymmetryOption::Auto => write!(f, "auto"),
        }
    }
}

impl Serialize for SymmetryOption {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.to_string())
    }
}

impl<'de> Deserialize<'de> for SymmetryOption {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

/// A symmetry of the network.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Symmetry {
    /// Rotation by `2π/order` about the axis through `center` along `axis`.
    Rotation {
        /// Its order.
        order: u32,
        /// A point of the axis (the network's centroid).
        center: [f64; 3],
        /// The axis direction (unit).
        axis: [f64; 3],
    },
    /// Reflection in the plane through `point` with unit normal `normal`.
    Mirror {
        /// A point of the plane (the network's centroid).
        point: [f64; 3],
        /// The plane's unit normal.
        normal: [f64; 3],
    },
}

/// A symmetry found, with the curves' orbits under it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SymmetryFound {
    /// The symmetry.
    pub symmetry: Symmetry,
    /// Every curve in exactly one orbit; each ascending, in order of their smallest curve.
    pub orbits: Vec<Vec<usize>>,
    /// The largest distance between a curve's image and the curve it maps to (scene units).
    pub mismatch: f64,
    /// The tolerance used (scene units).
    pub tolerance: f64,
    /// The scene's size (bounding-box diagonal).
    pub scene_size: f64,
}

impl Symmetry {
    /// `p` mapped by the symmetry applied `k` times (a mirror's every odd power is itself).
    pub fn apply(&self, p: Vec3, k: u32) -> Vec3 {
        let v = |a: &[f64; 3]| Vec3::new(a[0], a[1], a[2]);
        let t = match self {
            Symmetry::Rotation {
                order,
                center,
                axis,
            } => {
                let angle = std::f64::consts::TAU * f64::from(k % order) / f64::from(*order);
                Transform::Rotate {
                    center: v(center),
                    axis: v(axis),
                    cos: angle.cos(),
                    sin: angle.sin(),
                }
            }
            Symmetry::Mirror { .. } if k.is_multiple_of(2) => return p,
            Symmetry::Mirror { point, normal } => Transform::Reflect {
                point: v(point),
                normal: v(normal),
            },
        };
        t.apply(p)
    }
}

impl SymmetryFound {
    /// The number of elements of the symmetry group (the rotation's order, 2 for a mirror).
    pub fn group_order(&self) -> u32 {
        match self.symmetry {
            Symmetry::Rotation { order, .. } => order,
            Symmetry::Mirror { .. } => 2,
        }
    }

    /// The option that names it (`rotate:N` or `mirror`).
    pub fn option(&self) -> SymmetryOption {
        match self.symmetry {
            Symmetry::Rotation { order, .. } => SymmetryOption::Rotate(order),
            Symmetry::Mirror { .. } => SymmetryOption::Mirror,
        }
    }

    /// One line for reports.
    pub fn describe(&self) -> String {
        let p = |v: &[f64; 3]| format!("({:.6}, {:.6}, {:.6})", v[0], v[1], v[2]);
        let what = match &self.symmetry {
            Symmetry::Rotation {
                order,
                center,
                axis,
            } => format!(
                "rotation of order {order} about the axis through {} along {}",
                p(center),
                p(axis)
            ),
            Symmetry::Mirror { point, normal } => format!(
                "mirror plane through {} with normal {}",
                p(point),
                p(normal)
            ),
        };
        let mut by_size = std::collections::BTreeMap::new();
        for o in &self.orbits {
            *by_size.entry(o.len()).or_insert(0) += 1;
        }
        let counts: Vec<String> = (by_size.iter())
            .map(|(&s, k)| format!("{k} of {s} curve{}", if s == 1 { "" } else { "s" }))
            .collect();
        format!(
            "{what}: {} orbits ({}); curves match to {:.1e} of the scene's size (tolerance {:.1e})",
            self.orbits.len(),
            counts.join(", "),
            self.mismatch / self.scene_size.max(f64::MIN_POSITIVE),
            self.tolerance / self.scene_size.max(f64::MIN_POSITIVE),
        )
    }
}

/// A rigid map of the scene onto itself.
#[derive(Clone, Copy, Debug)]
enum Transform {
    Rotate {
        center: Vec3,
        axis: Vec3,
        cos: f64,
        sin: f64,
    },
    Reflect {
        point: Vec3,
        normal: Vec3,
    },
}

impl Transform {
    fn apply(&self, p: Vec3) -> Vec3 {
        match *self {
            Transform::Rotate {
                center,
                axis,
                cos,
                sin,
            } => {
                let v = p - center;
                center + v * cos + axis.cross(v) * sin + axis * (axis.dot(v) * (1.0 - cos))
            }
            Transform::Reflect { point, normal } => p - normal * (2.0 * (p - point).dot(normal)),
        }
    }

    /// The transform applied `k` times.
    fn power(&self, k: u32) -> Self {
        match *self {
            Transform::Rotate {
                center,
                axis,
                cos,
                sin,
            } => {
                let angle = f64::from(k) * sin.atan2(cos);
                Transform::Rotate {
                    center,
                    axis,
                    cos: angle.cos(),
                    sin: angle.sin(),
                }
            }
            r @ Transform::Reflect { .. } => r,
        }
    }

    fn inverse(&self) -> Self {
        match *self {
            Transform::Rotate {
                center,
                axis,
                cos,
                sin,
            } => Transform::Rotate {
                center,
                axis,
                cos,
                sin: -sin,
            },
            r @ Transform::Reflect { .. } => r,
        }
    }
}

/// What the test needs of one curve.
struct CurveGeo {
    /// The polyline (a closed one repeats its first vertex last).
    points: Vec<Vec3>,
    samples: Vec<Vec3>,
    centroid: Vec3,
    length: f64,
    closed: bool,
    anchors: usize,
}

/// Why a transform is not a symmetry: a curve with no curve where it maps.
struct Mismatch {
    curve: usize,
    /// How far the curve's image lands from the nearest curve (the largest distance between
    /// the image and that curve: the test's own measure).
    distance: f64,
    /// The power of the transform that fails (1: the transform itself; `k`: the rotation by
    /// `k` times its angle, which a symmetry of the group must also be).
    power: u32,
    /// Every curve has a curve where it maps, but the map is not a symmetry of the asked
    /// order (its cycle through `curve` does not close after that many steps).
    cycle: bool,
}

/// The network's geometry, ready for symmetry tests.
pub struct Detector {
    curves: Vec<CurveGeo>,
    center: Vec3,
    /// Principal axes of the edges' inertia about `center`: the distinct one first.
    principal: [Vec3; 3],
    scene_size: f64,
    tolerance: f64,
}

impl Detector {
    /// Prepares `net`'s rest geometry; `tolerance` is relative to the scene's size.
    pub fn new(net: &Network, tolerance: f64) -> Self {
        let curves: Vec<CurveGeo> = net
            .rods
            .iter()
            .map(|rod| {
                let mut points: Vec<Vec3> = rod
                    .vertices
                    .iter()
                    .map(|&v| net.positions[v as usize])
                    .collect();
                if rod.closed && !points.is_empty() {
                    points.push(points[0]);
                }
                let m = points.len();
                let k = SAMPLES.min(m);
                let samples = (0..k)
                    .map(|i| points[if k > 1 { i * (m - 1) / (k - 1) } else { 0 }])
                    .collect();
                let (mut sum, mut length) = (Vec3::ZERO, 0.0);
                for w in points.windows(2) {
                    let l = w[0].dist(w[1]);
                    sum += (w[0] + w[1]) * (0.5 * l);
                    length += l;
                }
                let centroid = if length > 0.0 {
                    sum / length
                } else {
                    points.first().copied().unwrap_or(Vec3::ZERO)
                };
                CurveGeo {
                    points,
                    samples,
                    centroid,
                    length,
                    closed: rod.closed,
                    anchors: rod.anchors.len(),
                }
            })
            .collect();
        let total: f64 = curves.iter().map(|c| c.length).sum();
        let center = if total > 0.0 {
            curves
                .iter()
                .fold(Vec3::ZERO, |s, c| s + c.centroid * c.length)
                / total
        } else {
            Vec3::ZERO
        };
        let scene_size = Aabb::of_points(&net.positions).extent().norm();
        let principal = principal_axes(&curves, center);
        Detector {
            curves,
            center,
            principal,
            scene_size,
            tolerance: tolerance * scene_size,
        }
    }

    /// The candidate rotation axes, in the documented order, without repeats.
    fn axes(&self) -> Vec<Vec3> {
        let mut out: Vec<Vec3> = Vec::new();
        for a in self.principal.iter().chain(&UNIT_AXES) {
            push_direction(&mut out, *a);
        }
        out
    }

    /// The candidate mirror normals, in the documented order, without repeats.
    fn normals(&self) -> Vec<Vec3> {
        let mut out = Vec::new();
        for a in self.principal {
            push_direction(&mut out, a);
        }
        // Reference ends: both ends of the first open curve and of the open curve whose end
        // lies farthest from the centroid.
        let open: Vec<usize> = (0..self.curves.len())
            .filter(|&i| !self.curves[i].closed && self.curves[i].points.len() >= 2)
            .collect();
        let ends = |i: usize| {
            let p = &self.curves[i].points;
            [p[0], p[p.len() - 1]]
        };
        let far = open.iter().copied().max_by(|&a, &b| {
            let d = |i: usize| {
                ends(i)
                    .iter()
                    .map(|e| e.dist(self.center))
                    .fold(0.0, f64::max)
            };
            d(a).total_cmp(&d(b)).then(b.cmp(&a))
        });
        let mut refs: Vec<usize> = open.first().copied().into_iter().chain(far).collect();
        refs.dedup();
        for &r in &refs {
            for a in ends(r) {
                let ra = a.dist(self.center);
                for &j in &open {
                    for b in ends(j) {
                        let d = a - b;
                        if d.norm() > self.tolerance
                            && (b.dist(self.center) - ra).abs() <= 2.0 * self.tolerance
                        {
                            push_direction(&mut out, d);
                        }
                    }
                }
            }
        }
        out
    }

    /// The permutation `T` makes of the curves, or the first curve with nothing where it
    /// maps; with the worst distance of a match. `order` is the number of times `T` must be
    /// applied to give the identity: a permutation with a cycle whose length does not divide
    /// it is no symmetry (within the tolerance a rotation by `2π/33` can map the tower's
    /// curves onto their neighbours, 11.25° apart, but its cycles of 16 give it away), and
    /// neither is a map of two curves onto one.
    fn matching(&self, t: &Transform, order: u32) -> Result<(Vec<usize>, f64), Mismatch> {
        let inv = t.inverse();
        let tol = self.tolerance;
        let mut perm = Vec::with_capacity(self.curves.len());
        let mut worst = 0.0f64;
        for (i, ci) in self.curves.iter().enumerate() {
            let image = t.apply(ci.centroid);
            let mut best: Option<(f64, usize)> = None;
            for (j, cj) in self.curves.iter().enumerate() {
                let dc = image.dist(cj.centroid);
                if cj.closed != ci.closed
                    || cj.anchors != ci.anchors
                    || (cj.length - ci.length).abs() > 1e-2 * ci.length + 2.0 * tol
                    || dc > 2.0 * tol
                {
                    continue;
                }
                let limit = best.map_or(tol, |b| b.0.min(tol));
                let Some(d) = hausdorff(ci, cj, t, &inv, limit) else {
                    continue;
                };
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, j));
                }
            }
            match best {
                Some((d, j)) => {
                    worst = worst.max(d);
                    perm.push(j);
                }
                None => {
                    return Err(Mismatch {
                        curve: i,
                        distance: self.landing(i, t),
                        power: 1,
                        cycle: false,
                    });
                }
            }
        }
        if let Some(curve) = inconsistent(&perm, order) {
            return Err(Mismatch {
                curve,
                distance: f64::INFINITY,
                power: 1,
                cycle: true,
            });
        }
        // Every element of the group must map the network onto itself too: the rotation by
        // `k` times the angle takes curve `i` to `perm^k(i)`. A small rotation maps every
        // curve within the tolerance of itself; its powers near a half turn do not, unless
        // the network has the symmetry. (`k` and `order − k` are inverses: half suffice.)
        let mut at = perm.clone();
        for k in 2..=order / 2 {
            let tk = t.power(k);
            let tk_inv = tk.inverse();
            for (i, a) in at.iter_mut().enumerate() {
                *a = perm[*a];
                match hausdorff(&self.curves[i], &self.curves[*a], &tk, &tk_inv, tol) {
                    Some(d) => worst = worst.max(d),
                    None => {
                        return Err(Mismatch {
                            curve: i,
                            distance: self.landing(i, &tk),
                            power: k,
                            cycle: false,
                        });
                    }
                }
            }
        }
        Ok((perm, worst))
    }

    /// How far `t` takes curve `i` from the nearest curve: the least, over every curve, of
    /// the largest distance between `t(i)` and it.
    fn landing(&self, i: usize, t: &Transform) -> f64 {
        let inv = t.inverse();
        let ci = &self.curves[i];
        self.curves
            .iter()
            .filter_map(|cj| hausdorff(ci, cj, t, &inv, f64::INFINITY))
            .fold(f64::INFINITY, f64::min)
    }

    /// The largest rotation order the network's curves can carry: a curve off the axis
    /// needs its whole orbit, an open curve on it is kept by a half turn at most, and a
    /// closed curve around the axis by as many turns as it has vertices. So twice the
    /// curves, and the vertices of the largest closed curve.
    pub fn max_rotation_order(&self) -> u32 {
        let ring = self
            .curves
            .iter()
            .filter(|c| c.closed)
            .map(|c| c.points.len().saturating_sub(1))
            .max()
            .unwrap_or(0);
        u32::try_from(2 * self.curves.len() + ring).unwrap_or(u32::MAX)
    }

    /// The orbits of `perm`'s cycles, each ascending, ordered by their smallest curve.
    fn orbits(&self, perm: &[usize]) -> Vec<Vec<usize>> {
        let all: Vec<usize> = (0..perm.len()).collect();
        curve_components(
            perm.len(),
            &all,
            perm.iter().enumerate().map(|(i, &j)| [i, j]),
        )
    }

    fn found(&self, symmetry: Symmetry, perm: &[usize], mismatch: f64) -> SymmetryFound {
        SymmetryFound {
            symmetry,
            orbits: self.orbits(perm),
            mismatch,
            tolerance: self.tolerance,
            scene_size: self.scene_size,
        }
    }

    /// The rotation of `order` about the first candidate axis where it is a symmetry, or why
    /// none is (the closest miss).
    pub fn rotation(&self, order: u32) -> Result<SymmetryFound, NoSymmetry> {
        let most = self.max_rotation_order();
        if order > most {
            return Err(NoSymmetry(format!(
                "the network has no rotation of order {order}: its {} curves can carry a \
                 rotation of order {most} at most (each curve off the axis needs its whole \
                 orbit of curves)",
                self.curves.len()
            )));
        }
        self.first_of(
            &format!("rotation of order {order}"),
            order,
            self.axes(),
            |axis| self.rotation_about(axis, order),
        )
    }

    /// The rotation of `order` about the axis through the centroid along `axis`.
    fn rotation_about(&self, axis: Vec3, order: u32) -> (Transform, Symmetry) {
        let t = std::f64::consts::TAU / f64::from(order);
        let transform = Transform::Rotate {
            center: self.center,
            axis,
            cos: t.cos(),
            sin: t.sin(),
        };
        let symmetry = Symmetry::Rotation {
            order,
            center: self.center.to_array(),
            axis: axis.to_array(),
        };
        (transform, symmetry)
    }

    /// The first candidate mirror plane that is a symmetry, or why none is.
    pub fn mirror(&self) -> Result<SymmetryFound, NoSymmetry> {
        self.first_of("mirror plane", 2, self.normals(), |normal| {
            (
                Transform::Reflect {
                    point: self.center,
                    normal,
                },
                Symmetry::Mirror {
                    point: self.center.to_array(),
                    normal: normal.to_array(),
                },
            )
        })
    }

    /// The first of the `candidates` (axes or normals) whose transform (of `order`, from
    /// `make` with its symmetry) maps the network onto itself, or why none does (the
    /// closest miss).
    fn first_of(
        &self,
        what: &str,
        order: u32,
        candidates: Vec<Vec3>,
        make: impl Fn(Vec3) -> (Transform, Symmetry),
    ) -> Result<SymmetryFound, NoSymmetry> {
        let mut miss: Option<(Mismatch, Vec3)> = None;
        for c in candidates {
            let (t, symmetry) = make(c);
            match self.matching(&t, order) {
                Ok((perm, worst)) => return Ok(self.found(symmetry, &perm, worst)),
                Err(m) => {
                    if miss.as_ref().is_none_or(|(b, _)| m.distance < b.distance) {
                        miss = Some((m, c));
                    }
                }
            }
        }
        Err(self.not_found(what, miss))
    }

    /// Every symmetry `auto` may use, largest group first: the rotations of every order
    /// dividing the largest order found (on the axis where it is largest), then the mirror.
    pub fn all(&self) -> Vec<SymmetryFound> {
        let mut best: Option<(u32, Vec3)> = None;
        let most = MAX_ORDER.min(self.max_rotation_order());
        for axis in self.axes() {
            for order in (2..=most).rev() {
                if best.is_some_and(|b| order <= b.0) {
                    break;
                }
                if self
                    .matching(&self.rotation_about(axis, order).0, order)
                    .is_ok()
                {
                    best = Some((order, axis));
                    break;
                }
            }
        }
        let mut out = Vec::new();
        if let Some((top, axis)) = best {
            for order in (2..=top).rev().filter(|d| top % d == 0) {
                let (t, symmetry) = self.rotation_about(axis, order);
                if let Ok((perm, worst)) = self.matching(&t, order) {
                    out.push(self.found(symmetry, &perm, worst));
                }
            }
        }
        if let Ok(m) = self.mirror() {
            out.push(m);
        }
        out
    }

    fn not_found(&self, what: &str, miss: Option<(Mismatch, Vec3)>) -> NoSymmetry {
        let rel = |d: f64| d / self.scene_size.max(f64::MIN_POSITIVE);
        NoSymmetry(match miss {
            Some((m, _)) if m.cycle => format!(
                "the network has no {what}: every curve has a curve where the map takes it, but \
                 repeating the map does not bring curve {} back to itself as a symmetry of \
                 this order would (a symmetry of another order, within the tolerance)",
                m.curve
            ),
            Some((m, dir)) => {
                let which = if m.power > 1 {
                    format!("applied {} times, it maps", m.power)
                } else {
                    "it maps".to_string()
                };
                format!(
                    "the network has no {what} within the tolerance ({:.1e} of the scene's \
                     size, {:.3e} scene units): the closest, about the centroid ({:.6}, {:.6}, \
                     {:.6}) with direction ({:.4}, {:.4}, {:.4}); {which} curve {} {:.3e} away \
                     from any curve ({:.1e} of the scene's size)",
                    rel(self.tolerance),
                    self.tolerance,
                    self.center.x,
                    self.center.y,
                    self.center.z,
                    dir.x,
                    dir.y,
                    dir.z,
                    m.curve,
                    m.distance,
                    rel(m.distance),
                )
            }
            None => format!("the network has no {what}: it has no curves to compare"),
        })
    }
}

/// Why the network lacks the symmetry asked for: how close it came (the closest miss: which
/// curve lands how far from any curve), or why it cannot have it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct NoSymmetry(pub String);

/// Finds the symmetry `option` asks for: none for [`SymmetryOption::None`], the one asked for
/// (an error saying how close the network came when it is not there), or for
/// [`SymmetryOption::Auto`] every candidate, largest first (possibly none).
pub fn find(
    net: &Network,
    option: SymmetryOption,
    tolerance: f64,
) -> Result<Vec<SymmetryFound>, NoSymmetry> {
    let d = || Detector::new(net, tolerance);
    match option {
        SymmetryOption::None => Ok(Vec::new()),
        SymmetryOption::Rotate(n) => d().rotation(n).map(|f| vec![f]),
        SymmetryOption::Mirror => d().mirror().map(|f| vec![f]),
        SymmetryOption::Auto => Ok(d().all()),
    }
}

/// The first curve of `perm` that is not a bijection's, or on a cycle whose length does not
/// divide `order`.
fn inconsistent(perm: &[usize], order: u32) -> Option<usize> {
    let n = perm.len();
    let mut hit = vec![false; n];
    for (i, &j) in perm.iter().enumerate() {
        if std::mem::replace(&mut hit[j], true) {
            return Some(i);
        }
    }
    let mut seen = vec![false; n];
    for start in 0..n {
        if seen[start] {
            continue;
        }
        let (mut len, mut c) = (0u32, start);
        while !seen[c] {
            seen[c] = true;
            len += 1;
            c = perm[c];
        }
        if !order.is_multiple_of(len) {
            return Some(start);
        }
    }
    None
}

/// Adds `d` (normalised, its largest component made positive) unless it repeats one there.
fn push_direction(out: &mut Vec<Vec3>, d: Vec3) {
    let mut d = d.normalized();
    if d.norm2() == 0.0 || !d.is_finite() {
        return;
    }
    let big = (0..3)
        .max_by(|&a, &b| d[a].abs().total_cmp(&d[b].abs()))
        .unwrap_or(0);
    if d[big] < 0.0 {
        d = -d;
    }
    if out.iter().all(|e| e.dot(d).abs() < 1.0 - 1e-9) {
        out.push(d);
    }
}

/// The largest distance between `T(a)` and `b` over both curves' samples, if at most `limit`
/// (`None` as soon as a sample is farther).
fn hausdorff(
    a: &CurveGeo,
    b: &CurveGeo,
    t: &Transform,
    inv: &Transform,
    limit: f64,
) -> Option<f64> {
    let mut worst = 0.0f64;
    for (from, to, map) in [(a, b, t), (b, a, inv)] {
        for &s in &from.samples {
            let p = map.apply(s);
            let d = polyline_distance(p, &to.points, limit)?;
            worst = worst.max(d);
        }
    }
    Some(worst)
}

/// The distance from `p` to the polyline, if at most `limit`.
fn polyline_distance(p: Vec3, points: &[Vec3], limit: f64) -> Option<f64> {
    let d = match points {
        [] => return None,
        [q] => p.dist(*q),
        _ => points
            .windows(2)
            .map(|w| point_segment_distance(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min),
    };
    (d <= limit).then_some(d)
}

/// The principal axes of the edges' inertia about `center` (each edge a point mass of its
/// length at its midpoint), the one with the most distinct eigenvalue first, then the others
/// by ascending eigenvalue.
fn principal_axes(curves: &[CurveGeo], center: Vec3) -> [Vec3; 3] {
    let mut m = [[0.0f64; 3]; 3];
    for c in curves {
        for w in c.points.windows(2) {
            let l = w[0].dist(w[1]);
            let r = (w[0] + w[1]) * 0.5 - center;
            let r2 = r.norm2();
            for a in 0..3 {
                for b in 0..3 {
                    let delta = if a == b { r2 } else { 0.0 };
                    m[a][b] += l * (delta - r[a] * r[b]);
                }
            }
        }
    }
    let mat = faer::Mat::<f64>::from_fn(3, 3, |i, j| 0.5 * (m[i][j] + m[j][i]));
    let Ok(eig) = mat.self_adjoint_eigen(faer::Side::Lower) else {
        return UNIT_AXES;
    };
    let s = eig.S();
    let u = eig.U();
    let (l0, l1, l2) = (s[0], s[1], s[2]);
    let v = |k: usize| Vec3::new(u[(0, k)], u[(1, k)], u[(2, k)]);
    // The eigenvalue farther from its neighbour is the distinct one.
    if l1 - l0 < l2 - l1 {
        [v(2), v(0), v(1)]
    } else {
        [v(0), v(1), v(2)]
    }
}

#[cfg(test)]
mod tests;

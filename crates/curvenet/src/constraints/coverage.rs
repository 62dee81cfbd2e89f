//! The largest gap between the surface and the kept curves (`--max-gap D`).
//!
//! # How it is measured
//!
//! The gap of a set `S` of curves is the largest distance from a point of the designed surface
//! (the mesh) to the nearest rod of `S` at rest (its polyline through the network's rest
//! vertices): `gap(S) = max_p min_{c ∈ S} dist(p, c)`. It is measured over samples of the
//! surface: every mesh vertex, and on every face the points of a triangular grid whose
//! spacing is at most `δ` (the face's edges divided into `k = ⌈longest edge / δ⌉` parts),
//! with `δ = max(D / 8, diagonal / 500)` (`diagonal`: the samples' bounding-box diagonal),
//! enlarged if needed to keep at most [`MAX_SAMPLES`] samples. Every point of a face lies
//! within `δ` of a sample and the distance to the curves changes by at most the distance
//! moved, so the surface's true gap exceeds the measured one by less than `δ` (reported as
//! the gap's resolution).
//!
//! # How it is tested fast
//!
//! The constraint `gap(S) ≤ D` says: every sample has a curve of `S` within `D`. Each sample's
//! *mask* is the set of curves within `D` of it; `S` is feasible when it meets every mask.
//! Samples with the same mask, and masks holding another mask, add nothing, so only the
//! distinct minimal masks are kept (a few dozen to a few thousand), and a test is a few word
//! operations per mask ([`Coverage::covers`]). Adding curves never opens a gap, so a search
//! may also drop any branch whose largest possible set (`S` with every curve it may still
//! add) leaves a mask unmet. The gap's value (for margins and reports) is computed exactly
//! over the samples by [`Coverage::gap`].

use super::CurveSet;
use crate::geom::point_segment_distance;
use crate::geom::{Aabb, Bvh, Vec3};
use crate::io::TriMesh;
use crate::network::Network;
use crate::words::{Message, Opt, message};
use rayon::prelude::*;

/// The most samples taken of a surface (the spacing grows to stay below it).
pub const MAX_SAMPLES: usize = 400_000;

/// The gap of a set of curves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gap {
    /// The largest distance from a sample of the surface to the nearest kept curve.
    pub value: f64,
    /// The sample where it is reached.
    pub at: Vec3,
}

/// The surface's samples and what each needs, for one limit `D`.
pub struct Coverage {
    limit: f64,
    spacing: f64,
    samples: Vec<Vec3>,
    /// The samples, for box queries.
    tree: Bvh,
    /// The distinct minimal masks: a feasible set meets each.
    needs: Vec<CurveSet>,
    /// A sample of each need.
    need_points: Vec<Vec3>,
    /// Each curve's rest segments.
    segments: Vec<Vec<(Vec3, Vec3)>>,
    /// The gap with every curve kept.
    full: Gap,
}

impl Coverage {
    /// Samples `mesh` and finds, for the limit `limit`, which curves of `net` each sample
    /// needs.
    ///
    /// # Errors
    ///
    /// A message when the limit is not a positive number or the mesh has no usable face.
    pub fn new(net: &Network, mesh: &TriMesh, limit: f64) -> Result<Coverage, Message> {
        if !(limit.is_finite() && limit > 0.0) {
            return Err(message![
                Opt::MaxGap,
                format!(" must be a positive distance in scene units, got {limit}")
            ]);
        }
        let (samples, spacing) = sample_surface(mesh, limit)?;
        let n = net.rods.len();
        let segments: Vec<Vec<(Vec3, Vec3)>> = net
            .rods
            .iter()
            .map(|rod| {
                (0..rod.edge_count())
                    .map(|j| {
                        let (a, b) = rod.edge(j);
                        (net.positions[a as usize], net.positions[b as usize])
                    })
                    .collect()
            })
            .collect();
        let tree = Bvh::new(samples.iter().map(|&p| Aabb { min: p, max: p }).collect());
        let mut cov = Coverage {
            limit,
            spacing,
            tree,
            needs: Vec::new(),
            need_points: Vec::new(),
            segments,
            full: Gap {
                value: 0.0,
                at: Vec3::ZERO,
            },
            samples,
        };
        // Each curve's samples within the limit, in parallel (one list per curve).
        let covered: Vec<Vec<u32>> = (0..n)
            .into_par_iter()
            .map(|c| cov.within(c, limit))
            .collect();
        let mut masks = vec![CurveSet::new(n); cov.samples.len()];
        for (c, list) in covered.iter().enumerate() {
            for &p in list {
                masks[p as usize].insert(c);
            }
        }
        let (needs, need_points) = minimal(&masks, &cov.samples);
        cov.needs = needs;
        cov.need_points = need_points;
        cov.full = cov.gap(&(0..n).collect::<Vec<_>>());
        Ok(cov)
    }

    /// The samples of the surface within `radius` of curve `c`, ascending.
    fn within(&self, c: usize, radius: f64) -> Vec<u32> {
        let mut hit = vec![false; self.samples.len()];
        for &(a, b) in &self.segments[c] {
            self.near_segment(a, b, radius, |i| {
                if !hit[i] && point_segment_distance(self.samples[i], a, b) <= radius {
                    hit[i] = true;
                }
            });
        }
        (0..self.samples.len() as u32)
            .filter(|&i| hit[i as usize])
            .collect()
    }

    /// Calls `f` on every sample in the box around the segment `[a, b]` grown by `radius`
    /// (every sample within `radius` of it, and others).
    fn near_segment(&self, a: Vec3, b: Vec3, radius: f64, mut f: impl FnMut(usize)) {
        let q = Aabb::of_points([&a, &b]).inflated(radius);
        self.tree.overlapping(&q, |i| f(i as usize));
    }

    /// The limit `D`.
    pub fn limit(&self) -> f64 {
        self.limit
    }

    /// The sample spacing `δ`: the true gap exceeds the measured one by less than it.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// Number of samples of the surface.
    pub fn sample_count(&self) -> usize {
        self.samples.len()
    }

    /// Number of distinct minimal masks (what a test checks).
    pub fn need_count(&self) -> usize {
        self.needs.len()
    }

    /// The gap with every curve kept.
    pub fn full_gap(&self) -> Gap {
        self.full
    }

    /// The needs (minimal masks: a feasible set meets each) with a point of the surface of
    /// each.
    pub fn needs(&self) -> impl Iterator<Item = (&CurveSet, Vec3)> + '_ {
        self.needs.iter().zip(self.need_points.iter().copied())
    }

    /// Whether `set` leaves no sample farther than the limit from its curves.
    pub fn covers(&self, set: &CurveSet) -> bool {
        self.needs.iter().all(|m| m.intersects(set))
    }

    /// The number of samples' needs `set` leaves unmet (0 when it covers the surface).
    pub fn unmet(&self, set: &CurveSet) -> usize {
        self.needs.iter().filter(|m| !m.intersects(set)).count()
    }

    /// The gap of `curves` over the samples (infinite for no curve).
    pub fn gap(&self, curves: &[usize]) -> Gap {
        let m = self.samples.len();
        if curves.is_empty() || m == 0 {
            return Gap {
                value: if m == 0 { 0.0 } else { f64::INFINITY },
                at: self.samples.first().copied().unwrap_or(Vec3::ZERO),
            };
        }
        // Exact for samples with a kept curve within the limit: each segment updates the
        // samples near it; the others are measured against every kept segment.
        let mut d = vec![f64::INFINITY; m];
        let r = self.limit;
        for &c in curves {
            for &(a, b) in &self.segments[c] {
                self.near_segment(a, b, r, |i| {
                    let x = point_segment_distance(self.samples[i], a, b);
                    if x < d[i] {
                        d[i] = x;
                    }
                });
            }
        }
        let kept: Vec<(Vec3, Vec3)> = curves
            .iter()
            .flat_map(|&c| self.segments[c].iter().copied())
            .collect();
        d.par_iter_mut().enumerate().for_each(|(i, di)| {
            if *di > r {
                let p = self.samples[i];
                *di = kept
                    .iter()
                    .map(|&(a, b)| point_segment_distance(p, a, b))
                    .fold(f64::INFINITY, f64::min);
            }
        });
        let (at, value) = (d.iter().copied().enumerate())
            .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best });
        Gap {
            value,
            at: self.samples[at],
        }
    }
}

/// Samples of the surface (its vertices and a grid on every face) and their spacing.
fn sample_surface(mesh: &TriMesh, limit: f64) -> Result<(Vec<Vec3>, f64), Message> {
    let faces = mesh.finite_triangles();
    if faces.is_empty() {
        return Err(message![
            Opt::MaxGap,
            " needs the surface, but the mesh has no usable face"
        ]);
    }
    let vertices: Vec<Vec3> = mesh
        .vertices
        .iter()
        .copied()
        .filter(|p| p.is_finite())
        .collect();
    let diagonal = Aabb::of_points(&vertices).extent().norm();
    let longest = |t: &[Vec3; 3]| t[0].dist(t[1]).max(t[1].dist(t[2])).max(t[2].dist(t[0]));
    let parts = |t: &[Vec3; 3], spacing: f64| (longest(t) / spacing).ceil().max(1.0) as usize;
    let mut spacing = (limit / 8.0).max(diagonal / 500.0).max(f64::MIN_POSITIVE);
    loop {
        let count: usize = vertices.len()
            + faces
                .iter()
                .map(|t| {
                    let k = parts(t, spacing);
                    // Grid points of the face, its corners (mesh vertices) left out.
                    ((k + 1) * (k + 2) / 2).saturating_sub(3)
                })
                .sum::<usize>();
        if count <= MAX_SAMPLES {
            break;
        }
        spacing *= 1.25;
    }
    let mut samples = vertices;
    for t in &faces {
        let k = parts(t, spacing);
        for i in 0..=k {
            for j in 0..=k - i {
                let l = k - i - j;
                if (i == k) || (j == k) || (l == k) {
                    continue;
                }
                let (a, b) = (i as f64 / k as f64, j as f64 / k as f64);
                samples.push(t[0] * (1.0 - a - b) + t[1] * a + t[2] * b);
            }
        }
    }
    Ok((samples, spacing))
}

/// The distinct masks that hold no other mask, in a fixed order (by size, then by content),
/// each with the first sample that has it.
fn minimal(masks: &[CurveSet], samples: &[Vec3]) -> (Vec<CurveSet>, Vec<Vec3>) {
    let mut first: std::collections::HashMap<&CurveSet, usize> = Default::default();
    for (i, m) in masks.iter().enumerate() {
        first.entry(m).or_insert(i);
    }
    let mut distinct: Vec<(&CurveSet, usize)> = first.into_iter().collect();
    distinct.sort_by(|a, b| a.0.len().cmp(&b.0.len()).then(a.0.cmp(b.0)));
    let mut kept: Vec<CurveSet> = Vec::new();
    let mut points = Vec::new();
    for (m, i) in distinct {
        if !kept.iter().any(|k| k.is_subset(m)) {
            kept.push(m.clone());
            points.push(samples[i]);
        }
    }
    (kept, points)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::testing::{grid, network, square_mesh};

    /// The gap by brute force over the same samples.
    fn brute_gap(cov: &Coverage, curves: &[usize]) -> f64 {
        cov.samples
            .iter()
            .map(|&p| {
                curves
                    .iter()
                    .flat_map(|&c| cov.segments[c].iter())
                    .map(|&(a, b)| point_segment_distance(p, a, b))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn the_gap_of_a_grid_matches_brute_force_and_geometry() {
        // Six lines each way over [-300, 300]², 100 apart, on a flat square mesh.
        let net = network(&grid(300.0, 6));
        let mesh = square_mesh(300.0, 0.0, 12);
        let cov = Coverage::new(&net, &mesh, 60.0).expect("samples");
        assert!(cov.spacing() <= 60.0 / 8.0 + 1e-12);
        // All curves: the farthest points are the cells' centres and the square's border, 50
        // from the nearest line.
        let all: Vec<usize> = (0..12).collect();
        let g = cov.gap(&all);
        assert!((g.value - 50.0).abs() < 1e-9, "{g:?}");
        assert!((g.value - brute_gap(&cov, &all)).abs() < 1e-12);
        assert!(cov.covers(&CurveSet::from_curves(12, &all)));
        for set in [vec![0, 2, 4, 6, 8, 10], vec![1, 4], vec![3], vec![0, 11]] {
            let g = cov.gap(&set);
            assert!((g.value - brute_gap(&cov, &set)).abs() < 1e-9, "{set:?}");
            let s = CurveSet::from_curves(12, &set);
            assert_eq!(cov.covers(&s), g.value <= 60.0, "{set:?}: {g:?}");
        }
    }

    #[test]
    fn masks_decide_exactly_as_the_gap_on_every_subset() {
        // Every subset of a 3 + 3 grid: the masks' verdict is the measured gap's.
        let net = network(&grid(300.0, 3));
        let mesh = square_mesh(300.0, 0.0, 6);
        for limit in [110.0, 150.0, 250.0] {
            let cov = Coverage::new(&net, &mesh, limit).expect("samples");
            for mask in 1u32..64 {
                let set: Vec<usize> = (0..6).filter(|i| mask & (1 << i) != 0).collect();
                let covers = cov.covers(&CurveSet::from_curves(6, &set));
                assert_eq!(covers, cov.gap(&set).value <= limit, "{limit} {set:?}");
                assert_eq!(covers, cov.unmet(&CurveSet::from_curves(6, &set)) == 0);
            }
        }
    }

    #[test]
    fn a_bad_limit_or_an_empty_mesh_is_refused() {
        let net = network(&grid(300.0, 2));
        let mesh = square_mesh(300.0, 0.0, 2);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(Coverage::new(&net, &mesh, bad).is_err());
        }
        let e = Coverage::new(&net, &TriMesh::default(), 10.0)
            .err()
            .expect("no faces")
            .to_string();
        assert!(e.contains("no usable face"), "{e}");
    }

    #[test]
    fn the_sample_count_stays_bounded() {
        let net = network(&grid(300.0, 2));
        let mesh = square_mesh(300.0, 0.0, 4);
        // A tiny limit asks for a spacing of 1e-3: the spacing grows instead.
        let cov = Coverage::new(&net, &mesh, 1e-2).expect("samples");
        assert!(cov.sample_count() <= MAX_SAMPLES);
        assert!(cov.spacing() >= 600.0 * 2f64.sqrt() / 500.0);
    }
}

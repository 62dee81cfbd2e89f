//! Shared helpers of the integration tests: a small deterministic PRNG, hand-made curves and
//! networks, dense expansions of the sparse Hessian and an independent evaluation of the energy
//! of docs/model.md (*Energy*).
//!
//! Not every test file uses every helper.
#![allow(dead_code)]

use curvenet::geom::Vec3;
use curvenet::io::{Origin, Polyline};
use curvenet::network::{BuildParams, Joint, Network, Rod, build_network};
use curvenet::rng::SplitMix64;
use curvenet::rod::{ActiveSet, EnergyModel, Material, Supports};
use faer::{Mat, MatRef};
use proptest::test_runner::{Config as ProptestConfig, FileFailurePersistence};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Bound on the relative residuals `‖Hv − λv‖/‖H‖₁` the eigen solver guarantees: its
/// convergence test is on the inverted operator, relative to the largest inverted eigenvalue,
/// which bounds the error components along stiff directions by about `tol = 1e-10` (default
/// `EigenParams::tol`), hence the residual by `tol·‖H‖`. Observed residuals are usually far
/// smaller (1e-17…1e-14), but depend on the Newton path and the factorization.
pub const RESIDUAL_BOUND: f64 = 1e-10;

/// The tests' random inputs: the library's [`SplitMix64`] with the draws the tests use.
#[derive(Clone, Debug)]
pub struct Rng(SplitMix64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(SplitMix64::new(seed ^ 0x9e37_79b9_7f4a_7c15))
    }

    /// Uniform in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        self.0.next_f64()
    }

    /// Uniform in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        self.0.uniform(a, b)
    }

    /// Uniform integer in `[a, b)`.
    pub fn index(&mut self, a: usize, b: usize) -> usize {
        a + (self.0.next_u64() % (b - a) as u64) as usize
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = self.uniform().max(1e-300);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }

    /// A vector with independent standard normal components.
    pub fn normal3(&mut self) -> Vec3 {
        Vec3::new(self.normal(), self.normal(), self.normal())
    }
}

/// A temporary folder named after the test binary and `tag`, removed when dropped.
pub struct TempDir(PathBuf);

impl TempDir {
    /// A fresh path, nothing there yet.
    pub fn new(tag: &str) -> Self {
        static COUNT: AtomicUsize = AtomicUsize::new(0);
        let n = COUNT.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!(
            "curvenet-{}-{}-{tag}-{n}",
            env!("CARGO_CRATE_NAME"),
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        TempDir(dir)
    }

    /// A fresh, empty folder.
    pub fn create(tag: &str) -> Self {
        let dir = TempDir::new(tag);
        std::fs::create_dir_all(dir.path()).expect("temp dir");
        dir
    }

    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The fuzz tests' proptest configuration: `default` cases per property unless the
/// environment's `CURVENET_FUZZ_CASES` or `PROPTEST_CASES` says otherwise; failures persisted
/// in `tests/fuzz_regressions/<test binary>.proptest-regressions`.
pub fn fuzz_config(default: u32) -> ProptestConfig {
    let cases = ["CURVENET_FUZZ_CASES", "PROPTEST_CASES"]
        .iter()
        .find_map(|k| std::env::var(k).ok()?.trim().parse().ok())
        .unwrap_or(default);
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(concat!(
            "tests/fuzz_regressions/",
            env!("CARGO_CRATE_NAME"),
            ".proptest-regressions"
        )))),
        max_shrink_iters: 4096,
        ..ProptestConfig::default()
    }
}

/// A polyline made in a test.
pub fn polyline(points: Vec<Vec3>, closed: bool) -> Polyline {
    Polyline {
        points,
        closed,
        origin: Origin::new("<test>", 0),
        label: None,
    }
}

/// A circle of radius `r` around `center` in the plane spanned by the unit vectors `a`, `b`,
/// with `n` points (closed, first point not repeated).
pub fn circle(center: Vec3, a: Vec3, b: Vec3, r: f64, n: usize) -> Polyline {
    let points = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            center + a * (r * t.cos()) + b * (r * t.sin())
        })
        .collect();
    polyline(points, true)
}

/// A small random 3D network: a wobbly closed ring of radius ~300 in a tilted plane, and
/// `n_open` (2–4) wobbly open arches, each passing through two input points of the ring and
/// every arch after the first also through an input point of the first arch, so the network is
/// connected and every open curve has joints with the ring and with arch 0.
pub fn random_curves(seed: u64, n_open: usize) -> Vec<Polyline> {
    assert!((2..=4).contains(&n_open));
    let mut rng = Rng::new(seed);
    // Ring in a slightly tilted plane, radius with noise.
    let m = 24;
    let tilt = Vec3::new(rng.range(-0.2, 0.2), rng.range(-0.2, 0.2), 1.0).normalized();
    let ax = Vec3::new(1.0, 0.0, 0.0);
    let e1 = (ax - tilt * ax.dot(tilt)).normalized();
    let e2 = tilt.cross(e1);
    let ring: Vec<Vec3> = (0..m)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / m as f64;
            let r = 300.0 + rng.range(-25.0, 25.0);
            e1 * (r * t.cos()) + e2 * (r * t.sin()) + tilt * rng.range(-15.0, 15.0)
        })
        .collect();
    let mut curves = vec![polyline(ring.clone(), true)];

    let mut arch0: Vec<Vec3> = Vec::new();
    for k in 0..n_open {
        // Ring points the arch passes through: roughly opposite, distinct per arch.
        let a = (k * 3 + rng.index(0, 2)) % m;
        let b = (a + m / 2 + rng.index(0, 3) - 1) % m;
        let (pa, pb) = (ring[a], ring[b]);
        let out_a = (pa - (pa + pb) * 0.5).normalized();
        let out_b = -out_a;
        let height = rng.range(150.0, 300.0);
        let mut pts = vec![
            pa + out_a * rng.range(100.0, 160.0) - tilt * rng.range(20.0, 60.0) + rng.normal3(),
            pa,
        ];
        let inner = 9;
        for i in 1..inner {
            let t = i as f64 / inner as f64;
            let base = pa.lerp(pb, t);
            let wobble = rng.normal3() * 6.0;
            pts.push(base + tilt * (height * (std::f64::consts::PI * t).sin()) + wobble);
        }
        pts.push(pb);
        pts.push(
            pb + out_b * rng.range(100.0, 160.0) - tilt * rng.range(20.0, 60.0) + rng.normal3(),
        );
        if k == 0 {
            arch0 = pts.clone();
        } else {
            // Pass through one inner point of arch 0 (a crossing at an input vertex).
            let j = rng.index(3, 8);
            let at = rng.index(3, 8);
            pts[at] = arch0[j];
        }
        curves.push(polyline(pts, false));
    }
    curves
}

/// Builds `curves` with edge length `h` and `supports`.
pub fn build(curves: &[Polyline], h: f64, supports: Supports) -> Network {
    build_network(
        curves,
        &BuildParams {
            edge_length: h,
            supports,
            ..Default::default()
        },
    )
    .expect("test network builds")
    .0
}

/// The built-in dome of arcs (radius 2000, height 700; `families` families of
/// `per_family` arcs), clamped, built at edge length `h`.
pub fn dome(families: usize, per_family: usize, h: f64) -> Network {
    let s = curvenet::builtin::dome_arcs(2000.0, 700.0, families, per_family);
    build(&s.curves, h, Supports::Clamped)
}

/// The eigenvalues (ascending) and eigenvectors (columns, in the same order) of the dense
/// symmetric matrix `a` (lower triangle read): the reference the sparse solvers are checked
/// against.
pub fn dense_eigen(a: MatRef<'_, f64>) -> (Vec<f64>, Mat<f64>) {
    let e = a
        .self_adjoint_eigen(faer::Side::Lower)
        .expect("dense eigen");
    let s = e.S();
    ((0..a.nrows()).map(|i| s[i]).collect(), e.U().to_owned())
}

/// A straight rod from `start` along unit `dir`, length `len`, `n` edges (built by
/// `build_network` from a two-point polyline).
pub fn straight_rod(start: Vec3, dir: Vec3, len: f64, n: usize, supports: Supports) -> Network {
    let curves = vec![polyline(vec![start, start + dir * len], false)];
    let net = build(&curves, len / n as f64, supports);
    assert_eq!(net.rods[0].edge_count(), n, "rod has the requested edges");
    net
}

/// The network with every anchor removed.
pub fn without_anchors(mut net: Network) -> Network {
    for r in &mut net.rods {
        r.anchors.clear();
    }
    net
}

/// The full symmetric dense Hessian (loose diagonal included) from the model's upper triangle.
pub fn dense_hessian(model: &EnergyModel, u: &[f64], active: &ActiveSet) -> Mat<f64> {
    let a = model.assemble(u, active, true);
    let p = model.pattern();
    let mut m = Mat::<f64>::zeros(p.n, p.n);
    for j in 0..p.n {
        for s in p.col_ptr[j]..p.col_ptr[j + 1] {
            let i = p.row_idx[s];
            m[(i, j)] = a.hess[s];
            m[(j, i)] = a.hess[s];
        }
    }
    m
}

/// `‖v‖₂`.
pub fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// `|a − b| / max(|a|, |b|)` (0 when both are 0).
pub fn rel_diff(a: f64, b: f64) -> f64 {
    let s = a.abs().max(b.abs());
    if s == 0.0 { 0.0 } else { (a - b).abs() / s }
}

/// The energy of docs/model.md (*Energy*) written out independently of the library, at positions
/// `x` (flat), for the curves in `active` (all when `None`). Anchor targets are the rest positions.
pub fn spec_energy(net: &Network, mat: &Material, x: &[f64], active: Option<&[usize]>) -> f64 {
    let p = |v: u32| {
        let i = 3 * v as usize;
        Vec3::new(x[i], x[i + 1], x[i + 2])
    };
    let (ks, kb, mu) = (mat.ks(), mat.kb(), mat.anchor_weight);
    let mut total = 0.0;
    for (c, rod) in net.rods.iter().enumerate() {
        if active.is_some_and(|a| !a.contains(&c)) {
            continue;
        }
        let m = rod.vertices.len();
        let ne = rod.edge_count();
        let edge = |j: usize| p(rod.vertices[(j + 1) % m]) - p(rod.vertices[j]);
        for j in 0..ne {
            let r = rod.rest_lengths[j];
            let s = edge(j).norm() / r - 1.0;
            total += 0.5 * ks * s * s * r;
        }
        let centers: Vec<usize> = if rod.closed {
            (0..m).collect()
        } else {
            (1..m - 1).collect()
        };
        for i in centers {
            let (jp, jn) = ((i + ne - 1) % ne, i % ne);
            let (e0, e1) = (edge(jp), edge(jn));
            let (r0, r1) = (rod.rest_lengths[jp], rod.rest_lengths[jn]);
            let kappa = e0.cross(e1) * (2.0 / (r0 * r1 + e0.dot(e1)));
            total += kb * kappa.norm2() / (r0 + r1);
        }
        for &v in &rod.anchors {
            total += mu * (p(v) - net.positions[v as usize]).norm2();
        }
    }
    total
}

/// Flat positions `rest + u`.
pub fn positions_of(net: &Network, u: &[f64]) -> Vec<f64> {
    net.rest_coordinates()
        .iter()
        .zip(u)
        .map(|(x, d)| x + d)
        .collect()
}

/// The simple surfaces `curvenet compare` traces on (from the reference data in `data`),
/// scaled to a largest extent of 4000, as `experiments::compare::instance_network` takes them.
pub fn compare_surfaces(data: &std::path::Path) -> Vec<(String, curvenet::io::TriMesh)> {
    ["1wave", "2waves", "half_sphere", "sine_disk", "leaf"]
        .iter()
        .map(|n| {
            let m = curvenet::io::read_mesh(&data.join("meshes").join(format!("{n}.obj")))
                .expect("mesh");
            (
                n.to_string(),
                curvenet::trace::scale_to_extent(&m.mesh, 4000.0).0,
            )
        })
        .collect()
}

/// A count from the environment variable `key` (for ignored measuring tests), or `default`.
pub fn env_usize(key: &str, default: usize) -> usize {
    std::env::var(key)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// The paper's data folder shipped in this crate (`data/paper`: the meshes and curves published
/// with the authors' implementation). Always there; an `Option` so tests read as "with the
/// data".
pub fn data_dir() -> Option<PathBuf> {
    Some(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/paper"))
}

/// The six edges of an irregular tetrahedron (~400 across) as straight open curves that meet
/// at the four corners: a rigid 3D frame whose rods are straight, so the drawn state is
/// stress-free (energy 0, gradient 0).
pub fn tetrahedron_curves() -> Vec<Polyline> {
    let c = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(410.0, 15.0, -10.0),
        Vec3::new(120.0, 360.0, 20.0),
        Vec3::new(160.0, 110.0, 390.0),
    ];
    let mut out = Vec::new();
    for i in 0..4 {
        for j in i + 1..4 {
            out.push(polyline(vec![c[i], c[j]], false));
        }
    }
    out
}

/// The rigid motions of positions `x` (flat): three unit translations and the three
/// infinitesimal rotations `e_k × (x − centroid)`, as vectors over `x.len()` coordinates.
pub fn rigid_motions(x: &[f64]) -> Vec<Vec<f64>> {
    let nv = x.len() / 3;
    let mut c = [0.0; 3];
    for v in 0..nv {
        for a in 0..3 {
            c[a] += x[3 * v + a] / nv as f64;
        }
    }
    let mut out = Vec::new();
    for a in 0..3 {
        let mut t = vec![0.0; x.len()];
        for v in 0..nv {
            t[3 * v + a] = 1.0;
        }
        out.push(t);
    }
    for k in 0..3 {
        let mut e = Vec3::ZERO;
        e[k] = 1.0;
        let mut r = vec![0.0; x.len()];
        for v in 0..nv {
            let p = Vec3::new(x[3 * v] - c[0], x[3 * v + 1] - c[1], x[3 * v + 2] - c[2]);
            let w = e.cross(p);
            r[3 * v..3 * v + 3].copy_from_slice(&w.to_array());
        }
        out.push(r);
    }
    out
}

/// An orthonormal basis (modified Gram–Schmidt, twice) of the span of `vs`.
pub fn orthonormalize(vs: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::new();
    for v in vs {
        let mut w = v.clone();
        for _ in 0..2 {
            for q in &out {
                let d: f64 = w.iter().zip(q).map(|(a, b)| a * b).sum();
                w.iter_mut().zip(q).for_each(|(a, b)| *a -= d * b);
            }
        }
        let n = norm(&w);
        assert!(n > 1e-12 * norm(v), "vectors are independent");
        w.iter_mut().for_each(|a| *a /= n);
        out.push(w);
    }
    out
}

/// An open curve along x through the origin with a circular curl of radius `r` in the xz-plane
/// that starts and ends at the origin: the curve passes the origin twice (a self-crossing
/// joint, listed twice in its rod).
pub fn curl_curve(r: f64) -> Polyline {
    let mut pts: Vec<Vec3> = (0..20)
        .map(|i| Vec3::new(-500.0 + 25.0 * i as f64, 0.0, 0.0))
        .collect();
    let m = 24;
    for k in 0..=m {
        let t = std::f64::consts::TAU * k as f64 / m as f64;
        pts.push(Vec3::new(r * t.sin(), 0.0, r * (1.0 - t.cos())));
    }
    pts.extend((0..20).map(|i| Vec3::new(10.0 + 25.0 * i as f64, 0.0, 0.0)));
    polyline(pts, false)
}

/// `n` random open arches over the paraboloid height field `z = 350·(1 − (x² + y²)/1000²)`:
/// each arch lies above a random chord of the unit-1000 ground circle (ends on the ground,
/// z = 0, angular spread at least 90°). Every crossing of two chords (seen from above) is
/// inserted as an input point of both arches, so crossing arches share that point exactly.
/// A seeded, deterministic test input; pick `h` for the vertex count.
pub fn random_arches(seed: u64, n: usize) -> Vec<Polyline> {
    let samples = 24;
    let uniform: Vec<f64> = (0..=samples).map(|i| i as f64 / samples as f64).collect();
    arches_over_chords(
        seed,
        n,
        &ArchLayout {
            spread: (0.5, 1.5),
            samples: &uniform,
            crossings: (0.01, 0.99),
            merge: 1e-12,
        },
    )
}

/// How [`arches_over_chords`] lays its arches out.
pub struct ArchLayout<'a> {
    /// Angular spread of a chord's ends, in units of π (drawn uniformly in this range).
    pub spread: (f64, f64),
    /// Parameters along each chord (0 to 1) of its input points besides the crossings.
    pub samples: &'a [f64],
    /// Crossings are inserted when they lie in this parameter range on both chords.
    pub crossings: (f64, f64),
    /// Parameters closer than this are merged.
    pub merge: f64,
}

/// Arches over the paraboloid of [`random_arches`] above `n` random chords of the ground
/// circle, with the input points `layout` asks for and every crossing of two chords shared.
pub fn arches_over_chords(seed: u64, n: usize, layout: &ArchLayout<'_>) -> Vec<Polyline> {
    let mut rng = Rng::new(seed);
    let (r, height) = (1000.0, 350.0);
    let surface =
        |x: f64, y: f64| Vec3::new(x, y, (height * (1.0 - (x * x + y * y) / (r * r))).max(0.0));
    let chords: Vec<([f64; 2], [f64; 2])> = (0..n)
        .map(|_| {
            let a = rng.range(0.0, std::f64::consts::TAU);
            let b = a + rng.range(layout.spread.0, layout.spread.1) * std::f64::consts::PI;
            ([r * a.cos(), r * a.sin()], [r * b.cos(), r * b.sin()])
        })
        .collect();
    let mut params: Vec<Vec<f64>> = vec![layout.samples.to_vec(); n];
    let inside = |t: f64| (layout.crossings.0..=layout.crossings.1).contains(&t);
    for i in 0..n {
        for j in i + 1..n {
            let (p, q) = chords[i];
            let (s, t) = chords[j];
            let d1 = [q[0] - p[0], q[1] - p[1]];
            let d2 = [t[0] - s[0], t[1] - s[1]];
            let den = d1[0] * d2[1] - d1[1] * d2[0];
            if den.abs() < 1e-9 {
                continue;
            }
            let w = [s[0] - p[0], s[1] - p[1]];
            let a = (w[0] * d2[1] - w[1] * d2[0]) / den;
            let b = (w[0] * d1[1] - w[1] * d1[0]) / den;
            if inside(a) && inside(b) {
                params[i].push(a);
                params[j].push(b);
            }
        }
    }
    chords
        .iter()
        .zip(params)
        .map(|(&(p, q), mut ts)| {
            ts.sort_by(f64::total_cmp);
            ts.dedup_by(|a, b| (*a - *b).abs() < layout.merge);
            let pts = ts
                .iter()
                .map(|&t| surface(p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
                .collect();
            polyline(pts, false)
        })
        .collect()
}

/// The network made of the curves `keep` only (ascending ids), built by hand: vertices
/// renumbered in order, rest lengths and anchors kept, joints restricted to the kept curves.
/// Returns it with the old index of every new vertex.
pub fn sub_network(net: &Network, keep: &[usize]) -> (Network, Vec<usize>) {
    let mut new_of = vec![u32::MAX; net.vertex_count()];
    let mut used = vec![false; net.vertex_count()];
    for &c in keep {
        for &v in &net.rods[c].vertices {
            used[v as usize] = true;
        }
    }
    let mut old_of = Vec::new();
    for v in 0..net.vertex_count() {
        if used[v] {
            new_of[v] = old_of.len() as u32;
            old_of.push(v);
        }
    }
    let map = |vs: &[u32]| -> Vec<u32> { vs.iter().map(|&v| new_of[v as usize]).collect() };
    let rods = keep
        .iter()
        .map(|&c| {
            let r = &net.rods[c];
            Rod {
                vertices: map(&r.vertices),
                closed: r.closed,
                rest_lengths: r.rest_lengths.clone(),
                anchors: map(&r.anchors),
                ends: r.ends,
                frames: r.frames,
            }
        })
        .collect();
    let joints = net
        .joints
        .iter()
        .filter_map(|j| {
            let curves: Vec<u32> = j
                .curves
                .iter()
                .filter_map(|&c| keep.iter().position(|&k| k == c as usize))
                .map(|i| i as u32)
                .collect();
            // A self-crossing joint (one curve) stays with its curve.
            let keeps = curves.len() >= 2 || (curves.len() == 1 && j.curves.len() == 1);
            keeps.then(|| Joint {
                vertex: new_of[j.vertex as usize],
                curves,
            })
        })
        .collect();
    let positions = old_of.iter().map(|&v| net.positions[v]).collect();
    (
        Network {
            positions,
            rods,
            joints,
            supports: net.supports,
        },
        old_of,
    )
}

/// A plane arch drawn through `at(t)` (`t` from 0 to 1, finely: 12 drawn points per edge of
/// length `h`, `edges` edges), then `links` short straight bars along y, 2h long, starting at
/// evenly spaced drawn points of the arch (so each meets it there): the arch first.
pub fn arch_with_links(
    at: impl Fn(f64) -> Vec3,
    edges: usize,
    h: f64,
    links: usize,
) -> Vec<Polyline> {
    let drawn = 12 * edges;
    let mut curves = vec![polyline(
        (0..=drawn).map(|i| at(i as f64 / drawn as f64)).collect(),
        false,
    )];
    for k in 1..=links {
        let p = at((k * drawn / (links + 1)) as f64 / drawn as f64);
        curves.push(polyline(vec![p, p + Vec3::new(0.0, 2.0 * h, 0.0)], false));
    }
    curves
}

/// Each rod's rest shape as drawn: straight when drawn straight, pre-bent otherwise.
pub fn drawn_rest_shapes(net: &Network) -> Vec<curvenet::material::RestShape> {
    use curvenet::material::RestShape;
    (net.rods.iter())
        .map(|r| {
            if r.is_drawn_straight(&net.positions) {
                RestShape::Straight
            } else {
                RestShape::PreBent
            }
        })
        .collect()
}

/// The physical analysis (mm) of `net` as steel bars of radius 10 mm with rest shapes `rest`,
/// under the load cases of the loads file `loads`.
pub fn steel_bars_under(
    net: &Network,
    loads: &str,
    rest: Vec<curvenet::material::RestShape>,
) -> curvenet::physics::PhysicalReport {
    use curvenet::material::{Physical, Section, presets};
    use curvenet::physics::{PhysicalParams, analyze_physical, cases::Loads};
    let mut params = PhysicalParams::new(Physical::uniform(
        curvenet::units::LengthUnit::Millimetre,
        presets::preset("steel").unwrap(),
        Section::Solid { radius: 10.0 },
    ));
    params.rest = rest;
    params.loads = Some(Loads::parse(loads, "loads.json").expect("loads"));
    analyze_physical(net, &params, &ActiveSet::all(net.rods.len())).expect("analysis")
}

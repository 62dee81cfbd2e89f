//! A pre-bent circular arc clamped at both ends, in and out of its plane, against the
//! continuum (`docs/units.md`, *Pre-bent rods*).
//!
//! **The reference** is the frequency equation of the continuum arc (Euler–Bernoulli curved
//! beam of radius `R` and opening angle `α`; no rotary inertia of bending, as the lumped
//! mass has none), solved here independently of curvenet: its equations of motion have
//! constant coefficients, a first-order system `y' = K y` of six components, so the
//! transfer matrix along the arc is `exp(K α)`; the three solutions that meet the clamped
//! conditions at one end meet those at the other where a 3×3 determinant of it vanishes,
//! and its zeros in `ω` are the natural frequencies.
//! - in the plane (tangential `u`, radial `w`): strain `ε = u' + w/R`, section rotation
//!   `ψ = w' − u/R`, curvature change `χ = ψ' − ε/R = w'' − 2u'/R − w/R²` (the change of the
//!   centreline's curvature `1/ρ − 1/R`, per deformed length: what the discrete curvature
//!   binormal measures on stretched edges; the textbooks' other choices, `ψ'` or
//!   `w'' + w/R²`, differ by `E I / (E A R²)` relative, 1e-4 here, which curvenet's arcs
//!   converge away from and to this one), energy `½ E A ε² + ½ E I χ²` (extensible, as the
//!   rods are); clamped: `u = w = w' = 0`;
//! - out of the plane (out-of-plane `w`, twist `φ`, with the torsional inertia `ρ J`):
//!   bending `κ = w'' + φ/R`, twist `τ = φ' − w'/R`, energy `½ E I κ² + ½ G J τ²`; clamped:
//!   `w = w' = φ = 0`.
//!
//! The out-of-plane equations are checked against the classical closed form of a circular
//! arc on fork supports (`w = φ = κ = 0`; Timoshenko & Young, *Vibration problems in
//! engineering*; Blevins, *Formulas for natural frequency and mode shape*, the out-of-plane
//! circular arc): `ω² = E I / (ρ A R⁴) · k² (k² − 1)² / (k² + E I / G J)`, `k = nπ/α`, and both
//! planes against the straight clamped beam as the arc flattens.
//!
//! curvenet's modes of a planar arc split exactly into in-plane ones (the vertices' in-plane
//! coordinates) and out-of-plane ones (the out-of-plane coordinates and the twists), so each
//! first frequency is the lowest of its block (`EigenOptions::keep`).
//!
//! The convergence study (edges doubled four times):
//! `cargo test --release -p curvenet --test physical_arc -- --ignored --nocapture`.

use curvenet::geom::Vec3;
use curvenet::material::{Physical, RestShape, Section, presets};
use curvenet::rod::mass::{inverse_sqrt_with_twists, lumped_masses, scale_hessian, twist_masses};
use curvenet::rod::physical::{
    masses_per_length, physical_rods, rigid_anchor_weight, twist_masses_per_length,
};
use curvenet::rod::{ActiveSet, EnergyModel, ModelRules, Network, Rod, Supports};
use curvenet::solve::eigen::{EigenOptions, EigenParams, smallest_eigenpairs};
use curvenet::solve::{Backend, SymbolicFactor};
use curvenet::units::LengthUnit;
use std::f64::consts::PI;

/// `exp(a)` of a 6×6 matrix (scaling and squaring of a Taylor series).
fn expm(a: [[f64; 6]; 6]) -> [[f64; 6]; 6] {
    let norm = a
        .iter()
        .map(|r| r.iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0f64, f64::max);
    let squarings = (norm / 0.25).log2().ceil().max(0.0) as i32;
    let scale = 0.5f64.powi(squarings);
    let a: [[f64; 6]; 6] = a.map(|r| r.map(|x| x * scale));
    let mul = |x: &[[f64; 6]; 6], y: &[[f64; 6]; 6]| -> [[f64; 6]; 6] {
        std::array::from_fn(|i| std::array::from_fn(|j| (0..6).map(|k| x[i][k] * y[k][j]).sum()))
    };
    let mut out: [[f64; 6]; 6] =
        std::array::from_fn(|i| std::array::from_fn(|j| f64::from(u8::from(i == j))));
    let mut term = out;
    for k in 1..30 {
        term = mul(&term, &a).map(|r| r.map(|x| x / k as f64));
        for i in 0..6 {
            for j in 0..6 {
                out[i][j] += term[i][j];
            }
        }
    }
    for _ in 0..squarings {
        out = mul(&out, &out);
    }
    out
}

/// The determinant of a 3×3 matrix.
fn det3(m: [[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// The continuum arc: radius, opening angle and the section's constants (scene units).
#[derive(Clone, Copy, Debug)]
struct Arc {
    r: f64,
    alpha: f64,
    ei: f64,
    ea: f64,
    gj: f64,
    rho_a: f64,
    rho_j: f64,
}

/// Which family of modes, and the supports of the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Plane {
    In,
    Out,
    /// Out of the plane on fork supports (`w = φ = κ = 0`): the classical closed form's case.
    OutFork,
}

impl Arc {
    /// The equations of motion at `ω` as a first-order system `y' = K y` in the angle
    /// `s / R`, with lengths over `R` and forces and moments over `E I / R²`, `E I / R`:
    /// in the plane `y = (u, w, w', N, M, V)`, out of it `y = (w, w', φ, M, V, T)`.
    fn system(&self, plane: Plane, omega: f64) -> [[f64; 6]; 6] {
        let r2 = self.r * self.r;
        let big = self.rho_a * omega * omega * r2 * r2 / self.ei;
        let mut k = [[0.0; 6]; 6];
        match plane {
            Plane::In => {
                let eps = self.ei / (self.ea * r2);
                // u' = ε N − w; w' = θ; θ' = M + 2 ε N − w; N' = 2 V − Ω u; M' = V;
                // V' = Ω w − N + M.
                k[0][3] = eps;
                k[0][1] = -1.0;
                k[1][2] = 1.0;
                k[2][4] = 1.0;
                k[2][3] = 2.0 * eps;
                k[2][1] = -1.0;
                k[3][5] = 2.0;
                k[3][0] = -big;
                k[4][5] = 1.0;
                k[5][1] = big;
                k[5][3] = -1.0;
                k[5][4] = 1.0;
            }
            Plane::Out | Plane::OutFork => {
                let gamma = self.ei / self.gj;
                let q = self.rho_j * omega * omega * r2 / self.ei;
                // w' = β; β' = M − φ; φ' = γ T + β; M' = V; V' = Ω w − M + Q φ;
                // T' = M − Q φ.
                k[0][1] = 1.0;
                k[1][3] = 1.0;
                k[1][2] = -1.0;
                k[2][5] = gamma;
                k[2][1] = 1.0;
                k[3][4] = 1.0;
                k[4][0] = big;
                k[4][3] = -1.0;
                k[4][2] = q;
                k[5][3] = 1.0;
                k[5][2] = -q;
            }
        }
        k
    }

    /// The determinant of the conditions at the far end on the solutions that meet those
    /// at the near end: zero at a natural frequency.
    fn residual(&self, plane: Plane, omega: f64) -> f64 {
        let k = self.system(plane, omega).map(|r| r.map(|x| x * self.alpha));
        let e = expm(k);
        // Free components at the near end, held components at both ends.
        let (free, held): ([usize; 3], [usize; 3]) = match plane {
            Plane::In => ([3, 4, 5], [0, 1, 2]),
            Plane::Out => ([3, 4, 5], [0, 1, 2]),
            Plane::OutFork => ([1, 4, 5], [0, 2, 3]),
        };
        det3(std::array::from_fn(|i| {
            std::array::from_fn(|j| e[held[i]][free[j]])
        }))
    }

    /// The lowest natural frequency (Hz) below `f_max`: the first sign change of the
    /// residual on a grid, refined by bisection.
    fn first_frequency(&self, plane: Plane, f_max: f64) -> f64 {
        let steps = 2000;
        let w = |i: usize| 2.0 * PI * f_max * i as f64 / steps as f64;
        let mut prev = self.residual(plane, w(1));
        for i in 2..=steps {
            let cur = self.residual(plane, w(i));
            if prev.signum() != cur.signum() {
                let (mut a, mut b, fa) = (w(i - 1), w(i), prev);
                for _ in 0..200 {
                    let m = 0.5 * (a + b);
                    if self.residual(plane, m).signum() == fa.signum() {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                return 0.25 * (a + b) / PI;
            }
            prev = cur;
        }
        panic!("no root below {f_max} Hz")
    }
}

fn steel() -> Physical {
    Physical::uniform(
        LengthUnit::Millimetre,
        presets::preset("steel").unwrap(),
        Section::Solid { radius: 10.0 },
    )
}

fn continuum(r: f64, alpha: f64) -> Arc {
    let s = steel().scene_rod(0);
    Arc {
        r,
        alpha,
        ei: s.kb,
        ea: s.ks,
        gj: s.gj,
        rho_a: s.mass_per_length,
        rho_j: s.polar_mass_per_length,
    }
}

/// The arc of radius `r` and opening `alpha` in the xy-plane with `n` edges, clamped.
fn arc_network(r: f64, alpha: f64, n: usize) -> Network {
    let positions: Vec<Vec3> = (0..=n)
        .map(|i| {
            let t = alpha * i as f64 / n as f64;
            Vec3::new(r * t.cos(), r * t.sin(), 0.0)
        })
        .collect();
    let rest_lengths = positions.windows(2).map(|w| w[0].dist(w[1])).collect();
    Network {
        rods: vec![Rod {
            vertices: (0..=n as u32).collect(),
            closed: false,
            rest_lengths,
            anchors: Supports::Clamped
                .anchored_indices(n + 1)
                .into_iter()
                .map(|i| i as u32)
                .collect(),
            ends: None,
            frames: None,
        }],
        positions,
        joints: Vec::new(),
        supports: Supports::Clamped,
    }
}

/// curvenet's first in-plane and out-of-plane frequencies (Hz) of the pre-bent steel arc
/// with `n` edges, clamped at both ends, in the physical mode's model.
fn curvenet_arc(r: f64, alpha: f64, n: usize) -> (f64, f64) {
    let phys = steel();
    let net = arc_network(r, alpha, n);
    let rods = physical_rods(&phys, 1, &[RestShape::PreBent]);
    let m = EnergyModel::with_rules(
        &net,
        &rods,
        rigid_anchor_weight(&net, &rods),
        ModelRules::PHYSICAL,
    );
    let all = ActiveSet::all(1);
    let mut h = m.assemble(&vec![0.0; m.dofs()], &all, true).hess;
    let masses = lumped_masses(&net, &masses_per_length(&phys, 1), &all);
    let twists = twist_masses(&net, m.twist_dofs(), &twist_masses_per_length(&phys, 1));
    scale_hessian(
        m.pattern(),
        &mut h,
        &inverse_sqrt_with_twists(&masses, &twists),
    );
    let symbolic = SymbolicFactor::new(m.pattern(), Backend::default());
    let nv = 3 * net.vertex_count();
    let lowest = |in_plane: bool| {
        let keep: Vec<bool> = (0..m.dofs())
            .map(|i| (i < nv && i % 3 != 2) == in_plane)
            .collect();
        let s = smallest_eigenpairs(
            &symbolic,
            m.pattern(),
            &h,
            &EigenParams::default().with_count(2),
            EigenOptions {
                keep: Some(&keep),
                ..EigenOptions::default()
            },
        )
        .expect("spectrum")
        .expect("pairs")
        .spectrum;
        assert_eq!((s.zero_modes, s.negative_modes), (0, 0), "{s:?}");
        s.lambda().sqrt() / (2.0 * PI)
    };
    (lowest(true), lowest(false))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn the_reference_is_the_classical_arc_and_the_straight_beam() {
    // Fork supports, without torsional inertia: the closed form, modes n = 1 and 2.
    let mut arc = continuum(500.0, 0.5 * PI);
    arc.rho_j = 0.0;
    let closed = |n: f64| {
        let k = n * PI / arc.alpha;
        let w2 = arc.ei / (arc.rho_a * arc.r.powi(4)) * k * k * (k * k - 1.0).powi(2)
            / (k * k + arc.ei / arc.gj);
        w2.sqrt() / (2.0 * PI)
    };
    let f = arc.first_frequency(Plane::OutFork, 2.0 * closed(1.0));
    println!(
        "fork supports: {f:.6} Hz, closed form {:.6} Hz",
        closed(1.0)
    );
    assert!(rel(f, closed(1.0)) < 1e-6, "{f} vs {}", closed(1.0));
    // A nearly flat arc (a rise of 0.04 mm over 1 m), in and out of its plane: the clamped
    // beam, 4.730²/(2π L²) √(EI/ρA).
    let len = 1000.0;
    let flat = continuum(len / 3e-4, 3e-4);
    let beam = 4.730_040_7f64.powi(2) / (2.0 * PI * len * len) * (flat.ei / flat.rho_a).sqrt();
    for plane in [Plane::In, Plane::Out] {
        let f = flat.first_frequency(plane, 2.0 * beam);
        println!("flat arc {plane:?}: {f:.5} Hz, beam {beam:.5} Hz");
        assert!(rel(f, beam) < 1e-4, "{plane:?}: {f} vs {beam}");
    }
}

/// The arcs of the fast test and the study: steel semicircle of radius 500 mm and quarter
/// circle of radius 1 m.
const SEMICIRCLE: (f64, f64) = (500.0, PI);
const QUARTER: (f64, f64) = (1000.0, 0.5 * PI);

/// The continuum's first in-plane and out-of-plane frequencies of an arc (Hz).
fn continuum_first(arc: (f64, f64)) -> (f64, f64) {
    let c = continuum(arc.0, arc.1);
    (
        c.first_frequency(Plane::In, 400.0),
        c.first_frequency(Plane::Out, 400.0),
    )
}

#[test]
fn clamped_pre_bent_arcs_match_the_continuum_at_second_order() {
    // Within 0.5 % at 64 edges, in and out of the plane.
    for (name, arc) in [("semicircle", SEMICIRCLE), ("quarter circle", QUARTER)] {
        let (f_in, f_out) = continuum_first(arc);
        let (c_in, c_out) = curvenet_arc(arc.0, arc.1, 64);
        println!(
            "{name}, 64 edges: in-plane {c_in:.4} Hz (continuum {f_in:.4}, {:.2e}), \
             out-of-plane {c_out:.4} Hz (continuum {f_out:.4}, {:.2e})",
            rel(c_in, f_in),
            rel(c_out, f_out)
        );
        assert!(rel(c_in, f_in) < 5e-3 && rel(c_out, f_out) < 5e-3, "{name}");
    }
    // Second order: the quarter circle's errors at 16 and 32 edges shrink about fourfold
    // (the semicircle's out-of-plane error is already 5e-4 at 16 edges, below its
    // asymptotic range).
    let (f_in, f_out) = continuum_first(QUARTER);
    let (a_in, a_out) = curvenet_arc(QUARTER.0, QUARTER.1, 16);
    let (b_in, b_out) = curvenet_arc(QUARTER.0, QUARTER.1, 32);
    let order = |a: f64, b: f64, f: f64| (rel(a, f) / rel(b, f)).log2();
    let (o_in, o_out) = (order(a_in, b_in, f_in), order(a_out, b_out, f_out));
    println!("quarter circle, orders 16 → 32 edges: in-plane {o_in:.2}, out-of-plane {o_out:.2}");
    assert!(o_in >= 1.8 && o_out >= 1.8, "{o_in}, {o_out}");
}

#[test]
#[ignore = "a study: prints the table of docs/units.md"]
fn convergence_study_of_clamped_pre_bent_arcs() {
    for (name, (r, alpha)) in [("semicircle", SEMICIRCLE), ("quarter circle", QUARTER)] {
        let arc = continuum(r, alpha);
        let (f_in, f_out) = (
            arc.first_frequency(Plane::In, 400.0),
            arc.first_frequency(Plane::Out, 400.0),
        );
        println!(
            "{name} (R = {r} mm, α = {:.1}°): continuum in-plane {f_in:.5} Hz, out-of-plane \
             {f_out:.5} Hz\n| edges | in-plane (Hz) | error | order | out-of-plane (Hz) | error | order |\n|---|---|---|---|---|---|---|",
            alpha.to_degrees()
        );
        let mut last: Option<(f64, f64)> = None;
        for n in [16usize, 32, 64, 128, 256] {
            let (c_in, c_out) = curvenet_arc(r, alpha, n);
            let (e_in, e_out) = (c_in / f_in - 1.0, c_out / f_out - 1.0);
            let (o_in, o_out) = last.map_or((String::new(), String::new()), |(a, b)| {
                (
                    format!("{:.2}", (a / e_in).abs().log2()),
                    format!("{:.2}", (b / e_out).abs().log2()),
                )
            });
            println!(
                "| {n} | {c_in:.4} | {e_in:+.2e} | {o_in} | {c_out:.4} | {e_out:+.2e} | {o_out} |"
            );
            last = Some((e_in, e_out));
        }
    }
}

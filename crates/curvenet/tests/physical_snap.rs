//! A shallow circular arch snaps through: one pre-bent steel rod (radius 10 mm) over a span of
//! 1000 mm with a rise of 20 mm, pinned at both ends, held in its plane by short links along y
//! whose far ends are guided (y fixed, tangent held: each link translates with the arch in its
//! plane and holds it out of it, with no stiffness in the plane), a point load down on its
//! crown. Its critical load factor is a limit point; the reference is the converged factor of
//! the same model: the edge length halved until two halvings agree to the factor's own
//! tolerance (`physics::loaded::FACTOR_TOLERANCE`, 0.1%), which bounds what an extrapolation
//! could add (`shallow_arch_snap_through_converges`, ignored in the default suite, prints the
//! table docs/units.md gives).

mod common;

use common::{arch_with_links, drawn_rest_shapes, rel_diff, steel_bars_under};
use curvenet::geom::Vec3;
use curvenet::material::{EndSupport, RestShape};
use curvenet::network::{BuildParams, Network, build_network};
use curvenet::physics::PhysicalReport;
use curvenet::rod::Supports;

/// Half the span, mm.
const HALF_SPAN: f64 = 500.0;
/// The rise, mm.
const RISE: f64 = 20.0;
/// Guided links holding the arch in its plane.
const LINKS: usize = 7;
/// The converged snap-through load, N: 128 and 256 edges agree to the factor's tolerance
/// (`shallow_arch_snap_through_converges`).
const CONVERGED: f64 = 3252.0;

/// The arch with `edges` edges (a multiple of `LINKS + 1`, so every link meets a vertex) in
/// the x–z plane, crown at x = 0, its rest shapes.
fn arch(edges: usize) -> (Network, Vec<RestShape>) {
    let radius = (HALF_SPAN * HALF_SPAN + RISE * RISE) / (2.0 * RISE);
    let half = (HALF_SPAN / radius).asin();
    let at = |t: f64| {
        let a = -half + 2.0 * half * t;
        Vec3::new(radius * a.sin(), 0.0, radius * a.cos() - (radius - RISE))
    };
    let h = 2.0 * half * radius / edges as f64;
    let curves = arch_with_links(at, edges, h, LINKS);
    // A link's end on the arch is a joint, not a support; its far end a guide along y.
    let guide = EndSupport {
        fixed: [false, true, false],
        rotation_held: true,
        ..EndSupport::FREE
    };
    let mut ends = vec![[None, None]];
    ends.extend((0..LINKS).map(|_| [Some(EndSupport::FREE), Some(guide)]));
    let params = BuildParams {
        edge_length: h,
        supports: Supports::Pinned,
        ends,
        ..BuildParams::default()
    };
    let net = build_network(&curves, &params).expect("the arch builds").0;
    let rest = drawn_rest_shapes(&net);
    (net, rest)
}

/// The load on the crown, N: the critical load factor times it is the snap-through load (the
/// load steps go up to a factor of 100).
const LOAD: f64 = 50.0;

/// The arch's analysis under `LOAD` down on its crown.
fn snap(edges: usize) -> PhysicalReport {
    let (net, rest) = arch(edges);
    let loads = format!(
        r#"{{"cases": [{{"name": "P", "points": [{{"at": [0, 0, {RISE}], "force": [0, 0, -{LOAD}]}}]}}]}}"#
    );
    steel_bars_under(&net, &loads, rest)
}

#[test]
fn a_shallow_arch_snaps_through_at_a_limit_point() {
    let r = snap(64);
    assert!(r.stable, "the unloaded arch stands");
    let c = &r.load_cases[0];
    let got = LOAD * c.buckling_factor.expect("the arch snaps");
    println!(
        "shallow arch, 64 edges: P_cr {got:.3} N (converged {CONVERGED} N, {:+.3}%), {:?}, \
         linearised {:?}",
        100.0 * (got / CONVERGED - 1.0),
        c.buckling,
        c.linear_buckling_factor
    );
    assert_eq!(c.buckling.as_deref(), Some("limit point"));
    assert!(rel_diff(got, CONVERGED) < 0.01, "{got} vs {CONVERGED}");
}

#[test]
#[ignore = "a convergence study (several seconds in release): cargo test --release --test physical_snap -- --ignored --nocapture"]
fn shallow_arch_snap_through_converges() {
    let mut rows = Vec::new();
    for edges in [16, 32, 64, 128, 256] {
        let r = snap(edges);
        let c = &r.load_cases[0];
        let p = LOAD * c.buckling_factor.expect("snaps");
        println!(
            "{edges} edges: P_cr {p:.4} N, {:?}, linearised {:?}",
            c.buckling, c.linear_buckling_factor
        );
        assert_eq!(c.buckling.as_deref(), Some("limit point"));
        rows.push(p);
    }
    // Converged: the last two halvings agree to the factor's tolerance.
    let last = rows[rows.len() - 1];
    let tol = curvenet::physics::loaded::FACTOR_TOLERANCE;
    assert!(
        rel_diff(rows[rows.len() - 2], last) <= 2.0 * tol,
        "{rows:?}"
    );
    for (p, edges) in rows.iter().zip([16, 32, 64, 128, 256]) {
        println!("| {edges} | {p:.1} | {:+.3}% |", 100.0 * (p / last - 1.0));
    }
    assert!(rel_diff(last, CONVERGED) <= 2.0 * tol, "{last}");
}

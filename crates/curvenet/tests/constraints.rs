//! Design constraints on the paper's tower and on curve files: the tower's rotational symmetry
//! (32 curves and the top ring: a rotation of order 32 about its axis, and its mirrors) found
//! on the tower and on moved copies of it, `auto` choosing the largest symmetry the budget
//! allows, and groups read from a JSON curve file.

mod common;

use common::data_dir;
use curvenet::constraints::groups::groups_of_tags;
use curvenet::constraints::symmetry::{self, DEFAULT_TOLERANCE};
use curvenet::constraints::{ConstraintParams, Constraints, Symmetry, SymmetryOption};
use curvenet::geom::Vec3;
use curvenet::io::{self, Polyline};
use curvenet::network::{Network, build_network};
use curvenet::rod::Supports;

/// The tower's curves and build parameters, or `None` without the data.
fn tower() -> Option<(Vec<Polyline>, curvenet::network::BuildParams)> {
    let data = data_dir()?;
    let ex = curvenet::paper::load("tower", &data, Supports::Clamped).expect("tower loads");
    Some((ex.curves, ex.build))
}

/// `curves` rotated about the unit `axis` through the origin by `angle`, then shifted.
fn moved(curves: &[Polyline], axis: Vec3, angle: f64, shift: Vec3) -> Vec<Polyline> {
    let a = axis.normalized();
    let (c, s) = (angle.cos(), angle.sin());
    curves
        .iter()
        .map(|pl| Polyline {
            points: pl
                .points
                .iter()
                .map(|&p| p * c + a.cross(p) * s + a * (a.dot(p) * (1.0 - c)) + shift)
                .collect(),
            ..pl.clone()
        })
        .collect()
}

fn orbit_sizes(net: &Network, option: SymmetryOption) -> (Vec<Vec<usize>>, Symmetry) {
    let f = symmetry::find(net, option, DEFAULT_TOLERANCE).expect("found");
    (f[0].orbits.clone(), f[0].symmetry.clone())
}

#[test]
fn the_tower_has_a_rotation_of_order_32_and_mirrors() {
    let Some((curves, build)) = tower() else {
        return;
    };
    let (net, _) = build_network(&curves, &build).expect("builds");
    let (orbits, sym) = orbit_sizes(&net, SymmetryOption::Rotate(32));
    // The ring alone; each of the two spiral families (every curve maps onto itself under a
    // half turn) an orbit of 16.
    let mut sizes: Vec<usize> = orbits.iter().map(Vec::len).collect();
    sizes.sort_unstable();
    assert_eq!(sizes, vec![1, 16, 16], "{orbits:?}");
    assert_eq!(orbits[0], vec![0], "the ring is curve 0");
    let Symmetry::Rotation { axis, .. } = sym else {
        panic!("a rotation");
    };
    assert!(
        axis[2].abs() > 1.0 - 1e-6,
        "the tower's axis is z: {axis:?}"
    );
    // No rotation of order 64; a rotation of order 8 pairs each curve with three others.
    assert!(symmetry::find(&net, SymmetryOption::Rotate(64), DEFAULT_TOLERANCE).is_err());
    let (o8, _) = orbit_sizes(&net, SymmetryOption::Rotate(8));
    assert_eq!(o8.len(), 1 + 8, "{o8:?}");
    // A mirror swaps the two families: orbits of one or two curves, 16 pairs.
    let (om, _) = orbit_sizes(&net, SymmetryOption::Mirror);
    assert!(om.iter().all(|o| o.len() <= 2), "{om:?}");
    assert!(om.iter().filter(|o| o.len() == 2).count() >= 15, "{om:?}");
    // Auto: order 32 is the largest; at the example's budget (0.2) with the ring kept, the
    // largest whose orbits fit is order 8 (ring + 4 curves).
    let total: f64 = net.rest_lengths().iter().sum();
    let p = ConstraintParams {
        symmetry: SymmetryOption::Auto,
        ..Default::default()
    };
    let c = Constraints::new(&net, None, &p, 0.2 * total, &[0]).expect("feasible");
    let f = c.symmetry().expect("a symmetry");
    assert_eq!(f.group_order(), 8, "{:?}", c.notes());
    assert!(
        c.notes()
            .iter()
            .any(|n| n.to_string().contains("rotate:32")),
        "{:?}",
        c.notes()
    );
}

#[test]
fn moved_copies_of_the_tower_keep_its_orbits() {
    let Some((curves, build)) = tower() else {
        return;
    };
    let (net, _) = build_network(&curves, &build).expect("builds");
    let (base, _) = orbit_sizes(&net, SymmetryOption::Rotate(32));
    for (axis, angle) in [
        (Vec3::new(1.0, 0.0, 0.0), 1.1),
        (Vec3::new(0.2, 0.9, -0.4), 2.7),
    ] {
        let copy = moved(&curves, axis, angle, Vec3::new(-3000.0, 250.0, 1e4));
        let (net, _) = build_network(&copy, &build).expect("builds");
        let (orbits, _) = orbit_sizes(&net, SymmetryOption::Rotate(32));
        assert_eq!(orbits, base, "axis {axis:?}, angle {angle}");
    }
}

#[test]
fn groups_come_from_a_json_curve_file() {
    let dir = std::env::temp_dir().join(format!("curvenet-groups-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("c.json");
    // Three parallel lines crossed by two: the crossing pair is one group.
    let line = |a: [f64; 3], b: [f64; 3]| {
        let pts: Vec<String> = (0..=10)
            .map(|i| {
                let t = i as f64 / 10.0;
                format!(
                    "[{}, {}, {}]",
                    a[0] + t * (b[0] - a[0]),
                    a[1] + t * (b[1] - a[1]),
                    a[2] + t * (b[2] - a[2])
                )
            })
            .collect();
        pts.join(", ")
    };
    let text = format!(
        "{{\"format\": \"curvenet-curves\", \"version\": 1, \"curves\": [\n\
         {{\"points\": [{}]}},\n\
         {{\"points\": [{}]}},\n\
         {{\"points\": [{}]}},\n\
         {{\"group\": \"cross\", \"points\": [{}]}},\n\
         {{\"group\": \"cross\", \"points\": [{}]}}\n]}}\n",
        line([0.0, 0.0, 0.0], [100.0, 0.0, 0.0]),
        line([0.0, 50.0, 0.0], [100.0, 50.0, 0.0]),
        line([0.0, 100.0, 0.0], [100.0, 100.0, 0.0]),
        line([25.0, -10.0, 0.0], [25.0, 110.0, 0.0]),
        line([75.0, -10.0, 0.0], [75.0, 110.0, 0.0]),
    );
    std::fs::write(&path, text).expect("written");
    let f = io::read_curves(&path).expect("reads");
    let origins: Vec<String> = f.curves.iter().map(|c| c.origin.to_string()).collect();
    let groups = groups_of_tags(&f.groups, &origins);
    assert_eq!(groups.len(), 1);
    assert_eq!(groups[0].curves, vec![3, 4]);
    assert!(
        groups[0].origin.ends_with("c.json:5"),
        "{}",
        groups[0].origin
    );
    let (net, _) = build_network(
        &f.curves,
        &curvenet::network::BuildParams {
            edge_length: 5.0,
            ..Default::default()
        },
    )
    .expect("builds");
    let total: f64 = net.rest_lengths().iter().sum();
    let p = ConstraintParams {
        groups,
        ..Default::default()
    };
    let c = Constraints::new(&net, None, &p, total, &[]).expect("feasible");
    assert_eq!(c.units(), &[vec![0], vec![1], vec![2], vec![3, 4]]);
    assert!(c.check(&[0, 3]).is_err());
    assert!(c.check(&[0, 3, 4]).is_ok());
    let _ = std::fs::remove_dir_all(&dir);
}

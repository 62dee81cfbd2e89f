use super::*;
use crate::constraints::testing::{moved, network, pavilion};

fn rotation_of(found: &SymmetryFound) -> (u32, Vec3) {
    match found.symmetry {
        Symmetry::Rotation { order, axis, .. } => (order, Vec3::from(axis)),
        Symmetry::Mirror { .. } => panic!("a mirror, not a rotation"),
    }
}

#[test]
fn options_parse_and_print() {
    for s in ["none", "mirror", "auto", "rotate:4", "ROTATE:12"] {
        let o: SymmetryOption = s.parse().expect("parses");
        assert_eq!(o.to_string(), s.to_ascii_lowercase());
    }
    for bad in ["rotate", "rotate:1", "rotate:x", "spin:3", ""] {
        assert!(bad.parse::<SymmetryOption>().is_err(), "{bad}");
    }
    let e = "rotate:1".parse::<SymmetryOption>().unwrap_err();
    assert!(e.contains("at least 2"), "{e}");
}

#[test]
fn a_pavilion_has_its_rotation_and_its_orbits() {
    let net = network(&pavilion(6, true, 0.3));
    let found = find(&net, SymmetryOption::Rotate(6), DEFAULT_TOLERANCE).expect("order 6");
    let (order, axis) = rotation_of(&found[0]);
    assert_eq!(order, 6);
    assert!(axis.z.abs() > 1.0 - 1e-9, "axis {axis:?}");
    assert_eq!(
        found[0].orbits,
        vec![vec![0], (1..=6).collect(), (7..=12).collect()]
    );
    // Order 3 divides 6: orbits of three curves.
    let f3 = find(&net, SymmetryOption::Rotate(3), DEFAULT_TOLERANCE).expect("order 3");
    assert_eq!(
        f3[0].orbits,
        vec![
            vec![0],
            vec![1, 3, 5],
            vec![2, 4, 6],
            vec![7, 9, 11],
            vec![8, 10, 12]
        ]
    );
    // Not order 4 nor 12.
    for n in [4, 12] {
        let e = find(&net, SymmetryOption::Rotate(n), DEFAULT_TOLERANCE)
            .expect_err("absent")
            .0;
        assert!(e.contains(&format!("no rotation of order {n}")), "{e}");
        assert!(e.contains("tolerance"), "{e}");
    }
}

#[test]
fn auto_lists_every_order_then_the_mirror() {
    let net = network(&pavilion(4, true, 0.0));
    let all = find(&net, SymmetryOption::Auto, DEFAULT_TOLERANCE).expect("auto");
    let orders: Vec<u32> = all.iter().map(SymmetryFound::group_order).collect();
    assert_eq!(orders, vec![4, 2, 2], "{all:#?}");
    assert!(matches!(all[2].symmetry, Symmetry::Mirror { .. }));
    // The mirror pairs curves: every orbit has one or two curves, and the ring is alone.
    assert!(all[2].orbits.iter().all(|o| o.len() <= 2));
    assert!(all[2].orbits.contains(&vec![0]));
    assert!(all[0].describe().contains("rotation of order 4"));
}

#[test]
fn rigid_copies_keep_the_symmetry_and_the_orbits() {
    let curves = pavilion(5, true, 0.2);
    let base = find(
        &network(&curves),
        SymmetryOption::Rotate(5),
        DEFAULT_TOLERANCE,
    )
    .expect("order 5")[0]
        .clone();
    let axis = Vec3::new(0.3, -0.5, 0.8).normalized();
    for (angle, mirror) in [(0.7, false), (2.1, true), (-1.3, false)] {
        let shift = Vec3::new(1234.5, -777.0, 42.0);
        let copy = moved(&curves, axis, angle, shift, mirror);
        let net = network(&copy);
        let found = find(&net, SymmetryOption::Rotate(5), DEFAULT_TOLERANCE).expect("order 5");
        assert_eq!(
            found[0].orbits, base.orbits,
            "angle {angle}, mirror {mirror}"
        );
        // The axis is the pavilion's z axis, moved.
        let (_, a) = rotation_of(&found[0]);
        let expected = moved(
            &[crate::constraints::testing::polyline(
                vec![Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)],
                false,
            )],
            axis,
            angle,
            Vec3::ZERO,
            mirror,
        );
        let e = expected[0].points[1] - expected[0].points[0];
        assert!(a.dot(e).abs() > 1.0 - 1e-6, "axis {a:?}, expected ±{e:?}");
        let m = find(&net, SymmetryOption::Mirror, DEFAULT_TOLERANCE).expect("a mirror");
        assert!(m[0].orbits.iter().all(|o| o.len() <= 2));
    }
}

#[test]
fn a_moved_arch_breaks_the_symmetry() {
    let mut curves = pavilion(6, false, 0.0);
    // Arch 3 leaves its place by 2° (about 35 units at the ground, 1.5% of the scene).
    let spin = moved(
        &curves[3..4],
        Vec3::new(0.0, 0.0, 1.0),
        2f64.to_radians(),
        Vec3::ZERO,
        false,
    );
    curves[3] = spin[0].clone();
    let net = network(&curves);
    let e = find(&net, SymmetryOption::Rotate(6), DEFAULT_TOLERANCE)
        .expect_err("broken")
        .0;
    assert!(e.contains("no rotation of order 6"), "{e}");
    // A loose tolerance accepts it again.
    assert!(find(&net, SymmetryOption::Rotate(6), 0.05).is_ok());
    // Order 2 (arches 1↔4, 2↔5, 3↔6) is broken too, through arch 3.
    assert!(find(&net, SymmetryOption::Rotate(2), DEFAULT_TOLERANCE).is_err());
    // Auto finds nothing it may use on the arches: only rotations that fix the ring and the
    // moved arch... none here, so at most the mirror through arch 3's opposite pair.
    let all = find(&net, SymmetryOption::Auto, DEFAULT_TOLERANCE).expect("auto runs");
    assert!(all.iter().all(|f| f.group_order() <= 2), "{all:#?}");
}

#[test]
fn none_finds_nothing_and_costs_nothing() {
    let net = network(&pavilion(3, false, 0.0));
    assert!(
        find(&net, SymmetryOption::None, DEFAULT_TOLERANCE)
            .expect("ok")
            .is_empty()
    );
}

/// Twelve curves with no symmetry at all: chords of a disc at scattered angles and offsets.
fn scattered() -> Vec<crate::io::Polyline> {
    use crate::io::{Origin, Polyline};
    let mut rng = crate::rng::SplitMix64::new(7);
    (0..12)
        .map(|k| {
            let a = std::f64::consts::TAU * rng.next_f64();
            let off = 800.0 * (rng.next_f64() - 0.5);
            let (c, s) = (a.cos(), a.sin());
            let points = (0..=40)
                .map(|i| {
                    let t = -1000.0 + 50.0 * i as f64;
                    Vec3::new(t * c - off * s, t * s + off * c, 0.1 * t * (k as f64 + 1.0))
                })
                .collect();
            Polyline {
                points,
                closed: false,
                origin: Origin::new("<scattered>", k + 1),
                label: None,
            }
        })
        .collect()
}

#[test]
fn a_small_rotation_of_a_huge_order_is_no_symmetry() {
    let net = network(&scattered());
    // Its orders beyond what twelve open curves can carry are refused outright.
    let e = find(&net, SymmetryOption::Rotate(100_000), DEFAULT_TOLERANCE)
        .expect_err("refused")
        .0;
    assert!(e.contains("rotation of order 24 at most"), "{e}");
    // An order they could carry is tested in full: each curve lands far from every curve
    // under a power of the rotation, and the message says how far (beyond the tolerance).
    let e = find(&net, SymmetryOption::Rotate(24), DEFAULT_TOLERANCE)
        .expect_err("absent")
        .0;
    let away: f64 = e
        .split(" away")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|d| d.parse().ok())
        .unwrap_or_else(|| panic!("a distance: {e}"));
    let tol: f64 = e
        .split("scene's size, ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|d| d.parse().ok())
        .unwrap_or_else(|| panic!("a tolerance: {e}"));
    assert!(away > tol, "{e}");
    // Auto finds nothing either.
    assert!(
        find(&net, SymmetryOption::Auto, DEFAULT_TOLERANCE)
            .unwrap()
            .is_empty()
    );
}

#[test]
fn refusals_name_a_distance_beyond_the_tolerance() {
    // A pavilion of 6 arches has no rotation of order 5: the reason is a real miss.
    let net = network(&pavilion(6, true, 0.3));
    let e = find(&net, SymmetryOption::Rotate(5), DEFAULT_TOLERANCE)
        .expect_err("absent")
        .0;
    let away: f64 = e
        .split(" away")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|d| d.parse().ok())
        .unwrap_or_else(|| panic!("a distance: {e}"));
    assert!(away > 1.0, "{e}");
}

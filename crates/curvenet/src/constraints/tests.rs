//! The constraints against brute force on small networks.

use super::testing::{grid, network, pavilion, square_mesh};
use super::*;

/// Every non-empty subset of `n` curves.
fn all_subsets(n: usize) -> Vec<Vec<usize>> {
    (1u32..(1 << n))
        .map(|m| (0..n).filter(|i| m & (1 << i) != 0).collect())
        .collect()
}

/// The brute-force verdict: each constraint tested on its own definition.
fn brute_ok(net: &Network, c: &Constraints, s: &[usize], mesh: Option<&TriMesh>) -> bool {
    let p = c.params();
    let length: f64 = s.iter().map(|&i| net.rods[i].rest_length()).sum();
    if s.is_empty() || length > c.budget() * (1.0 + 1e-12) {
        return false;
    }
    if !c.keep().iter().all(|k| s.contains(k)) {
        return false;
    }
    let whole = |g: &[usize]| g.iter().all(|x| s.contains(x)) || g.iter().all(|x| !s.contains(x));
    if !p.groups.iter().all(|g| whole(&g.curves)) {
        return false;
    }
    if let Some(f) = c.symmetry()
        && !f.orbits.iter().all(|o| whole(o))
    {
        return false;
    }
    if p.min_curves.is_some_and(|k| s.len() < k) {
        return false;
    }
    if p.connected {
        let links = net.vertex_curves();
        let parts = crate::network::subnet::curve_components(
            net.rods.len(),
            s,
            links.iter().map(|cs| cs.iter().map(|&x| x as usize)),
        );
        if parts.len() != 1 {
            return false;
        }
    }
    if let (Some(d), Some(_)) = (p.max_gap, mesh) {
        let g = c.coverage.as_ref().expect("coverage").gap(s);
        if g.value > d {
            return false;
        }
    }
    true
}

/// Checks `check`, the enumeration, the draws, the moves and the greedy's candidates against
/// brute force.
fn against_brute_force(net: &Network, c: &Constraints, mesh: Option<&TriMesh>) {
    let n = net.rods.len();
    let subsets = all_subsets(n);
    let feasible: Vec<Vec<usize>> = subsets
        .iter()
        .filter(|s| brute_ok(net, c, s, mesh))
        .cloned()
        .collect();
    for s in &subsets {
        assert_eq!(
            c.check(s).is_ok(),
            feasible.contains(s),
            "{s:?}: {:?}",
            c.check(s)
        );
        assert_eq!(c.margins(s, None).all_met(), feasible.contains(s), "{s:?}");
    }
    let mut listed = c.feasible_subsets(1 << 20).expect("small");
    listed.sort();
    let mut expected = feasible.clone();
    expected.sort();
    assert_eq!(listed, expected, "enumeration");
    let (drawn, _, exhausted) = c.draw_subsets(feasible.len() + 5, 7);
    assert!(exhausted);
    let mut d = drawn.clone();
    d.sort();
    assert_eq!(d, expected, "the draws reach every feasible set once");
    for s in feasible.iter().take(40) {
        // Moves: every feasible set one unit away, and only those.
        let moves = c.neighbours(s, true, true, None);
        for (_, t) in &moves {
            assert!(feasible.contains(t), "{s:?} → {t:?}");
        }
        let units_of = |x: &[usize]| {
            let mut u: Vec<usize> = x.iter().map(|&i| c.unit_of(i)).collect();
            u.sort_unstable();
            u.dedup();
            u
        };
        let su = units_of(s);
        for t in &feasible {
            let tu = units_of(t);
            let gone = su.iter().filter(|u| !tu.contains(u)).count();
            let new = tu.iter().filter(|u| !su.contains(u)).count();
            let one_move = (gone, new) == (1, 0) || (gone, new) == (0, 1) || (gone, new) == (1, 1);
            assert_eq!(moves.iter().any(|(_, x)| x == t), one_move, "{s:?} → {t:?}");
        }
    }
    // The greedy's candidates from the whole network.
    let all: Vec<usize> = (0..n).collect();
    for u in c.removal_candidates(&all) {
        let rest: Vec<usize> = all.iter().copied().filter(|&x| c.unit_of(x) != u).collect();
        assert!(!rest.is_empty());
        assert!(c.check_shape(&CurveSet::from_curves(n, &rest)).is_ok());
    }
}

#[test]
fn groups_and_symmetry_match_brute_force() {
    let curves = pavilion(4, true, 0.1);
    let net = network(&curves);
    let total: f64 = net.rest_lengths().iter().sum();
    let groups = parse_groups("a: 1 2\nb: 5 8\n", "g.txt").expect("groups");
    let params = ConstraintParams {
        groups,
        ..Default::default()
    };
    let c = Constraints::new(&net, None, &params, 0.5 * total, &[]).expect("feasible");
    assert_eq!(c.units().len(), 7);
    against_brute_force(&net, &c, None);
    let sym = ConstraintParams {
        symmetry: SymmetryOption::Rotate(2),
        ..Default::default()
    };
    let c = Constraints::new(&net, None, &sym, 0.5 * total, &[0]).expect("feasible");
    assert_eq!(
        c.units(),
        &[vec![0], vec![1, 3], vec![2, 4], vec![5, 7], vec![6, 8]]
    );
    assert!(
        c.notes()[0].to_string().contains("rotation of order 2"),
        "{:?}",
        c.notes()
    );
    against_brute_force(&net, &c, None);
}

#[test]
fn connected_and_min_curves_match_brute_force() {
    // Two pavilions side by side: separate structures.
    let mut curves = pavilion(3, false, 0.0);
    let far = super::testing::moved(
        &pavilion(3, false, 0.5),
        Vec3::new(0.0, 0.0, 1.0),
        0.0,
        Vec3::new(5000.0, 0.0, 0.0),
        false,
    );
    curves.extend(far);
    let net = network(&curves);
    let total: f64 = net.rest_lengths().iter().sum();
    let params = ConstraintParams {
        connected: true,
        min_curves: Some(2),
        ..Default::default()
    };
    let c = Constraints::new(&net, None, &params, 0.45 * total, &[]).expect("feasible");
    against_brute_force(&net, &c, None);
    // Keep-list curves in the two pavilions: no connected network holds both.
    let e = Constraints::new(&net, None, &params, total, &[1, 5]).expect_err("apart");
    assert!(matches!(e, ConstraintError::Infeasible(_)));
    assert!(e.to_string().contains("separate parts"), "{e}");
}

use crate::geom::Vec3;

#[test]
fn max_gap_matches_brute_force() {
    let net = network(&grid(300.0, 3));
    let mesh = square_mesh(300.0, 0.0, 6);
    let total: f64 = net.rest_lengths().iter().sum();
    let params = ConstraintParams {
        max_gap: Some(150.0),
        ..Default::default()
    };
    let c = Constraints::new(&net, Some(&mesh), &params, 0.7 * total, &[]).expect("feasible");
    against_brute_force(&net, &c, Some(&mesh));
    let m = c.margins(&[0, 1, 2, 3, 4, 5], None);
    let gap = m.max_gap.expect("asked for");
    assert!(gap.met && gap.value <= 150.0 && gap.resolution.is_some());
}

#[test]
fn infeasible_combinations_are_refused_with_the_reason() {
    let curves = pavilion(4, true, 0.1);
    let net = network(&curves);
    let lengths = net.rest_lengths();
    let total: f64 = lengths.iter().sum();
    let refuse = |params: &ConstraintParams,
                  budget: f64,
                  keep: &[usize],
                  mesh: Option<&TriMesh>,
                  phrase: &str| {
        let e = Constraints::new(&net, mesh, params, budget, keep).expect_err(phrase);
        assert!(e.to_string().contains(phrase), "`{e}` lacks `{phrase}`");
    };
    // The keep list fits, its group does not.
    let groups = parse_groups("1 2 3 4\n", "g.txt").expect("groups");
    let p = ConstraintParams {
        groups,
        ..Default::default()
    };
    refuse(
        &p,
        lengths[1] * 1.5,
        &[1],
        None,
        "with the groups holding its curves",
    );
    // Every group too long, no keep list.
    let p = ConstraintParams {
        symmetry: SymmetryOption::Rotate(4),
        ..Default::default()
    };
    refuse(
        &p,
        0.5 * lengths[0].min(lengths[1]),
        &[],
        None,
        "every group is longer",
    );
    // More curves than the budget holds.
    let p = ConstraintParams {
        min_curves: Some(6),
        ..Default::default()
    };
    refuse(&p, 0.2 * total, &[], None, "at most");
    refuse(
        &ConstraintParams {
            min_curves: Some(10),
            ..Default::default()
        },
        total,
        &[],
        None,
        "only 9 curves",
    );
    // A gap no curve closes; a surface without curves nearby.
    let mesh = square_mesh(3000.0, 0.0, 6);
    let p = ConstraintParams {
        max_gap: Some(100.0),
        ..Default::default()
    };
    refuse(&p, total, &[], Some(&mesh), "even with every curve kept");
    refuse(&p, total, &[], None, "give the mesh");
    // A symmetry that is not there.
    let p = ConstraintParams {
        symmetry: SymmetryOption::Rotate(3),
        ..Default::default()
    };
    let e = Constraints::new(&net, None, &p, total, &[]).expect_err("absent");
    assert!(matches!(e, ConstraintError::Usage(_)));
    // Bad values.
    for p in [
        ConstraintParams {
            min_curves: Some(0),
            ..Default::default()
        },
        ConstraintParams {
            max_deviation: Some(-1.0),
            ..Default::default()
        },
        ConstraintParams {
            groups: parse_groups("0 99\n", "g.txt").expect("parses"),
            ..Default::default()
        },
    ] {
        let e = Constraints::new(&net, None, &p, total, &[]).expect_err("bad");
        assert!(matches!(e, ConstraintError::Usage(_)), "{e}");
    }
}

#[test]
fn auto_takes_the_largest_symmetry_the_budget_allows() {
    let net = network(&pavilion(4, true, 0.0));
    let lengths = net.rest_lengths();
    let total: f64 = lengths.iter().sum();
    let p = ConstraintParams {
        symmetry: SymmetryOption::Auto,
        ..Default::default()
    };
    // A large budget: the rotation of order 4.
    let c = Constraints::new(&net, None, &p, total, &[0]).expect("feasible");
    assert_eq!(c.symmetry().map(SymmetryFound::group_order), Some(4));
    // Room for the ring and two short arches only: order 4 (orbits of four) is refused.
    let budget = lengths[0] + 2.0 * lengths[5] * 1.01;
    let c = Constraints::new(&net, None, &p, budget, &[0]).expect("feasible");
    assert_eq!(c.symmetry().map(SymmetryFound::group_order), Some(2));
    assert!(
        c.notes().iter().any(|n| n.to_string().contains("refused")),
        "{:?}",
        c.notes()
    );
    // Not even two: no symmetry, said so.
    let c = Constraints::new(&net, None, &p, lengths[0] * 1.01, &[0]).expect("feasible");
    assert!(c.symmetry().is_none());
    assert!(
        c.notes()
            .iter()
            .any(|n| n.to_string().contains("none is used")),
        "{:?}",
        c.notes()
    );
}

#[test]
fn without_constraints_units_are_curves() {
    let net = network(&pavilion(3, false, 0.0));
    let total: f64 = net.rest_lengths().iter().sum();
    let c = Constraints::none(&net, 0.6 * total, &[0]);
    assert!(!c.is_active());
    assert!(c.units().iter().enumerate().all(|(u, s)| s == &vec![u]));
    against_brute_force(&net, &c, None);
}

#[test]
fn the_largest_displacement_is_over_the_structure() {
    let net = network(&pavilion(3, false, 0.0));
    let mut u = vec![0.0; net.dofs()];
    let v = net.rods[2].vertices[3] as usize;
    u[3 * v..3 * v + 3].copy_from_slice(&[3.0, 4.0, 0.0]);
    assert_eq!(max_displacement(&net, &[2], &u), 5.0);
    assert_eq!(max_displacement(&net, &[1], &u), 0.0);
    let p = ConstraintParams {
        max_deviation: Some(4.0),
        ..Default::default()
    };
    let c = Constraints::new(&net, None, &p, 1e9, &[]).expect("feasible");
    let m = c.margins(&[2], Some(5.0));
    assert!(!m.all_met() && !m.max_deviation.expect("given").met);
    assert!(!c.deviation_ok(5.0) && c.deviation_ok(4.0));
}

#[test]
fn empty_and_overlapping_groups_are_refused_wherever_they_come_from() {
    let group = |name: &str, curves: &[usize]| Group {
        name: name.into(),
        curves: curves.to_vec(),
        origin: format!("groups[{name}]"),
    };
    let with = |groups: Vec<Group>| ConstraintParams {
        groups,
        ..ConstraintParams::default()
    };
    assert!(
        with(vec![group("a", &[0, 1]), group("b", &[2])])
            .validate()
            .is_ok()
    );
    let e = with(vec![group("a", &[0, 1]), group("b", &[1, 2])])
        .validate()
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("curve 1 is in two groups") && e.contains("groups[a]"),
        "{e}"
    );
    let e = with(vec![group("a", &[])])
        .validate()
        .unwrap_err()
        .to_string();
    assert!(e.contains("names no curve"), "{e}");
}

//! What differs between a recorded run and the one asked to resume it, in a user's words
//! (options named by [`Opt`]): `budget was 0.3, now 0.4`, `the curves' content differs from
//! the run's (…)`.
//!
//! Inputs are compared by content, never by the paths as typed: the same file given by another
//! path resumes the run (which keeps its recorded description). The options come first (the
//! physical mode's, then the others in the set-up's order); then the mesh (against `mesh.obj`)
//! and the network the inputs build (against `network.json`, naming the first curve that
//! differs); then anything else of the set-up, named by its place in `result.json`.

use super::RunFolderError;
use super::schema::RunSetup;
use crate::io::TriMesh;
use crate::network::Network;
use crate::words::{Message, Opt, given, message};
use serde_json::Value;
use std::path::Path;

/// What a place of the set-up is named by: an option, or something a user gives otherwise.
#[derive(Clone, Copy)]
enum Named {
    /// An option.
    Opt(Opt),
    /// The paper's example asked for.
    Example,
    /// The groups: the groups file and the curve files' `"group"`.
    Groups,
}

impl Named {
    fn message(self) -> Message {
        match self {
            Named::Opt(o) => message![o],
            Named::Example => message!["the example"],
            Named::Groups => message!["the groups (", Opt::Groups, ", the curve files' \"group\")"],
        }
    }
}

/// Places in `result.json`'s set-up, what a user sets them with, and what an absent value
/// reads as (the option's default). The physical mode's options come first: in that mode
/// the radius and Young's modulus describe the physical rods (`physical.radius`), and the
/// paper's model keeps its defaults, so a resume without the units is named as such, not as
/// a change of the radius.
const OPTIONS: &[(&str, Named, &str)] = &[
    ("input.example", Named::Example, NOT_GIVEN),
    ("physical.units", Named::Opt(Opt::Units), NOT_GIVEN),
    ("physical.material", Named::Opt(Opt::Material), NOT_GIVEN),
    ("physical.young", Named::Opt(Opt::Young), NOT_GIVEN),
    ("physical.density", Named::Opt(Opt::Density), NOT_GIVEN),
    ("physical.strength", Named::Opt(Opt::Strength), NOT_GIVEN),
    ("physical.radius", Named::Opt(Opt::Radius), NOT_GIVEN),
    ("physical.tube", Named::Opt(Opt::Tube), NOT_GIVEN),
    ("physical.load", Named::Opt(Opt::Load), NOT_GIVEN),
    ("physical.gravity", Named::Opt(Opt::Gravity), NOT_GIVEN),
    ("physical_model.loads", Named::Opt(Opt::Loads), NOT_GIVEN),
    ("stability.objective", Named::Opt(Opt::Objective), "lambda"),
    ("input.scale", Named::Opt(Opt::Scale), NOT_GIVEN),
    ("build.edge_length", Named::Opt(Opt::EdgeLength), NOT_GIVEN),
    ("build.supports", Named::Opt(Opt::Supports), NOT_GIVEN),
    ("build.ends", Named::Opt(Opt::SupportsFile), NOT_GIVEN),
    ("build.end_frames", Named::Opt(Opt::Mesh), NOT_GIVEN),
    (
        "build.merge_joints_below",
        Named::Opt(Opt::MergeJoints),
        NOT_GIVEN,
    ),
    (
        "stability.material.radius",
        Named::Opt(Opt::Radius),
        NOT_GIVEN,
    ),
    (
        "stability.material.young",
        Named::Opt(Opt::Young),
        NOT_GIVEN,
    ),
    (
        "stability.material.anchor_weight",
        Named::Opt(Opt::AnchorWeight),
        NOT_GIVEN,
    ),
    (
        "stability.eigen.count",
        Named::Opt(Opt::EigenCount),
        NOT_GIVEN,
    ),
    ("greedy.keep", Named::Opt(Opt::Keep), NOT_GIVEN),
    ("constraints.groups", Named::Groups, "none"),
    ("constraints.symmetry", Named::Opt(Opt::Symmetry), NOT_GIVEN),
    (
        "constraints.connected",
        Named::Opt(Opt::Connected),
        NOT_GIVEN,
    ),
    (
        "constraints.min_curves",
        Named::Opt(Opt::MinCurves),
        NOT_GIVEN,
    ),
    ("constraints.max_gap", Named::Opt(Opt::MaxGap), NOT_GIVEN),
    (
        "constraints.max_deviation",
        Named::Opt(Opt::MaxDeviation),
        NOT_GIVEN,
    ),
];

/// How an option not given reads.
const NOT_GIVEN: &str = "not given";

/// A value as a user reads it: numbers and words bare, `absent` for an option not given.
fn show(v: Option<&Value>, absent: &str) -> String {
    match v {
        None | Some(Value::Null) => absent.into(),
        Some(Value::String(s)) => s.clone(),
        Some(v) => v.to_string(),
    }
}

/// The value at a dotted `path` of `v`.
fn at<'a>(v: &'a Value, path: &str) -> Option<&'a Value> {
    path.split('.').try_fold(v, |v, k| v.get(k))
}

/// The first place (dotted path) where `a` and `b` differ, objects descended key by key (in
/// `a`'s order, then `b`'s new keys), anything else compared whole.
fn first_difference(a: Option<&Value>, b: Option<&Value>, path: &str) -> Option<String> {
    match (a, b) {
        (Some(Value::Object(x)), Some(Value::Object(y))) => x
            .keys()
            .chain(y.keys().filter(|k| !x.contains_key(*k)))
            .find_map(|k| {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                first_difference(x.get(k), y.get(k), &p)
            }),
        (a, b) if a == b => None,
        _ => Some(path.to_string()),
    }
}

/// The budget in words: the budget as a fraction (`0.3`) or as a length (`500`).
fn budget_words(v: Option<&Value>) -> (Option<Opt>, String) {
    match v.and_then(Value::as_object).and_then(|o| o.iter().next()) {
        Some((k, x)) if k == "fraction" => (Some(Opt::Budget), show(Some(x), NOT_GIVEN)),
        Some((k, x)) if k == "length" => (Some(Opt::BudgetLength), show(Some(x), NOT_GIVEN)),
        _ => (None, show(v, NOT_GIVEN)),
    }
}

/// The budgets' difference, when they differ.
fn budget_difference(old: &Value, new: &Value) -> Option<Message> {
    let (a, b) = (at(old, "greedy.budget"), at(new, "greedy.budget"));
    if a == b {
        return None;
    }
    let ((oa, va), (ob, vb)) = (budget_words(a), budget_words(b));
    Some(match (oa, ob) {
        (Some(x), Some(y)) if x == y => message![x, format!(" was {va}, now {vb}")],
        (Some(x), Some(y)) => message!["the budget was ", given(x, va), ", now ", given(y, vb)],
        _ => message![format!("the budget was {va}, now {vb}")],
    })
}

/// The first option whose value differs between `old` and `new` (the set-ups as JSON).
fn option_difference(old: &Value, new: &Value) -> Option<Message> {
    let found = OPTIONS
        .iter()
        .position(|(path, _, _)| first_difference(at(old, path), at(new, path), path).is_some());
    // The budget belongs after the material options and before the keep list.
    let budget_at = OPTIONS
        .iter()
        .position(|(p, _, _)| *p == "greedy.keep")
        .unwrap_or(OPTIONS.len());
    if found.is_none_or(|i| i >= budget_at)
        && let Some(d) = budget_difference(old, new)
    {
        return Some(d);
    }
    let (path, name, absent) = OPTIONS[found?];
    Some(
        name.message().then([format!(
            " was {}, now {}",
            show(at(old, path), absent),
            show(at(new, path), absent)
        )
        .into()]),
    )
}

/// Whether an input was given (`mesh`), in words, for a run and its resume.
fn presence_difference(old: &Value, new: &Value, key: &str, option: Opt) -> Option<Message> {
    let given = |v: &Value| at(v, key).is_some_and(|x| !x.is_null());
    let (a, b) = (given(old), given(new));
    (a != b).then(|| {
        let word = |g| if g { "given" } else { "not given" };
        message![option, format!(" was {}, now {}", word(a), word(b))]
    })
}

/// The set-up with its design constraints spelled out: a run without any records none, and
/// comparing that absence with a run's constraints would name the first field (the groups)
/// rather than the constraint that changed.
fn with_constraints(mut v: Value) -> Value {
    if let Some(o) = v.as_object_mut()
        && !o.contains_key("constraints")
        && let Ok(d) = serde_json::to_value(crate::constraints::ConstraintParams::default())
    {
        o.insert("constraints".into(), d);
    }
    v
}

/// The set-up without what depends on how the inputs were named rather than on their content:
/// the paths as typed, and the build's messages (which quote them).
fn without_paths(mut v: Value) -> Value {
    if let Some(input) = v.get_mut("input").and_then(Value::as_object_mut) {
        input.remove("mesh");
        input.remove("curve_files");
    }
    if let Some(net) = v.get_mut("network").and_then(Value::as_object_mut) {
        net.remove("warnings");
    }
    v
}

/// How the mesh given now differs from the run's `mesh.obj` (the surface as the run wrote it,
/// in scene units): `None` when it is the same, or when either is missing (whether a mesh was
/// given at all is compared with the options).
fn mesh_difference(dir: &Path, mesh: Option<&TriMesh>) -> Option<Message> {
    let stored = std::fs::read_to_string(dir.join("mesh.obj")).ok()?;
    let now = crate::io::mesh_to_obj(mesh?);
    if stored == now {
        return None;
    }
    let count = |t: &str, p: &str| t.lines().filter(|l| l.starts_with(p)).count();
    let counts = |t: &str| (count(t, "v "), count(t, "f "));
    let ((v0, f0), (v1, f1)) = (counts(&stored), counts(&now));
    let what = |detail: String| message![Opt::Mesh, "'s content differs from the run's", detail];
    if (v0, f0) != (v1, f1) {
        return Some(what(format!(
            ": {v1} vertices and {f1} triangles, the run's {v0} and {f0}"
        )));
    }
    let (mut v, mut f) = (0, 0);
    for (a, b) in stored.lines().zip(now.lines()) {
        if a != b {
            if a.starts_with("v ") {
                return Some(what(format!(": its vertex {v} moved")));
            }
            if a.starts_with("f ") {
                return Some(what(format!(": its triangle {f} differs")));
            }
            break;
        }
        v += usize::from(a.starts_with("v "));
        f += usize::from(a.starts_with("f "));
    }
    Some(what(String::new()))
}

/// The first curve whose rod differs between two networks: its vertices' rest positions, its
/// edges' rest lengths, closed or open, its anchors (compared by position along the rod, so a
/// change of one curve does not name every later one).
fn first_differing_curve(old: &Network, new: &Network) -> Option<usize> {
    (0..old.rods.len().min(new.rods.len())).find(|&c| {
        let (a, b) = (&old.rods[c], &new.rods[c]);
        let points = |n: &Network, vs: &[u32]| {
            vs.iter()
                .map(|&v| n.positions[v as usize].to_array())
                .collect::<Vec<_>>()
        };
        a.closed != b.closed
            || a.rest_lengths != b.rest_lengths
            || points(old, &a.vertices) != points(new, &b.vertices)
            || points(old, &a.anchors) != points(new, &b.anchors)
    })
}

/// How the network the inputs build now (`built`, as `network.json` would hold it) differs
/// from the run's `network.json` (`stored`), in words: the first curve that differs, else the
/// counts. Both are read back alike, so equal numbers compare equal.
fn network_difference(
    stored: &[u8],
    built: &[u8],
    recorded: &RunSetup,
    setup: &RunSetup,
) -> String {
    let what = if recorded.input.example.is_some() {
        "the example's curve files differ"
    } else {
        "the curves files' content differs"
    };
    let mut names = String::new();
    if recorded.input.curve_files != setup.input.curve_files {
        names = format!(
            "; the run read {}, now {}",
            recorded.input.curve_files.join(", "),
            setup.input.curve_files.join(", ")
        );
    }
    let read = |b: &[u8]| serde_json::from_slice::<Network>(b).ok();
    let first = read(stored)
        .zip(read(built))
        .and_then(|(old, new)| first_differing_curve(&old, &new));
    let (n0, n1) = (recorded.network.curves, setup.network.curves);
    match first {
        Some(c) => format!(
            "{what} from the run's: curve {c} is not the one recorded in network.json (its \
             points, lengths or supports differ){names}"
        ),
        None if n0 != n1 => format!(
            "{what} from the run's: the run had {n0} curves, now {n1} (the first {} are the \
             same){names}",
            n0.min(n1)
        ),
        None => format!(
            "{what} from the run's (the network they build now, {n1} curves and {} vertices, \
             is not the one recorded in network.json, {n0} curves and {} vertices{names})",
            setup.network.vertices, recorded.network.vertices
        ),
    }
}

/// What differs between the run recorded in `dir` (its `setup`, `mesh.obj` and
/// `network.json`) and the one asked for (`setup`, with `mesh`, building `network`), first
/// difference first; `None` when the run can be resumed.
///
/// # Errors
///
/// `network.json` missing or unreadable.
pub fn resume_difference(
    dir: &Path,
    recorded: &RunSetup,
    setup: &RunSetup,
    mesh: Option<&TriMesh>,
    network: &Network,
) -> Result<Option<Message>, RunFolderError> {
    let to_value = |s: &RunSetup| serde_json::to_value(s).map_err(|e| e.to_string());
    let (old, new) = (
        with_constraints(to_value(recorded)?),
        with_constraints(to_value(setup)?),
    );
    if let Some(d) = presence_difference(&old, &new, "input.mesh", Opt::Mesh)
        .or_else(|| option_difference(&old, &new))
        .or_else(|| mesh_difference(dir, mesh))
    {
        return Ok(Some(d));
    }
    let path = dir.join("network.json");
    let stored = std::fs::read(&path).map_err(|e| RunFolderError::io(&path, e))?;
    let built = serde_json::to_vec(network).map_err(|e| e.to_string())?;
    if stored != built {
        return Ok(Some(
            network_difference(&stored, &built, recorded, setup).into(),
        ));
    }
    let (old, new) = (without_paths(old), without_paths(new));
    Ok(first_difference(Some(&old), Some(&new), "").map(|p| {
        Message::from(format!(
            "the set-up's {p} was {}, now {}",
            show(at(&old, &p), "none"),
            show(at(&new, &p), "none")
        ))
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A difference as the command line words it.
    fn flags(m: Option<Message>) -> Option<String> {
        m.map(|m| m.render(&crate::words::Recorded))
    }

    #[test]
    fn a_constraint_added_or_dropped_is_named() {
        let none = json!({"greedy": {"budget": {"fraction": 0.3}, "keep": []}});
        let default = serde_json::to_value(crate::constraints::ConstraintParams::default())
            .expect("serialises");
        for (field, value, said) in [
            ("connected", json!(true), "--connected was false, now true"),
            ("min_curves", json!(3), "--min-curves was not given, now 3"),
            (
                "symmetry",
                json!("mirror"),
                "--symmetry was none, now mirror",
            ),
            (
                "max_gap",
                json!(900.0),
                "--max-gap was not given, now 900.0",
            ),
            (
                "max_deviation",
                json!(2.0),
                "--max-deviation was not given, now 2.0",
            ),
        ] {
            let mut with = none.clone();
            with["constraints"] = default.clone();
            with["constraints"][field] = value;
            let (a, b) = (with_constraints(none.clone()), with_constraints(with));
            assert_eq!(flags(option_difference(&a, &b)).as_deref(), Some(said));
            // And dropping it again.
            let back = said
                .split(" was ")
                .next()
                .map(|o| format!("{o} was {}", said.rsplit(", now ").next().unwrap()));
            let got = flags(option_difference(&b, &a)).unwrap();
            assert!(got.starts_with(back.as_deref().unwrap()), "{got}");
        }
    }

    #[test]
    fn differences_are_named_as_a_user_sets_them() {
        let a = json!({"greedy": {"budget": {"fraction": 0.3}, "keep": [1]},
                       "build": {"edge_length": 100.0}, "stability": {"tuning": {"prune": true}}});
        let mut b = a.clone();
        b["greedy"]["budget"] = json!({"fraction": 0.4});
        assert_eq!(
            flags(option_difference(&a, &b)).as_deref(),
            Some("--budget was 0.3, now 0.4")
        );
        b["greedy"]["budget"] = json!({"length": 500.0});
        assert_eq!(
            flags(option_difference(&a, &b)).as_deref(),
            Some("the budget was --budget 0.3, now --budget-length 500.0")
        );
        b["build"]["edge_length"] = json!(50.0);
        assert_eq!(
            flags(option_difference(&a, &b)).as_deref(),
            Some("--edge-length was 100.0, now 50.0"),
            "the first difference first"
        );
        let mut d = a.clone();
        d["greedy"]["keep"] = json!([1, 2]);
        assert_eq!(
            flags(option_difference(&a, &d)).as_deref(),
            Some("--keep was [1], now [1,2]")
        );
        assert_eq!(option_difference(&a, &a), None);
        assert_eq!(
            first_difference(Some(&a), Some(&d), "").as_deref(),
            Some("greedy.keep")
        );
        // The objective in a user's words, the paper's by default.
        let mut f = a.clone();
        f["stability"]["objective"] = json!("frequency");
        assert_eq!(
            flags(option_difference(&a, &f)).as_deref(),
            Some("--objective was lambda, now frequency")
        );
        // The physical mode's options before the paper's radius they leave at its default.
        let mut mm = a.clone();
        mm["physical"] = json!({"units": "mm", "radius": "0.01"});
        mm["stability"]["material"] = json!({"radius": 2.0});
        let mut paper = a.clone();
        paper["stability"]["material"] = json!({"radius": 0.01});
        assert_eq!(
            flags(option_difference(&mm, &paper)).as_deref(),
            Some("--units was mm, now not given")
        );
        let mut m = mm.clone();
        m["physical"]["units"] = json!("m");
        assert_eq!(
            flags(option_difference(&mm, &m)).as_deref(),
            Some("--units was mm, now m")
        );
        m["physical"]["units"] = json!("mm");
        m["physical"]["density"] = json!("1000kg/m3");
        assert_eq!(
            flags(option_difference(&mm, &m)).as_deref(),
            Some("--density was not given, now 1000kg/m3")
        );
        // Every option named is one a user sets.
        assert!(
            OPTIONS
                .iter()
                .all(|(_, name, _)| !name.message().to_string().is_empty())
        );
    }

    #[test]
    fn networks_name_their_first_differing_curve() {
        use crate::network::checks::tests::polyline;
        use crate::network::{BuildParams, build_network};
        let line = |y: f64| polyline(&[[-2.0, y, 0.0], [0.0, y, 0.0], [2.0, y, 0.0]]);
        let cross = |x: f64| polyline(&[[x, -2.0, 0.0], [x, 0.0, 0.0], [x, 2.0, 0.0]]);
        let params = BuildParams {
            edge_length: 0.5,
            ..BuildParams::default()
        };
        let build = |curves: &[crate::io::Polyline]| build_network(curves, &params).expect("net").0;
        let a = build(&[line(-1.0), line(1.0), cross(-1.0), cross(1.0)]);
        // Curve 3 runs further past its crossings: the others keep their joints.
        let longer = polyline(&[[1.0, -2.0, 0.0], [1.0, 0.0, 0.0], [1.0, 2.5, 0.0]]);
        let b = build(&[line(-1.0), line(1.0), cross(-1.0), longer]);
        assert_eq!(first_differing_curve(&a, &a), None);
        assert_eq!(first_differing_curve(&a, &b), Some(3));
        let c = build(&[line(-1.0), line(1.0), cross(-1.0)]);
        assert_eq!(first_differing_curve(&a, &c), None);
    }
}

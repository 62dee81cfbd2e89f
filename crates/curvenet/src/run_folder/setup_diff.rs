//! What differs between a recorded run and the one asked to resume it, in a user's words:
//! `--budget was 0.3, now 0.4`, `the curves' content differs from the run's (…)`.
//!
//! Inputs are compared by content, never by the paths as typed: the same file given by another
//! path resumes the run (which keeps its recorded description). The options come first, in the
//! set-up's order; then the network the inputs build (against `network.json`); then anything
//! else of the set-up, named by its place in `result.json`.

use super::schema::RunSetup;
use crate::network::Network;
use serde_json::Value;
use std::path::Path;

/// Places in `result.json`'s set-up and the option a user sets them with.
const OPTIONS: &[(&str, &str)] = &[
    ("input.example", "the example"),
    ("input.scale", "--scale"),
    ("build.edge_length", "--edge-length"),
    ("build.supports", "--supports"),
    ("build.merge_joints_below", "--merge-joints"),
    ("stability.material.radius", "--radius"),
    ("stability.material.young", "--young"),
    ("stability.material.anchor_weight", "--anchor-weight"),
    ("stability.eigen.count", "--eigen-count"),
    ("stability.tuning.prune", "--no-prune"),
    ("greedy.keep", "--keep"),
    (
        "constraints.groups",
        "the groups (--groups, the curve files' \"group\")",
    ),
    ("constraints.symmetry", "--symmetry"),
    ("constraints.connected", "--connected"),
    ("constraints.min_curves", "--min-curves"),
    ("constraints.max_gap", "--max-gap"),
    ("constraints.max_deviation", "--max-deviation"),
];

/// A value as a user reads it: numbers and words bare, `none` for an option not given.
fn show(v: Option<&Value>) -> String {
    match v {
        None | Some(Value::Null) => "none".into(),
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

/// The budget in words: `--budget 0.3` or `--budget-length 500`.
fn budget_words(v: Option<&Value>) -> (Option<&'static str>, String) {
    match v.and_then(Value::as_object).and_then(|o| o.iter().next()) {
        Some((k, x)) if k == "fraction" => (Some("--budget"), show(Some(x))),
        Some((k, x)) if k == "length" => (Some("--budget-length"), show(Some(x))),
        _ => (None, show(v)),
    }
}

/// The budgets' difference, when they differ.
fn budget_difference(old: &Value, new: &Value) -> Option<String> {
    let (a, b) = (at(old, "greedy.budget"), at(new, "greedy.budget"));
    if a == b {
        return None;
    }
    let ((oa, va), (ob, vb)) = (budget_words(a), budget_words(b));
    Some(match (oa, ob) {
        (Some(x), Some(y)) if x == y => format!("{x} was {va}, now {vb}"),
        (Some(x), Some(y)) => format!("the budget was {x} {va}, now {y} {vb}"),
        _ => format!("the budget was {va}, now {vb}"),
    })
}

/// The first option whose value differs between `old` and `new` (the set-ups as JSON).
fn option_difference(old: &Value, new: &Value) -> Option<String> {
    let mut found = None;
    for (i, (path, name)) in OPTIONS.iter().enumerate() {
        if first_difference(at(old, path), at(new, path), path).is_some() {
            found = Some((i, *path, *name));
            break;
        }
    }
    // The budget belongs after the material options and before the keep list.
    let budget_at = OPTIONS
        .iter()
        .position(|(p, _)| *p == "greedy.keep")
        .unwrap_or(OPTIONS.len());
    if found.is_none_or(|(i, _, _)| i >= budget_at)
        && let Some(d) = budget_difference(old, new)
    {
        return Some(d);
    }
    let (_, path, name) = found?;
    let (a, b) = (at(old, path), at(new, path));
    Some(if path == "stability.tuning.prune" {
        let given = |v: Option<&Value>| v == Some(&Value::Bool(false));
        format!(
            "{name} was {}, now {}",
            if given(a) { "given" } else { "not given" },
            if given(b) { "given" } else { "not given" }
        )
    } else {
        format!("{name} was {}, now {}", show(a), show(b))
    })
}

/// Whether an input was given (`mesh`), in words, for a run and its resume.
fn presence_difference(old: &Value, new: &Value, key: &str, option: &str) -> Option<String> {
    let given = |v: &Value| at(v, key).is_some_and(|x| !x.is_null());
    let (a, b) = (given(old), given(new));
    (a != b).then(|| {
        let word = |g| if g { "given" } else { "not given" };
        format!("{option} was {}, now {}", word(a), word(b))
    })
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

/// What differs between the run recorded in `dir` (its `setup` and `network.json`) and the
/// one asked for (`setup`, building `network`), first difference first; `None` when the run
/// can be resumed.
///
/// # Errors
///
/// `network.json` missing or unreadable.
pub fn resume_difference(
    dir: &Path,
    recorded: &RunSetup,
    setup: &RunSetup,
    network: &Network,
) -> Result<Option<String>, String> {
    let to_value = |s: &RunSetup| serde_json::to_value(s).map_err(|e| e.to_string());
    let (old, new) = (to_value(recorded)?, to_value(setup)?);
    if let Some(d) = presence_difference(&old, &new, "input.mesh", "--mesh")
        .or_else(|| option_difference(&old, &new))
    {
        return Ok(Some(d));
    }
    let path = dir.join("network.json");
    let stored = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let built = serde_json::to_vec(network).map_err(|e| e.to_string())?;
    if stored != built {
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
        return Ok(Some(format!(
            "{what} from the run's (the network they build now, {} curves and {} vertices, is \
             not the one recorded in network.json, {} curves and {} vertices{names})",
            setup.network.curves,
            setup.network.vertices,
            recorded.network.curves,
            recorded.network.vertices
        )));
    }
    let (old, new) = (without_paths(old), without_paths(new));
    Ok(first_difference(Some(&old), Some(&new), "").map(|p| {
        format!(
            "the set-up's {p} was {}, now {}",
            show(at(&old, &p)),
            show(at(&new, &p))
        )
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn differences_are_named_as_a_user_sets_them() {
        let a = json!({"greedy": {"budget": {"fraction": 0.3}, "keep": [1]},
                       "build": {"edge_length": 100.0}, "stability": {"tuning": {"prune": true}}});
        let mut b = a.clone();
        b["greedy"]["budget"] = json!({"fraction": 0.4});
        assert_eq!(
            option_difference(&a, &b).as_deref(),
            Some("--budget was 0.3, now 0.4")
        );
        b["greedy"]["budget"] = json!({"length": 500.0});
        assert_eq!(
            option_difference(&a, &b).as_deref(),
            Some("the budget was --budget 0.3, now --budget-length 500.0")
        );
        b["build"]["edge_length"] = json!(50.0);
        assert_eq!(
            option_difference(&a, &b).as_deref(),
            Some("--edge-length was 100.0, now 50.0"),
            "the first difference first"
        );
        let mut c = a.clone();
        c["stability"]["tuning"]["prune"] = json!(false);
        assert_eq!(
            option_difference(&a, &c).as_deref(),
            Some("--no-prune was not given, now given")
        );
        let mut d = a.clone();
        d["greedy"]["keep"] = json!([1, 2]);
        assert_eq!(
            option_difference(&a, &d).as_deref(),
            Some("--keep was [1], now [1,2]")
        );
        assert_eq!(option_difference(&a, &a), None);
        assert_eq!(
            first_difference(Some(&a), Some(&d), "").as_deref(),
            Some("greedy.keep")
        );
    }
}

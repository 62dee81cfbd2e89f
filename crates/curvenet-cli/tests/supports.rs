//! Supports per curve end on the command line: a column held by a curve file's own supports
//! and by a supports file buckles where Euler says, each end's support is listed in `--json`'s
//! network, and a supports file naming no curve end is refused with exit 2, its file, line and
//! how far the nearest end is.

mod common;

use common::{BIN, TempDir};
use std::process::{Command, Output};

/// A 1 m steel column along x (radius 10 mm), its ends held as `supports` says (a JSON value
/// or nothing).
fn column(supports: Option<&str>) -> String {
    let points: Vec<String> = (0..=50).map(|i| format!("[{}, 0, 0]", 20 * i)).collect();
    let own = supports.map_or(String::new(), |s| format!(", \"supports\": {s}"));
    format!(
        r#"{{"format": "curvenet-curves", "version": 1, "units": "mm",
  "curves": [{{"points": [{}]{own}}}]}}"#,
        points.join(", ")
    )
}

const LOADS: &str =
    r#"{"cases": [{"name": "P", "points": [{"at": [1000, 0, 0], "force": [-1000, 0, 0]}]}]}"#;

fn analyze(dir: &TempDir, extra: &[&str]) -> Output {
    let mut args = vec![
        "analyze",
        "--curves",
        "column.json",
        "--material",
        "steel",
        "--radius",
        "10",
        "--edge-length",
        "20",
        "--loads",
        "loads.json",
        "--json",
    ];
    args.extend_from_slice(extra);
    Command::new(BIN)
        .args(&args)
        .current_dir(&dir.0)
        .output()
        .expect("runs")
}

fn buckling_factor(out: &Output) -> f64 {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    report["physical"]["load_cases"][0]["buckling_factor"]
        .as_f64()
        .expect("a buckling factor")
}

#[test]
fn a_column_held_per_end_buckles_where_euler_says() {
    let dir = TempDir::new("supports");
    dir.write("loads.json", LOADS);
    // E I / L² of the column, in kN: the load is 1 kN.
    let ei_l2 = 210e3 * std::f64::consts::PI * 1e4 / 4.0 / 1e6 / 1000.0;
    let euler = |k: f64| std::f64::consts::PI.powi(2) * ei_l2 / (k * k);
    // Clamped at the start, free at the end, from the curve file.
    dir.write(
        "column.json",
        column(Some(r#"{"start": "clamped", "end": "free"}"#)),
    );
    let got = buckling_factor(&analyze(&dir, &[]));
    assert!(
        (got / euler(2.0) - 1.0).abs() < 0.01,
        "{got} vs {}",
        euler(2.0)
    );
    // The same column held by a supports file instead: by point and by curve end.
    dir.write("column.json", column(None));
    dir.write(
        "ends.json",
        r#"{"format": "curvenet-supports", "version": 1, "supports": [
  {"at": [0, 0, 0], "support": "pinned"},
  {"curve": 0, "end": "end", "support": {"fixed": "yz", "rotation": "free"}}
]}"#,
    );
    let got = buckling_factor(&analyze(&dir, &["--supports-file", "ends.json"]));
    assert!(
        (got / euler(1.0) - 1.0).abs() < 0.01,
        "{got} vs {}",
        euler(1.0)
    );
}

#[test]
fn a_supports_file_naming_no_curve_end_is_refused() {
    let dir = TempDir::new("supports-bad");
    dir.write("loads.json", LOADS);
    dir.write("column.json", column(None));
    dir.write(
        "ends.json",
        r#"{"format": "curvenet-supports", "version": 1, "supports": [
  {"at": [0, 0, 0], "support": "pinned"},
  {"at": [500, 0, 0], "support": "pinned"}
]}"#,
    );
    let out = analyze(&dir, &["--supports-file", "ends.json"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("ends.json:3")
            && err.contains("is not a curve end")
            && err.contains("500.0 away"),
        "{err}"
    );
    dir.write("column.json", column(Some(r#"{"start": "hinged"}"#)));
    let out = analyze(&dir, &[]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("column.json:2") && err.contains("unknown support \"hinged\""),
        "{err}"
    );
}

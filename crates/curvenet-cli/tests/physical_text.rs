//! What the physical mode tells a designer: every figure physical with its unit, or labelled as
//! the paper's model's; the largest deviation measured in the physical model; warnings when
//! the units imply an absurd structure.

mod common;

use common::{BIN, TempDir};
use std::path::Path;
use std::process::{Command, Output};

/// Twelve random geodesics on the built-in dome (seed 1), 4000 units across, in `dir/d.json`.
fn dome12(dir: &Path) {
    let status = Command::new(BIN)
        .args([
            "trace",
            "--mesh",
            "dome",
            "--geodesics",
            "12",
            "--seed",
            "1",
        ])
        .args(["--out", "d.json"])
        .current_dir(dir)
        .output()
        .expect("trace runs");
    assert!(status.status.success(), "{status:?}");
}

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

const STEEL_MM: &[&str] = &["--units", "mm", "--material", "steel", "--radius", "10"];

#[test]
fn analyze_gives_every_length_its_unit_and_labels_the_paper_s_figures() {
    let dir = TempDir::new("phys-analyze");
    dome12(&dir.0);
    let mut args = vec!["analyze", "--curves", "d.json", "--edge-length", "100"];
    args.extend_from_slice(STEEL_MM);
    let o = run(&dir.0, &args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    for line in out.lines() {
        assert!(!line.contains("scene units"), "{line}");
    }
    let line = |start: &str| {
        out.lines()
            .find(|l| l.trim_start().starts_with(start))
            .unwrap_or_else(|| panic!("no line {start:?} in\n{out}"))
            .to_string()
    };
    assert!(line("edge lengths:").contains(" mm /"), "{out}");
    assert!(line("structure:").contains(" mm;"), "{out}");
    assert!(line("units:").contains("radius 10.00 mm"), "{out}");
    assert!(line("lambda").contains("the paper's model"), "{out}");
    assert!(line("eigenvalues").contains("the paper's model"), "{out}");
    assert!(
        line("gravity deflection").contains("the paper's model"),
        "{out}"
    );
    assert!(line("physical:").contains("solid, radius 10.0 mm"), "{out}");
    assert!(line("self-weight").contains(" mm at vertex"), "{out}");
    assert!(
        line("deviation from the design").contains(" mm at vertex"),
        "{out}"
    );
}

#[test]
fn a_network_kilometres_across_or_deflecting_more_than_its_size_is_warned_about() {
    let dir = TempDir::new("phys-units");
    dome12(&dir.0);
    // Read as metres the dome is 4 km across and sags 13.8 km under its own weight.
    let o = run(
        &dir.0,
        &[
            "analyze",
            "--curves",
            "d.json",
            "--edge-length",
            "100",
            "--units",
            "m",
            "--young",
            "210GPa",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("warning: with --units m the network is 4.0 km across"),
        "{err}"
    );
    assert!(
        err.contains("under its own weight the structure deflects by 13.8 km, more than its size (4.0 km across)"),
        "{err}"
    );
    // In millimetres the same network is 4 m across and stiff: no such warning.
    let mut args = vec!["analyze", "--curves", "d.json", "--edge-length", "100"];
    args.extend_from_slice(STEEL_MM);
    let err = text(&run(&dir.0, &args).stderr);
    assert!(!err.contains("across"), "{err}");
    assert!(!err.contains("more than its size"), "{err}");
}

#[test]
fn the_largest_deviation_is_the_physical_model_s_and_the_summary_gives_units() {
    let dir = TempDir::new("phys-dev");
    dome12(&dir.0);
    let mut args = vec![
        "simplify",
        "--curves",
        "d.json",
        "--edge-length",
        "100",
        "--budget",
        "0.3",
        "--max-deviation",
        "2",
        "--local-search",
        "--out",
        "r",
    ];
    args.extend_from_slice(STEEL_MM);
    let o = run(&dir.0, &args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("--max-deviation 2.000000 mm: measured in the physical model"),
        "{err}"
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.0.join("r/result.json")).unwrap())
            .unwrap();
    let a = &r["answer"];
    let margin = a["margins"]["max_deviation"]["value"].as_f64().unwrap();
    let physical = a["physical"]["max_deviation"].as_f64().unwrap();
    // The constraint is measured as the physical analysis measures it (the equilibrium of the
    // structure's own rods plus its self-weight sag), not on the paper's model.
    assert!(
        (margin - physical).abs() <= 1e-6 * physical,
        "margin {margin}, physical {physical}"
    );
    assert!(margin <= 2.0, "{margin}");
    let summary = std::fs::read_to_string(dir.0.join("r/summary.txt")).unwrap();
    let stdout = text(&o.stdout);
    for s in [&summary, &stdout] {
        assert!(s.contains("budget: 14680.67 mm of 48935.56 mm"), "{s}");
        assert!(
            s.contains("largest deviation under self-weight (the physical model) ")
                && s.contains(" mm (limit 2.000000 mm)"),
            "{s}"
        );
        assert!(s.contains("physical (the answer): "), "{s}");
        assert!(!s.contains("scene units"), "{s}");
    }
}

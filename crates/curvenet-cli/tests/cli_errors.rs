//! Bad input on the command line: the real `curvenet` binary on tiny broken files and
//! nonsensical options.
//!
//! Every error case asserts exit code 2 (no network can be built, or the request makes no
//! sense) and the key parts of the message: the file, the line, what was wrong. Every warning
//! case asserts exit code 0 and the warning both on stderr and in the output (`--json`'s
//! `warnings`, or `result.json` for `simplify`). Each case runs in a fresh temporary folder with
//! its input files written there, so messages name short relative paths.

mod common;

use common::{BIN, GRID, TempDir};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A square mesh under [`GRID`]: [-1, 1]² at z = 0.
const SQUARE: &str = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n";

/// Options that keep the grid's analysis quiet and fast: a rod radius fit for curves of length
/// 2 and a short edge length.
const QUIET: &[&str] = &["--radius", "0.01", "--edge-length", "0.25"];

/// What one run of the binary gave.
struct Run {
    code: i32,
    stdout: String,
    stderr: String,
    dir: PathBuf,
    /// Removes the folder when the run is dropped.
    _folder: TempDir,
}

/// Writes `files` into a fresh folder and runs the binary there with `args`.
fn run(files: &[(&str, &[u8])], args: &[&str]) -> Run {
    let dir = TempDir::new("cli-errors");
    for (name, content) in files {
        dir.write(name, content);
    }
    let out = Command::new(BIN)
        .args(args)
        .current_dir(&dir.0)
        .output()
        .expect("the curvenet binary runs");
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        dir: dir.0.clone(),
        _folder: dir,
    }
}

/// Runs and checks exit code 2 with every part of `parts` in the message on stderr; no panic and
/// nothing on stdout.
fn expect_error(files: &[(&str, &[u8])], args: &[&str], parts: &[&str]) {
    let r = run(files, args);
    let context = format!(
        "args {args:?}\n--- stderr:\n{}\n--- stdout:\n{}",
        r.stderr, r.stdout
    );
    assert_eq!(r.code, 2, "exit code, {context}");
    for part in parts {
        assert!(r.stderr.contains(part), "stderr lacks `{part}`, {context}");
    }
    assert!(!r.stderr.contains("panicked"), "{context}");
    assert!(r.stdout.is_empty(), "stdout not empty, {context}");
}

/// `analyze` on one curve file named `name` holding `text`, plus `extra` options.
fn analyze_error(name: &str, text: &str, extra: &[&str], parts: &[&str]) {
    let mut args = vec!["analyze", "--curves", name];
    args.extend_from_slice(extra);
    expect_error(&[(name, text.as_bytes())], &args, parts);
}

/// Runs `analyze --json` and checks exit code 0 and that every part of `parts` appears in a
/// warning on stderr (a line `warning: …`, or `file:line: warning: …` for a finding with a
/// place) and in the JSON `warnings`; returns the report.
fn expect_warnings(files: &[(&str, &[u8])], args: &[&str], parts: &[&str]) -> serde_json::Value {
    let mut all = vec!["analyze", "--json"];
    all.extend_from_slice(args);
    let r = run(files, &all);
    let context = format!("args {all:?}\n--- stderr:\n{}", r.stderr);
    assert_eq!(r.code, 0, "exit code, {context}");
    let report: serde_json::Value = serde_json::from_str(&r.stdout)
        .unwrap_or_else(|e| panic!("stdout is not one JSON object ({e}): {}", r.stdout));
    let warnings: Vec<String> = report["warnings"]
        .as_array()
        .expect("a warnings array")
        .iter()
        .map(|w| w.as_str().expect("warnings are strings").to_owned())
        .collect();
    for part in parts {
        assert!(
            r.stderr
                .lines()
                .any(|l| l.contains("warning: ") && l.contains(part)),
            "no warning on stderr with `{part}`, {context}"
        );
        assert!(
            warnings.iter().any(|w| w.contains(part)),
            "no JSON warning with `{part}`: {warnings:#?}"
        );
    }
    report
}

// ---------------------------------------------------------------------------------------------
// Curve files

#[test]
fn reference_format_errors_name_file_and_line() {
    analyze_error(
        "bad.txt",
        "CURVE 0\n0 0 0\n1 x 0\n",
        &[],
        &["bad.txt:3:", "malformed number `x`"],
    );
    analyze_error(
        "trunc.txt",
        "CURVE 0\n0 0 0\n1 0\n",
        &[],
        &["trunc.txt:3:", "truncated point", "expected 3 coordinates"],
    );
    analyze_error(
        "nan.txt",
        "CURVE 0\n0 0 0\n1 nan 0\n",
        &[],
        &["nan.txt:3:", "`nan` is not a finite number"],
    );
    analyze_error(
        "inf.txt",
        "CURVE 0\n0 0 0\n1 0 0\nCURVE 1\n0 0 0\n-inf 1 1\n",
        &[],
        &["inf.txt:6:", "`-inf` is not a finite number"],
    );
    analyze_error(
        "overflow.txt",
        "CURVE 0\n0 0 0\n1e999 0 0\n",
        &[],
        &["overflow.txt:3:", "`1e999` is not a finite number"],
    );
    analyze_error(
        "one.txt",
        "CURVE 0\n1 2 3\n1 2 3\n1 2 3\n",
        &[],
        &["one.txt:1:", "curve 0 has 1 distinct point", "at least 2"],
    );
    analyze_error(
        "closed2.txt",
        "CURVE 0\n0 0 0\n1 0 0\nCURVE 1\n0 0 0\n0 1 0\n0 0 0\n",
        &[],
        &["closed2.txt:4:", "closed curve 1 has 2 distinct points"],
    );
    analyze_error(
        "nopoints.txt",
        "CURVE 0\n0 0 0\n1 0 0\nCURVE 1\n",
        &[],
        &["nopoints.txt:4:", "curve 1 has no points"],
    );
    analyze_error(
        "orphan.txt",
        "0 0 0\nCURVE 0\n",
        &[],
        &["orphan.txt:1:", "before the first `CURVE` line"],
    );
    analyze_error(
        "extra.txt",
        "CURVE 0\n0 0 0\n1 0 0 7\n",
        &[],
        &["extra.txt:3:", "too many coordinates"],
    );
}

#[test]
fn empty_missing_binary_and_misnamed_files() {
    analyze_error("empty.txt", "", &[], &["empty.txt:1:", "no curves"]);
    analyze_error(
        "blank.obj",
        "\n\n# nothing\n",
        &[],
        &["blank.obj:1:", "no `l` (polyline) records"],
    );
    analyze_error(
        "empty.json",
        "",
        &[],
        &["empty.json:1:", "the file is empty"],
    );
    analyze_error(
        "array.json",
        "[1,2,3]",
        &[],
        &["array.json:1:", "expected a JSON object", "found an array"],
    );
    let garbage: Vec<u8> = (0..=255u8).cycle().skip(128).take(600).collect();
    expect_error(
        &[("garbage.txt", &garbage)],
        &["analyze", "--curves", "garbage.txt"],
        &["garbage.txt:1:", "not valid UTF-8"],
    );
    expect_error(
        &[],
        &["analyze", "--curves", "missing.txt"],
        &["missing.txt: ", "cannot read the file", "No such file"],
    );
    // The I/O error is named once, not repeated as its own cause.
    let r = run(&[], &["analyze", "--curves", "missing.txt"]);
    assert_eq!(r.stderr.matches("No such file").count(), 1, "{}", r.stderr);
    expect_error(
        &[("folder.txt/x", b"")],
        &["analyze", "--curves", "folder.txt"],
        &["folder.txt: ", "it is a directory, not a file"],
    );
    expect_error(
        &[("folder/x", b"")],
        &["analyze", "--curves", "folder"],
        &["folder: ", "it is a directory"],
    );
    analyze_error(
        "curves.csv",
        "0,0,0\n",
        &[],
        &[
            "curves.csv: ",
            "unsupported curve file extension",
            ".txt",
            ".obj",
            ".json",
        ],
    );
}

#[test]
fn obj_and_json_curve_errors_name_file_and_line() {
    analyze_error(
        "c.obj",
        "v 0 0 0\nv 1 0 0\nl 1 2 3\n",
        &[],
        &["c.obj:3:", "vertex index 3 refers to a missing vertex"],
    );
    analyze_error(
        "zero.obj",
        "v 0 0 0\nv 1 0 0\nl 0 1\n",
        &[],
        &["zero.obj:3:", "vertex index 0 is invalid"],
    );
    analyze_error(
        "mesh.obj",
        SQUARE,
        &[],
        &["mesh.obj:1:", "no curves", "it is a mesh"],
    );
    analyze_error(
        "short.obj",
        "v 0 0\nv 1 0 0\nl 1 2\n",
        &[],
        &["short.obj:1:", "truncated vertex"],
    );
    analyze_error(
        "nurbs.obj",
        "v 0 0 0\ncstype bspline\n",
        &[],
        &["nurbs.obj:2:", "free-form curves are not supported"],
    );
    analyze_error(
        "syntax.json",
        "{\"format\": \"curvenet-curves\",\n \"version\": 1,\n \"curves\": [\n",
        &[],
        &["syntax.json:4:", "invalid curvenet-curves JSON"],
    );
    analyze_error(
        "other.json",
        "{\"format\": \"geojson\", \"version\": 1, \"curves\": []}",
        &[],
        &["other.json:1:", "not a curvenet curves file"],
    );
    analyze_error(
        "typo.json",
        "{\"format\": \"curvenet-curves\", \"version\": 1,\n \"curves\": [{\"points\": [[0,0,0],[1,0,0]],\n \"close\": true}]}",
        &[],
        &["typo.json:3:", "unknown field `close`"],
    );
    analyze_error(
        "none.json",
        "{\"format\": \"curvenet-curves\", \"version\": 1, \"curves\": []}",
        &[],
        &["none.json:1:", "\"curves\" is empty"],
    );
    analyze_error(
        "null.json",
        "{\"format\": \"curvenet-curves\", \"version\": 1,\n \"curves\": [{\"points\": [[0,0,0],\n [null,0,0]]}]}",
        &[],
        &["null.json:3:", "invalid type: null"],
    );
}

/// A JSON key given twice in one object (serde_json would keep the last silently) is refused,
/// naming the file, the line, the key and where it stands.
#[test]
fn json_keys_given_twice_are_refused_naming_file_line_and_key() {
    analyze_error(
        "twice.json",
        "{\"format\": \"curvenet-curves\", \"version\": 1,\n \"curves\": [\n  {\"points\": [[0,0,0],[1,0,0]]},\n  {\"points\": [[0,0,0],[0,1,0]],\n   \"points\": [[0,0,0],[0,2,0]]}]}",
        &[],
        &[
            "twice.json:5:",
            "duplicate key \"points\" in curves[1] (first at line 4)",
        ],
    );
    analyze_error(
        "units.json",
        "{\"format\": \"curvenet-curves\", \"version\": 1, \"units\": \"m\",\n \"units\": \"mm\",\n \"curves\": [{\"points\": [[0,0,0],[1,0,0]]}]}",
        &[],
        &["units.json:2:", "duplicate key \"units\" (first at line 1)"],
    );
    analyze_error(
        "material.json",
        "{\"format\": \"curvenet-curves\", \"version\": 1, \"units\": \"mm\",\n \"curves\": [{\"points\": [[0,0,0],[1000,0,0]],\n  \"material\": {\"preset\": \"steel\", \"young\": \"1GPa\",\n   \"young\": \"200GPa\"}}]}",
        &[],
        &[
            "material.json:4:",
            "duplicate key \"young\" in curves[0].material",
        ],
    );
}

// ---------------------------------------------------------------------------------------------
// Curves that cannot become rods

#[test]
fn degenerate_geometry_is_refused_with_the_curve_named() {
    // A curve that retraces itself: bending is undefined at the turn.
    analyze_error(
        "hairpin.txt",
        "CURVE 0\n0 0 0\n1 0 0\n0.35 0 0\n",
        &["--edge-length", "0.1"],
        &["hairpin.txt:1: curve 0:", "folds back on itself"],
    );
    expect_error(
        &[("hairpin.txt", b"CURVE 0\n0 0 0\n1 0 0\n0.35 0 0\n")],
        &[
            "simplify",
            "--curves",
            "hairpin.txt",
            "--edge-length",
            "0.1",
            "--budget",
            "0.5",
            "--out",
            "out",
        ],
        &["hairpin.txt:1: curve 0:", "folds back on itself"],
    );
    // Coordinates so small that the rod model cannot compute with them.
    analyze_error(
        "atoms.txt",
        "CURVE 0\n0 0 0\n1e-40 0 0\n",
        &["--edge-length", "1e-41"],
        &["atoms.txt:1: curve 0:", "outside", "--scale"],
    );
    // No default edge length can be chosen from overflowing segments.
    analyze_error(
        "huge.txt",
        "CURVE 0\n-1e308 0 0\n1e308 0 0\n",
        &[],
        &["cannot choose the edge length", "--edge-length"],
    );
}

// ---------------------------------------------------------------------------------------------
// Meshes

#[test]
fn mesh_errors_name_file_and_line() {
    let grid = ("grid.txt", GRID.as_bytes());
    expect_error(
        &[grid, ("m.obj", b"v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n")],
        &["analyze", "--mesh", "m.obj", "--curves", "grid.txt"],
        &["m.obj:3:", "truncated vertex"],
    );
    expect_error(
        &[grid, ("m.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")],
        &["analyze", "--mesh", "m.obj", "--curves", "grid.txt"],
        &["m.obj:4:", "vertex index 9 refers to a missing vertex"],
    );
    expect_error(
        &[grid, ("m.obj", b"v 0 0 0\nv 1 0 0\n")],
        &["analyze", "--mesh", "m.obj", "--curves", "grid.txt"],
        &["m.obj:1:", "no faces"],
    );
    expect_error(
        &[grid, ("m.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")],
        &["analyze", "--mesh", "m.obj", "--curves", "grid.txt"],
        &["m.obj:4:", "no usable faces", "degenerate"],
    );
    expect_error(
        &[grid],
        &["analyze", "--mesh", "nowhere.obj", "--curves", "grid.txt"],
        &["nowhere.obj", "no such file"],
    );
    expect_error(
        &[grid, ("meshdir.obj/x", b"")],
        &["analyze", "--mesh", "meshdir.obj", "--curves", "grid.txt"],
        &["meshdir.obj: ", "it is a directory"],
    );
}

// ---------------------------------------------------------------------------------------------
// Options that make no sense

#[test]
fn nonsensical_numbers_are_usage_errors() {
    let grid = [("grid.txt", GRID.as_bytes())];
    let with = |extra: &[&str], parts: &[&str]| {
        let mut args = vec!["analyze", "--curves", "grid.txt"];
        args.extend_from_slice(extra);
        expect_error(&grid, &args, parts);
    };
    // Refused while the command line is parsed, naming the option (the fuzz test of
    // tests/fuzz_options.rs tries every numeric option so).
    with(
        &["--scale", "0"],
        &["invalid value '0' for '--scale <SCALE>': must be a positive number"],
    );
    with(
        &["--scale", "-2"],
        &["invalid value '-2' for '--scale <SCALE>': must be a positive number"],
    );
    with(
        &["--scale", "NaN"],
        &["invalid value 'NaN' for '--scale <SCALE>': must be a finite number"],
    );
    with(
        &["--scale", "inf"],
        &["invalid value 'inf' for '--scale <SCALE>': must be a finite number"],
    );
    with(
        &["--scale", "1e300", "--edge-length", "1e299"],
        &["grid.txt:1: curve 0:", "outside", "rescale the scene"],
    );
    with(
        &["--scale", "1e-300"],
        &["grid.txt:1: --scale 1.000000e-300 makes curve 0 so small that its length underflows"],
    );
    with(
        &["--edge-length", "0"],
        &["'--edge-length <EDGE_LENGTH>': must be a positive number"],
    );
    with(
        &["--edge-length=-1"],
        &["'--edge-length <EDGE_LENGTH>': must be a positive number"],
    );
    with(
        &["--edge-length", "nan"],
        &["'--edge-length <EDGE_LENGTH>': must be a finite number"],
    );
    with(
        &["--edge-length", "1e-9"],
        &[
            "the edge length h = 1e-9",
            "vertices, more than",
            "larger --edge-length",
        ],
    );
    with(
        &["--radius", "0"],
        &["'--radius <RADIUS>': must be a positive number"],
    );
    with(
        &["--young", "nan"],
        &["'--young <YOUNG>': must be a finite number"],
    );
    with(
        &["--radius", "1e100"],
        &[
            "--radius 1e100",
            "stretching stiffness E π r² = 3.141592653589793e200",
            "out of the range the solvers handle",
        ],
    );
    with(
        &["--radius", "1e-100"],
        &[
            "--radius 1e-100",
            "stretching stiffness E π r² = 3.141592653589793e-200",
            "out of the range the solvers handle",
        ],
    );
    // Stiffnesses whose energy, gradient or spectrum would overflow (λ was -7e280).
    with(
        &["--young", "1e300"],
        &[
            "--radius 2e0 and --young 1e300",
            "out of the range the solvers handle",
        ],
    );
    with(
        &["--young", "1e-300"],
        &["--young 1e-300", "out of the range the solvers handle"],
    );
    with(
        &["--anchor-weight", "1e300"],
        &["--anchor-weight 1e300", "must lie between"],
    );
    with(
        &["--anchor-weight", "-5"],
        &["'--anchor-weight <ANCHOR_WEIGHT>': must be a positive number"],
    );
    with(
        &["--merge-joints", "1.5"],
        &["'--merge-joints <MERGE_JOINTS>': must lie strictly between 0 and 1"],
    );
    with(
        &["--supports", "glued"],
        &["invalid value 'glued'", "pinned or clamped"],
    );
    with(
        &["--remove", "7"],
        &[
            "--remove names curve 7",
            "the input has 4 curves (ids 0..3)",
        ],
    );
    with(
        &["--remove", "0,1,2,3"],
        &["--remove would remove every curve"],
    );
    with(&["--remove", "x"], &["invalid value 'x'"]);
    expect_error(&[], &["analyze"], &["--curves"]);
    expect_error(
        &[],
        &["analyse", "--curves", "x.txt"],
        &["unrecognized subcommand"],
    );
}

#[test]
fn simplify_budgets_and_keep_lists_are_checked() {
    let grid = [("grid.txt", GRID.as_bytes())];
    let with = |extra: &[&str], parts: &[&str]| {
        let mut args = vec!["simplify", "--curves", "grid.txt", "--out", "out"];
        args.extend_from_slice(QUIET);
        args.extend_from_slice(extra);
        expect_error(&grid, &args, parts);
    };
    with(
        &[],
        &["give a budget: --budget FRACTION or --budget-length L"],
    );
    let fraction = "'--budget <BUDGET>': a budget fraction lies in (0, 1]";
    with(&["--budget", "0"], &[fraction]);
    with(&["--budget", "-0.5"], &[fraction]);
    with(&["--budget", "1.5"], &[fraction]);
    with(
        &["--budget", "NaN"],
        &["'--budget <BUDGET>': must be a finite number"],
    );
    with(
        &["--budget-length", "0"],
        &["'--budget-length <BUDGET_LENGTH>': must be a positive number"],
    );
    with(
        &["--budget-length", "inf"],
        &["'--budget-length <BUDGET_LENGTH>': must be a finite number"],
    );
    with(
        &["--budget", "0.5", "--keep", "1,9"],
        &["--keep names curve 9", "4 curves (ids 0..3)"],
    );
    with(
        &["--budget", "0.5", "--budget-length", "3"],
        &["cannot be used with"],
    );
}

#[test]
fn objectives_are_checked_and_searches_that_cannot_honour_one_say_why() {
    let grid = [("grid.txt", GRID.as_bytes())];
    let simplify = |extra: &[&str]| {
        let mut args = vec!["simplify", "--curves", "grid.txt", "--out", "out"];
        args.extend_from_slice(QUIET);
        args.extend_from_slice(&["--budget", "0.6"]);
        args.extend_from_slice(extra);
        args.iter().map(|s| s.to_string()).collect::<Vec<_>>()
    };
    let args = simplify(&["--objective", "freq"]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    expect_error(
        &grid,
        &args,
        &[
            "--objective",
            "unknown objective \"freq\"",
            "lambda",
            "frequency",
        ],
    );
    let args = simplify(&["--objective", "frequency", "--certify"]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    expect_error(
        &grid,
        &args,
        &["--certify with --objective frequency", "mass metric"],
    );
    expect_error(
        &[],
        &["compare", "--objective", "frequency", "--sizes", "4"],
        &["--objective frequency needs --fresh", "exact λ_fix"],
    );
    // With the objective frequency the run records it, and μ_min with its frequency.
    let args = simplify(&["--objective", "frequency", "--local-search"]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let r = run(&grid, &args);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(
        r.stdout.contains("objective the first natural frequency"),
        "{}",
        r.stdout
    );
    let result = std::fs::read_to_string(r.dir.join("out/result.json")).unwrap();
    let result: serde_json::Value = serde_json::from_str(&result).unwrap();
    assert_eq!(result["objective"], "frequency");
    assert_eq!(result["setup"]["stability"]["objective"], "frequency");
    assert_eq!(result["local_search"]["objective"], "frequency");
    for it in result["iterations"].as_array().unwrap() {
        let mu = it["lambda"].as_f64().unwrap();
        let f = it["first_frequency"]
            .as_f64()
            .expect("a stable grid has a frequency");
        assert!((f - mu.sqrt() / (2.0 * std::f64::consts::PI)).abs() <= 1e-12 * f);
    }
    // Every text shows the value as μ_min, never as λ_eq: the summary (file and stdout), the
    // answer's and the local search's lines, and the viewer's labels.
    let summary = std::fs::read_to_string(r.dir.join("out/summary.txt")).unwrap();
    for text in [&summary, &r.stdout] {
        assert!(!text.contains("λ_eq"), "{text}");
        assert!(text.contains("answer (the network to build): "), "{text}");
        assert!(text.contains("μ_min"), "{text}");
    }
    let answer = summary.lines().find(|l| l.starts_with("answer")).unwrap();
    assert!(answer.contains(", μ_min "), "{answer}");
    let local = summary
        .lines()
        .find(|l| l.starts_with("local search"))
        .unwrap();
    assert!(local.contains(", μ_min "), "{local}");
    let viewer = std::fs::read_to_string(r.dir.join("out/viewer.html")).unwrap();
    assert!(
        viewer.contains(r#""objective":{"name":"frequency","score":"μ_fix","value":"μ_min"}"#)
            || viewer
                .contains(r#""objective":{"name":"frequency","value":"μ_min","score":"μ_fix"}"#),
        "the viewer's data names the objective"
    );
    // analyze --objective frequency gives the number the greedy maximised, for the same set.
    let its = result["iterations"].as_array().unwrap();
    let last = its.last().unwrap();
    let kept: Vec<u64> = last["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap())
        .collect();
    let removed: Vec<String> = (0..its[0]["curves"].as_array().unwrap().len() as u64)
        .filter(|c| !kept.contains(c))
        .map(|c| c.to_string())
        .collect();
    let analyze = |objective: &str| {
        let mut args = vec!["analyze", "--json", "--curves", "grid.txt"];
        args.extend_from_slice(QUIET);
        args.extend_from_slice(&["--objective", objective]);
        let removed = removed.join(",");
        if !removed.is_empty() {
            args.extend_from_slice(&["--remove", &removed]);
        }
        let r = run(&grid, &args);
        assert_eq!(r.code, 0, "{}", r.stderr);
        serde_json::from_str::<serde_json::Value>(&r.stdout).expect("one JSON object")
    };
    let report = analyze("frequency");
    assert_eq!(report["objective"], "frequency");
    let (mu, recorded) = (
        report["lambda"].as_f64().unwrap(),
        last["lambda"].as_f64().unwrap(),
    );
    assert!(
        (mu - recorded).abs() <= 1e-6 * recorded,
        "{mu} vs {recorded}"
    );
    let f = report["first_frequency"].as_f64().unwrap();
    assert!((f - last["first_frequency"].as_f64().unwrap()).abs() <= 1e-6 * f);
    // The paper's objective: its λ_eq, the report as before (no objective, no frequency).
    let paper = analyze("lambda");
    assert!(paper.get("objective").is_none(), "{paper}");
    assert!(paper.get("first_frequency").is_none(), "{paper}");
    assert!(paper["lambda"].as_f64().unwrap() != mu);
}

#[test]
fn unknown_examples_and_missing_data_are_usage_errors() {
    expect_error(
        &[],
        &["example", "nosuch", "--data", "."],
        &["unknown example 'nosuch'", "tower", "kagome"],
    );
    expect_error(
        &[],
        &["example", "tower", "--data", "nodata", "--analyze-only"],
        &["--data nodata: no such folder"],
    );
    expect_error(
        &[("nodata/curves/x.txt", b"")],
        &["example", "tower", "--data", "nodata", "--analyze-only"],
        &["nodata/meshes/tower.obj: cannot read the file"],
    );
}

/// `λ` of `example NAME --analyze-only --json` run in a fresh folder, with `extra` options.
fn example_lambda(name: &str, extra: &[&str]) -> f64 {
    let mut args = vec!["example", name, "--analyze-only", "--json"];
    args.extend_from_slice(extra);
    let r = run(&[], &args);
    assert_eq!(r.code, 0, "{args:?}: {}", r.stderr);
    let report: serde_json::Value = serde_json::from_str(&r.stdout).expect("one JSON object");
    report["lambda"].as_f64().expect("lambda is a number")
}

#[test]
fn the_paper_examples_run_from_any_folder_with_the_data_in_the_box() {
    // The run's folder is a fresh temporary one: no `../shared` beside it, no files at all.
    let embedded = example_lambda("tower", &[]);
    let folder = concat!(env!("CARGO_MANIFEST_DIR"), "/../curvenet/data/paper");
    let from_folder = example_lambda("tower", &["--data", folder]);
    assert_eq!(embedded.to_bits(), from_folder.to_bits());
    assert!((embedded - 2.301247e-9).abs() < 1e-14, "tower λ {embedded}");
}

#[test]
fn bench_options_are_checked_before_any_run() {
    expect_error(
        &[],
        &["bench", "--repeat", "0", "--data", "."],
        &["--repeat"],
    );
    expect_error(
        &[],
        &["bench", "--examples", "nosuch,tower", "--data", "."],
        &["unknown example 'nosuch'"],
    );
    expect_error(
        &[],
        &[
            "bench",
            "--worker",
            "--examples",
            "tower,roof",
            "--data",
            ".",
        ],
        &["--worker runs exactly one example"],
    );
}

// ---------------------------------------------------------------------------------------------
// Warnings: the run goes on (exit 0), and the warning is on stderr and in the output

/// A tiny scene's lengths keep their significant digits (they printed as `0.0000`).
#[test]
fn a_tiny_scene_prints_its_lengths_with_their_digits() {
    let r = run(
        &[("grid.txt", GRID.as_bytes())],
        &[
            "analyze", "--curves", "grid.txt", "--scale", "1e-3", "--radius", "1e-5",
        ],
    );
    assert_eq!(r.code, 0, "{}", r.stderr);
    for line in r.stdout.lines().chain(r.stderr.lines()) {
        assert!(
            !line.contains("0.0000 ") && !line.ends_with("0.0000"),
            "{line}"
        );
    }
    assert!(
        r.stdout
            .contains("edge lengths: min 3.846e-5 / median 3.846e-5 / max 4.000e-5"),
        "{}",
        r.stdout
    );
    assert!(r.stdout.contains("rest length 0.008000000"), "{}", r.stdout);
    assert!(
        r.stdout
            .contains("median curve length 0.002000000 (slenderness 200.0)"),
        "{}",
        r.stdout
    );
}

#[test]
fn a_clean_grid_has_no_warnings() {
    let mut args = vec!["--curves", "grid.txt"];
    args.extend_from_slice(QUIET);
    let report = expect_warnings(&[("grid.txt", GRID.as_bytes())], &args, &[]);
    assert_eq!(report["warnings"].as_array().unwrap().len(), 0, "{report}");
    assert_eq!(report["joints"], 4);
}

#[test]
fn a_curve_removed_twice_is_removed_once() {
    let mut args = vec!["--curves", "grid.txt", "--remove", "2,2,2,2"];
    args.extend_from_slice(QUIET);
    let report = expect_warnings(&[("grid.txt", GRID.as_bytes())], &args, &[]);
    assert_eq!(report["removed"], serde_json::json!([2]), "{report}");
    assert_eq!(report["curves"], 3, "{report}");
}

#[test]
fn duplicate_points_are_warned_about() {
    let text = format!("{GRID}CURVE 4\n-1 0 0\n-1 0 0\n0 0 0\n1e-12 0 0\n1 0 0\n");
    let mut args = vec!["--curves", "dups.txt"];
    args.extend_from_slice(QUIET);
    expect_warnings(
        &[("dups.txt", text.as_bytes())],
        &args,
        &[
            "dups.txt:19: warning: curve 4: point repeats the previous point exactly; dropped",
            "dups.txt:21: warning: curve 4: consecutive points are only",
            "kept",
        ],
    );
}

#[test]
fn curves_that_cross_nothing_are_named() {
    let text = format!("{GRID}CURVE lonely\n-1 0 1\n1 0 1\n");
    let mut args = vec!["--curves", "lonely.txt"];
    args.extend_from_slice(QUIET);
    let report = expect_warnings(
        &[("lonely.txt", text.as_bytes())],
        &args,
        &["1 curve(s) cross no other curve", "4 (lonely.txt:17)"],
    );
    assert_eq!(report["build"]["isolated_curves"], serde_json::json!([4]));
}

#[test]
fn mechanisms_say_where_they_are() {
    let text = format!("{GRID}CURVE ring\n0 0 3\n0.5 0 3\n0 0.5 3\n0 0 3\n");
    let mut args = vec!["--curves", "ring.txt"];
    args.extend_from_slice(QUIET);
    let report = expect_warnings(
        &[("ring.txt", text.as_bytes())],
        &args,
        &[
            "zero mode(s) (a mechanism)",
            "it moves most at vertex",
            "on curve(s) 4",
            "float free",
            "4 (ring.txt:17)",
        ],
    );
    assert!(report["zero_modes"].as_u64().unwrap() > 0, "{report}");
}

#[test]
fn unstable_or_unfinished_equilibria_are_reported_with_their_place() {
    // A free square loop with rods as thick as it is wide: today Newton stops at its iteration
    // limit with negative modes. Whatever the solver does with it, what it reports must come
    // with a warning, and a mode warning must say where the mode moves.
    let text = "CURVE loop\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 0\n";
    let report = expect_warnings(
        &[("loop.txt", text.as_bytes())],
        &["--curves", "loop.txt", "--edge-length", "0.1"],
        &["float free", "0 (loop.txt:1)"],
    );
    let warnings = report["warnings"].to_string();
    if report["negative_modes"].as_u64().unwrap() > 0 {
        assert!(
            warnings.contains("the equilibrium is unstable")
                && warnings.contains("negative mode(s)")
                && warnings.contains("it moves most at vertex")
                && warnings.contains("on curve(s) 0"),
            "{warnings}"
        );
    }
    if report["newton"]["converged"] == false {
        assert!(warnings.contains("equilibrium not reached"), "{warnings}");
    }
    assert!(
        report["negative_modes"].as_u64().unwrap() > 0
            || report["zero_modes"].as_u64().unwrap() > 0,
        "a free loop has zero modes at least: {report}"
    );
}

#[test]
fn curves_lying_on_each_other_are_warned_about() {
    let text = format!("{GRID}CURVE copy\n-1 -0.5 0\n0 -0.5 0\n1 -0.5 0\n");
    let mut args = vec!["--curves", "copy.txt"];
    args.extend_from_slice(QUIET);
    expect_warnings(
        &[("copy.txt", text.as_bytes())],
        &args,
        &[
            "pair(s) of curves run together",
            "curves 0 and 4 over 2.0000e0",
        ],
    );
}

#[test]
fn nearly_coincident_joints_are_warned_about() {
    // Curves 2 and 2b cross curve 0 2e-3 apart: a piece of two 1e-3 edges, far below h.
    let text = format!("{GRID}CURVE 2b\n-0.498 -1 0.0\n-0.498 0 0\n-0.498 1 0\n");
    let mut args = vec!["--curves", "close.txt"];
    args.extend_from_slice(QUIET);
    expect_warnings(
        &[("close.txt", text.as_bytes())],
        &args,
        &[
            "the shortest rest edge",
            "two joints nearly coincide",
            "--merge-joints",
        ],
    );
}

#[test]
fn units_that_make_the_radius_absurd_are_warned_about() {
    let grid = [("grid.txt", GRID.as_bytes())];
    // The default radius 2 against curves of length 2.
    let report = expect_warnings(
        &grid,
        &["--curves", "grid.txt", "--edge-length", "0.25"],
        &[
            "rod radius 2 is large against the median curve length",
            "--radius",
        ],
    );
    assert!(report["units"]["warning"].is_string(), "{report}");
    // In the physical mode `--radius` is the real section's: the paper model's stand-in
    // radius 2 is not the user's and is not warned about (2 m curves of 10 mm steel rods).
    let r = run(
        &grid,
        &[
            "analyze",
            "--json",
            "--curves",
            "grid.txt",
            "--edge-length",
            "0.25",
            "--units",
            "m",
            "--material",
            "steel",
            "--radius",
            "0.01",
        ],
    );
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(!r.stderr.contains("rod radius 2"), "{}", r.stderr);
    let physical: serde_json::Value = serde_json::from_str(&r.stdout).expect("one JSON object");
    assert!(physical["units"]["warning"].is_null(), "{physical}");
    assert!(
        !physical["warnings"].to_string().contains("rod radius 2"),
        "{physical}"
    );
    // The units note describes the real section, not the paper model's stand-in.
    assert_eq!(physical["units"]["radius"], 0.01, "{physical}");
    // Under the frequency objective analyze's value is the physical structure's μ_min.
    let r = run(
        &grid,
        &[
            "analyze",
            "--json",
            "--curves",
            "grid.txt",
            "--edge-length",
            "0.25",
            "--units",
            "m",
            "--material",
            "steel",
            "--radius",
            "0.01",
            "--objective",
            "frequency",
        ],
    );
    assert_eq!(r.code, 0, "{}", r.stderr);
    let report: serde_json::Value = serde_json::from_str(&r.stdout).expect("one JSON object");
    let (mu, physical_mu) = (
        report["lambda"].as_f64().unwrap(),
        report["physical"]["mu_min"].as_f64().unwrap(),
    );
    assert!(
        (mu - physical_mu).abs() <= 1e-6 * physical_mu,
        "{mu} vs {physical_mu}"
    );
    let hz = report["physical"]["first_frequency_hz"].as_f64().unwrap();
    let f = report["first_frequency"].as_f64().unwrap();
    assert!((f - hz).abs() <= 1e-6 * hz, "{f} vs {hz}");
    // A radius far too thin for the curves.
    expect_warnings(
        &grid,
        &[
            "--curves",
            "grid.txt",
            "--edge-length",
            "0.25",
            "--radius",
            "1e-9",
        ],
        &["rod radius 0.000000001 is tiny"],
    );
    // A fine median, but one stub curve.
    let text = format!("{GRID}CURVE stub\n0 -0.52 0\n0 -0.48 0\n");
    expect_warnings(
        &[("stub.txt", text.as_bytes())],
        &[
            "--curves",
            "stub.txt",
            "--edge-length",
            "0.01",
            "--radius",
            "0.015",
        ],
        &["curve 4 is only", "a stub"],
    );
}

#[test]
fn meshes_far_from_the_curves_and_broken_meshes_are_warned_about() {
    // The grid on the square, plus one curve lifted far above it.
    let text = format!("{GRID}CURVE high\n-1 0 0.5\n0 0 0.6\n1 0 0.5\n");
    let mut args = vec!["--mesh", "square.obj", "--curves", "high.txt"];
    args.extend_from_slice(QUIET);
    expect_warnings(
        &[
            ("high.txt", text.as_bytes()),
            ("square.obj", SQUARE.as_bytes()),
        ],
        &args,
        &[
            "1 curve(s) far from the mesh square.obj",
            "curve 4 (high.txt:17: 3 of 3 points, up to 6.0000e-1 away)",
            // A share as a person writes it (was 2.9999999999999996%).
            "3.00% of its bounding-box diagonal",
        ],
    );
    // Curves in other units than the mesh: every curve is far.
    let mut args = vec!["--mesh", "big.obj", "--curves", "grid.txt"];
    args.extend_from_slice(QUIET);
    let big = "v 1000 1000 0\nv 3000 1000 0\nv 3000 3000 0\nv 1000 3000 0\nf 1 2 3\nf 1 3 4\n";
    expect_warnings(
        &[("grid.txt", GRID.as_bytes()), ("big.obj", big.as_bytes())],
        &args,
        &[
            "4 curve(s) far from the mesh big.obj",
            "same units and position",
        ],
    );
    // A third face on an edge, an orientation flip and a degenerate face.
    let broken = format!("{SQUARE}v 0 0 1\nf 1 3 5\nf 1 2 4\nf 1 2 1\n");
    let mut args = vec!["--mesh", "broken.obj", "--curves", "grid.txt"];
    args.extend_from_slice(QUIET);
    expect_warnings(
        &[
            ("grid.txt", GRID.as_bytes()),
            ("broken.obj", broken.as_bytes()),
        ],
        &args,
        &[
            "broken.obj:10: warning: degenerate face (repeated vertex",
            "mesh broken.obj: 1 non-manifold edge(s) shared by more than two faces: vertices 1–3 (3 faces)",
            "disagree on orientation",
        ],
    );
}

#[test]
fn simplify_warnings_reach_stderr_and_result_json() {
    // A budget above the total, and a curve that crosses nothing: the run goes on.
    let text = format!("{GRID}CURVE lonely\n-1 0 1\n1 0 1\n");
    let mut args = vec![
        "simplify",
        "--curves",
        "lonely.txt",
        "--out",
        "out",
        "--budget",
        "1",
    ];
    args.extend_from_slice(QUIET);
    let r = run(&[("lonely.txt", text.as_bytes())], &args);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(
        r.stderr.contains("warning: the budget") && r.stderr.contains("nothing will be removed"),
        "{}",
        r.stderr
    );
    assert!(
        r.stderr.contains("curves that cross nothing: 4\n"),
        "{}",
        r.stderr
    );
    let result = std::fs::read_to_string(r.dir.join("out/result.json")).unwrap();
    let result: serde_json::Value = serde_json::from_str(&result).unwrap();
    let warnings = result["setup"]["network"]["warnings"].as_array().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.as_str().unwrap().contains("4 (lonely.txt:17)")),
        "{warnings:?}"
    );
    // A keep list that alone exceeds the budget.
    let mut args = vec![
        "simplify", "--curves", "grid.txt", "--out", "out", "--budget", "0.2", "--keep", "0,1",
    ];
    args.extend_from_slice(QUIET);
    let r = run(&[("grid.txt", GRID.as_bytes())], &args);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(
        r.stderr.contains("the keep list alone needs") && r.stderr.contains("cannot be met"),
        "{}",
        r.stderr
    );
    assert!(Path::new(&r.dir.join("out/result.json")).is_file());
}

#[test]
fn simplify_writes_a_fixed_geometry_certificate_only_with_certify() {
    let mut args = vec![
        "simplify", "--curves", "grid.txt", "--out", "out", "--budget", "0.6",
    ];
    args.extend_from_slice(QUIET);
    // --no-certificate, once parsed and never read, is gone: the default is no certificate.
    {
        let mut a = args.clone();
        a.push("--no-certificate");
        let r = run(&[("grid.txt", GRID.as_bytes())], &a);
        assert_eq!(r.code, 2, "{}", r.stderr);
        assert!(r.stderr.contains("'--no-certificate'"), "{}", r.stderr);
    }
    // By default no certificate.
    {
        let r = run(&[("grid.txt", GRID.as_bytes())], &args);
        assert_eq!(r.code, 0, "{}", r.stderr);
        assert!(!r.stdout.contains("certificate"), "{}", r.stdout);
        let result = std::fs::read_to_string(r.dir.join("out/result.json")).unwrap();
        assert!(!result.contains("certificate"), "{result}");
        let timings = std::fs::read_to_string(r.dir.join("out/timings.json")).unwrap();
        assert!(
            timings.contains("\"certificate_seconds\": null"),
            "{timings}"
        );
    }

    args.push("--certify");
    let r = run(&[("grid.txt", GRID.as_bytes())], &args);
    assert_eq!(r.code, 0, "{}", r.stderr);
    // Its guarantee in plain words.
    assert!(
        r.stdout
            .contains("certificate: no network within the budget can exceed λ_fix = "),
        "{}",
        r.stdout
    );
    assert!(r.stdout.contains("% of that bound"), "{}", r.stdout);
    let result = std::fs::read_to_string(r.dir.join("out/result.json")).unwrap();
    let result: serde_json::Value = serde_json::from_str(&result).unwrap();
    let c = &result["certificate"];
    assert_eq!(c["objective"], "lambda_fix", "{c}");
    // The certificate is the answer's.
    assert_eq!(c["curves"], result["answer"]["curves"]);
    let lam = c["lambda_fix"].as_f64().unwrap();
    let up = c["upper_bound"].as_f64().unwrap();
    let best = c["best_found"].as_f64().unwrap();
    assert!(up >= best && best >= lam, "{c}");
    if let Some(ratio) = c["ratio"].as_f64() {
        assert!((ratio - lam / up).abs() <= 1e-12 && ratio <= 1.0, "{c}");
    }
    let timings = std::fs::read_to_string(r.dir.join("out/timings.json")).unwrap();
    let timings: serde_json::Value = serde_json::from_str(&timings).unwrap();
    assert!(
        timings["certificate_seconds"].as_f64().is_some(),
        "{timings}"
    );
}

#[test]
fn simplify_records_the_local_search_when_asked() {
    let mut args = vec![
        "simplify", "--curves", "grid.txt", "--out", "out", "--budget", "0.6",
    ];
    args.extend_from_slice(QUIET);
    args.push("--local-search");
    let r = run(&[("grid.txt", GRID.as_bytes())], &args);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(
        r.stdout.contains("local search from the greedy"),
        "{}",
        r.stdout
    );
    let result = std::fs::read_to_string(r.dir.join("out/result.json")).unwrap();
    let result: serde_json::Value = serde_json::from_str(&result).unwrap();
    let l = &result["local_search"];
    assert_eq!(l["objective"], "lambda_eq", "{l}");
    assert_eq!(l["strategy"], "variable_depth", "{l}");
    assert_eq!(l["start_curves"], result["final"]["curves"]);
    let (start, end) = (
        l["start_lambda"].as_f64().unwrap(),
        l["lambda"].as_f64().unwrap(),
    );
    assert!(end >= start, "{l}");
    assert!(l["length"].as_f64().unwrap() <= result["budget"].as_f64().unwrap());
    let moves = l["moves"].as_array().unwrap();
    assert_eq!(moves.is_empty(), l["curves"] == l["from_curves"], "{l}");
    // The greedy's set first, then single curves; the best search came from one of them.
    let starts = l["starts"].as_array().unwrap();
    assert_eq!(starts[0]["curves"], l["start_curves"], "{l}");
    assert!((2..=4).contains(&starts.len()), "{l}");
    assert!(
        starts[1..]
            .iter()
            .all(|s| s["curves"].as_array().unwrap().len() == 1)
    );
    assert!(
        starts.iter().any(|s| s["curves"] == l["from_curves"]),
        "{l}"
    );
    for key in ["rounds", "chains", "evaluations", "structures"] {
        assert!(l[key].as_u64().is_some(), "{key}: {l}");
    }
    let timings = std::fs::read_to_string(r.dir.join("out/timings.json")).unwrap();
    assert!(timings.contains("local_search_seconds"));

    args.pop();
    let r = run(&[("grid.txt", GRID.as_bytes())], &args);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let result = std::fs::read_to_string(r.dir.join("out/result.json")).unwrap();
    assert!(!result.contains("local_search"), "{result}");
}

// ---------------------------------------------------------------------------------------------
// Found by trying the binary as a hostile user would

#[test]
fn time_limits_that_are_no_durations_are_refused_not_a_panic() {
    for v in ["-1", "NaN", "inf", "1e30", "0"] {
        expect_error(
            &[],
            &[
                "compare",
                "--sizes",
                "4",
                "--instances",
                "1",
                "--exact-time-limit",
                v,
            ],
            &["invalid value", "'--exact-time-limit <EXACT_TIME_LIMIT>'"],
        );
    }
}

#[test]
fn the_default_edge_length_follows_the_curves_lengths_not_their_sampling() {
    // The grid plus one straight curve of length 2 drawn with 20,001 points: the median input
    // segment (1e-4) would make a network of about 100,000 vertices; the curves' lengths give
    // h = 2 / 50 and a few hundred.
    let mut text = GRID.to_string();
    text.push_str("CURVE 4\n");
    for i in 0..=20_000 {
        text.push_str(&format!("{} 0.25 0\n", -1.0 + 2.0 * i as f64 / 20_000.0));
    }
    let r = run(
        &[("dense.txt", text.as_bytes())],
        &[
            "analyze",
            "--curves",
            "dense.txt",
            "--radius",
            "0.01",
            "--json",
        ],
    );
    assert_eq!(r.code, 0, "{}", r.stderr);
    let report: serde_json::Value = serde_json::from_str(&r.stdout).expect("JSON");
    let vertices = report["vertices"].as_u64().expect("vertices");
    assert!(vertices < 1000, "{vertices} vertices");
    let median = report["edge_length"]["median"]
        .as_f64()
        .expect("median edge");
    assert!((median - 0.04).abs() < 0.005, "median edge {median}");
}

#[test]
fn a_budget_the_run_cannot_meet_is_a_warning() {
    let r = run(
        &[("grid.txt", GRID.as_bytes())],
        &[
            "simplify",
            "--curves",
            "grid.txt",
            "--radius",
            "0.01",
            "--edge-length",
            "0.25",
            "--budget",
            "1e-9",
            "--local-search",
            "--out",
            "out",
        ],
    );
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(
        r.stderr
            .lines()
            .any(|l| l.starts_with("warning: the budget")
                && l.contains("was not met")
                && l.contains("1 curve(s)")),
        "{}",
        r.stderr
    );
    // The local search cannot start (no curve fits either): said in words, and no time is
    // printed for it.
    assert!(
        r.stderr.contains("no local search: ") && r.stderr.contains("no feasible start"),
        "{}",
        r.stderr
    );
    assert!(!r.stderr.contains("BudgetUnmet"), "{}", r.stderr);
    assert!(!r.stdout.contains("local search time"), "{}", r.stdout);
    // The stop reason in words on stdout and in summary.txt, never Rust debug text.
    let summary = std::fs::read_to_string(r.dir.join("out/summary.txt")).expect("summary.txt");
    for text in [&r.stdout, &summary] {
        assert!(text.contains("stop: budget not met"), "{text}");
        assert!(
            !text.contains("Some(") && !text.contains("BudgetUnmet"),
            "{text}"
        );
    }
}

#[test]
fn output_paths_that_cannot_be_written_are_usage_errors_before_any_work() {
    let grid = [
        ("grid.txt", GRID.as_bytes()),
        ("taken", b"a file".as_slice()),
    ];
    let mut args = vec!["simplify", "--curves", "grid.txt", "--budget", "0.5"];
    args.extend_from_slice(QUIET);
    args.extend_from_slice(&["--out", "taken"]);
    expect_error(&grid, &args, &["--out taken: is a file, not a folder"]);
    expect_error(
        &[],
        &[
            "compare",
            "--sizes",
            "4",
            "--instances",
            "1",
            "--surfaces",
            "dome",
            "--json",
            "nowhere/report.json",
        ],
        &["--json nowhere/report.json: the folder nowhere does not exist"],
    );
    expect_error(
        &[],
        &[
            "trace",
            "--mesh",
            "dome",
            "--geodesics",
            "2",
            "--out",
            "nowhere/x.json",
        ],
        &["--out nowhere/x.json: the folder nowhere does not exist"],
    );
}

#[test]
fn compare_fresh_reports_its_networks_and_checks_its_count() {
    // Seed 5: three small networks (9–12 curves), each decided by exhaustive search.
    let args = [
        "compare",
        "--fresh",
        "3",
        "--seed",
        "5",
        "--json",
        "fresh.json",
    ];
    let r = run(&[], &args);
    assert_eq!(r.code, 0, "{}\n{}", r.stderr, r.stdout);
    assert!(!r.stderr.contains("panicked"), "{}", r.stderr);
    assert!(
        r.stdout.contains("3 networks drawn afresh") && r.stdout.contains("greedy + local search"),
        "{}",
        r.stdout
    );
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(r.dir.join("fresh.json")).unwrap()).unwrap();
    let rows = report["rows"].as_array().expect("rows");
    assert_eq!(rows.len(), 3);
    for row in rows {
        // Greedy + local search is never below the greedy, nor above the optimum.
        let (g, l) = (row["greedy"].as_f64(), row["local"].as_f64());
        assert!(l >= g || g.is_none(), "{row}");
        let o = row["optimum"].as_f64().expect("decided");
        assert!(l.expect("a λ") <= o * (1.0 + 1e-6), "{row}");
    }
    for v in ["0", "-1", "x"] {
        expect_error(&[], &["compare", "--fresh", v], &["--fresh <N>"]);
    }
}

#[test]
fn compare_with_a_budget_no_subset_meets_is_a_usage_error() {
    expect_error(
        &[],
        &[
            "compare",
            "--sizes",
            "4",
            "--instances",
            "1",
            "--surfaces",
            "dome",
            "--budget",
            "1e-9",
        ],
        &["--budget", "a larger --budget"],
    );
}

#[test]
fn reader_warnings_are_printed_once_with_one_prefix() {
    // A mesh with a degenerate face: its reader's warning reads `file:line: warning: …`.
    let mesh = "v 0 0 0\nv 1000 0 0\nv 0 1000 0\nv 2000 0 0\nv 1000 1000 0\n\
                f 1 2 3\nf 2 5 3\nf 1 2 4\n";
    let r = run(
        &[("flat.obj", mesh.as_bytes())],
        &[
            "trace",
            "--mesh",
            "flat.obj",
            "--geodesics",
            "2",
            "--out",
            "x.json",
        ],
    );
    assert!(r.stderr.contains("flat.obj:8: warning:"), "{}", r.stderr);
    for line in r.stderr.lines() {
        assert!(
            line.matches("warning:").count() <= 1,
            "warning printed twice: {line}"
        );
    }
}

/// `curvenet slide` refuses, with exit 2 and the option named, a run without a surface, a
/// largest move out of range, a pinned curve the network lacks and too many rounds; a physical
/// run under a largest deviation slides, the slid network's deviation recorded.
#[test]
fn a_slide_without_a_surface_or_with_bad_options_is_refused() {
    let dir = TempDir::new("cli-errors-slide");
    dir.write("grid.txt", GRID);
    dir.write("square.obj", SQUARE);
    let curvenet = |args: &[&str]| {
        let out = Command::new(BIN)
            .args(args)
            .current_dir(&dir.0)
            .output()
            .expect("the curvenet binary runs");
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        (out.status.code().unwrap_or(-1), stderr)
    };
    let simplify = |out: &str, mesh: bool| {
        let mut args = vec![
            "simplify", "--curves", "grid.txt", "--budget", "0.8", "--out", out,
        ];
        if mesh {
            args.extend(["--mesh", "square.obj"]);
        }
        args.extend(QUIET);
        let (code, stderr) = curvenet(&args);
        assert_eq!(code, 0, "{stderr}");
    };
    simplify("bare", false);
    simplify("run", true);
    // A physical run under a largest deviation: a slide keeps it.
    let (code, stderr) = curvenet(&[
        "simplify",
        "--curves",
        "grid.txt",
        "--mesh",
        "square.obj",
        "--budget",
        "0.8",
        "--units",
        "m",
        "--material",
        "steel",
        "--radius",
        "0.01",
        "--max-deviation",
        "1",
        "--out",
        "physical",
        "--edge-length",
        "0.25",
    ]);
    assert_eq!(code, 0, "{stderr}");
    for (args, part) in [
        (&["slide", "bare", "--out", "s"][..], "--mesh"),
        (
            &["slide", "run", "--out", "s", "--max-move", "-1"],
            "--max-move",
        ),
        (
            &["slide", "run", "--out", "s", "--max-move", "90%"],
            "--max-move",
        ),
        (&["slide", "run", "--out", "s", "--max-move", "far"], "far"),
        (
            &["slide", "run", "--out", "s", "--pin", "99"],
            "--pin names curve 99",
        ),
        (&["slide", "run", "--out", "run"], "--out"),
        (
            &["slide", "run", "--out", "s", "--slide-rounds", "101"],
            "--slide-rounds",
        ),
    ] {
        let (code, stderr) = curvenet(args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(part), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    let (code, stderr) = curvenet(&["slide", "run", "--out", "s"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(dir.0.join("s/result.json").is_file());
    let (code, stderr) = curvenet(&["slide", "physical", "--out", "sp"]);
    assert_eq!(code, 0, "{stderr}");
    let result = std::fs::read_to_string(dir.0.join("sp/result.json")).expect("result.json");
    assert!(result.contains("\"deviation\""), "{result}");
}

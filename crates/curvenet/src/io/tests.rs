//! Tests of the module as a whole, and helpers shared by the per-format tests.

use super::*;
use proptest::prelude::*;
use std::path::PathBuf;

/// Asserts that `result` is an error at line `line` of `file` whose message holds `phrase`,
/// displayed as `file:line: …`.
pub(super) fn assert_input_error<T: std::fmt::Debug>(
    result: Result<T, InputError>,
    file: &str,
    line: usize,
    phrase: &str,
) {
    let e = result.unwrap_err();
    assert_eq!(e.file(), file);
    assert_eq!(e.line(), Some(line), "{e}");
    assert!(e.to_string().contains(phrase), "`{e}` lacks `{phrase}`");
    assert!(
        e.to_string().starts_with(&format!("{file}:{line}: ")),
        "{e}"
    );
}

/// Curves exercising labels, closure and awkward numbers.
pub(super) fn sample_curves() -> Vec<Polyline> {
    let origin = Origin::new("sample", 0);
    vec![
        Polyline {
            points: vec![
                Vec3::new(-175.877451073, 46.6826835475, -16.0579801900),
                Vec3::new(-176.111798064, 46.5856138454, -16.0012626566),
                Vec3::new(-176.111798064 + 4.5e-7, 46.5856138454, -16.0012626566),
            ],
            closed: false,
            origin: origin.clone(),
            label: Some("0".to_owned()),
        },
        Polyline {
            points: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 1e-7),
                Vec3::new(1.0, 1.0, 0.1 + 0.2),
                Vec3::new(-0.0, 1.0, 2.5e3),
            ],
            closed: true,
            origin: origin.clone(),
            label: Some("top ring".to_owned()),
        },
        Polyline {
            points: vec![Vec3::new(5.0, 5.0, 5.0), Vec3::new(6.0, 5.0, 5.0)],
            closed: false,
            origin,
            label: None,
        },
    ]
}

/// Asserts that two curve lists agree in everything but their origins (coordinates bit for bit).
pub(super) fn assert_same_curves(expected: &[Polyline], actual: &[Polyline]) {
    assert_eq!(expected.len(), actual.len(), "curve counts differ");
    for (i, (e, a)) in expected.iter().zip(actual).enumerate() {
        assert_eq!(e.closed, a.closed, "curve {i}: closed");
        assert_eq!(e.label, a.label, "curve {i}: label");
        assert_eq!(e.points.len(), a.points.len(), "curve {i}: point count");
        for (p, q) in e.points.iter().zip(&a.points) {
            for k in 0..3 {
                assert_eq!(p[k].to_bits(), q[k].to_bits(), "curve {i}: {p:?} vs {q:?}");
            }
        }
    }
}

/// The path of a file of the paper's data shipped in this crate (`data/paper/KIND/NAME`).
pub(super) fn reference_file(kind: &str, name: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("data/paper")
        .join(kind)
        .join(name);
    p.is_file().then_some(p)
}

/// A fresh, empty directory for one test.
fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("curvenet-io-{tag}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn polyline_length_and_segments() {
    let mut c = Polyline {
        points: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(3.0, 4.0, 0.0),
        ],
        closed: false,
        origin: Origin::new("x", 1),
        label: None,
    };
    assert_eq!(c.length(), 7.0);
    assert_eq!(c.segment_count(), 2);
    c.closed = true;
    assert_eq!(c.length(), 12.0);
    assert_eq!(c.segment_count(), 3);
    c.points.truncate(1);
    assert_eq!(c.length(), 0.0);
    assert_eq!(c.segment_count(), 0);
    c.points.clear();
    assert_eq!(c.length(), 0.0);
    assert_eq!(c.segment_count(), 0);
}

#[test]
fn errors_display_file_and_line() {
    let e = InputError::parse("a.txt", 12, "curve 3 is bad");
    assert_eq!(e.to_string(), "a.txt:12: curve 3 is bad");
    assert_eq!(e.file(), "a.txt");
    assert_eq!(e.line(), Some(12));
    assert_eq!(e.message(), "curve 3 is bad");
    let e = InputError::parse("a.txt", 0, "somewhere");
    assert_eq!(e.line(), None);
    // A whole-file error names the file alone, not a line 0.
    assert_eq!(e.to_string(), "a.txt: somewhere");
    assert_eq!(
        InputWarning::new("a.txt", 0, "empty").to_string(),
        "a.txt: warning: empty"
    );
    let w = InputWarning::new("a.txt", 4, "close points");
    assert_eq!(w.to_string(), "a.txt:4: warning: close points");
}

#[test]
fn read_curves_dispatches_on_the_extension() {
    let dir = temp_dir("dispatch");
    let curves = sample_curves();
    let files = [
        ("c.txt", curves_to_reference_text(&curves)),
        ("c.OBJ", curves_to_obj(&curves)),
        ("c.json", curves_to_json(&curves)),
    ];
    for (name, text) in files {
        let path = dir.join(name);
        write_atomic(&path, text.as_bytes()).unwrap();
        let f = read_curves(&path).unwrap();
        assert_same_curves(&curves, &f.curves);
        assert_eq!(f.curves[0].origin.file, path.display().to_string());
    }
    let e = read_curves(&dir.join("c.csv")).unwrap_err();
    assert!(matches!(e, InputError::UnsupportedFormat { .. }));
    assert!(
        e.to_string()
            .contains("c.csv: unsupported curve file extension"),
        "{e}"
    );
    let e = read_curves(&dir.join("noext")).unwrap_err();
    assert!(matches!(e, InputError::UnsupportedFormat { .. }));
    let e = read_curves(&dir.join("missing.txt")).unwrap_err();
    assert!(matches!(e, InputError::Io { .. }));
    assert!(
        e.to_string().contains("missing.txt: cannot read the file"),
        "{e}"
    );
    assert_eq!(e.line(), None);
    // A file of the wrong kind is a parse error at its line, not a panic.
    let path = dir.join("wrong.txt");
    write_atomic(&path, curves_to_obj(&curves).as_bytes()).unwrap();
    let e = read_curves(&path).unwrap_err();
    assert_eq!(e.line(), Some(1), "{e}");
    assert!(
        e.to_string()
            .contains("found `#` before the first `CURVE` line"),
        "{e}"
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn directories_are_refused_whatever_their_name() {
    let dir = temp_dir("dirs");
    for name in ["curves.txt", "noext", "mesh.obj"] {
        let path = dir.join(name);
        fs::create_dir_all(&path).unwrap();
        let e = read_curves(&path).unwrap_err();
        assert!(matches!(e, InputError::Io { .. }), "{e}");
        assert!(
            e.to_string().ends_with(&format!(
                "{name}: cannot read the file: it is a directory, not a file"
            )),
            "{e}"
        );
        let e = read_mesh(&path).unwrap_err();
        assert!(e.to_string().contains("it is a directory"), "{e}");
    }
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn invalid_utf8_is_an_error_at_its_line() {
    let dir = temp_dir("utf8");
    let path = dir.join("bad.txt");
    fs::write(&path, b"CURVE 0\n0 0 0\n1 \xff 1\n").unwrap();
    let e = read_curves(&path).unwrap_err();
    assert_eq!(e.line(), Some(3));
    assert!(e.to_string().contains("not valid UTF-8"), "{e}");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn read_mesh_wants_obj() {
    let dir = temp_dir("mesh");
    let mesh = TriMesh {
        vertices: vec![
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        faces: vec![[0, 1, 2]],
    };
    let path = dir.join("m.obj");
    write_atomic(&path, mesh_to_obj(&mesh).as_bytes()).unwrap();
    assert_eq!(read_mesh(&path).unwrap().mesh, mesh);
    let e = read_mesh(&dir.join("m.stl")).unwrap_err();
    assert!(matches!(e, InputError::UnsupportedFormat { .. }));
    let e = read_mesh(&dir.join("none.obj")).unwrap_err();
    assert!(matches!(e, InputError::Io { .. }));
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn write_atomic_replaces_content_and_leaves_no_temp_file() {
    let dir = temp_dir("atomic");
    let path = dir.join("out.json");
    write_atomic(&path, b"first version, rather long").unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"first version, rather long");
    write_atomic(&path, b"second").unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"second");
    let long = "n".repeat(250);
    write_atomic(&dir.join(&long), b"long name").unwrap();
    let mut names: Vec<String> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, vec![long, "out.json".to_owned()]);
    let _ = fs::remove_dir_all(&dir);
}

#[cfg(unix)]
#[test]
fn write_atomic_keeps_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = temp_dir("perms");
    let path = dir.join("script.sh");
    fs::write(&path, b"old").unwrap();
    fs::set_permissions(&path, fs::Permissions::from_mode(0o750)).unwrap();
    write_atomic(&path, b"new").unwrap();
    assert_eq!(
        fs::metadata(&path).unwrap().permissions().mode() & 0o777,
        0o750
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn background_writes_land_in_order_and_flush_waits_for_them() {
    let dir = temp_dir("background");
    let w = BackgroundWriter::new().unwrap();
    // Many writes to one file, then one to another: the last submitted content wins.
    for i in 0..100 {
        w.submit(dir.join("counter.txt"), format!("{i}").into_bytes())
            .unwrap();
    }
    let big = vec![7u8; 3 << 20];
    w.submit(dir.join("big.bin"), big.clone()).unwrap();
    w.flush().unwrap();
    assert_eq!(fs::read(dir.join("counter.txt")).unwrap(), b"99");
    assert_eq!(fs::read(dir.join("big.bin")).unwrap(), big);
    // Dropping the writer writes what is still queued.
    w.submit(dir.join("last.txt"), b"queued".to_vec()).unwrap();
    drop(w);
    assert_eq!(fs::read(dir.join("last.txt")).unwrap(), b"queued");
    let _ = fs::remove_dir_all(&dir);
}

/// The failure a writer reports once a submitted job has failed: `path` submitted after it
/// returns the failure if the writer thread has met it already, else the flush does. Either
/// is the rule; which one depends on the threads' timing.
fn failure_after(w: &BackgroundWriter, path: PathBuf, bytes: &[u8]) -> WriteError {
    match w.submit(path, bytes.to_vec()) {
        Err(err) => err,
        Ok(()) => w.flush().unwrap_err(),
    }
}

#[test]
fn a_failed_background_write_is_reported_and_stops_later_ones() {
    let dir = temp_dir("background-fail");
    let w = BackgroundWriter::new().unwrap();
    w.submit(dir.join("first.txt"), b"1".to_vec()).unwrap();
    // A folder that does not exist: the temporary file cannot be made.
    w.submit(dir.join("missing/second.txt"), b"2".to_vec())
        .unwrap();
    let err = failure_after(&w, dir.join("third.txt"), b"3");
    assert!(err.to_string().contains("missing/second.txt"), "{err}");
    // Reported again by the next submission; nothing after the failure was written.
    let again = w.submit(dir.join("fourth.txt"), b"4".to_vec()).unwrap_err();
    assert_eq!(again, err);
    drop(w);
    assert_eq!(fs::read(dir.join("first.txt")).unwrap(), b"1");
    assert!(!dir.join("third.txt").exists());
    assert!(!dir.join("fourth.txt").exists());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn bytes_made_off_the_submitting_thread_keep_the_order_and_report_failures() {
    let dir = temp_dir("background-make");
    let w = BackgroundWriter::new().unwrap();
    let main = std::thread::current().id();
    // Made on a background thread, written between the plain writes submitted around it.
    w.submit(dir.join("f.txt"), b"1".to_vec()).unwrap();
    w.submit_with(dir.join("f.txt"), move || {
        assert_ne!(
            std::thread::current().id(),
            main,
            "made on the submitting thread"
        );
        Ok(b"2".to_vec())
    })
    .unwrap();
    w.flush().unwrap();
    assert_eq!(fs::read(dir.join("f.txt")).unwrap(), b"2");
    w.submit(dir.join("f.txt"), b"3".to_vec()).unwrap();
    w.flush().unwrap();
    assert_eq!(fs::read(dir.join("f.txt")).unwrap(), b"3");
    // Bytes that cannot be made fail like a write: reported with the file, and nothing after.
    w.submit_with(dir.join("g.txt"), || Err("no bytes".into()))
        .unwrap();
    let err = failure_after(&w, dir.join("h.txt"), b"4");
    assert!(
        err.to_string().contains("g.txt") && err.to_string().contains("no bytes"),
        "{err}"
    );
    drop(w);
    assert!(!dir.join("g.txt").exists() && !dir.join("h.txt").exists());
    let _ = fs::remove_dir_all(&dir);
}

/// The low-priority writer may get no CPU time at all while other programs keep every core
/// busy: here it is stuck making a file's bytes. Neither a full queue nor a flush nor the end
/// waits for it: the relief writes that file again and the rest in order, and nothing the stuck
/// writer began is left behind or put in place.
#[test]
fn the_computation_never_waits_for_the_low_priority_writer() {
    use std::sync::{Arc, Condvar, Mutex};
    let dir = temp_dir("background-writer-stuck");
    let w = BackgroundWriter::new().unwrap();
    // Whatever calls this on the low-priority writer's thread stays there until released.
    let gate = Arc::new((Mutex::new(false), Condvar::new()));
    let stuck = Arc::new(Mutex::new(0usize));
    let (g, st) = (Arc::clone(&gate), Arc::clone(&stuck));
    w.submit_with(dir.join("first.txt"), move || {
        if std::thread::current().name() == Some("curvenet-writer") {
            *st.lock().unwrap() += 1;
            let (open, opened) = &*g;
            let mut o = open.lock().unwrap();
            while !*o {
                o = opened.wait(o).unwrap();
            }
        }
        Ok(b"first".to_vec())
    })
    .unwrap();
    while *stuck.lock().unwrap() == 0 {
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    // More than the queue holds: a submission finds it full and the relief takes over.
    for i in 0..40 {
        w.submit(dir.join("counter.txt"), format!("{i}").into_bytes())
            .unwrap();
    }
    w.flush().unwrap();
    assert_eq!(fs::read(dir.join("first.txt")).unwrap(), b"first");
    assert_eq!(fs::read(dir.join("counter.txt")).unwrap(), b"39");
    w.submit(dir.join("last.txt"), b"queued".to_vec()).unwrap();
    drop(w);
    assert_eq!(fs::read(dir.join("last.txt")).unwrap(), b"queued");
    // The stuck writer's temporary file was removed; released, it puts nothing in place.
    let (open, opened) = &*gate;
    *open.lock().unwrap() = true;
    opened.notify_all();
    std::thread::sleep(std::time::Duration::from_millis(100));
    let mut names: Vec<String> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["counter.txt", "first.txt", "last.txt"]);
    assert_eq!(*stuck.lock().unwrap(), 1);
    let _ = fs::remove_dir_all(&dir);
}

/// A function making a file's bytes that panics fails that file like any failed write (the
/// writing threads live on, and a flush reports it instead of waiting).
#[test]
fn a_panic_making_bytes_fails_the_file() {
    let dir = temp_dir("background-panic");
    let w = BackgroundWriter::new().unwrap();
    w.submit_with(dir.join("p.txt"), || panic!("a bug"))
        .unwrap();
    let err = failure_after(&w, dir.join("q.txt"), b"q");
    assert!(err.to_string().contains("p.txt"), "{err}");
    drop(w);
    assert!(!dir.join("p.txt").exists() && !dir.join("q.txt").exists());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn write_atomic_failures_leave_nothing_behind() {
    let dir = temp_dir("atomic-fail");
    // The target is a non-empty directory: the rename fails.
    let target = dir.join("occupied");
    fs::create_dir(&target).unwrap();
    fs::write(target.join("keep"), b"x").unwrap();
    assert!(write_atomic(&target, b"data").is_err());
    let names: Vec<_> = fs::read_dir(&dir).unwrap().collect();
    assert_eq!(names.len(), 1);
    // A missing directory and a path without a file name are errors too.
    assert!(write_atomic(&dir.join("no/such/dir/f.txt"), b"x").is_err());
    assert!(write_atomic(Path::new("/"), b"x").is_err());
    assert!(write_atomic(Path::new(".."), b"x").is_err());
    let _ = fs::remove_dir_all(&dir);
}

/// Text made of the characters the parsers care about, to reach past the first checks.
fn format_soup() -> impl Strategy<Value = String> {
    prop::collection::vec(
        prop::sample::select(vec![
            "CURVE",
            "CURVE 1",
            "v",
            "l",
            "f",
            "o x",
            "#",
            "\\",
            "/",
            "//",
            " ",
            "\t",
            "\n",
            "\r\n",
            "0",
            "1",
            "-1",
            "2",
            "1e-12",
            "1e999",
            "nan",
            "inf",
            ".",
            "e",
            "abc",
            "{",
            "}",
            "[",
            "]",
            ",",
            ":",
            "\"",
            "\"format\"",
            "\"curvenet-curves\"",
            "\"version\"",
            "\"curves\"",
            "\"points\"",
            "\"closed\"",
            "\"label\"",
            "true",
            "null",
            "cstype",
            "\u{feff}",
            "é",
        ]),
        0..80,
    )
    .prop_map(|parts| parts.concat())
}

/// Runs every parser on `text`; the test fails if any of them panics.
fn run_all_parsers(text: &str) {
    let _ = parse_reference_curves(text, "p.txt");
    let _ = parse_obj_polylines(text, "p.obj");
    let _ = parse_json_curves(text, "p.json");
    let _ = parse_obj_mesh(text, "m.obj");
}

/// A JSON document built from loosely valid pieces, for the JSON reader's deeper paths.
fn json_soup() -> impl Strategy<Value = String> {
    let number = prop_oneof![
        any::<f64>().prop_map(|v| format!("{v:?}")),
        Just("1e999".to_owned()),
        Just("\"1\"".to_owned()),
        Just("null".to_owned()),
    ];
    let point = prop::collection::vec(number, 0..5).prop_map(|n| format!("[{}]", n.join(", ")));
    let curve = (
        prop::collection::vec(point, 0..5),
        prop::option::of(any::<bool>()),
        prop::option::of("[a-z\"\\\\ \n]{0,6}"),
    )
        .prop_map(|(points, closed, label)| {
            let mut fields = vec![format!("\"points\": [{}]", points.join(",\n"))];
            if let Some(c) = closed {
                fields.push(format!("\"closed\": {c}"));
            }
            if let Some(l) = label {
                fields.push(format!("\"label\": {}", serde_json::Value::String(l)));
            }
            format!("{{{}}}", fields.join(", "))
        });
    (prop::collection::vec(curve, 0..4), 0u64..3).prop_map(|(curves, version)| {
        format!(
            "{{\"format\": \"curvenet-curves\", \"version\": {version},\n\"curves\": [{}]}}",
            curves.join(",\n")
        )
    })
}

/// Arbitrary valid curves with labels the text formats can hold.
fn any_curves() -> impl Strategy<Value = Vec<Polyline>> {
    let coordinate = prop_oneof![
        -1e6..1e6f64,
        // Full-precision mantissas over a wide range of magnitudes.
        (-1.0..1.0f64, -60i32..60).prop_map(|(m, e)| m * 2f64.powi(e)),
        (-100i32..100).prop_map(f64::from),
    ];
    let curve = (
        prop::collection::vec([coordinate.clone(), coordinate.clone(), coordinate], 3..12),
        any::<bool>(),
        prop::option::of("[A-Za-z0-9_]{1,8}( [A-Za-z0-9_]{1,8})?"),
    )
        .prop_map(|(points, closed, label)| Polyline {
            points: points.into_iter().map(Vec3::from).collect(),
            closed,
            origin: Origin::new("gen", 0),
            label,
        })
        .prop_filter("valid curve", |c| {
            let n = c.points.len();
            let consecutive_distinct = c.points.windows(2).all(|w| w[0] != w[1]);
            let all_distinct = (0..n).all(|i| (i + 1..n).all(|j| c.points[i] != c.points[j]));
            // The reader would see an open curve whose ends (nearly) meet as closed.
            let diag = crate::geom::Aabb::of_points(&c.points).extent().norm();
            let ends_apart = c.points[0].dist(c.points[n - 1]) > 1e-8 * diag;
            consecutive_distinct && all_distinct && ends_apart
        });
    prop::collection::vec(curve, 1..5)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn parsers_never_panic_on_arbitrary_text(text in any::<String>()) {
        run_all_parsers(&text);
    }

    #[test]
    fn parsers_never_panic_on_arbitrary_bytes(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        run_all_parsers(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn parsers_never_panic_on_format_soup(text in format_soup()) {
        run_all_parsers(&text);
    }

    #[test]
    fn json_parser_never_panics_on_near_valid_documents(text in json_soup()) {
        if let Err(e) = parse_json_curves(&text, "p.json") {
            // Every error names the file, and a line whenever the document could be scanned.
            prop_assert!(e.to_string().starts_with("p.json:"));
            prop_assert!(e.line().is_some(), "{}", e);
        }
    }

    #[test]
    fn all_curve_formats_round_trip(curves in any_curves()) {
        let reference = parse_reference_curves(&curves_to_reference_text(&curves), "rt.txt");
        let obj = parse_obj_polylines(&curves_to_obj(&curves), "rt.obj");
        let json = parse_json_curves(&curves_to_json(&curves), "rt.json");
        for parsed in [reference, obj, json] {
            let parsed = parsed.map_err(|e| TestCaseError::fail(e.to_string()))?;
            assert_same_curves(&curves, &parsed.curves);
        }
    }
}

//! Fuzzing the parsers: the reference text format, OBJ polylines, OBJ meshes and JSON curves
//! must answer any input with curves (or a mesh) or with an error naming the file and a line,
//! never with a panic.
//!
//! Inputs: arbitrary bytes (read as lossy UTF-8, and as files through `read_curves` and
//! `read_mesh`, which check UTF-8 themselves), soups of the formats' own tokens, and valid files
//! written by the crate's writers, then mutated: bit flips, truncations, inserted tokens (`nan`,
//! `1e999`, huge and tiny numbers, separators, keywords, braces, a byte-order mark…), numbers
//! replaced, lines duplicated, deleted and swapped, whole files repeated.
//!
//! What a successful parse must satisfy: at least one curve; every curve with at least two
//! finite points (three when closed) and no exact consecutive repeats; origins and warnings
//! naming the file at a line of the text. A mesh: finite vertices, at least one face, every index
//! in range. An error: displayed as `file:line: message` with a line within the text.
//!
//! Cases per property: `CURVENET_FUZZ_CASES` (or `PROPTEST_CASES`), default small so that CI
//! stays fast; for a long local run, e.g. `CURVENET_FUZZ_CASES=200000 cargo test --release
//! --test fuzz_parsers`. Failing seeds are kept in `tests/fuzz_regressions/`, and every file of
//! `tests/fuzz_regressions/parsers/` is fed to every parser by `regressions_parse_cleanly`.

mod common;

use common::{TempDir, fuzz_config};
use curvenet::geom::Vec3;
use curvenet::io::{
    self, CurveFile, InputError, MeshFile, Origin, Polyline, TriMesh, curves_to_json,
    curves_to_obj, curves_to_reference_text, mesh_to_obj, parse_json_curves, parse_obj_mesh,
    parse_obj_polylines, parse_reference_curves,
};
use proptest::prelude::*;
use std::path::Path;

/// The name every parse is given.
const FILE: &str = "fuzz.in";

/// The four parsers, by name.
type Parser = fn(&str) -> Result<(), String>;

const PARSERS: [(&str, Parser); 4] = [
    ("reference", |t| {
        check_curves(t, parse_reference_curves(t, FILE))
    }),
    ("obj polylines", |t| {
        check_curves(t, parse_obj_polylines(t, FILE))
    }),
    ("json", |t| check_curves(t, parse_json_curves(t, FILE))),
    ("obj mesh", |t| check_mesh(t, parse_obj_mesh(t, FILE))),
];

/// Runs every parser on `text`; `Err` names the parser and the broken rule.
fn all_parsers(text: &str) -> Result<(), String> {
    for (name, parse) in PARSERS {
        parse(text).map_err(|e| format!("{name}: {e}"))?;
    }
    Ok(())
}

/// The last line a message may name: the text's line count (plus one for a missing final
/// newline or an empty file).
fn max_line(text: &str) -> usize {
    text.split('\n').count() + 1
}

/// An error must read `FILE:line: message` with the line inside the text.
fn check_error(text: &str, e: &InputError) -> Result<(), String> {
    let shown = e.to_string();
    if e.file() != FILE || !shown.starts_with(&format!("{FILE}:")) {
        return Err(format!("error does not name the file: {shown}"));
    }
    let line = e.line().unwrap_or(0);
    if line > max_line(text) {
        return Err(format!("error names line {line} beyond the text: {shown}"));
    }
    if e.message().trim().is_empty() {
        return Err(format!("empty message: {shown}"));
    }
    Ok(())
}

fn check_origin(text: &str, o: &Origin) -> Result<(), String> {
    if o.file != FILE || o.line > max_line(text) {
        return Err(format!("bad origin {o}"));
    }
    Ok(())
}

/// The rules of a curve parse.
fn check_curves(text: &str, result: Result<CurveFile, InputError>) -> Result<(), String> {
    let f = match result {
        Ok(f) => f,
        Err(e) => return check_error(text, &e),
    };
    if f.curves.is_empty() {
        return Err("Ok with no curves".into());
    }
    for (i, c) in f.curves.iter().enumerate() {
        let n = c.points.len();
        if n < 2 || (c.closed && n < 3) {
            return Err(format!("curve {i}: {n} points, closed {}", c.closed));
        }
        if let Some(p) = c.points.iter().find(|p| !p.is_finite()) {
            return Err(format!("curve {i}: non-finite point {p:?}"));
        }
        if c.points.windows(2).any(|w| w[0] == w[1]) {
            return Err(format!("curve {i}: exact consecutive repeat"));
        }
        if c.closed && c.points.first() == c.points.last() {
            return Err(format!("closed curve {i} repeats its first point"));
        }
        check_origin(text, &c.origin).map_err(|e| format!("curve {i}: {e}"))?;
    }
    for w in &f.warnings {
        check_origin(text, &w.origin).map_err(|e| format!("warning {w}: {e}"))?;
    }
    Ok(())
}

/// The rules of a mesh parse.
fn check_mesh(text: &str, result: Result<MeshFile, InputError>) -> Result<(), String> {
    let m = match result {
        Ok(m) => m,
        Err(e) => return check_error(text, &e),
    };
    if m.mesh.faces.is_empty() {
        return Err("Ok with no faces".into());
    }
    if let Some(p) = m.mesh.vertices.iter().find(|p| !p.is_finite()) {
        return Err(format!("non-finite vertex {p:?}"));
    }
    let n = m.mesh.vertices.len();
    if let Some(f) = m
        .mesh
        .faces
        .iter()
        .find(|f| f.iter().any(|&i| i as usize >= n))
    {
        return Err(format!("face {f:?} beyond {n} vertices"));
    }
    if let Some(f) = m
        .mesh
        .faces
        .iter()
        .find(|f| f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
    {
        return Err(format!("degenerate face {f:?} kept"));
    }
    for w in &m.warnings {
        check_origin(text, &w.origin).map_err(|e| format!("warning {w}: {e}"))?;
    }
    Ok(())
}

/// Tokens of all four formats, and the troublemakers.
const TOKENS: &[&str] = &[
    "CURVE",
    "v",
    "l",
    "f",
    "o",
    "g",
    "vt",
    "vn",
    "cstype",
    "curv",
    "#",
    "\\",
    "1",
    "2",
    "3",
    "-1",
    "-2",
    "0",
    "1/1",
    "1//1",
    "1/1/1",
    "1/",
    "/1",
    "//",
    "2/x",
    "0.5",
    "-0.25",
    "1e-7",
    "1e308",
    "-1e308",
    "1e999",
    "4.9e-324",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "infinity",
    "+1",
    "1.0.0",
    "0x10",
    "99999999999999999999",
    "-9223372036854775808",
    "4294967296",
    "{",
    "}",
    "[",
    "]",
    ",",
    ":",
    "\"format\"",
    "\"curvenet-curves\"",
    "\"version\"",
    "\"curves\"",
    "\"points\"",
    "\"closed\"",
    "\"label\"",
    "\"units\"",
    "true",
    "false",
    "null",
    "\"",
    "\u{feff}",
    "é",
    "\0",
    "[[0,0,0],[1,0,0]]",
    "[0, 1, 2]",
];

const SEPARATORS: &[&str] = &[" ", " ", " ", "\n", "\n", "\t", "\r\n", "", "\\\n"];

/// A soup of tokens and separators.
fn soup() -> impl Strategy<Value = String> {
    prop::collection::vec(
        (
            prop::sample::select(TOKENS),
            prop::sample::select(SEPARATORS),
        ),
        0..60,
    )
    .prop_map(|parts| {
        let mut s = String::new();
        for (t, sep) in parts {
            s.push_str(t);
            s.push_str(sep);
        }
        s
    })
}

/// A JSON-shaped soup: a curvenet-curves header with a random body.
fn json_soup() -> impl Strategy<Value = String> {
    (soup(), any::<bool>()).prop_map(|(body, closed)| {
        format!(
            "{{\"format\": \"curvenet-curves\", \"version\": 1, \"curves\": [{{\"closed\": \
             {closed}, \"points\": [{body}]}}]}}"
        )
    })
}

fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => (-5i32..=5).prop_map(f64::from),
        4 => -1e3..1e3f64,
        1 => prop_oneof![Just(1e300), Just(-1e300), Just(1e-300), Just(5e-324), Just(-0.0)],
    ]
}

/// Random curves (possibly degenerate: the writers write anything).
fn curves() -> impl Strategy<Value = Vec<Polyline>> {
    prop::collection::vec(
        (
            prop::collection::vec([coordinate(), coordinate(), coordinate()], 0..8),
            any::<bool>(),
            prop::option::of("[a-z \n#\\\\]{0,8}"),
        ),
        0..5,
    )
    .prop_map(|list| {
        list.into_iter()
            .enumerate()
            .map(|(i, (pts, closed, label))| Polyline {
                points: pts.into_iter().map(Vec3::from).collect(),
                closed,
                origin: Origin::new("gen", i),
                label,
            })
            .collect()
    })
}

/// A random mesh with valid indices.
fn mesh() -> impl Strategy<Value = TriMesh> {
    prop::collection::vec([coordinate(), coordinate(), coordinate()], 1..10).prop_flat_map(|v| {
        let n = v.len() as u32;
        prop::collection::vec(prop::array::uniform3(0..n), 0..12).prop_map(move |faces| TriMesh {
            vertices: v.iter().map(|&p| Vec3::from(p)).collect(),
            faces,
        })
    })
}

/// One edit of a file's bytes; positions are taken modulo the length.
#[derive(Clone, Debug)]
enum Mutation {
    FlipBit(usize, u8),
    Truncate(usize),
    Insert(usize, &'static str),
    ReplaceNumber(usize, &'static str),
    DuplicateLine(usize),
    DeleteLine(usize),
    SwapLines(usize, usize),
    Repeat,
}

/// What inserted or replacing tokens may be.
const INSERTS: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e999",
    "-1e400",
    "1e308",
    "1.7976931348623157e308",
    "4.9e-324",
    "1e-320",
    "-0",
    "0",
    "99999999999999999999",
    "-1",
    "0/0",
    " ",
    "\n",
    "\r\n",
    "\t",
    "#",
    "\\\n",
    "/",
    "//",
    "CURVE",
    "CURVE\n",
    "v",
    "l",
    "f",
    "l 1",
    "f 1 2",
    "\"",
    "{",
    "}",
    "[",
    "]",
    ",",
    ":",
    "null",
    "true",
    "\u{feff}",
    "\0",
    "é",
    "1 2 3",
    "\n\n\n",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => (any::<usize>(), 0u8..8).prop_map(|(p, b)| Mutation::FlipBit(p, b)),
        2 => any::<usize>().prop_map(Mutation::Truncate),
        3 => (any::<usize>(), prop::sample::select(INSERTS)).prop_map(|(p, t)| Mutation::Insert(p, t)),
        3 => (any::<usize>(), prop::sample::select(INSERTS)).prop_map(|(p, t)| Mutation::ReplaceNumber(p, t)),
        1 => any::<usize>().prop_map(Mutation::DuplicateLine),
        1 => any::<usize>().prop_map(Mutation::DeleteLine),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        1 => Just(Mutation::Repeat),
    ]
}

/// Applies `m` to `bytes`.
fn mutate(bytes: &mut Vec<u8>, m: &Mutation) {
    let len = bytes.len();
    match *m {
        Mutation::FlipBit(p, b) if len > 0 => bytes[p % len] ^= 1 << b,
        Mutation::Truncate(p) => bytes.truncate(p % (len + 1)),
        Mutation::Insert(p, t) => {
            let at = p % (len + 1);
            bytes.splice(at..at, t.bytes());
        }
        Mutation::ReplaceNumber(k, t) => {
            // The k-th maximal run of number characters.
            let is_num = |b: u8| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e');
            let mut runs = Vec::new();
            let mut i = 0;
            while i < len {
                if is_num(bytes[i]) {
                    let s = i;
                    while i < len && is_num(bytes[i]) {
                        i += 1;
                    }
                    runs.push(s..i);
                } else {
                    i += 1;
                }
            }
            if !runs.is_empty() {
                let r = runs[k % runs.len()].clone();
                bytes.splice(r, t.bytes());
            }
        }
        Mutation::DuplicateLine(k) | Mutation::DeleteLine(k) | Mutation::SwapLines(k, _) => {
            let mut lines: Vec<Vec<u8>> =
                bytes.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
            let n = lines.len();
            match *m {
                Mutation::DuplicateLine(_) => {
                    let l = lines[k % n].clone();
                    lines.insert(k % n, l);
                }
                Mutation::DeleteLine(_) if n > 1 => {
                    lines.remove(k % n);
                }
                Mutation::SwapLines(a, b) => lines.swap(a % n, b % n),
                _ => {}
            }
            *bytes = lines.join(&b'\n');
        }
        Mutation::Repeat => {
            let copy = bytes.clone();
            bytes.extend_from_slice(&copy);
        }
        Mutation::FlipBit(..) => {}
    }
}

/// The valid file of one format, mutated.
fn mutated(text: String, edits: &[Mutation]) -> String {
    let mut bytes = text.into_bytes();
    for m in edits {
        mutate(&mut bytes, m);
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

proptest! {
    #![proptest_config(fuzz_config(1500))]

    /// Arbitrary bytes, read as lossy UTF-8.
    #[test]
    fn arbitrary_bytes(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        prop_assert!(all_parsers(&text).is_ok(), "{}", all_parsers(&text).unwrap_err());
    }

    /// Arbitrary strings of any characters.
    #[test]
    fn arbitrary_strings(text in ".{0,200}") {
        prop_assert!(all_parsers(&text).is_ok(), "{}", all_parsers(&text).unwrap_err());
    }

    /// Soups of the formats' tokens.
    #[test]
    fn token_soup(text in prop_oneof![3 => soup(), 1 => json_soup()]) {
        prop_assert!(all_parsers(&text).is_ok(), "{}", all_parsers(&text).unwrap_err());
    }

    /// Valid curve files of every format, mutated; each is also fed to the other parsers.
    #[test]
    fn mutated_curve_files(
        curves in curves(),
        edits in prop::collection::vec(mutation(), 0..5),
    ) {
        for text in [
            curves_to_reference_text(&curves),
            curves_to_obj(&curves),
            curves_to_json(&curves),
        ] {
            let text = mutated(text, &edits);
            prop_assert!(all_parsers(&text).is_ok(), "{}\n--- input:\n{text}", all_parsers(&text).unwrap_err());
        }
    }

    /// Valid mesh files, mutated.
    #[test]
    fn mutated_mesh_files(
        mesh in mesh(),
        edits in prop::collection::vec(mutation(), 0..5),
    ) {
        let text = mutated(mesh_to_obj(&mesh), &edits);
        prop_assert!(all_parsers(&text).is_ok(), "{}\n--- input:\n{text}", all_parsers(&text).unwrap_err());
    }
}

proptest! {
    #![proptest_config(fuzz_config(100))]

    /// Files of arbitrary bytes read through `read_curves` and `read_mesh` (UTF-8 checked by
    /// the readers): an error names the file.
    #[test]
    fn files_of_arbitrary_bytes(
        bytes in prop::collection::vec(any::<u8>(), 0..300),
        ext in prop::sample::select(&["txt", "obj", "json", "OBJ", "csv"][..]),
    ) {
        let dir = TempDir::create("bytes");
        let path = dir.path().join(format!("in.{ext}"));
        std::fs::write(&path, &bytes).unwrap();
        let name = path.display().to_string();
        for result in [io::read_curves(&path).err(), io::read_mesh(&path).err()].into_iter().flatten() {
            prop_assert!(result.to_string().starts_with(&format!("{name}:")), "{result}");
        }
    }
}

/// Every file of the regression folder goes through every parser cleanly.
#[test]
fn regressions_parse_cleanly() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions/parsers");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .expect("the regression folder exists")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .collect();
    paths.sort();
    assert!(
        !paths.is_empty(),
        "no regression inputs in {}",
        dir.display()
    );
    for path in paths {
        let bytes = std::fs::read(&path).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        if let Err(e) = all_parsers(&text) {
            panic!("{}: {e}", path.display());
        }
    }
}

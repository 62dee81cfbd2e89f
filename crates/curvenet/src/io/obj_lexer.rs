//! What the OBJ curve and mesh readers share: splitting the text into records (comments removed,
//! backslash continuations joined, every token tagged with its physical line), and reading
//! vertices and vertex references.

use super::InputError;
use super::checks::{parse_coordinates, push_point, shorten};
use crate::geom::Vec3;

/// One logical OBJ record, such as `v 1 2 3` or `l 1 2 3`.
pub(crate) struct ObjRecord<'a> {
    /// The record's keyword (`v`, `l`, `f`, `o`, …).
    pub keyword: &'a str,
    /// 1-based line of the keyword.
    pub line: usize,
    /// The arguments after the keyword, each with its 1-based physical line.
    pub args: Vec<(&'a str, usize)>,
    /// The text after the keyword, pieces from continued lines joined by a space, trimmed.
    pub rest: String,
}

/// The records of `text`, in order. Blank and comment-only lines yield nothing.
pub(crate) fn records(text: &str) -> Vec<ObjRecord<'_>> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut out = Vec::new();
    let mut pieces: Vec<(&str, usize)> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw
            .split_once('#')
            .map_or(raw, |(before, _)| before)
            .trim_end();
        match content.strip_suffix('\\') {
            Some(head) => pieces.push((head, line)),
            None => {
                pieces.push((content, line));
                if let Some(record) = make_record(&pieces) {
                    out.push(record);
                }
                pieces.clear();
            }
        }
    }
    if let Some(record) = make_record(&pieces) {
        out.push(record);
    }
    out
}

/// Builds a record from the pieces of one logical line; `None` when they hold no token.
fn make_record<'a>(pieces: &[(&'a str, usize)]) -> Option<ObjRecord<'a>> {
    let mut tokens = pieces
        .iter()
        .flat_map(|&(piece, line)| piece.split_whitespace().map(move |t| (t, line)));
    let (keyword, line) = tokens.next()?;
    let args: Vec<(&str, usize)> = tokens.collect();
    let joined = pieces
        .iter()
        .map(|(piece, _)| *piece)
        .collect::<Vec<_>>()
        .join(" ");
    let rest = joined
        .trim_start()
        .strip_prefix(keyword)
        .unwrap_or("")
        .trim()
        .to_owned();
    Some(ObjRecord {
        keyword,
        line,
        args,
        rest,
    })
}

/// Reads the coordinates of a `v` record: `x y z`, `x y z w` (the weight is checked and
/// ignored) or `x y z r g b` (the vertex-colour extension; the colour is checked and ignored).
pub(crate) fn parse_vertex(record: &ObjRecord<'_>, file: &str) -> Result<Vec3, InputError> {
    match parse_coordinates(record.args.iter().copied(), file)? {
        (p, 3 | 4 | 6) => Ok(p),
        (_, n) => {
            let line = record.args.last().map_or(record.line, |&(_, l)| l);
            let what = if n < 3 {
                "truncated vertex"
            } else {
                "too many numbers in vertex"
            };
            Err(InputError::parse(
                file,
                line,
                format!(
                    "{what}: expected `v x y z [w]`, found {n} number{}",
                    plural(n)
                ),
            ))
        }
    }
}

/// `"s"` unless `n` is 1.
pub(crate) fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// What follows `vert` for `n` vertices: `"ex"` for one, else `"ices"`.
pub(crate) fn vertex_suffix(n: usize) -> &'static str {
    if n == 1 { "ex" } else { "ices" }
}

/// Appends a `v x y z` record per point, numbers in the shortest round-trip form.
pub(crate) fn push_vertices<'a>(out: &mut String, points: impl IntoIterator<Item = &'a Vec3>) {
    for &p in points {
        out.push_str("v ");
        push_point(out, p);
        out.push('\n');
    }
}

impl ObjRecord<'_> {
    /// The record's arguments read as vertex references (an `l` or `f` record), each with its
    /// line.
    pub(crate) fn vertex_refs(
        &self,
        vertex_count: usize,
        file: &str,
    ) -> Result<Vec<(VertexRef, usize)>, InputError> {
        self.args
            .iter()
            .map(|&(token, line)| {
                parse_vertex_ref(token, line, vertex_count, file).map(|r| (r, line))
            })
            .collect()
    }
}

/// A vertex reference from an `l` or `f` record, resolved as far as possible while reading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum VertexRef {
    /// A 0-based index, already known to exist.
    Resolved(usize),
    /// A 0-based index from a positive (absolute) reference; checked against the final vertex
    /// count, since some writers refer to vertices defined further down.
    Absolute(usize),
}

/// Reads one vertex reference (`i`, `i/t`, `i//n` or `i/t/n`; only `i` is used, the texture and
/// normal parts must be empty or integers). Negative indices count back from the last vertex
/// defined so far (`vertex_count`).
pub(crate) fn parse_vertex_ref(
    token: &str,
    line: usize,
    vertex_count: usize,
    file: &str,
) -> Result<VertexRef, InputError> {
    let malformed = || {
        InputError::parse(
            file,
            line,
            format!(
                "malformed vertex reference `{}`: expected `i`, `i/t`, `i//n` or `i/t/n` with \
                 integer indices",
                shorten(token)
            ),
        )
    };
    let mut parts = token.split('/');
    let index: i64 = parts
        .next()
        .and_then(|p| p.parse().ok())
        .ok_or_else(malformed)?;
    let mut extra = 0;
    for part in parts {
        extra += 1;
        if extra > 2 || (!part.is_empty() && part.parse::<i64>().is_err()) {
            return Err(malformed());
        }
    }
    if index == 0 {
        return Err(InputError::parse(
            file,
            line,
            "vertex index 0 is invalid; OBJ indices start at 1 (negative indices count back)",
        ));
    }
    if index > 0 {
        return usize::try_from(index - 1)
            .map(VertexRef::Absolute)
            .map_err(|_| malformed());
    }
    let back = usize::try_from(index.unsigned_abs()).unwrap_or(usize::MAX);
    match vertex_count.checked_sub(back) {
        Some(i) => Ok(VertexRef::Resolved(i)),
        None => Err(InputError::parse(
            file,
            line,
            format!(
                "relative vertex index {index} reaches before the first vertex; only \
                 {vertex_count} vertices are defined so far"
            ),
        )),
    }
}

/// The 0-based index of a reference, once all `vertex_count` vertices are known.
pub(crate) fn resolve(
    r: VertexRef,
    line: usize,
    vertex_count: usize,
    file: &str,
) -> Result<usize, InputError> {
    match r {
        VertexRef::Resolved(i) => Ok(i),
        VertexRef::Absolute(i) if i < vertex_count => Ok(i),
        VertexRef::Absolute(i) => Err(InputError::parse(
            file,
            line,
            format!(
                "vertex index {} refers to a missing vertex; the file defines {vertex_count} \
                 vert{}",
                i as u128 + 1,
                vertex_suffix(vertex_count)
            ),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_blank_lines_and_continuations() {
        let text = "\u{feff}# header\n\nv 1 2 3 # trailing\r\nl 1 \\\n  2 \\\n3\n  o  my   name \n";
        let r = records(text);
        assert_eq!(r.len(), 3);
        assert_eq!(r[0].keyword, "v");
        assert_eq!(r[0].line, 3);
        assert_eq!(r[0].args, vec![("1", 3), ("2", 3), ("3", 3)]);
        assert_eq!(r[1].keyword, "l");
        assert_eq!(r[1].line, 4);
        assert_eq!(r[1].args, vec![("1", 4), ("2", 5), ("3", 6)]);
        assert_eq!(r[2].keyword, "o");
        assert_eq!(r[2].rest, "my   name");
    }

    fn record(text: &str) -> ObjRecord<'_> {
        records(text).into_iter().next().unwrap()
    }

    #[test]
    fn vertices_take_three_four_or_six_numbers() {
        assert_eq!(
            parse_vertex(&record("v 1 2 3"), "m.obj").unwrap(),
            Vec3::new(1.0, 2.0, 3.0)
        );
        assert!(parse_vertex(&record("v 1 2 3 1"), "m.obj").is_ok());
        assert!(parse_vertex(&record("v 1 2 3 0.5 0.5 0.5"), "m.obj").is_ok());
        let e = parse_vertex(&record("v 1 2"), "m.obj").unwrap_err();
        assert!(e.to_string().contains("truncated vertex"), "{e}");
        let e = parse_vertex(&record("v 1 2 3 4 5"), "m.obj").unwrap_err();
        assert!(e.to_string().contains("too many numbers"), "{e}");
        let e = parse_vertex(&record("v 1 2 3 nan"), "m.obj").unwrap_err();
        assert!(e.to_string().contains("not a finite number"), "{e}");
    }

    #[test]
    fn vertex_references() {
        let p = |t: &str| parse_vertex_ref(t, 5, 4, "m.obj");
        assert_eq!(p("3").unwrap(), VertexRef::Absolute(2));
        assert_eq!(p("3/7").unwrap(), VertexRef::Absolute(2));
        assert_eq!(p("3//7").unwrap(), VertexRef::Absolute(2));
        assert_eq!(p("3/1/7").unwrap(), VertexRef::Absolute(2));
        assert_eq!(p("-1").unwrap(), VertexRef::Resolved(3));
        assert_eq!(p("-4/2").unwrap(), VertexRef::Resolved(0));
        for bad in [
            "x",
            "",
            "/1",
            "1/2/3/4",
            "1/a",
            "1.5",
            "99999999999999999999",
        ] {
            let e = p(bad).unwrap_err();
            assert_eq!(e.line(), Some(5));
            assert!(
                e.to_string().contains("malformed vertex reference"),
                "{bad}: {e}"
            );
        }
        assert!(p("0").unwrap_err().to_string().contains("start at 1"));
        assert!(
            p("-5")
                .unwrap_err()
                .to_string()
                .contains("before the first vertex")
        );
        assert!(p(&i64::MIN.to_string()).is_err());
        assert_eq!(resolve(VertexRef::Absolute(3), 5, 4, "m.obj").unwrap(), 3);
        let e = resolve(VertexRef::Absolute(4), 5, 4, "m.obj").unwrap_err();
        assert!(
            e.to_string()
                .contains("vertex index 5 refers to a missing vertex"),
            "{e}"
        );
    }

    #[test]
    fn a_final_continuation_is_harmless() {
        let r = records("l 1 2 \\");
        assert_eq!(r.len(), 1);
        assert_eq!(r[0].args.len(), 2);
        assert!(records("\\").is_empty());
        assert!(records("").is_empty());
    }
}

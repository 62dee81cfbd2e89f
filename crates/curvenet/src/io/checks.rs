//! Checks and conversions shared by the parsers and writers: numbers, and the normalisation and
//! validation of one curve.

use super::{InputError, InputWarning, Origin, Polyline};
use crate::geom::{Aabb, Vec3};
use std::fmt::Write as _;

/// Relative tolerance (times the curve's bounding-box diagonal) under which two points count as
/// the same for closure detection and near-duplicate warnings.
pub(crate) const RELATIVE_TOLERANCE: f64 = 1e-9;

/// Parses one coordinate; malformed and non-finite values (`nan`, `inf`, overflow such as
/// `1e999`) are errors at `line`.
pub(crate) fn parse_coordinate(token: &str, file: &str, line: usize) -> Result<f64, InputError> {
    match token.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(InputError::parse(
            file,
            line,
            format!("coordinate `{}` is not a finite number", shorten(token)),
        )),
        Err(_) => Err(InputError::parse(
            file,
            line,
            format!("malformed number `{}`", shorten(token)),
        )),
    }
}

/// Parses every token (with its line) as a coordinate: the first three as a point, and how
/// many there were.
pub(crate) fn parse_coordinates<'a>(
    tokens: impl IntoIterator<Item = (&'a str, usize)>,
    file: &str,
) -> Result<(Vec3, usize), InputError> {
    let mut coords = [0.0; 3];
    let mut count = 0;
    for (token, line) in tokens {
        let v = parse_coordinate(token, file, line)?;
        if let Some(slot) = coords.get_mut(count) {
            *slot = v;
        }
        count += 1;
    }
    Ok((Vec3::from(coords), count))
}

/// A token cut to a length fit for an error message.
pub(crate) fn shorten(token: &str) -> String {
    const MAX: usize = 40;
    if token.chars().count() <= MAX {
        token.to_owned()
    } else {
        let head: String = token.chars().take(MAX).collect();
        format!("{head}…")
    }
}

/// Appends `v` in Rust's shortest round-trip form (`1.0`, `-0.25`, `1e-7`), which the parsers of
/// every format read back bit for bit.
pub(crate) fn push_number(out: &mut String, v: f64) {
    // Writing into a String cannot fail.
    let _ = write!(out, "{v:?}");
}

/// Appends a point as `x y z` with [`push_number`].
pub(crate) fn push_point(out: &mut String, p: Vec3) {
    for (k, v) in [p.x, p.y, p.z].into_iter().enumerate() {
        if k > 0 {
            out.push(' ');
        }
        push_number(out, v);
    }
}

/// A label fit for a one-line record: line breaks and other control characters become spaces and
/// surrounding whitespace is trimmed. `None` when nothing is left.
pub(crate) fn one_line_label(label: &str) -> Option<String> {
    let cleaned: String = label
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let trimmed = cleaned.trim();
    (!trimmed.is_empty()).then(|| trimmed.to_owned())
}

/// How a curve's closure is decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Closure {
    /// Closed when the last point equals the first (exactly or within the tolerance).
    Detect,
    /// Declared closed; a repeated first point at the end is dropped if present.
    Closed,
    /// Declared open; the points are kept as they are.
    Open,
}

impl Closure {
    /// Closure as a curve declares it: `Some(true)` closed, `Some(false)` open, `None` detected.
    pub(crate) fn declared(closed: Option<bool>) -> Self {
        match closed {
            None => Closure::Detect,
            Some(true) => Closure::Closed,
            Some(false) => Closure::Open,
        }
    }
}

/// A curve as read, before normalisation and validation.
pub(crate) struct RawCurve {
    /// 0-based position of the curve in its file, for messages.
    pub index: usize,
    /// Line of the record that opened the curve (0 if unknown).
    pub line: usize,
    /// The curve's label.
    pub label: Option<String>,
    /// How closure is decided.
    pub closure: Closure,
    /// The points, each with the line it came from (0 if unknown).
    pub points: Vec<(Vec3, usize)>,
}

/// Normalises and validates one curve: drops exact consecutive duplicates (with a warning),
/// decides closure and drops the repeated closing point, warns about near-duplicate neighbours,
/// and rejects curves with too few distinct points or non-finite coordinates.
pub(crate) fn finish_curve(
    raw: RawCurve,
    file: &str,
    warnings: &mut Vec<InputWarning>,
) -> Result<Polyline, InputError> {
    let RawCurve {
        index,
        line,
        label,
        closure,
        points,
    } = raw;
    let ctx = CurveContext { file, index };
    if points.is_empty() {
        return Err(InputError::parse(
            file,
            line,
            format!("curve {index} has no points"),
        ));
    }
    if let Some(&(_, at)) = points.iter().find(|(p, _)| !p.is_finite()) {
        return Err(InputError::parse(
            file,
            at,
            format!("curve {index} has a coordinate that is not a finite number"),
        ));
    }
    let mut points = ctx.drop_exact_duplicates(points, warnings);
    let tol = tolerance(points.iter().map(|(p, _)| p));
    let closed = ctx.apply_closure(&mut points, closure, tol, warnings);
    let distinct = count_distinct_up_to(points.iter().map(|(p, _)| *p), 3);
    if distinct < 2 {
        return Err(InputError::parse(
            file,
            line,
            format!(
                "curve {index} has {distinct} distinct point{}; a curve needs at least 2",
                if distinct == 1 { "" } else { "s" }
            ),
        ));
    }
    if closed && distinct < 3 {
        return Err(InputError::parse(
            file,
            line,
            format!(
                "closed curve {index} has {distinct} distinct points; a closed curve needs at \
                 least 3"
            ),
        ));
    }
    ctx.warn_near_duplicates(&points, closed, tol, warnings);
    Ok(Polyline {
        points: points.into_iter().map(|(p, _)| p).collect(),
        closed,
        origin: Origin::new(file, line),
        label,
    })
}

/// The curve being finished, for messages.
struct CurveContext<'a> {
    file: &'a str,
    index: usize,
}

impl CurveContext<'_> {
    /// Records a warning about this curve at `line`.
    fn warn(&self, warnings: &mut Vec<InputWarning>, line: usize, what: &str) {
        warnings.push(InputWarning::new(
            self.file,
            line,
            format!("curve {}: {what}", self.index),
        ));
    }

    /// Exact consecutive duplicates carry no information: drops them, loudly.
    fn drop_exact_duplicates(
        &self,
        raw: Vec<(Vec3, usize)>,
        warnings: &mut Vec<InputWarning>,
    ) -> Vec<(Vec3, usize)> {
        let mut points: Vec<(Vec3, usize)> = Vec::with_capacity(raw.len());
        for (p, line) in raw {
            if points.last().is_some_and(|&(q, _)| q == p) {
                self.warn(
                    warnings,
                    line,
                    "point repeats the previous point exactly; dropped",
                );
            } else {
                points.push((p, line));
            }
        }
        points
    }

    /// Decides whether the curve is closed and drops its repeated closing point. Returns
    /// `closed`.
    fn apply_closure(
        &self,
        points: &mut Vec<(Vec3, usize)>,
        closure: Closure,
        tol: f64,
        warnings: &mut Vec<InputWarning>,
    ) -> bool {
        let repeats_first = points.len() >= 2 && is_closing(points, tol);
        let closed = match closure {
            Closure::Open => false,
            Closure::Closed => true,
            Closure::Detect => repeats_first,
        };
        if !closed {
            return false;
        }
        if repeats_first {
            points.pop();
        }
        // Further exact copies of the first point at the end would make a zero-length closing
        // segment.
        while points.len() >= 2 && points.last().map(|l| l.0) == points.first().map(|f| f.0) {
            if let Some((_, line)) = points.pop() {
                self.warn(
                    warnings,
                    line,
                    "point repeats the first point of the closed curve exactly; dropped",
                );
            }
        }
        true
    }

    /// Warns about consecutive points (including the closing pair) closer than `tol`; they are
    /// kept.
    fn warn_near_duplicates(
        &self,
        points: &[(Vec3, usize)],
        closed: bool,
        tol: f64,
        warnings: &mut Vec<InputWarning>,
    ) {
        if tol <= 0.0 || points.len() < 2 {
            return;
        }
        let n = points.len();
        let pairs = if closed { n } else { n - 1 };
        for k in 0..pairs {
            let (a, a_line) = points[k];
            let (b, b_line) = points[(k + 1) % n];
            let d = a.dist(b);
            if d < tol {
                // The closing pair is reported at its last point, every other pair at its second.
                let line = if k + 1 == n { a_line } else { b_line };
                self.warn(
                    warnings,
                    line,
                    &format!(
                        "consecutive points are only {d:e} apart, below {RELATIVE_TOLERANCE:e} \
                         x the curve's bounding-box diagonal; kept"
                    ),
                );
            }
        }
    }
}

/// `RELATIVE_TOLERANCE ×` the bounding-box diagonal of `points`; 0 when that is not finite
/// (coordinates so large that the diagonal overflows), so only exact equality counts then.
fn tolerance<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> f64 {
    let diag = Aabb::of_points(points).extent().norm();
    let tol = RELATIVE_TOLERANCE * diag;
    if tol.is_finite() { tol } else { 0.0 }
}

/// True when the last point repeats the first, exactly or within `tol`.
fn is_closing(points: &[(Vec3, usize)], tol: f64) -> bool {
    match (points.first(), points.last()) {
        (Some(&(f, _)), Some(&(l, _))) => f == l || scaled_distance(f, l) <= tol,
        _ => false,
    }
}

/// `|a − b|` without the underflow of squaring tiny differences (or the overflow of squaring
/// huge ones): two distinct points are never 0 apart.
fn scaled_distance(a: Vec3, b: Vec3) -> f64 {
    let d = a - b;
    let m = d.x.abs().max(d.y.abs()).max(d.z.abs());
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * (d / m).norm()
}

/// The number of distinct points, counted up to `limit` (the scan stops there).
pub(crate) fn count_distinct_up_to(points: impl IntoIterator<Item = Vec3>, limit: usize) -> usize {
    let mut seen: Vec<Vec3> = Vec::with_capacity(limit);
    for p in points {
        if !seen.contains(&p) {
            seen.push(p);
            if seen.len() >= limit {
                break;
            }
        }
    }
    seen.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw(points: &[[f64; 3]], closure: Closure) -> RawCurve {
        RawCurve {
            index: 4,
            line: 10,
            label: None,
            closure,
            points: points
                .iter()
                .enumerate()
                .map(|(i, &p)| (Vec3::from(p), 11 + i))
                .collect(),
        }
    }

    #[test]
    fn coordinates_reject_malformed_and_non_finite() {
        assert_eq!(parse_coordinate("-1.5e3", "f", 1).unwrap(), -1500.0);
        for bad in ["nan", "NaN", "inf", "-inf", "infinity", "1e999", "-1e400"] {
            let e = parse_coordinate(bad, "f", 7).unwrap_err();
            assert_eq!(e.line(), Some(7));
            assert!(e.to_string().contains("not a finite number"), "{e}");
        }
        for bad in ["abc", "1.0.0", "1,5", "", "0x10"] {
            let e = parse_coordinate(bad, "f", 3).unwrap_err();
            assert!(e.to_string().contains("malformed number"), "{e}");
        }
    }

    #[test]
    fn numbers_round_trip_bit_for_bit() {
        for v in [
            0.0,
            -0.0,
            1.0,
            -175.877451073,
            1e-7,
            4.5e-300,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            0.1 + 0.2,
        ] {
            let mut s = String::new();
            push_number(&mut s, v);
            let back: f64 = s.parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{s}");
        }
    }

    #[test]
    fn long_tokens_are_shortened() {
        let s = shorten(&"x".repeat(100));
        assert_eq!(s.chars().count(), 41);
        assert_eq!(shorten("abc"), "abc");
    }

    #[test]
    fn labels_are_made_one_line() {
        assert_eq!(one_line_label(" a\nb\tc "), Some("a b c".to_owned()));
        assert_eq!(one_line_label(" \r\n "), None);
    }

    #[test]
    fn exact_duplicates_are_dropped_with_a_warning() {
        let mut w = Vec::new();
        let c = finish_curve(
            raw(
                &[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
                Closure::Detect,
            ),
            "f",
            &mut w,
        )
        .unwrap();
        assert_eq!(c.points.len(), 2);
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].origin.line, 12);
        assert!(w[0].message.contains("dropped"));
    }

    #[test]
    fn near_duplicates_are_kept_with_a_warning() {
        let mut w = Vec::new();
        let c = finish_curve(
            raw(
                &[[0.0, 0.0, 0.0], [1e-12, 0.0, 0.0], [1.0, 0.0, 0.0]],
                Closure::Detect,
            ),
            "f",
            &mut w,
        )
        .unwrap();
        assert_eq!(c.points.len(), 3);
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].origin.line, 12);
        assert!(w[0].message.contains("kept"));
    }

    #[test]
    fn closure_is_detected_exactly_and_within_tolerance() {
        let mut w = Vec::new();
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let mut pts = square.to_vec();
        pts.push([0.0, 0.0, 0.0]);
        let c = finish_curve(raw(&pts, Closure::Detect), "f", &mut w).unwrap();
        assert!(c.closed);
        assert_eq!(c.points.len(), 4);
        let mut pts = square.to_vec();
        pts.push([1e-10, 0.0, 0.0]);
        let c = finish_curve(raw(&pts, Closure::Detect), "f", &mut w).unwrap();
        assert!(c.closed);
        assert_eq!(c.points.len(), 4);
        let mut pts = square.to_vec();
        pts.push([1e-6, 0.0, 0.0]);
        let c = finish_curve(raw(&pts, Closure::Detect), "f", &mut w).unwrap();
        assert!(!c.closed);
        assert_eq!(c.points.len(), 5);
        assert!(w.is_empty(), "{w:?}");
    }

    #[test]
    fn declared_closure_is_respected() {
        let mut w = Vec::new();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let c = finish_curve(raw(&tri, Closure::Closed), "f", &mut w).unwrap();
        assert!(c.closed);
        assert_eq!(c.points.len(), 3);
        let mut pts = tri.to_vec();
        pts.push(tri[0]);
        let c = finish_curve(raw(&pts, Closure::Open), "f", &mut w).unwrap();
        assert!(!c.closed);
        assert_eq!(c.points.len(), 4);
        let c = finish_curve(raw(&pts, Closure::Closed), "f", &mut w).unwrap();
        assert!(c.closed);
        assert_eq!(c.points.len(), 3);
    }

    #[test]
    fn too_few_distinct_points_are_errors_at_the_curve_line() {
        let mut w = Vec::new();
        let e = finish_curve(raw(&[[1.0, 2.0, 3.0]], Closure::Detect), "f", &mut w).unwrap_err();
        assert_eq!(e.line(), Some(10));
        assert!(
            e.to_string()
                .contains("curve 4 has 1 distinct point; a curve needs at least 2"),
            "{e}"
        );
        let e = finish_curve(raw(&[[1.0, 2.0, 3.0]; 4], Closure::Detect), "f", &mut w).unwrap_err();
        assert!(e.to_string().contains("1 distinct point"), "{e}");
        let e = finish_curve(
            raw(
                &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
                Closure::Detect,
            ),
            "f",
            &mut w,
        )
        .unwrap_err();
        assert_eq!(e.line(), Some(10));
        assert!(
            e.to_string()
                .contains("closed curve 4 has 2 distinct points"),
            "{e}"
        );
        let e = finish_curve(raw(&[], Closure::Detect), "f", &mut w).unwrap_err();
        assert!(e.to_string().contains("curve 4 has no points"), "{e}");
    }

    #[test]
    fn trailing_copies_of_the_first_point_are_dropped_from_closed_curves() {
        let mut w = Vec::new();
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0],
            [1e-12, 0.0, 0.0],
        ];
        let c = finish_curve(raw(&pts, Closure::Detect), "f", &mut w).unwrap();
        assert!(c.closed);
        assert_eq!(c.points.len(), 3);
        assert_eq!(w.len(), 1);
    }

    #[test]
    fn huge_coordinates_do_not_break_the_tolerance() {
        let mut w = Vec::new();
        let c = finish_curve(
            raw(&[[-1e308, 0.0, 0.0], [1e308, 0.0, 0.0]], Closure::Detect),
            "f",
            &mut w,
        )
        .unwrap();
        assert!(!c.closed);
        assert!(w.is_empty());
    }

    #[test]
    fn tiny_coordinates_do_not_close_an_open_curve() {
        let mut w = Vec::new();
        let c = finish_curve(
            raw(&[[0.0, 0.0, 0.0], [1e-300, 0.0, 0.0]], Closure::Detect),
            "f",
            &mut w,
        )
        .unwrap();
        assert!(!c.closed);
        assert_eq!(c.points.len(), 2);
        assert_eq!(
            scaled_distance(Vec3::new(3e-300, 0.0, 0.0), Vec3::ZERO),
            3e-300
        );
    }

    #[test]
    fn distinct_counting_stops_at_the_limit() {
        let pts = (0..100).map(|i| Vec3::new(i as f64, 0.0, 0.0));
        assert_eq!(count_distinct_up_to(pts, 3), 3);
        assert_eq!(count_distinct_up_to([Vec3::ZERO, -Vec3::ZERO], 3), 1);
    }
}

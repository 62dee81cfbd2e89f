//! The reference curve text format (`.txt`).
//!
//! ```text
//! CURVE 0
//! -175.877451073 46.6826835475 -16.0579801900
//! -176.111798064 46.5856138454 -16.0012626566
//! CURVE 1
//! …
//! ```
//!
//! A line whose first token is `CURVE` opens a curve; the rest of that line is the curve's label.
//! Every other non-blank line holds exactly three whitespace-separated coordinates. A closed
//! curve repeats its first point last.

use super::checks::{
    Closure, RawCurve, finish_curve, one_line_label, parse_coordinates, push_point, shorten,
};
use super::{CurveFile, InputError, Polyline};

/// The keyword that opens a curve.
const CURVE: &str = "CURVE";

/// Parses the reference curve text format. `file` names the input in messages.
///
/// # Errors
///
/// [`InputError::Parse`], at the offending line, for a malformed or non-finite coordinate, a
/// point line without exactly three coordinates, a point before the first `CURVE` line, and a
/// file without curves; at the curve's `CURVE` line for a curve without points or with fewer
/// than 2 distinct points (3 when closed).
pub fn parse_reference_curves(text: &str, file: &str) -> Result<CurveFile, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut curves: Vec<Polyline> = Vec::new();
    let mut warnings = Vec::new();
    let mut current: Option<RawCurve> = None;
    for (i, line_text) in text.lines().enumerate() {
        let line = i + 1;
        let mut tokens = line_text.split_whitespace();
        let Some(first) = tokens.next() else {
            continue;
        };
        if first == CURVE {
            // Finish the previous curve first, so errors come out in file order.
            if let Some(raw) = current.take() {
                curves.push(finish_curve(raw, file, &mut warnings)?);
            }
            let rest = line_text.trim_start().get(CURVE.len()..).unwrap_or("");
            current = Some(RawCurve {
                index: curves.len(),
                line,
                label: one_line_label(rest),
                closure: Closure::Detect,
                points: Vec::new(),
            });
            continue;
        }
        let Some(curve) = current.as_mut() else {
            return Err(InputError::parse(
                file,
                line,
                format!(
                    "found `{}` before the first `CURVE` line; every point must belong to a curve",
                    shorten(first)
                ),
            ));
        };
        let tokens = std::iter::once(first).chain(tokens).map(|t| (t, line));
        let (point, count) = parse_coordinates(tokens, file)?;
        if count != 3 {
            let what = if count < 3 {
                "truncated point"
            } else {
                "too many coordinates"
            };
            return Err(InputError::parse(
                file,
                line,
                format!("{what}: expected 3 coordinates `x y z`, found {count}"),
            ));
        }
        curve.points.push((point, line));
    }
    match current {
        Some(raw) => curves.push(finish_curve(raw, file, &mut warnings)?),
        None => {
            return Err(InputError::parse(
                file,
                1,
                "no curves: the file has no `CURVE` line",
            ));
        }
    }
    Ok(CurveFile::plain(curves, warnings))
}

/// Writes curves in the reference text format. Each curve opens with `CURVE <label>` (a bare
/// `CURVE` when it has none; line breaks in labels become spaces); a closed curve repeats its
/// first point last.
pub fn curves_to_reference_text(curves: &[Polyline]) -> String {
    let mut out = String::new();
    for curve in curves {
        out.push_str(CURVE);
        if let Some(label) = curve.label.as_deref().and_then(one_line_label) {
            out.push(' ');
            out.push_str(&label);
        }
        out.push('\n');
        let closing = curve.points.first().filter(|_| curve.closed);
        for &p in curve.points.iter().chain(closing) {
            push_point(&mut out, p);
            out.push('\n');
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::Origin;
    use super::super::tests::{
        assert_input_error, assert_same_curves, reference_file, sample_curves,
    };
    use super::*;
    use crate::geom::Vec3;

    fn assert_err(text: &str, line: usize, phrase: &str) {
        assert_input_error(
            parse_reference_curves(text, "roof.txt"),
            "roof.txt",
            line,
            phrase,
        );
    }

    #[test]
    fn parses_labels_points_tabs_and_crlf() {
        let text = "CURVE 7\r\n0 0 0\r\n1\t0   0\r\n\r\n  \r\n2 1e-3 -0.5\r\nCURVE\n3 3 3\n4 4 4\n";
        let f = parse_reference_curves(text, "a.txt").unwrap();
        assert_eq!(f.curves.len(), 2);
        let c = &f.curves[0];
        assert_eq!(c.label.as_deref(), Some("7"));
        assert_eq!(c.origin, Origin::new("a.txt", 1));
        assert_eq!(c.points.len(), 3);
        assert_eq!(c.points[2], Vec3::new(2.0, 1e-3, -0.5));
        assert!(!c.closed);
        assert_eq!(f.curves[1].label, None);
        assert_eq!(f.curves[1].origin.line, 7);
        assert!(f.warnings.is_empty());
    }

    #[test]
    fn labels_keep_the_whole_rest_of_the_line() {
        let text = "  CURVE   top ring \t\n0 0 0\n1 0 0\n";
        let f = parse_reference_curves(text, "a.txt").unwrap();
        assert_eq!(f.curves[0].label.as_deref(), Some("top ring"));
    }

    #[test]
    fn errors_come_in_file_order() {
        assert_err(
            "CURVE 0\n1 1 1\nCURVE 1\n1 2 x\n",
            1,
            "curve 0 has 1 distinct point",
        );
        assert_err(
            "CURVE 0\n1 1 1\n2 2 2\nCURVE 1\n1 2 x\n",
            5,
            "malformed number `x`",
        );
    }

    #[test]
    fn closed_curves_drop_the_repeated_point() {
        let text = "CURVE 0\n0 0 0\n1 0 0\n1 1 0\n0 0 0\n";
        let f = parse_reference_curves(text, "a.txt").unwrap();
        assert!(f.curves[0].closed);
        assert_eq!(f.curves[0].points.len(), 3);
        assert_eq!(f.curves[0].segment_count(), 3);
    }

    #[test]
    fn malformed_number() {
        assert_err("CURVE 0\n0 0 0\n1.0 abc 3\n", 3, "malformed number `abc`");
    }

    #[test]
    fn truncated_point() {
        assert_err("CURVE 0\n0 0 0\n1.0 2.0\n", 3, "truncated point");
    }

    #[test]
    fn too_many_coordinates() {
        assert_err(
            "CURVE 0\n0 0 0\n1 2 3 4\n",
            3,
            "expected 3 coordinates `x y z`, found 4",
        );
    }

    #[test]
    fn nan_and_infinite_coordinates() {
        assert_err("CURVE 0\n0 0 0\n1 nan 3\n", 3, "not a finite number");
        assert_err("CURVE 0\n0 0 0\n\n1 2 inf\n", 4, "not a finite number");
        assert_err("CURVE 0\n-inf 0 0\n1 2 3\n", 2, "not a finite number");
        assert_err("CURVE 0\n1e999 0 0\n1 2 3\n", 2, "not a finite number");
    }

    #[test]
    fn empty_file() {
        assert_err("", 1, "no curves");
        assert_err("\n  \n\t\n", 1, "no curves");
    }

    #[test]
    fn points_before_the_first_curve() {
        assert_err(
            "\n0 0 0\nCURVE 0\n1 1 1\n2 2 2\n",
            2,
            "before the first `CURVE` line",
        );
    }

    #[test]
    fn curve_with_one_point() {
        assert_err(
            "CURVE 0\n0 0 0\n1 0 0\nCURVE 1\n5 5 5\n",
            4,
            "curve 1 has 1 distinct point; a curve needs at least 2",
        );
    }

    #[test]
    fn curve_with_one_repeated_point() {
        assert_err(
            "CURVE 0\n0 0 0\n1 0 0\nCURVE 1\n5 5 5\n5 5 5\n5 5 5\n",
            4,
            "curve 1 has 1 distinct point",
        );
    }

    #[test]
    fn closed_curve_with_two_distinct_points() {
        assert_err(
            "CURVE 0\n0 0 0\n1 0 0\n0 0 0\n",
            1,
            "closed curve 0 has 2 distinct points; a closed curve needs at least 3",
        );
    }

    #[test]
    fn empty_curve_block() {
        assert_err(
            "CURVE 0\nCURVE 1\n0 0 0\n1 1 1\n",
            1,
            "curve 0 has no points",
        );
        assert_err(
            "CURVE 0\n0 0 0\n1 1 1\nCURVE 1\n\n",
            4,
            "curve 1 has no points",
        );
    }

    #[test]
    fn duplicates_warn_and_near_duplicates_are_kept() {
        let text = "CURVE 0\n0 0 0\n0 0 0\n1e-12 0 0\n1 0 0\n";
        let f = parse_reference_curves(text, "a.txt").unwrap();
        assert_eq!(f.curves[0].points.len(), 3);
        assert_eq!(f.warnings.len(), 2);
        assert_eq!(f.warnings[0].origin.line, 3);
        assert!(f.warnings[0].message.contains("repeats the previous point"));
        assert_eq!(f.warnings[1].origin.line, 4);
        assert!(f.warnings[1].message.contains("kept"));
    }

    #[test]
    fn round_trip() {
        let curves = sample_curves();
        let text = curves_to_reference_text(&curves);
        let back = parse_reference_curves(&text, "rt.txt").unwrap();
        assert!(back.warnings.is_empty(), "{:?}", back.warnings);
        assert_same_curves(&curves, &back.curves);
        assert_eq!(back.curves[0].origin, Origin::new("rt.txt", 1));
    }

    #[test]
    fn labels_with_line_breaks_are_written_on_one_line() {
        let mut curves = sample_curves();
        curves[0].label = Some("two\nlines".to_owned());
        curves[1].label = Some("  ".to_owned());
        let back = parse_reference_curves(&curves_to_reference_text(&curves), "rt.txt").unwrap();
        assert_eq!(back.curves[0].label.as_deref(), Some("two lines"));
        assert_eq!(back.curves[1].label, None);
    }

    #[test]
    fn reference_files_counts() {
        // (file, curves, points after dropping closing repeats, closed curves)
        let expected = [
            ("roof_75.txt", 75, 4793, 0),
            ("tower_top_ring.txt", 1, 136, 1),
            ("tower_32.txt", 32, 9952, 0),
            ("shell_elipse.txt", 1, 854, 1),
            ("kagome_114_regular.txt", 114, 4597, 0),
            ("hill_3.txt", 3, 217, 0),
            ("shell_3.txt", 3, 251, 0),
            ("shell_100.txt", 60, 3670, 0),
            ("shell_100_for_arcs.txt", 60, 3659, 0),
            ("shell_arcs.txt", 6, 1496, 0),
            ("tent_3_regular_curves.txt", 3, 426, 0),
            ("tent_curves.txt", 43, 8331, 0),
        ];
        for (name, curves, points, closed) in expected {
            let Some(path) = reference_file("curves", name) else {
                return;
            };
            let f = super::super::read_curves(&path).unwrap();
            assert_eq!(f.curves.len(), curves, "{name}");
            let total: usize = f.curves.iter().map(|c| c.points.len()).sum();
            assert_eq!(total, points, "{name}");
            assert_eq!(
                f.curves.iter().filter(|c| c.closed).count(),
                closed,
                "{name}"
            );
            assert!(f.warnings.is_empty(), "{name}: {:?}", f.warnings.first());
            // The labels are numbers, but not always the curve's position.
            assert!(
                f.curves
                    .iter()
                    .all(|c| c.label.as_deref().is_some_and(|l| l.parse::<u32>().is_ok()))
            );
            assert_eq!(f.curves[0].label.as_deref(), Some("0"), "{name}");
        }
    }

    #[test]
    fn roof_keeps_its_short_segments_exactly() {
        let Some(path) = reference_file("curves", "roof_75.txt") else {
            return;
        };
        let f = super::super::read_curves(&path).unwrap();
        let lengths: Vec<f64> = f
            .curves
            .iter()
            .flat_map(|c| c.points.windows(2).map(|w| w[0].dist(w[1])))
            .collect();
        assert_eq!(lengths.iter().filter(|&&d| d < 1e-3).count(), 198);
        let shortest = lengths.iter().copied().fold(f64::INFINITY, f64::min);
        assert!((shortest - 4.466e-7).abs() < 1e-9, "{shortest}");
        // First point of the file, bit for bit.
        assert_eq!(
            f.curves[0].points[0],
            Vec3::new(-175.877451073, 46.6826835475, -16.0579801900)
        );
    }

    #[test]
    fn tower_top_ring_is_closed() {
        let Some(path) = reference_file("curves", "tower_top_ring.txt") else {
            return;
        };
        let f = super::super::read_curves(&path).unwrap();
        assert_eq!(f.curves.len(), 1);
        let ring = &f.curves[0];
        assert!(ring.closed);
        assert_eq!(ring.points.len(), 136);
        assert_eq!(ring.segment_count(), 136);
        assert_ne!(ring.points.first(), ring.points.last());
        assert!(ring.length() > 0.0);
    }
}

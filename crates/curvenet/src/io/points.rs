//! Curves handed over as point lists (from Python arrays, a Rhino document, …) rather than
//! read from a file: the same normalisation and checks as the file readers.

use super::checks::{Closure, RawCurve, finish_curve};
use super::{CurveFile, InputError};
use crate::geom::Vec3;

/// One curve given as points.
#[derive(Clone, Debug, PartialEq)]
pub struct PointCurve {
    /// The points in order.
    pub points: Vec<Vec3>,
    /// `Some(true)`/`Some(false)` declares the curve closed/open; `None` closes it when its last
    /// point repeats its first (as the file readers do).
    pub closed: Option<bool>,
    /// The curve's label, if any.
    pub label: Option<String>,
    /// Where the curve came from, for messages: a 1-based position (line or object number) in
    /// `file`, 0 when unknown.
    pub line: usize,
}

/// Normalises and checks `curves` exactly as the file readers do (exact duplicates dropped
/// with a warning, closure detected, too few distinct points or a non-finite coordinate
/// rejected), naming `file` and each curve's `line` in messages.
///
/// # Errors
///
/// [`InputError::Parse`] for the first curve the checks reject.
pub fn curves_from_points(file: &str, curves: Vec<PointCurve>) -> Result<CurveFile, InputError> {
    let mut warnings = Vec::new();
    let mut out = Vec::with_capacity(curves.len());
    for (index, c) in curves.into_iter().enumerate() {
        let raw = RawCurve {
            index,
            line: c.line,
            label: c.label,
            closure: Closure::declared(c.closed),
            points: c.points.into_iter().map(|p| (p, c.line)).collect(),
        };
        out.push(finish_curve(raw, file, &mut warnings)?);
    }
    Ok(CurveFile::plain(out, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(points: &[[f64; 3]], line: usize) -> PointCurve {
        PointCurve {
            points: points.iter().map(|&p| Vec3::from(p)).collect(),
            closed: None,
            label: None,
            line,
        }
    }

    #[test]
    fn point_curves_are_normalised_like_file_curves() {
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 0.0, 0.0],
        ];
        let f = curves_from_points("<arrays>", vec![curve(&square, 1)]).unwrap();
        assert_eq!(f.curves[0].points.len(), 3);
        assert!(f.curves[0].closed);
        assert_eq!(f.warnings.len(), 1, "{:?}", f.warnings);
    }

    #[test]
    fn a_bad_point_curve_names_the_file_and_its_position() {
        let good = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let bad = [[0.0, 0.0, 0.0], [f64::NAN, 0.0, 0.0]];
        let e =
            curves_from_points("sketch.3dm", vec![curve(&good, 1), curve(&bad, 2)]).unwrap_err();
        assert_eq!(e.file(), "sketch.3dm");
        assert_eq!(e.line(), Some(2));
        assert!(e.to_string().contains("curve 1"), "{e}");
    }
}

//! Numbers for people: what every message, summary and picture prints a computed value with.
//! A fixed number of decimals prints a tiny scene's lengths as `0.0000` and a computed share
//! as `2.9999999999999996%`; these keep a number of significant digits instead, in scientific
//! notation where fixed notation would need leading or padding zeros.

/// `v` with `sig` significant digits: fixed notation from 1e-4 up to (not including)
/// `10^sig`, scientific notation beyond (`1234.57`, `0.0001235`, `2.301e-9`, `1.235e7`).
/// Zero prints as `0`; infinities and NaN as Rust prints them.
pub fn significant(v: f64, sig: usize) -> String {
    let sig = sig.max(1);
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { v.to_string() };
    }
    let e = v.abs().log10().floor() as i64;
    if (-4..sig as i64).contains(&e) {
        let decimals = (sig as i64 - 1 - e).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{:.*e}", sig - 1, v)
    }
}

/// A length (or any value of a scene's size) with seven significant digits: `26791.22`,
/// `0.0001234568`, `1.234568e-9`.
pub fn length(x: f64) -> String {
    significant(x, 7)
}

/// [`length`] followed by its unit when there is one (the physical mode's scene unit:
/// `13622.22 mm`), bare otherwise (the paper's scene units).
pub fn length_in(x: f64, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{} {u}", length(x)),
        None => length(x),
    }
}

/// A percentage (already multiplied by 100) with three significant digits, without the `%`:
/// `3.00`, `0.0500`, `150`.
pub fn percent(p: f64) -> String {
    significant(p, 3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_their_significant_digits_at_any_scale() {
        assert_eq!(length(26791.215185), "26791.22");
        assert_eq!(length(8.0), "8.000000");
        assert_eq!(length(0.00012345678), "0.0001234568");
        assert_eq!(length(1.2345678e-9), "1.234568e-9");
        assert_eq!(length(2.0e-6), "2.000000e-6");
        assert_eq!(length(2.5e20), "2.500000e20");
        assert_eq!(length(0.0), "0");
        assert_eq!(length_in(8.0, Some("mm")), "8.000000 mm");
        assert_eq!(length_in(8.0, None), "8.000000");
        assert_eq!(significant(1234.5678, 6), "1234.57");
        assert_eq!(significant(2.301247e-9, 4), "2.301e-9");
        assert_eq!(significant(12345678.0, 4), "1.235e7");
        assert_eq!(significant(-0.5, 2), "-0.50");
        assert_eq!(significant(f64::INFINITY, 3), "inf");
        assert_eq!(percent(2.9999999999999996), "3.00");
        assert_eq!(percent(100.0 * 0.03), "3.00");
        assert_eq!(percent(150.0), "150");
    }
}

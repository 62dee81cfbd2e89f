//! Value parsers of the numeric options: each rejects, while the command line is parsed and
//! before any work, what its option cannot mean. clap turns the message into
//! `error: invalid value 'X' for '--option <OPTION>': MESSAGE` and exit code 2, so the message
//! says only what the value must be.
//!
//! Numeric options are declared with `allow_hyphen_values`, so that `-1` and `-inf` reach these
//! parsers (and are refused for what they are) instead of being taken for unknown flags.
//!
//! Integer options get ranges (`count`): a count of geodesics, seeds, instances or branch and
//! bound nodes beyond them would run for hours or exhaust memory, not answer a question.

use crate::front::say;
use clap::builder::{RangedU64ValueParser, TypedValueParser};
use curvenet::physics::options::check_option;
use curvenet::simplify::exact::MAX_TIME_LIMIT;
use curvenet::trace::check_extent;
use curvenet::words::Opt;

/// Parses a floating-point number (`1.5`, `2e-3`); `nan`, `inf` and garbage are refused here or
/// by the caller's test.
fn number(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    if !v.is_finite() {
        return Err("must be a finite number".into());
    }
    Ok(v)
}

/// A finite number greater than 0 (lengths, scales, material constants).
pub fn positive(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err("must be a positive number".into())
    }
}

/// An extent to scale a mesh to: 0 (keep the mesh's size) or within the range
/// `curvenet::trace::check_extent` accepts.
pub fn extent(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    check_extent(v).map(|()| v.abs()).map_err(|m| say(&m))
}

/// A budget as a fraction of the total rest length: in (0, 1].
pub fn budget_fraction(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    if v > 0.0 && v <= 1.0 {
        Ok(v)
    } else {
        Err("a budget fraction lies in (0, 1] (0.3 keeps 30% of the total length)".into())
    }
}

/// A fraction strictly between 0 and 1 (the joint merging distance, as a fraction of `h`).
pub fn open_fraction(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    if v > 0.0 && v < 1.0 {
        Ok(v)
    } else {
        Err("must lie strictly between 0 and 1".into())
    }
}

/// A time limit in seconds: positive, at most the exact solver's
/// [`MAX_TIME_LIMIT`] (about 31 years: "no limit" in practice).
pub fn seconds(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    if v > 0.0 && v <= MAX_TIME_LIMIT {
        Ok(v)
    } else {
        Err(format!(
            "a time limit in seconds must lie in (0, {MAX_TIME_LIMIT:e}]"
        ))
    }
}

/// `--young`: a positive number (the paper's mode), or a positive modulus with a stress unit
/// (`210GPa`, the physical mode); kept as written, for the mode to read.
pub fn young(s: &str) -> Result<String, String> {
    if s.trim().parse::<f64>().is_ok() || curvenet::units::split_number(s).1.is_empty() {
        positive(s).map(|_| s.trim().to_string())
    } else {
        check_option(Opt::Young, s)
            .map(|()| s.trim().to_string())
            .map_err(|m| say(&m))
    }
}

/// A physical-mode option (`--units`, `--material`, `--density`, `--strength`, `--tube`,
/// `--load`, `--gravity`), checked as the physical mode reads it and kept as written.
pub fn physical(opt: Opt) -> impl Fn(&str) -> Result<String, String> + Clone {
    move |s: &str| {
        check_option(opt, s)
            .map(|()| s.trim().to_string())
            .map_err(|m| say(&m))
    }
}

/// A TCP port: 0 (any free port) to 65535.
pub fn port(s: &str) -> Result<u16, String> {
    s.trim()
        .parse()
        .map_err(|_| "a port is a whole number from 0 (any free port) to 65535".into())
}

/// An integer in `lo..=hi` (a count), as `usize`.
pub fn count(lo: u64, hi: u64) -> impl TypedValueParser<Value = usize> {
    RangedU64ValueParser::<usize>::new().range(lo..=hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hostile_numbers_are_refused_with_what_the_value_must_be() {
        for bad in ["nan", "NaN", "inf", "-inf", "1e400", "abc", "", "1,5"] {
            assert!(positive(bad).is_err(), "{bad}");
            assert!(extent(bad).is_err(), "{bad}");
            assert!(seconds(bad).is_err(), "{bad}");
        }
        assert!(positive("0").is_err() && positive("-1").is_err());
        assert_eq!(positive("2e3"), Ok(2000.0));
        assert_eq!(extent("0"), Ok(0.0));
        assert_eq!(extent("4000"), Ok(4000.0));
        assert!(extent("-0.5").is_err() && extent("1e300").is_err() && extent("1e-300").is_err());
        assert!(budget_fraction("0").is_err() && budget_fraction("1.5").is_err());
        assert_eq!(budget_fraction("1"), Ok(1.0));
        assert!(open_fraction("1").is_err() && open_fraction("0").is_err());
        assert!(seconds("-1").is_err() && seconds("1e30").is_err() && seconds("0").is_err());
        assert_eq!(seconds("60"), Ok(60.0));
        assert_eq!(port("0"), Ok(0));
        assert!(port("-1").is_err() && port("65536").is_err() && port("nan").is_err());
        assert_eq!(young("2.5").as_deref(), Ok("2.5"));
        assert_eq!(young("210GPa").as_deref(), Ok("210GPa"));
        for bad in [
            "nan", "inf", "-1", "0", "210kg/m3", "-210GPa", "1e30GPa", "abc",
        ] {
            assert!(young(bad).is_err(), "{bad}");
        }
        assert!(
            young("nan")
                .unwrap_err()
                .contains("must be a finite number")
        );
        assert!(physical(Opt::Density)("7850kg/m3").is_ok());
        assert!(physical(Opt::Density)("-1kg/m3").is_err());
        assert!(physical(Opt::Units)("inch").is_err());
        assert!(physical(Opt::Gravity)("1e9").is_err());
        assert!(
            positive("-1")
                .unwrap_err()
                .contains("must be a positive number")
        );
    }
}

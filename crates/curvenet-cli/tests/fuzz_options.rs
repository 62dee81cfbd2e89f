//! Every numeric option of every subcommand, driven with hostile values on the real binary:
//! negative, zero, NaN, infinite, huge, not a number at all. The binary must never panic (exit
//! 101) or die by a signal: an illegal value exits 2 with a message naming the option, before
//! any work; a legal one exits 0, or 2 with a message naming the option when the value makes
//! no sense for these inputs (a radius whose stiffness overflows, an edge length that would
//! make a network of billions of vertices).
//!
//! Fast by construction: every base command runs on tiny inputs (a 2 × 2 grid of straight
//! curves, three geodesics on a built-in dome, the roof's analysis only), illegal values are
//! refused while the command line is parsed, and the generated legal values are small counts
//! or huge lengths, which make small networks. Two tests: a sweep of every option against one
//! value of each hostile kind, and a property test with random values of those kinds
//! (`FUZZ_CASES` cases, 64 by default).

mod common;

use common::{BIN, GRID};
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// What an option's values must be (the contract the help states).
#[derive(Clone, Copy, Debug)]
enum Rule {
    /// A finite number above 0.
    Positive,
    /// 0, or an extent in [1e-12, 1e15].
    Extent,
    /// A budget fraction, in (0, 1].
    Fraction,
    /// Strictly between 0 and 1.
    OpenFraction,
    /// Seconds, in (0, 1e9].
    Seconds,
    /// An integer in the range.
    Count(u64, u64),
    /// Comma-separated integers, each in the range.
    Counts(u64, u64),
    /// Any 32-bit unsigned integer (a seed).
    Seed,
    /// Comma-separated curve ids (each below the grid's 4 curves, or the run is refused).
    Ids,
    /// A quantity that needs its unit suffix (`7850kg/m3`) or a section (`60x4`): no hostile
    /// value (bare numbers, garbage) is one.
    WithUnit,
    /// Gravity along -z, m/s²: 0, or in [1e-6, 1e4].
    Gravity,
    /// A TCP port: 0 to 65535.
    Port,
}

impl Rule {
    /// Whether `value` is legal. A legal value may still be refused for the inputs at hand
    /// (exit 2 naming the option); an illegal one must be.
    fn legal(self, value: &str) -> bool {
        let float = value.trim().parse::<f64>().ok().filter(|v| v.is_finite());
        let int = value.parse::<u64>().ok();
        match self {
            Rule::Positive => float.is_some_and(|v| v > 0.0),
            Rule::Extent => float.is_some_and(|v| v == 0.0 || (1e-12..=1e15).contains(&v)),
            Rule::Fraction => float.is_some_and(|v| v > 0.0 && v <= 1.0),
            Rule::OpenFraction => float.is_some_and(|v| v > 0.0 && v < 1.0),
            Rule::Seconds => float.is_some_and(|v| v > 0.0 && v <= 1e9),
            Rule::Count(lo, hi) => int.is_some_and(|v| (lo..=hi).contains(&v)),
            Rule::Counts(lo, hi) => value
                .split(',')
                .all(|s| s.parse::<u64>().is_ok_and(|v| (lo..=hi).contains(&v))),
            // Seeds go through clap's own integer parser, which reads "-0" as 0.
            Rule::Seed => value
                .parse::<i64>()
                .is_ok_and(|v| (0..=u32::MAX as i64).contains(&v)),
            Rule::Ids => value.split(',').all(|s| s.parse::<usize>().is_ok()),
            Rule::WithUnit => false,
            Rule::Gravity => float.is_some_and(|v| v == 0.0 || (1e-6..=1e4).contains(&v)),
            Rule::Port => value.parse::<u16>().is_ok(),
        }
    }
}

/// One numeric option of one subcommand, with the command it is tried in.
struct Opt {
    /// The option, e.g. `--scale`.
    name: &'static str,
    /// Its rule.
    rule: Rule,
    /// The base command (the option is appended; an option of the base with the same name is
    /// left out). `{dir}` is the case's folder, `{run}` a finished run folder.
    base: &'static [&'static str],
    /// Legal values end in another usage error (the bench's unknown example, a curve the
    /// input does not have): the message to expect instead of the option's name.
    legal_refusal: Option<&'static str>,
}

const ANALYZE: &[&str] = &[
    "analyze",
    "--curves",
    "grid.txt",
    "--radius",
    "0.01",
    "--edge-length",
    "0.25",
];
const ANALYZE_PHYSICAL: &[&str] = &[
    "analyze",
    "--curves",
    "grid.txt",
    "--radius",
    "0.01",
    "--edge-length",
    "0.25",
    "--units",
    "m",
];
const SIMPLIFY: &[&str] = &[
    "simplify",
    "--curves",
    "grid.txt",
    "--radius",
    "0.01",
    "--edge-length",
    "0.25",
    "--budget",
    "0.6",
    "--out",
    "out",
];
const SIMPLIFY_CERT: &[&str] = &[
    "simplify",
    "--curves",
    "grid.txt",
    "--radius",
    "0.01",
    "--edge-length",
    "0.25",
    "--budget",
    "0.6",
    "--certify",
    "--out",
    "out",
];
const EXAMPLE: &[&str] = &["example", "roof", "--analyze-only", "--json"];
const DEMO: &[&str] = &["demo", "--geodesics", "3", "--out", "out"];
const TRACE: &[&str] = &[
    "trace",
    "--mesh",
    "dome",
    "--geodesics",
    "2",
    "--out",
    "x.json",
];
const STREAMLINES: &[&str] = &[
    "trace", "--mesh", "hill", "--field", "2", "--seeds", "8", "--out", "x.json",
];
const COMPARE: &[&str] = &[
    "compare",
    "--sizes",
    "5",
    "--instances",
    "1",
    "--surfaces",
    "dome",
];
const BENCH: &[&str] = &["bench", "--examples", "nosuch"];
const EXPORT: &[&str] = &["export", "{run}", "--out", "exported"];
/// Compare's generalisation measurement, stopped by a surface it does not know.
const FRESH: &[&str] = &["compare", "--surfaces", "nosuch"];
/// `serve --bench` (it listens on nothing) on the grid, stopped by a curve the grid lacks:
/// every legal value of the other options is read and checked first.
#[cfg(feature = "serve")]
const SERVE: &[&str] = &[
    "serve",
    "--curves",
    "grid.txt",
    "--radius",
    "0.01",
    "--edge-length",
    "0.25",
    "--bench",
    "--bench-removals",
    "1",
    "--remove",
    "9",
];
/// `serve` listening on a port, stopped by a curve the grid lacks.
#[cfg(feature = "serve")]
const SERVE_PORT: &[&str] = &[
    "serve", "--curves", "grid.txt", "--port", "0", "--remove", "9",
];
/// `example` and `demo` stopped, once their options are read, by a name they do not know: the
/// options they share with `simplify` (constraints, alternatives, the certificate's nodes) run
/// there with their legal values; here they are checked as these commands read them.
const EXAMPLE_UNKNOWN: &[&str] = &["example", "nosuch", "--out", "out"];
const DEMO_UNKNOWN: &[&str] = &["demo", "--surface", "nosuch", "--out", "out"];

/// Every numeric option of every subcommand.
fn options() -> Vec<Opt> {
    use Rule::*;
    let o = |name, rule, base| Opt {
        name,
        rule,
        base,
        legal_refusal: None,
    };
    let mut all = vec![
        o("--scale", Positive, ANALYZE),
        o("--edge-length", Positive, ANALYZE),
        o("--radius", Positive, ANALYZE),
        o("--young", Positive, ANALYZE),
        o("--anchor-weight", Positive, ANALYZE),
        o("--eigen-count", Count(1, 100), ANALYZE),
        o("--merge-joints", OpenFraction, ANALYZE),
        o("--remove", Ids, ANALYZE),
        o("--young", WithUnit, ANALYZE_PHYSICAL),
        o("--density", WithUnit, ANALYZE_PHYSICAL),
        o("--strength", WithUnit, ANALYZE_PHYSICAL),
        o("--load", WithUnit, ANALYZE_PHYSICAL),
        o("--tube", WithUnit, ANALYZE_PHYSICAL),
        o("--gravity", Gravity, ANALYZE_PHYSICAL),
        o("--radius", Positive, ANALYZE_PHYSICAL),
        o("--budget", Fraction, SIMPLIFY),
        o("--budget-length", Positive, SIMPLIFY),
        o("--keep", Ids, SIMPLIFY),
        o("--min-curves", Count(1, 1_000_000), SIMPLIFY),
        o("--max-gap", Positive, SIMPLIFY),
        o("--max-deviation", Positive, SIMPLIFY),
        o("--certificate-nodes", Count(0, 100_000), SIMPLIFY_CERT),
        o("--budget", Fraction, EXAMPLE),
        o("--certificate-nodes", Count(0, 100_000), EXAMPLE),
        o("--eigen-count", Count(1, 100), EXAMPLE),
        o("--geodesics", Count(1, 10_000), DEMO),
        o("--seed", Seed, DEMO),
        o("--edge-length", Positive, DEMO),
        o("--budget", Fraction, DEMO),
        o("--geodesics", Count(1, 100_000), TRACE),
        o("--seed", Seed, TRACE),
        o("--extent", Extent, TRACE),
        o("--seeds", Count(1, 100_000), STREAMLINES),
        o("--field", Count(2, 3), STREAMLINES),
        o("--sizes", Counts(2, 30), COMPARE),
        o("--instances", Count(1, 10_000), COMPARE),
        o("--budget", Fraction, COMPARE),
        o("--seed", Seed, COMPARE),
        o("--exact-time-limit", Seconds, COMPARE),
        Opt {
            name: "--repeat",
            rule: Count(1, 1000),
            base: BENCH,
            legal_refusal: Some("unknown example 'nosuch'"),
        },
        Opt {
            name: "--threads",
            rule: Count(1, 1024),
            base: BENCH,
            legal_refusal: Some("unknown example 'nosuch'"),
        },
        Opt {
            name: "--modes",
            rule: Count(1, 64),
            base: BENCH,
            legal_refusal: Some("unknown example 'nosuch'"),
        },
        o("--iteration", Ids, EXPORT),
        o("--alternative", Count(1, 100), EXPORT),
        Opt {
            name: "--fresh",
            rule: Count(1, 10_000),
            base: FRESH,
            legal_refusal: Some("nosuch"),
        },
        o("--alternatives", Count(0, 100), SIMPLIFY),
        o("--alternatives", Count(0, 100), DEMO),
    ];
    let unknown = |name, rule, base, refusal| Opt {
        name,
        rule,
        base,
        legal_refusal: Some(refusal),
    };
    for (base, refusal) in [
        (EXAMPLE_UNKNOWN, "unknown example 'nosuch'"),
        (DEMO_UNKNOWN, "unknown built-in surface 'nosuch'"),
    ] {
        all.extend([
            unknown("--alternatives", Count(0, 100), base, refusal),
            unknown("--min-curves", Count(1, 1_000_000), base, refusal),
            unknown("--max-gap", Positive, base, refusal),
            unknown("--max-deviation", Positive, base, refusal),
            unknown("--certificate-nodes", Count(0, 100_000), base, refusal),
        ]);
    }
    #[cfg(feature = "serve")]
    {
        let refused = |name, rule, base| Opt {
            name,
            rule,
            base,
            legal_refusal: Some("--remove names curve 9"),
        };
        all.extend([
            refused("--port", Port, SERVE_PORT),
            refused("--bench-removals", Count(1, 1000), SERVE),
            refused("--scale", Positive, SERVE),
            refused("--edge-length", Positive, SERVE),
            refused("--radius", Positive, SERVE),
            refused("--young", Positive, SERVE),
            refused("--anchor-weight", Positive, SERVE),
            refused("--eigen-count", Count(1, 100), SERVE),
            refused("--merge-joints", OpenFraction, SERVE),
            // Legal curve ids are served in the benchmark (or refused, naming --remove).
            o("--remove", Ids, SERVE),
        ]);
    }
    all
}

/// One value of each hostile kind.
const SWEEP: &[&str] = &[
    "-1",
    "-0.5",
    "0",
    "NaN",
    "inf",
    "-inf",
    "1e30",
    "1e300",
    "1e-300",
    "1e400",
    "18446744073709551616",
    "abc",
    "",
    "1,,2",
    // Values with a unit suffix: hostile for the options written with one, garbage for the
    // others.
    "1e-300kg/m3",
    "-1GPa",
    "nanMPa",
    "1e400MPa",
    "0MPa",
];

/// A finished run folder of the grid (for `export --iteration`), made once.
fn run_folder() -> &'static Path {
    static RUN: OnceLock<PathBuf> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = temp("run");
        std::fs::write(dir.join("grid.txt"), GRID).unwrap();
        let out = Command::new(BIN)
            .args(SIMPLIFY)
            .current_dir(&dir)
            .output()
            .expect("simplify runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        dir.join("out")
    })
}

/// A fresh temporary folder.
fn temp(tag: &str) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static N: AtomicUsize = AtomicUsize::new(0);
    let n = N.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!(
        "curvenet-fuzz-options-{}-{tag}-{n}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `opt` with `value` and checks the outcome; `Err` describes a failure.
fn check(opt: &Opt, value: &str) -> Result<(), String> {
    let dir = temp("case");
    std::fs::write(dir.join("grid.txt"), GRID).unwrap();
    let run = run_folder().display().to_string();
    let mut args: Vec<String> = Vec::new();
    let mut skip = false;
    for a in opt.base {
        if skip {
            skip = false;
            continue;
        }
        if *a == opt.name {
            skip = true;
            continue;
        }
        args.push(a.replace("{run}", &run));
    }
    // As a user types it (`--scale -1`), or with `=` for the empty value.
    if value.is_empty() {
        args.push(format!("{}=", opt.name));
    } else {
        args.push(opt.name.to_string());
        args.push(value.to_string());
    }
    let start = Instant::now();
    let out = Command::new(BIN)
        .args(&args)
        .current_dir(&dir)
        .output()
        .expect("the binary runs");
    let took = start.elapsed();
    let _ = std::fs::remove_dir_all(&dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let context = format!(
        "curvenet {}\nexit {:?}\n{stderr}",
        args.join(" "),
        out.status.code()
    );
    let Some(code) = out.status.code() else {
        return Err(format!("killed by a signal: {context}"));
    };
    if stderr.contains("panicked") || code == 101 {
        return Err(format!("panic: {context}"));
    }
    if took > Duration::from_secs(30) {
        return Err(format!("took {took:?}: {context}"));
    }
    let legal = opt.rule.legal(value);
    let want = match (legal, opt.legal_refusal) {
        (true, Some(m)) => m,
        _ => opt.name,
    };
    match code {
        0 if legal && opt.legal_refusal.is_none() => Ok(()),
        2 if stderr.contains(want) => Ok(()),
        // A legal value that makes no sense for the inputs, refused naming the option.
        2 if legal && stderr.contains(opt.name) => Ok(()),
        2 => Err(format!("the message does not name `{want}`: {context}")),
        _ => Err(format!(
            "unexpected exit code for a{} value: {context}",
            if legal { " legal" } else { "n illegal" }
        )),
    }
}

#[test]
fn every_numeric_option_refuses_every_kind_of_hostile_value() {
    let start = Instant::now();
    let mut failures = Vec::new();
    let mut runs = 0;
    for opt in options() {
        for value in SWEEP {
            runs += 1;
            if let Err(e) = check(&opt, value) {
                failures.push(e);
            }
        }
    }
    println!("{runs} runs in {:.1} s", start.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// A hostile value: negative, zero, NaN, infinite, huge, tiny, a small count, or garbage.
fn hostile() -> impl Strategy<Value = String> {
    prop_oneof![
        (1e-300f64..1e300).prop_map(|v| format!("-{v}")),
        (1u64..u64::MAX).prop_map(|v| format!("-{v}")),
        Just("0".to_string()),
        Just("-0".to_string()),
        Just("nan".to_string()),
        Just("infinity".to_string()),
        Just("-inf".to_string()),
        (1e15f64..1e300).prop_map(|v| format!("{v:e}")),
        (1e-300f64..1e-15).prop_map(|v| format!("{v:e}")),
        (u64::MAX as u128 + 1..u128::MAX).prop_map(|v| v.to_string()),
        (1u64..4).prop_map(|v| v.to_string()),
        "[a-z%#,.+-]{0,6}",
        "[0-9]{1,3}[,.;][0-9e]{0,3}",
    ]
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: std::env::var("FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(64),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_hostile_values_never_panic(index in 0usize..1000, value in hostile()) {
        let opts = options();
        let opt = &opts[index % opts.len()];
        if let Err(e) = check(opt, &value) {
            prop_assert!(false, "{}", e);
        }
    }
}

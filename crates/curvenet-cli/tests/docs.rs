//! The numbers the documentation states come from commands this test runs, so they cannot
//! drift from what the tool does.
//!
//! A claim in `docs/*.md` carries, right after it, a check the rendered page does not show (an
//! HTML comment):
//!
//! ```text
//! <!-- check
//! write: pairs.txt p0: 0 1\np1: 2 3
//! run: demo --surface stadium --budget 0.2 --min-curves 3 --local-search --out minc
//! expect: minc/result.json answer.curves = [2, 14, 22] as "curves 2, 14 and 22"
//! expect: minc/result.json answer.lambda ~ 3.63e-6
//! expect: minc/result.json answer.margins.budget.value / answer.margins.budget.limit ~ 60%
//! expect: stderr contains "a warning the page quotes"
//! -->
//! ```
//!
//! - `write: NAME TEXT` writes `TEXT` (`\n` for a newline) to `NAME` in the check's own fresh
//!   folder; `run: ARGS` runs `curvenet ARGS` there (split at spaces), which must succeed.
//! - `expect: SOURCE …` checks what the last run printed (`stdout`, `stderr`, or `stdout.json`
//!   for the JSON on its stdout) or a file it wrote (`DIR/FILE.json` read as JSON, any other
//!   file as text):
//!   - `PATH = VALUE`: the JSON value at `PATH` (keys joined by `.`, `[i]` an element, a
//!     trailing `#` the length of an array) equals `VALUE` (JSON);
//!   - `PATH ~ NUMBER` (or `PATH / PATH ~ NUMBER`, a ratio): the value, rounded to the digits
//!     `NUMBER` is written with, is `NUMBER` (`1.89e-8`, `26,393`, `45%` for a ratio ×100);
//!   - `contains "TEXT"`: the text holds `TEXT`.
//!
//!   And the page must say it: the stated value as written (`1.89e-8`, `45%`; the `TEXT` of
//!   `contains`), or the text after `as` (`as "three crossing curves"`; `as -`: nothing to
//!   find), must appear in the page's lines around the check (the paragraph, caption or table
//!   it follows, the paragraph after it). A claim edited without its check, or a tool whose
//!   numbers changed, fails here.
//!
//! Checks run two at a time, those with the same steps on one run; each is a second or a few
//! of the release build.

mod common;

use common::{BIN, TempDir};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The page's lines above a check where it must state what it checks (checks' own lines not
/// counted)…
const PROSE_LINES: usize = 30;
/// … and below it.
const PROSE_LINES_BELOW: usize = 12;

/// One `<!-- check … -->` block.
#[derive(Debug)]
struct Check {
    /// `docs/NAME.md:LINE` of the block.
    place: String,
    steps: Vec<Step>,
    expects: Vec<(usize, String)>,
    /// The page's lines just above the block.
    prose: String,
}

#[derive(Debug)]
enum Step {
    Write(String, String),
    Run(Vec<String>),
}

fn docs_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs")
}

/// Every check of `docs/NAME.md`.
fn checks_of(name: &str) -> Vec<Check> {
    let text = std::fs::read_to_string(docs_dir().join(name)).expect("the page reads");
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut k = 0;
    while k < lines.len() {
        if lines[k].trim() != "<!-- check" {
            k += 1;
            continue;
        }
        let start = k;
        // The page's own text just above: earlier checks' lines are not prose (checks may
        // follow one another under one table).
        let mut above: Vec<&str> = Vec::new();
        let mut inside = false;
        for l in lines[..start].iter().rev() {
            if l.trim() == "-->" {
                inside = true;
            } else if inside && l.trim() == "<!-- check" {
                inside = false;
            } else if !inside {
                above.push(l);
                if above.len() == PROSE_LINES {
                    break;
                }
            }
        }
        let mut prose: String = above.iter().rev().map(|l| format!("{l}\n")).collect();
        // And the page's text just below (a paragraph after the checks of a table).
        let mut below = 0;
        let mut inside = true;
        for l in &lines[start..] {
            if l.trim() == "<!-- check" {
                inside = true;
            } else if inside && l.trim() == "-->" {
                inside = false;
            } else if !inside {
                prose.push_str(l);
                prose.push('\n');
                below += 1;
                if below == PROSE_LINES_BELOW {
                    break;
                }
            }
        }
        let mut check = Check {
            place: format!("docs/{name}:{}", start + 1),
            steps: Vec::new(),
            expects: Vec::new(),
            prose,
        };
        k += 1;
        while k < lines.len() && lines[k].trim() != "-->" {
            let l = lines[k].trim();
            if let Some(rest) = l.strip_prefix("run:") {
                check.steps.push(Step::Run(
                    rest.split_whitespace().map(str::to_string).collect(),
                ));
            } else if let Some(rest) = l.strip_prefix("write:") {
                let (file, content) = rest.trim().split_once(' ').expect("write: NAME TEXT");
                check
                    .steps
                    .push(Step::Write(file.to_string(), content.replace("\\n", "\n")));
            } else if let Some(rest) = l.strip_prefix("expect:") {
                check.expects.push((k + 1, rest.trim().to_string()));
            } else if !l.is_empty() {
                panic!("docs/{name}:{}: not a check line: {l}", k + 1);
            }
            k += 1;
        }
        assert!(k < lines.len(), "{}: the check is not closed", check.place);
        out.push(check);
        k += 1;
    }
    out
}

/// What the last run of a check printed, and its folder.
struct Ran {
    dir: PathBuf,
    stdout: String,
    stderr: String,
}

/// Runs a check's steps; `Err` says which failed.
fn run(check: &Check, dir: &Path) -> Result<Ran, String> {
    let mut ran = Ran {
        dir: dir.to_path_buf(),
        stdout: String::new(),
        stderr: String::new(),
    };
    for step in &check.steps {
        match step {
            Step::Write(file, content) => {
                std::fs::write(dir.join(file), content).map_err(|e| format!("{file}: {e}"))?;
            }
            Step::Run(args) => {
                let o = Command::new(BIN)
                    .args(args)
                    .current_dir(dir)
                    .output()
                    .map_err(|e| e.to_string())?;
                ran.stdout = String::from_utf8_lossy(&o.stdout).into_owned();
                ran.stderr = String::from_utf8_lossy(&o.stderr).into_owned();
                if !o.status.success() {
                    return Err(format!(
                        "`curvenet {}` failed ({}): {}",
                        args.join(" "),
                        o.status,
                        ran.stderr
                    ));
                }
            }
        }
    }
    Ok(ran)
}

/// The text after `as` in quotes (`Some("")` for `as -`), and the expectation before it.
fn split_as(e: &str) -> (&str, Option<String>) {
    match e.rfind(" as ") {
        Some(i) if e[i + 4..].trim_start().starts_with('"') || e[i + 4..].trim() == "-" => {
            let said = e[i + 4..].trim();
            let said = if said == "-" {
                String::new()
            } else {
                said.trim_matches('"').to_string()
            };
            (&e[..i], Some(said))
        }
        _ => (e, None),
    }
}

/// The JSON value at `path` of `v` (`a.b[2].c`, a trailing `#`: the array's length).
fn at(v: &Value, path: &str) -> Result<Value, String> {
    let (path, count) = match path.strip_suffix('#') {
        Some(p) => (p, true),
        None => (path, false),
    };
    let mut cur = v;
    for part in path.split('.') {
        let (key, indices) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if !key.is_empty() {
            cur = cur
                .get(key)
                .ok_or_else(|| format!("no `{key}` in `{path}`"))?;
        }
        for index in indices.split('[').skip(1) {
            let i: usize = index
                .trim_end_matches(']')
                .parse()
                .map_err(|_| format!("bad index in `{path}`"))?;
            cur = cur.get(i).ok_or_else(|| format!("no [{i}] in `{path}`"))?;
        }
    }
    if count {
        let n = cur
            .as_array()
            .ok_or_else(|| format!("`{path}` is not an array"))?
            .len();
        return Ok(Value::from(n));
    }
    Ok(cur.clone())
}

/// Whether `actual` rounds to `written` (a number as a page writes it: `1.89e-8`, `26,393`,
/// `0.0099`) at the digits it is written with.
fn rounds_to(actual: f64, written: &str) -> Result<bool, String> {
    let plain = written.replace(',', "");
    let stated: f64 = plain
        .parse()
        .map_err(|_| format!("`{written}` is not a number"))?;
    let mantissa = plain
        .split(['e', 'E'])
        .next()
        .unwrap_or("")
        .trim_start_matches('-');
    let significant = mantissa
        .chars()
        .filter(char::is_ascii_digit)
        .collect::<String>();
    let significant = significant.trim_start_matches('0');
    // An integer's trailing zeros hold its place, not its precision (`26,400`: three digits).
    let significant = if mantissa.contains('.') {
        significant
    } else {
        significant.trim_end_matches('0')
    };
    let digits = significant.len().max(1);
    let rounded: f64 = format!("{:.*e}", digits - 1, actual).parse().unwrap();
    Ok((rounded - stated).abs() <= 1e-9 * stated.abs().max(f64::MIN_POSITIVE))
}

/// Checks one expectation against what the check's last run gave.
fn expect(ran: &Ran, e: &str, prose: &str) -> Result<(), String> {
    let (e, said) = split_as(e);
    let (source, rest) = e.split_once(' ').ok_or("an expectation needs a source")?;
    let text = |source: &str| -> Result<String, String> {
        match source {
            "stdout" => Ok(ran.stdout.clone()),
            "stderr" => Ok(ran.stderr.clone()),
            file => std::fs::read_to_string(ran.dir.join(file)).map_err(|e| format!("{file}: {e}")),
        }
    };
    let json = |source: &str| -> Result<Value, String> {
        let t = match source {
            "stdout.json" => ran.stdout.clone(),
            file => text(file)?,
        };
        serde_json::from_str(&t).map_err(|e| format!("{source}: not JSON: {e}"))
    };
    let stated = if let Some(quoted) = rest.strip_prefix("contains ") {
        let wanted = quoted.trim().trim_matches('"');
        let t = text(source)?;
        if !t.contains(wanted) {
            return Err(format!("{source} lacks {wanted:?}; it holds:\n{t}"));
        }
        wanted.to_string()
    } else if let Some((path, value)) = rest.split_once(" = ") {
        let v = at(&json(source)?, path.trim())?;
        let want: Value = serde_json::from_str(value.trim())
            .map_err(|_| format!("`{}` is not JSON", value.trim()))?;
        if v != want {
            return Err(format!("{source} {path} is {v}, the page says {want}"));
        }
        value.trim().to_string()
    } else if let Some((expr, value)) = rest.split_once(" ~ ") {
        let doc = json(source)?;
        let number = |p: &str| -> Result<f64, String> {
            at(&doc, p.trim())?
                .as_f64()
                .ok_or_else(|| format!("`{p}` is not a number"))
        };
        let mut actual = match expr.split_once(" / ") {
            Some((a, b)) => number(a)? / number(b)?,
            None => number(expr)?,
        };
        let value = value.trim();
        let written = match value.strip_suffix('%') {
            Some(v) => {
                actual *= 100.0;
                v
            }
            None => value,
        };
        if !rounds_to(actual, written)? {
            return Err(format!(
                "{source} {expr} is {actual}, the page says {value}"
            ));
        }
        value.to_string()
    } else {
        return Err(format!("not an expectation: {rest}"));
    };
    let said = said.unwrap_or(stated);
    // Lines wrap anywhere in a paragraph: compared with their whitespace folded.
    let fold = |t: &str| t.split_whitespace().collect::<Vec<_>>().join(" ");
    if !said.is_empty() && !fold(prose).contains(&fold(&said)) {
        return Err(format!(
            "the page does not say {said:?} in the lines around the check"
        ));
    }
    Ok(())
}

/// Runs every check of the pages, two commands at a time (checks with the same steps share
/// one run); the failures, each with its place.
fn run_all(checks: &[Check]) -> Vec<String> {
    let mut groups: Vec<Vec<&Check>> = Vec::new();
    for c in checks {
        let key = format!("{:?}", c.steps);
        match groups
            .iter_mut()
            .find(|g| format!("{:?}", g[0].steps) == key)
        {
            Some(g) => g.push(c),
            None => groups.push(vec![c]),
        }
    }
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(group) = groups.get(i) else { break };
                    let dir = TempDir::new("docs");
                    let fail = |line: String, why: String| {
                        failures.lock().unwrap().push(format!("{line}: {why}"));
                    };
                    let started = std::time::Instant::now();
                    let ran = run(group[0], &dir.0);
                    eprintln!(
                        "{}: {:.1} s",
                        group[0].place,
                        started.elapsed().as_secs_f64()
                    );
                    for check in group {
                        match &ran {
                            Err(why) => fail(check.place.clone(), why.clone()),
                            Ok(ran) => {
                                for (line, e) in &check.expects {
                                    if let Err(why) = expect(ran, e, &check.prose) {
                                        let file = check.place.rsplit_once(':').unwrap().0;
                                        fail(format!("{file}:{line}"), why);
                                    }
                                }
                            }
                        }
                    }
                }
            });
        }
    });
    failures.into_inner().unwrap()
}

#[test]
fn the_harness_reads_numbers_as_pages_write_them() {
    assert!(rounds_to(1.890923e-8, "1.89e-8").unwrap());
    assert!(!rounds_to(1.890923e-8, "1.88e-8").unwrap());
    assert!(rounds_to(26393.1, "26,393").unwrap());
    assert!(rounds_to(0.010568, "0.0106").unwrap());
    assert!(rounds_to(330.36, "330").unwrap());
    assert!(rounds_to(26393.1, "26,400").unwrap());
    assert!(!rounds_to(336.6, "330").unwrap());
    assert!(rounds_to(0.5596, "0.560").unwrap());
    let v: Value = serde_json::from_str(r#"{"a": {"b": [1, {"c": 2.5}]}}"#).unwrap();
    assert_eq!(at(&v, "a.b#").unwrap(), Value::from(2));
    assert_eq!(at(&v, "a.b[1].c").unwrap(), Value::from(2.5));
    assert!(at(&v, "a.x").is_err());
    assert_eq!(
        split_as(r#"f x = [1] as "one""#),
        ("f x = [1]", Some("one".to_string()))
    );
}

#[test]
fn the_pages_state_what_the_tool_gives() {
    let mut pages: Vec<String> = std::fs::read_dir(docs_dir())
        .expect("docs/")
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .collect();
    pages.sort();
    let mut checks = Vec::new();
    for page in &pages {
        let found = checks_of(page);
        if ["constraints.md", "units.md"].contains(&page.as_str()) {
            assert!(
                found.len() >= 5,
                "docs/{page} has {} checks: its numbers are not checked",
                found.len()
            );
        }
        checks.extend(found);
    }
    let failures = run_all(&checks);
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}

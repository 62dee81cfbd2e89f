//! What a user reads points to nothing they do not have: the `--help` of every subcommand, the
//! README and the documents in `docs/` name no design document ("SPEC §…") and no issue
//! ("issue 8"), and the paper's example data keeps its licence visible (`example --license`).

mod common;

use common::BIN;
use std::path::Path;
use std::process::Command;

/// The places in `text` that point outside the repository: the word `SPEC` (not a longer
/// identifier such as `SPECTRUM_TOL`) and `issue N` / `issue #N`, any case.
fn outside_references(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let spec = line.match_indices("SPEC").any(|(i, _)| {
            let next = line[i + 4..].chars().next();
            let prev = line[..i].chars().next_back();
            !next.is_some_and(|c| c.is_ascii_uppercase() || c == '_')
                && !prev.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
        });
        let lower = line.to_lowercase();
        let issue = lower.match_indices("issue").any(|(i, _)| {
            let rest = lower[i + 5..].trim_start_matches('s');
            let rest = rest.strip_prefix(' ').unwrap_or("");
            let rest = rest.strip_prefix('#').unwrap_or(rest);
            rest.starts_with(|c: char| c.is_ascii_digit())
        });
        if spec || issue {
            found.push(format!("line {}: {line}", n + 1));
        }
    }
    found
}

#[test]
fn the_guard_finds_what_it_should() {
    assert_eq!(outside_references("see SPEC §9").len(), 1);
    assert_eq!(outside_references("the SPEC's tie rule").len(), 1);
    assert_eq!(outside_references("fixed in issue 4").len(), 1);
    assert_eq!(outside_references("Issue #12 says").len(), 1);
    assert!(outside_references("SPECTRUM_TOL and SPEC_X").is_empty());
    assert!(outside_references("an issue with 3 curves? issues: none").is_empty());
}

/// The subcommands `curvenet --help` lists.
fn subcommands() -> Vec<String> {
    let out = Command::new(BIN).arg("--help").output().expect("runs");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let list: Vec<String> = text
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|c| c != "help")
        .collect();
    assert!(list.len() >= 10, "{text}");
    list
}

#[test]
fn help_and_docs_point_to_nothing_a_user_does_not_have() {
    let mut bad = Vec::new();
    let top = Command::new(BIN).arg("--help").output().expect("runs");
    bad.extend(
        outside_references(&String::from_utf8_lossy(&top.stdout))
            .into_iter()
            .map(|l| format!("curvenet --help {l}")),
    );
    for sub in subcommands() {
        let out = Command::new(BIN)
            .args([sub.as_str(), "--help"])
            .output()
            .expect("runs");
        assert_eq!(out.status.code(), Some(0), "{sub} --help");
        bad.extend(
            outside_references(&String::from_utf8_lossy(&out.stdout))
                .into_iter()
                .map(|l| format!("curvenet {sub} --help {l}")),
        );
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = vec![root.join("README.md")];
    let mut docs: Vec<_> = std::fs::read_dir(root.join("docs"))
        .expect("docs/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    assert!(!docs.is_empty());
    files.extend(docs);
    for f in files {
        let text = std::fs::read_to_string(&f).expect("readable");
        bad.extend(
            outside_references(&text)
                .into_iter()
                .map(|l| format!("{} {l}", f.display())),
        );
    }
    assert!(
        bad.is_empty(),
        "references a user cannot follow:\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_paper_data_licence_is_visible() {
    let out = Command::new(BIN)
        .args(["example", "--license"])
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("MIT License"), "{stdout}");
    assert!(stdout.contains("Copyright (c) 2022 wwwnev"), "{stdout}");
    assert!(
        stdout.contains("THE SOFTWARE IS PROVIDED \"AS IS\""),
        "{stdout}"
    );
    let help = Command::new(BIN)
        .args(["example", "--help"])
        .output()
        .expect("runs");
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(help.contains("example --license"), "{help}");
    assert!(help.contains("MIT"), "{help}");
    // The name is still required for a run.
    let none = Command::new(BIN).arg("example").output().expect("runs");
    assert_eq!(none.status.code(), Some(2));
}

/// The help gives the default edge length the application layer chooses (the curves'
/// lengths), not the median input segment it once was.
#[test]
fn the_help_gives_the_default_edge_length_the_library_chooses() {
    for sub in ["analyze", "simplify", "serve"] {
        let out = Command::new(BIN)
            .args([sub, "--help"])
            .output()
            .expect("runs");
        let help = String::from_utf8_lossy(&out.stdout)
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        let expected = format!(
            "the median curve's length over {}, and no less than the total length over 100,000",
            curvenet::pipeline::DEFAULT_EDGES_PER_CURVE
        );
        assert!(help.contains(&expected), "{sub}: {help}");
        assert!(!help.contains("segment"), "{sub}: {help}");
    }
}

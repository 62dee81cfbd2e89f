//! docs/benchmarks.md cannot drift from the code unnoticed: its generated sections keep their
//! markers (docs/tools/bench_tables.py rewrites the text between them), the reference times it
//! cites are a file `bench --reference` reads, its table of techniques names exactly the ones
//! `bench --off` takes, and the sections the code's comments and the other docs cite exist.
//! Reads files only: no run, no timing.

use curvenet::experiments::bench::References;
use curvenet::stability::Technique;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn doc() -> String {
    std::fs::read_to_string(repo().join("docs/benchmarks.md")).expect("docs/benchmarks.md")
}

#[test]
fn the_generated_sections_keep_their_markers() {
    let text = doc();
    for name in ["commands", "reference", "techniques"] {
        let begin = format!("<!-- bench_tables:{name} begin -->");
        let end = format!("<!-- bench_tables:{name} end -->");
        assert_eq!(text.matches(&begin).count(), 1, "{begin}");
        assert_eq!(text.matches(&end).count(), 1, "{end}");
        assert!(
            text.find(&begin) < text.find(&end),
            "{name}: end before begin"
        );
    }
}

#[test]
fn the_reference_times_are_a_file_bench_reads() {
    let refs = References::read(&repo().join("docs/tools/reference-times.json"))
        .expect("bench --reference reads docs/tools/reference-times.json");
    for name in ["tower", "arcshell", "shell"] {
        assert!(refs.0.contains_key(name), "{name} has no reference time");
    }
}

#[test]
fn the_techniques_table_names_every_technique_and_no_other() {
    let text = doc();
    let section = text
        .split("## What each technique contributes")
        .nth(1)
        .and_then(|s| s.split("<!-- bench_tables:techniques begin -->").next())
        .expect("the section *What each technique contributes* and its generated table");
    let listed: Vec<&str> = section
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .collect();
    let names: Vec<&str> = Technique::ALL.iter().map(|t| t.name()).collect();
    assert_eq!(
        listed, names,
        "the rows of the techniques' table, in `Technique::ALL`'s order"
    );
}

#[test]
fn the_sections_cited_elsewhere_exist() {
    let text = doc();
    let headings: Vec<&str> = text.lines().filter(|l| l.starts_with("## ")).collect();
    // Cited by docs/serve.md, docs/compare.md, README.md, the local search's and other
    // modules' comments, ARCHITECTURE.md.
    for cited in [
        "## Warm edits",
        "## Local search: where it starts",
        "## Sliding",
        "## What each technique contributes",
        "## Experiments tried and not kept",
        "## Figures behind the code's rules",
    ] {
        assert!(
            headings.iter().any(|h| h.starts_with(cited)),
            "docs/benchmarks.md lost its section {cited:?}"
        );
    }
}

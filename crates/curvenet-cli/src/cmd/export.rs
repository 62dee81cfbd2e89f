//! `curvenet export`: a recorded network of a run (an iteration, the answer, an alternative)
//! as OBJ, JSON, CSV, fabrication table or network file.

use crate::args::ExportArgs;
use crate::exit::{ExitError, usage};
use crate::front::{Flags, report_exit};
use curvenet::report::export::{ExportFormat, export_files, write_exports};
use curvenet::run_folder::{RunFolder, Which};
use std::path::Path;

pub fn run(a: ExportArgs) -> anyhow::Result<()> {
    let format: ExportFormat = a.format.parse().map_err(usage)?;
    let run = RunFolder::open(&a.dir).map_err(|e| usage(e.render(&Flags)))?;
    // Held to the end: no run starts writing here while the files are exported.
    let _lock = super::hold_run_folder(&a.dir, "export")?;
    super::print_warnings(&run.warnings);
    let k = match (a.answer, a.alternative) {
        (true, _) => Which::Answer,
        (false, Some(n)) => Which::Alternative(n),
        (false, None) => Which::Iteration(a.iteration.unwrap_or_else(|| run.last_index())),
    };
    // An iteration or alternative the run did not record is the option's fault: say which.
    let option = match k {
        Which::Iteration(_) if a.iteration.is_none() => "",
        Which::Iteration(_) => "--iteration: ",
        Which::Alternative(_) => "--alternative: ",
        Which::Answer => "--answer: ",
    };
    let shown = run
        .network_of(k)
        .map_err(|e| usage(format!("{option}{}", e.render(&Flags))))?;
    let internal = |message: String| ExitError { code: 1, message };
    let out = a.out.unwrap_or_else(|| a.dir.join("export"));
    // One file to a named path: one format and a path with an extension that is not an existing
    // folder get that format's main file (the first of `export_files`).
    let single = format != ExportFormat::All && out.extension().is_some() && !out.is_dir();
    if single {
        let files = export_files(&run, k, format).map_err(|e| report_exit(&e))?;
        let (_, text) = files
            .into_iter()
            .next()
            .ok_or_else(|| internal("nothing to export".into()))?;
        if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent)
                .map_err(|e| usage(format!("{}: {e}", parent.display())))?;
        }
        curvenet::io::write_atomic(&out, text.as_bytes())
            .map_err(|e| usage(format!("{}: {e}", out.display())))?;
        warn_unstable(&shown);
        println!("{}", out.display());
        return Ok(());
    }
    if out.is_file() {
        return Err(usage(format!(
            "{}: is a file; --out names a folder for this format",
            out.display()
        )));
    }
    let paths = write_exports(&run, k, format, Path::new(&out)).map_err(|e| report_exit(&e))?;
    eprintln!(
        "{}: {} curves, length {}, {} {:.6e}",
        shown.what,
        shown.curves.len(),
        super::fmt_length(shown.length),
        run.result.setup.stability.objective.value_symbol(),
        shown.lambda
    );
    warn_unstable(&shown);
    for p in paths {
        println!("{}", p.display());
    }
    Ok(())
}

/// The warning of an export of an unstable network (its files say so in their headers too).
fn warn_unstable(shown: &curvenet::run_folder::Chosen) {
    if let Some(w) = &shown.unstable {
        super::print_warnings(&[format!("{} is {w}: it cannot stand as built", shown.what)]);
    }
}

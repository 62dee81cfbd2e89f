//! `curvenet view`: the self-contained viewer page and the pictures of a run folder.

use crate::args::ViewArgs;
use crate::exit::usage;
use crate::front::{Flags, report_exit};
use curvenet::report::viewer::{ViewerOptions, write_pictures, write_viewer};
use curvenet::run_folder::RunFolder;

pub fn run(a: ViewArgs) -> anyhow::Result<()> {
    let run = RunFolder::open(&a.dir).map_err(|e| usage(e.render(&Flags)))?;
    // Held to the end: no run starts writing here while the pictures and the page are drawn.
    let _lock = super::hold_run_folder(&a.dir, "view")?;
    super::print_warnings(&run.warnings);
    if !a.no_pictures {
        for p in write_pictures(&run).map_err(|e| report_exit(&e))? {
            eprintln!("wrote {}", p.display());
        }
    }
    let path = a.output.unwrap_or_else(|| a.dir.join("viewer.html"));
    let options = ViewerOptions {
        gravity: !a.no_gravity,
    };
    write_viewer(&run, &path, &options).map_err(|e| report_exit(&e))?;
    println!("{}", path.display());
    if a.open {
        super::open_in_browser(&path.display().to_string());
    }
    Ok(())
}

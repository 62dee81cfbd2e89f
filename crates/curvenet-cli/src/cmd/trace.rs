//! `curvenet trace`: curves generated on a mesh, written to a curve file.

use crate::args::TraceArgs;
use crate::exit::usage;
use curvenet::io;
use curvenet::trace::{Generator, generate, scale_to_extent};

pub fn run(a: TraceArgs) -> anyhow::Result<()> {
    super::writable_file("--out", &a.out)?;
    if let Some(m) = &a.mesh_out {
        super::writable_file("--mesh-out", m)?;
    }
    let (input, description) = super::mesh_arg(&a.mesh)?;
    let (mesh, scale) = if a.extent > 0.0 {
        scale_to_extent(&input, a.extent)
    } else {
        (input.clone(), 1.0)
    };
    let generator = match (a.geodesics, a.field) {
        (Some(count), None) => Generator::Random {
            count,
            seed: a.seed,
        },
        (None, Some(f)) => Generator::Streamlines {
            degree: 2 * f,
            seeds: a.seeds,
        },
        _ => return Err(usage("give --geodesics N or --field 2|3")),
    };
    let out = generate(&mesh, &generator).map_err(|e| usage(format!("{}: {e}", description)))?;
    if out.curves.is_empty() {
        let why = out
            .failures
            .first()
            .map_or_else(String::new, |f| format!("; first failure: {f}"));
        return Err(usage(format!(
            "{}: no curve could be traced ({} attempt(s): {} rejected, {} failed{why}); try more \
             seeds, another seed or another surface",
            description, out.attempts, out.rejected, out.failed
        )));
    }
    super::print_warnings(&out.failures[..out.failures.len().min(5)]);
    let text = match a
        .out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("json") => io::curves_to_json(&out.curves),
        Some("obj") => io::curves_to_obj(&out.curves),
        Some("txt") => io::curves_to_reference_text(&out.curves),
        _ => {
            return Err(usage(format!(
                "{}: output must end in .json, .obj or .txt",
                a.out.display()
            )));
        }
    };
    io::write_atomic(&a.out, text.as_bytes())
        .map_err(|e| usage(format!("{}: {e}", a.out.display())))?;
    if let Some(m) = &a.mesh_out {
        io::write_atomic(m, io::mesh_to_obj(&mesh).as_bytes())
            .map_err(|e| usage(format!("{}: {e}", m.display())))?;
    }
    let total: f64 = out.curves.iter().map(|c| c.length()).sum();
    println!(
        "{}: {} curves ({} attempts, {} rejected, {} failed), total length {} at scale {}; written to {}",
        description,
        out.curves.len(),
        out.attempts,
        out.rejected,
        out.failed,
        super::fmt_length(total),
        super::fmt_length(scale),
        a.out.display()
    );
    Ok(())
}

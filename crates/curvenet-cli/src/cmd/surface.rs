//! Mesh arguments: a path to an OBJ file, or the name of a built-in surface.

use crate::exit::usage;
use curvenet::io::{self, TriMesh};
use curvenet::trace::{SURFACE_NAMES, builtin_surface};
use std::path::Path;

/// A mesh read from a file or made in code, with what the user should know about it.
pub struct MeshArg {
    /// The mesh (file units, or the built-in surface's own units).
    pub mesh: TriMesh,
    /// Where it came from (path or `builtin:NAME`).
    pub description: String,
    /// Reading warnings.
    pub warnings: Vec<String>,
}

/// Reads `arg`: an existing file is read as OBJ; otherwise `builtin:NAME` or a bare `NAME`
/// of a built-in surface (hill, tent, stadium, shell, dome, saddle, wave) is made in code.
pub fn read_mesh_arg(arg: &Path) -> anyhow::Result<MeshArg> {
    let text = arg.to_string_lossy();
    let name = text.strip_prefix("builtin:");
    if name.is_none() && arg.exists() {
        let file = io::read_mesh(arg)?;
        return Ok(MeshArg {
            mesh: file.mesh,
            description: arg.display().to_string(),
            warnings: file.warnings.iter().map(|w| w.to_string()).collect(),
        });
    }
    let name = name.unwrap_or(&text);
    match builtin_surface(name) {
        Some(mesh) => Ok(MeshArg {
            mesh,
            description: format!("builtin:{name}"),
            warnings: Vec::new(),
        }),
        None => Err(usage(format!(
            "{text}: no such file, and not a built-in surface (built-in: {})",
            SURFACE_NAMES.join(", ")
        ))),
    }
}

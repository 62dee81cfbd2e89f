//! Where the paper's input files come from: the copies embedded in curvenet, or a folder.
//!
//! The meshes and curves published with the authors' implementation (MIT License, Copyright
//! (c) 2022 wwwnev; the notice is `data/paper/LICENSE` in this crate, next to the files) are
//! embedded in the library with `include_bytes!` (2.7 MB), so the examples and `curvenet
//! compare`'s surfaces need no files of the user's. A [`DataSource::Folder`] with the same
//! layout (`meshes/`, `curves/`) overrides them (`--data DIR`).

use crate::io::{self, CurveFile, InputError, MeshFile};
use std::path::{Path, PathBuf};

/// The authors' MIT licence text, shipped with the embedded files.
pub const LICENSE: &str = include_str!("../../data/paper/LICENSE");

/// `(path, bytes)` of each file named, embedded from `data/paper`.
macro_rules! embed {
    ($($path:literal),* $(,)?) => {
        &[$(($path, include_bytes!(concat!("../../data/paper/", $path)))),*]
    };
}

/// The embedded files, by path relative to the data folder (`meshes/NAME.obj`,
/// `curves/NAME.txt`), in name order.
const FILES: &[(&str, &[u8])] = embed![
    "meshes/1wave.obj",
    "meshes/2waves.obj",
    "meshes/bunny_modified.obj",
    "meshes/half_sphere.obj",
    "meshes/hill.obj",
    "meshes/kagome.obj",
    "meshes/leaf.obj",
    "meshes/roof.obj",
    "meshes/shell.obj",
    "meshes/sine_disk.obj",
    "meshes/stadium.obj",
    "meshes/tent.obj",
    "meshes/tower.obj",
    "curves/hill_3.txt",
    "curves/kagome_114_regular.txt",
    "curves/roof_75.txt",
    "curves/shell_100.txt",
    "curves/shell_100_for_arcs.txt",
    "curves/shell_3.txt",
    "curves/shell_arcs.txt",
    "curves/shell_elipse.txt",
    "curves/tent_3_regular_curves.txt",
    "curves/tent_curves.txt",
    "curves/tower_32.txt",
    "curves/tower_top_ring.txt",
];

/// The paths of the embedded files (`meshes/…`, `curves/…`).
pub fn embedded_files() -> impl Iterator<Item = &'static str> {
    FILES.iter().map(|(p, _)| *p)
}

/// The bytes of an embedded file, by its path relative to the data folder.
pub fn embedded(path: &str) -> Option<&'static [u8]> {
    FILES.iter().find(|(p, _)| *p == path).map(|(_, b)| *b)
}

/// Where the paper's input files are read from.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum DataSource {
    /// The copies embedded in curvenet.
    #[default]
    Embedded,
    /// A folder holding `meshes/` and `curves/` (the layout of the embedded files).
    Folder(PathBuf),
}

impl DataSource {
    /// A folder if one is given, the embedded copies otherwise.
    pub fn folder_or_embedded(folder: Option<&Path>) -> Self {
        folder.map_or(DataSource::Embedded, |f| {
            DataSource::Folder(f.to_path_buf())
        })
    }

    /// Reads `meshes/{file}`. Messages name the file as `meshes/{file}` (embedded) or by its
    /// path in the folder.
    pub fn read_mesh(&self, file: &str) -> Result<MeshFile, InputError> {
        let rel = format!("meshes/{file}");
        match self {
            DataSource::Folder(dir) => io::read_mesh(&dir.join(&rel)),
            DataSource::Embedded => io::parse_obj_mesh(&embedded_text(&rel)?, &rel),
        }
    }

    /// Reads `curves/{file}` (the reference text format when embedded; any curve format in a
    /// folder, chosen by its extension).
    pub fn read_curves(&self, file: &str) -> Result<CurveFile, InputError> {
        let rel = format!("curves/{file}");
        match self {
            DataSource::Folder(dir) => io::read_curves(&dir.join(&rel)),
            DataSource::Embedded => io::parse_reference_curves(&embedded_text(&rel)?, &rel),
        }
    }

    /// Where the files come from, for messages: `the embedded copies` or the folder.
    pub fn describe(&self) -> String {
        match self {
            DataSource::Embedded => "the paper's data embedded in curvenet".to_string(),
            DataSource::Folder(dir) => dir.display().to_string(),
        }
    }
}

/// An embedded file as text, or an error naming it when there is no such file.
fn embedded_text(rel: &str) -> Result<String, InputError> {
    let bytes = embedded(rel).ok_or_else(|| InputError::Io {
        file: rel.to_string(),
        source: std::io::Error::new(
            std::io::ErrorKind::NotFound,
            "no such file among the paper's data embedded in curvenet",
        ),
    })?;
    String::from_utf8(bytes.to_vec())
        .map_err(|_| InputError::parse(rel, 0, "the embedded file is not valid UTF-8 text"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_embedded_file_parses_and_the_licence_is_the_authors() {
        for path in embedded_files() {
            let (kind, file) = path.split_once('/').expect("kind/file");
            match kind {
                "meshes" => {
                    let m = DataSource::Embedded.read_mesh(file).expect("mesh parses");
                    assert!(!m.mesh.faces.is_empty(), "{path}");
                }
                "curves" => {
                    let c = DataSource::Embedded
                        .read_curves(file)
                        .expect("curves parse");
                    assert!(!c.curves.is_empty(), "{path}");
                }
                _ => panic!("unexpected embedded path {path}"),
            }
        }
        assert!(LICENSE.contains("MIT License") && LICENSE.contains("Copyright (c) 2022 wwwnev"));
    }

    #[test]
    fn a_missing_embedded_file_is_an_error_naming_it() {
        let e = DataSource::Embedded.read_mesh("nothing.obj").unwrap_err();
        assert_eq!(e.file(), "meshes/nothing.obj");
    }
}

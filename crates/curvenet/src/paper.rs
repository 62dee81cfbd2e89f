//! The paper's examples with the reference set-ups: which mesh and curve files, the scales,
//! the edge length, the budget and the keep list (docs/model.md, *The paper's examples*).
//!
//! The input files are the ones published with the authors' implementation, embedded in
//! curvenet ([`data`]), or read from a folder with the same layout. Examples whose curves are
//! generated on the mesh (hill, stadium, bunny, tent) trace them with [`crate::trace`] on the
//! mesh in file units, following the reference's conventions (docs/model.md, *Curve
//! generation*), and append them after the file curves.

pub mod data;

pub use data::DataSource;

use crate::io::{self, InputError, Polyline, TriMesh};
use crate::network::build::BuildError;
use crate::network::{BuildParams, build_network};
use crate::rod::Supports;
use serde::Serialize;
use std::path::Path;

/// Random geodesics generated on the mesh, appended after the file curves.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GeneratedCurves {
    /// Number of curves.
    pub count: usize,
    /// Seed of the reference's `rand()`.
    pub seed: u32,
}

/// One example's set-up.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Setup {
    /// Example name.
    pub name: &'static str,
    /// Mesh file (relative to `meshes/`).
    pub mesh: &'static str,
    /// Mesh scale.
    pub mesh_scale: f64,
    /// Curve files (relative to `curves/`) and their scales, in loading order.
    pub curves: Vec<(&'static str, f64)>,
    /// Curves generated on the mesh, if any.
    pub generated: Option<GeneratedCurves>,
    /// Scale applied to the generated curves (traced in file units).
    pub generated_scale: f64,
    /// When set, curves are first built at this edge length in file units, then scaled by
    /// the value in the pair ("resampled at 2, then ×s").
    pub pre_resample: Option<(f64, f64)>,
    /// Target edge length `h` (scene units).
    pub edge_length: f64,
    /// Budget as a fraction of the total rest length.
    pub budget_fraction: f64,
    /// Curves the designer keeps.
    pub keep: Vec<usize>,
    /// The paper's figures: curves in, curves out, vertices, minutes.
    pub paper: PaperFigures,
}

/// Table 1 of the paper for one example.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct PaperFigures {
    /// Curves in the input network.
    pub curves_in: usize,
    /// Curves in the paper's result.
    pub curves_out: usize,
    /// Vertices of the input network.
    pub vertices: usize,
    /// Minutes the paper's implementation took.
    pub minutes: f64,
}

/// Names of all examples, in the order of the paper's Table 1.
pub const NAMES: [&str; 9] = [
    "hill", "roof", "kagome", "stadium", "tower", "shell", "bunny", "tent", "arcshell",
];

/// The set-up of example `name`, or `None` for an unknown name.
pub fn setup(name: &str) -> Option<Setup> {
    let p = |curves_in, curves_out, vertices, minutes| PaperFigures {
        curves_in,
        curves_out,
        vertices,
        minutes,
    };
    let s = match name {
        "hill" => Setup {
            curves: vec![("hill_3.txt", 50.0)],
            generated: Some(GeneratedCurves { count: 70, seed: 2 }),
            generated_scale: 50.0,
            keep: vec![0, 1],
            paper: p(73, 9, 6319, 17.7),
            ..plain("hill", "hill.obj", 50.0, 100.0, 0.05)
        },
        "roof" => Setup {
            curves: vec![("roof_75.txt", 70.0)],
            paper: p(75, 7, 2813, 4.6),
            ..plain("roof", "roof.obj", 70.0, 140.0, 0.05)
        },
        // The reference scales this mesh by 60 but not its curves, which then float far from
        // it; the curves lie on the mesh as it is, so neither is scaled.
        "kagome" => Setup {
            curves: vec![("kagome_114_regular.txt", 1.0)],
            paper: p(114, 23, 10224, 53.9),
            ..plain("kagome", "kagome.obj", 1.0, 2.0, 0.05)
        },
        // Traced on the mesh as it is, unscaled (h = 50 in file units), as the paper's run
        // did (docs/model.md, *The paper's examples*).
        "stadium" => Setup {
            generated: Some(GeneratedCurves {
                count: 100,
                seed: 4,
            }),
            paper: p(100, 25, 6646, 16.9),
            ..plain("stadium", "stadium.obj", 1.0, 50.0, 0.10)
        },
        "tower" => Setup {
            curves: vec![("tower_top_ring.txt", 10.0), ("tower_32.txt", 10.0)],
            keep: vec![0],
            paper: p(33, 9, 5699, 2.5),
            ..plain("tower", "tower.obj", 10.0, 20.0, 0.20)
        },
        "shell" => Setup {
            curves: vec![("shell_3.txt", 50.0), ("shell_100.txt", 50.0)],
            paper: p(63, 5, 5504, 7.1),
            ..plain("shell", "shell.obj", 50.0, 50.0, 0.05)
        },
        "bunny" => Setup {
            generated: Some(GeneratedCurves { count: 75, seed: 9 }),
            pre_resample: Some((2.0, 22.222)),
            keep: vec![60, 65, 67],
            paper: p(75, 7, 25442, 266.0),
            ..plain("bunny", "bunny_modified.obj", 22.222, 44.4, 0.10)
        },
        "tent" => Setup {
            curves: vec![("tent_3_regular_curves.txt", 1.0), ("tent_curves.txt", 1.0)],
            generated: Some(GeneratedCurves { count: 66, seed: 2 }),
            pre_resample: Some((2.0, 50.0)),
            keep: vec![0, 1],
            paper: p(112, 42, 6107, 24.7),
            ..plain("tent", "tent.obj", 50.0, 100.0, 0.05)
        },
        "arcshell" => Setup {
            curves: vec![
                ("shell_arcs.txt", 1.0),
                ("shell_elipse.txt", 1.0),
                ("shell_100_for_arcs.txt", 1.0),
            ],
            pre_resample: Some((2.0, 50.0)),
            keep: (0..7).collect(),
            paper: p(67, 21, 3514, 2.6),
            ..plain("arcshell", "shell.obj", 50.0, 100.0, 0.10)
        },
        _ => return None,
    };
    Some(s)
}

/// An example's set-up with what most examples have: no curve file, no generated curves, no
/// resampling before the build, no curve that every network keeps (the paper's figures are
/// each example's own).
fn plain(
    name: &'static str,
    mesh: &'static str,
    mesh_scale: f64,
    edge_length: f64,
    budget_fraction: f64,
) -> Setup {
    Setup {
        name,
        mesh,
        mesh_scale,
        curves: Vec::new(),
        generated: None,
        generated_scale: 1.0,
        pre_resample: None,
        edge_length,
        budget_fraction,
        keep: Vec::new(),
        paper: PaperFigures::default(),
    }
}

/// Why an example could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ExampleError {
    /// Unknown example name.
    #[error("unknown example '{0}' (known: {names})", names = NAMES.join(", "))]
    Unknown(String),
    /// A data file could not be read.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The pre-resampling build failed.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// Tracing the example's generated curves failed.
    #[error("{mesh}: tracing the generated curves failed: {source}")]
    Trace {
        /// Mesh the curves are traced on.
        mesh: String,
        /// The failure.
        source: crate::trace::TraceError,
    },
}

/// An example ready to build: mesh, curves (scaled, in id order) and build parameters.
#[derive(Clone, Debug)]
pub struct LoadedExample {
    /// The set-up.
    pub setup: Setup,
    /// The scaled mesh.
    pub mesh: TriMesh,
    /// The scaled curves.
    pub curves: Vec<Polyline>,
    /// Parameters of the final build.
    pub build: BuildParams,
    /// Non-fatal findings while reading.
    pub warnings: Vec<io::InputWarning>,
}

fn scaled(mut curves: Vec<Polyline>, s: f64) -> Vec<Polyline> {
    for c in &mut curves {
        for p in &mut c.points {
            *p = *p * s;
        }
    }
    curves
}

/// Loads example `name` from the folder `data` (holding `meshes/` and `curves/`).
pub fn load(name: &str, data: &Path, supports: Supports) -> Result<LoadedExample, ExampleError> {
    load_from(name, &DataSource::Folder(data.to_path_buf()), supports)
}

/// Loads example `name` from the copies of the paper's files embedded in curvenet.
pub fn load_embedded(name: &str, supports: Supports) -> Result<LoadedExample, ExampleError> {
    load_from(name, &DataSource::Embedded, supports)
}

/// Loads example `name` from `source`.
pub fn load_from(
    name: &str,
    source: &DataSource,
    supports: Supports,
) -> Result<LoadedExample, ExampleError> {
    let setup = setup(name).ok_or_else(|| ExampleError::Unknown(name.to_string()))?;
    let mesh_file = source.read_mesh(setup.mesh)?;
    let mut warnings = mesh_file.warnings;
    let mesh_file_units = mesh_file.mesh.clone();
    let mut mesh = mesh_file.mesh;
    for v in &mut mesh.vertices {
        *v = *v * setup.mesh_scale;
    }
    let mut curves = Vec::new();
    for (file, scale) in &setup.curves {
        let f = source.read_curves(file)?;
        warnings.extend(f.warnings);
        curves.extend(scaled(f.curves, *scale));
    }
    if let Some(g) = &setup.generated {
        // Traced on the mesh in file units, appended after the file curves, then scaled like
        // them.
        let generator =
            crate::trace::Generator::paper(name).expect("every generated example has a generator");
        let generated = crate::trace::generate(&mesh_file_units, &generator).map_err(|source| {
            ExampleError::Trace {
                mesh: setup.mesh.to_string(),
                source,
            }
        })?;
        for f in &generated.failures {
            warnings.push(io::InputWarning::new(
                setup.mesh,
                0,
                format!("generated curve failed: {f}"),
            ));
        }
        if generated.curves.len() != g.count {
            warnings.push(io::InputWarning::new(
                setup.mesh,
                0,
                format!(
                    "generated {} curves instead of {}",
                    generated.curves.len(),
                    g.count
                ),
            ));
        }
        curves.extend(scaled(generated.curves, setup.generated_scale));
    }
    if let Some((h0, s)) = setup.pre_resample {
        let pre = BuildParams {
            edge_length: h0,
            supports,
            ..BuildParams::default()
        };
        let (net, _) = build_network(&curves, &pre)?;
        curves = scaled(net.to_polylines(&curves), s);
    }
    let build = BuildParams {
        edge_length: setup.edge_length,
        supports,
        ..BuildParams::default()
    };
    Ok(LoadedExample {
        setup,
        mesh,
        curves,
        build,
        warnings,
    })
}

/// The reference's simple surfaces for random experiments (`curvenet compare`), meshes among
/// the paper's data (`meshes/NAME.obj`).
pub const SIMPLE_SURFACES: [&str; 5] = ["1wave", "2waves", "half_sphere", "sine_disk", "leaf"];

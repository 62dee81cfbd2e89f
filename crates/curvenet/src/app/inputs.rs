//! What a run starts from ([`InputSpec`]: where the curves and the surface come from, the
//! scale, the edge length, the supports) read into [`Inputs`]: the curves scaled, the surface,
//! the network's build parameters (the default edge length chosen here, once, for every front
//! end), the groups and per-curve specs the curve files declare, and the warnings a user
//! should read before a long computation.

use crate::app::{AppError, ends};
use crate::constraints::Group;
use crate::io::{self, Polyline, TriMesh};
use crate::material::CurveSpec;
use crate::network::{BuildParams, checks};
use crate::paper;
use crate::rod::Supports;
use crate::run_folder::InputDescription;
use crate::trace::{
    Generator, SURFACE_NAMES, SurfaceError, builtin_surface, generate, read_surface,
    scale_to_extent,
};
use crate::words::{Message, Opt, Piece, given, message};
use crate::{fmt, pipeline};
use std::path::{Path, PathBuf};

/// Where the curves come from.
#[derive(Clone, Debug)]
pub enum CurveSource {
    /// Curve files (`.txt`, `.obj`, `.json`), in id order.
    Files(Vec<PathBuf>),
    /// Curves read by the front end (point arrays, Rhino objects), unscaled.
    Given(GivenCurves),
    /// One of the paper's examples: its curves, surface, scale, edge length, budget and keep
    /// list. `data` names a folder holding `meshes/` and `curves/` to read instead of the
    /// copies embedded in curvenet.
    Example {
        /// The example's name (`tower`).
        name: String,
        /// The folder of the paper's data.
        data: Option<PathBuf>,
    },
    /// Random geodesics traced on a built-in surface scaled to a largest extent of 4000 (the
    /// demo; the reference's command-line scenes).
    Geodesics {
        /// The built-in surface's name.
        surface: String,
        /// How many geodesics.
        count: usize,
        /// The seed of the directions.
        seed: u32,
    },
}

impl CurveSource {
    /// `count` random geodesics on the built-in surface `surface`, directions drawn from
    /// `seed`.
    pub fn geodesics(surface: &str, count: usize, seed: u32) -> Self {
        CurveSource::Geodesics {
            surface: surface.to_string(),
            count,
            seed,
        }
    }
}

/// Curves a front end read itself, with what their source declared.
#[derive(Clone, Debug, Default)]
pub struct GivenCurves {
    /// The curves, unscaled, in id order.
    pub curves: Vec<Polyline>,
    /// Each curve's group name (`None`: none), aligned with `curves` or empty.
    pub groups: Vec<Option<String>>,
    /// Each curve's material, section and rest shape, aligned with `curves` or empty.
    pub specs: Vec<CurveSpec>,
    /// The length unit the source declares.
    pub units: Option<String>,
    /// The edge length the source declares (unscaled): the network's when no edge length is
    /// given.
    pub edge_length: Option<f64>,
    /// The files they came from, as recorded in a run folder.
    pub files: Vec<String>,
    /// What reading them found.
    pub warnings: Vec<String>,
}

/// Where the surface comes from.
#[derive(Clone, Debug)]
pub enum MeshSource {
    /// An OBJ file; or, when no such file exists, `builtin:NAME` or a bare `NAME` of a
    /// built-in surface.
    Path(PathBuf),
    /// A mesh the front end holds (arrays), unscaled, named `name` in messages.
    Given {
        /// The mesh.
        mesh: TriMesh,
        /// Its name in messages and in the run folder's record.
        name: String,
    },
}

/// The inputs of a run or an analysis, as a user gives them.
#[derive(Clone, Debug)]
pub struct InputSpec {
    /// The curves.
    pub curves: CurveSource,
    /// The surface (an example and the demo bring their own: then `None`).
    pub mesh: Option<MeshSource>,
    /// The scale applied to the curves and the mesh (an example has its own: 1 here).
    pub scale: f64,
    /// The target edge length `h` (scene units, after scaling); `None`: the default
    /// ([`pipeline::default_edge_length`], or the example's own).
    pub edge_length: Option<f64>,
    /// Merge joints closer than this fraction of `h`.
    pub merge_joints: Option<f64>,
    /// The supports of open curves (default clamped).
    pub supports: Option<Supports>,
    /// A supports file: how chosen curve ends are held, overriding `supports` and the curve
    /// files' own (`crate::io::parse_supports_file`).
    pub supports_file: Option<PathBuf>,
}

impl InputSpec {
    /// The inputs of `curves` with every other field at its default.
    pub fn new(curves: CurveSource) -> Self {
        InputSpec {
            curves,
            mesh: None,
            scale: 1.0,
            edge_length: None,
            merge_joints: None,
            supports: None,
            supports_file: None,
        }
    }
}

/// What a paper's example brings beyond its inputs: its budget and keep list.
#[derive(Clone, Debug, PartialEq)]
pub struct ExampleDefaults {
    /// The example's name.
    pub name: String,
    /// Its budget, a fraction of the total length.
    pub budget: f64,
    /// Its keep list.
    pub keep: Vec<usize>,
    /// The paper's figures for it (curves in, vertices).
    pub paper: paper::PaperFigures,
}

/// The inputs read and scaled.
#[derive(Clone, Debug)]
pub struct Inputs {
    /// The curves, scaled, in id order.
    pub curves: Vec<Polyline>,
    /// The surface, scaled, when known.
    pub mesh: Option<TriMesh>,
    /// How the network is built (the edge length chosen).
    pub build: BuildParams,
    /// What was read, as a run folder records it.
    pub description: InputDescription,
    /// The groups the curve files declare.
    pub groups: Vec<Group>,
    /// Each curve's material, section and rest shape (empty when no file says anything).
    pub specs: Vec<CurveSpec>,
    /// The length unit the curve files declare (the first that does).
    pub file_units: Option<String>,
    /// What reading found, for the user to read before the (possibly long) work.
    pub warnings: Vec<Message>,
    /// A paper's example's budget and keep list.
    pub example: Option<ExampleDefaults>,
}

/// Reads `spec`: curves and surface read, scaled and checked, the edge length chosen.
pub fn read_inputs(spec: &InputSpec) -> Result<Inputs, AppError> {
    if !(spec.scale.is_finite() && spec.scale > 0.0) {
        return Err(AppError::usage(message![
            given(Opt::Scale, spec.scale),
            ": must be a positive number"
        ]));
    }
    if let Some(h) = spec.edge_length
        && !(h.is_finite() && h > 0.0)
    {
        return Err(AppError::usage(message![
            given(Opt::EdgeLength, h),
            ": must be a positive number (scene units)"
        ]));
    }
    // The edge length a curve file declares (a saved design's), scaled below.
    let file_edge_length;
    let mut inputs = match &spec.curves {
        CurveSource::Example { name, data } => {
            return with_file_ends(spec, example_inputs(spec, name, data.as_deref())?);
        }
        CurveSource::Geodesics {
            surface,
            count,
            seed,
        } => return with_file_ends(spec, geodesic_inputs(spec, surface, *count, *seed)?),
        CurveSource::Files(paths) => {
            let given = read_files(paths)?;
            file_edge_length = given.edge_length;
            given_inputs(&given)
        }
        CurveSource::Given(given) => {
            file_edge_length = given.edge_length;
            given_inputs(given)
        }
    };
    let mut mesh = None;
    let mut mesh_name = None;
    if let Some(source) = &spec.mesh {
        let (m, name, warnings) = read_mesh(source)?;
        inputs
            .warnings
            .extend(warnings.into_iter().map(Message::from));
        mesh = Some(scaled_mesh(m, spec.scale));
        mesh_name = Some(name);
    }
    pipeline::scale_curves(&mut inputs.curves, spec.scale);
    check_scaled(
        &inputs.curves,
        mesh.as_ref(),
        spec.scale,
        mesh_name.as_deref(),
    )?;
    let given_h = spec
        .edge_length
        .or(file_edge_length.map(|h| h * spec.scale));
    let h = match given_h {
        Some(h) => h,
        None => pipeline::default_edge_length(&inputs.curves).ok_or_else(|| {
            AppError::usage(message![
                "cannot choose the edge length: the curves' lengths are out of range; give ",
                Opt::EdgeLength,
                " or another ",
                Opt::Scale
            ])
        })?,
    };
    inputs.warnings.extend(network_size_warning(
        &inputs.curves,
        h,
        given_h.is_some(),
        spec.scale,
    ));
    if let Some(m) = &mesh {
        let name = mesh_name.clone().unwrap_or_default();
        inputs.warnings.extend(
            checks::mesh_warnings(m, &name)
                .into_iter()
                .map(Message::from),
        );
        let far = checks::curves_far_from_mesh(&inputs.curves, m, checks::FAR_FROM_MESH);
        inputs
            .warnings
            .extend(checks::far_from_mesh_warning(&far, &name).map(Message::from));
    }
    let mut build = build_params(spec, h)?;
    let file = spec.supports_file.as_deref();
    (build.ends, build.end_frames) = ends::curve_ends(
        &inputs.curves,
        &inputs.specs,
        file,
        spec.scale,
        mesh.as_ref(),
    )?;
    inputs.description.mesh = mesh_name;
    inputs.description.scale = spec.scale;
    Ok(Inputs {
        build,
        mesh,
        ..inputs
    })
}

/// `inputs` (an example's or generated curves, which have no curve file) with the end
/// supports of `spec`'s supports file.
fn with_file_ends(spec: &InputSpec, mut inputs: Inputs) -> Result<Inputs, AppError> {
    let file = spec.supports_file.as_deref();
    let scale = inputs.description.scale;
    (inputs.build.ends, inputs.build.end_frames) =
        ends::curve_ends(&inputs.curves, &[], file, scale, inputs.mesh.as_ref())?;
    Ok(inputs)
}

/// The curve files `paths` read in order (unscaled), their groups, specs, units and edge
/// length.
fn read_files(paths: &[PathBuf]) -> Result<GivenCurves, AppError> {
    if paths.is_empty() {
        return Err(AppError::usage(message![
            "no curves given: give ",
            Opt::Curves
        ]));
    }
    let mut given = GivenCurves::default();
    for path in paths {
        given.read_file(path)?;
    }
    Ok(given)
}

impl GivenCurves {
    /// Appends the curves of a curve file (`.txt`, `.obj`, `.json`), with what it declares
    /// (groups, per-curve specs, units) and what reading it found.
    pub fn read_file(&mut self, path: &std::path::Path) -> Result<(), io::InputError> {
        let f = io::read_curves(path)?;
        self.warnings
            .extend(f.warnings.iter().map(|w| w.to_string()));
        self.groups.resize(self.curves.len(), None);
        self.groups.extend(
            f.groups
                .iter()
                .cloned()
                .chain(std::iter::repeat(None))
                .take(f.curves.len()),
        );
        if !f.specs.is_empty() {
            self.specs.resize(self.curves.len(), Default::default());
            self.specs.extend(f.specs);
        }
        self.units = self.units.clone().or(f.units);
        self.edge_length = self.edge_length.or(f.edge_length);
        self.curves.extend(f.curves);
        self.files.push(path.display().to_string());
        Ok(())
    }

    /// Appends a curve the front end read itself (no group, no spec).
    pub fn push(&mut self, curve: Polyline) {
        self.groups.resize(self.curves.len(), None);
        self.groups.push(None);
        self.curves.push(curve);
    }
}

/// The inputs of curves the front end read (unscaled; no mesh yet).
fn given_inputs(given: &GivenCurves) -> Inputs {
    let origins: Vec<String> = given.curves.iter().map(|c| c.origin.to_string()).collect();
    let groups = crate::constraints::groups::groups_of_tags(&given.groups, &origins);
    Inputs {
        curves: given.curves.clone(),
        mesh: None,
        build: BuildParams::default(),
        description: InputDescription {
            example: None,
            mesh: None,
            curve_files: given.files.clone(),
            scale: 1.0,
        },
        groups,
        specs: given.specs.clone(),
        file_units: given.units.clone(),
        warnings: given.warnings.iter().cloned().map(Message::from).collect(),
        example: None,
    }
}

/// The build parameters of `spec` at edge length `h`, checked.
fn build_params(spec: &InputSpec, h: f64) -> Result<BuildParams, AppError> {
    let build = BuildParams {
        edge_length: h,
        supports: spec.supports.unwrap_or_default(),
        merge_joints_below: spec.merge_joints,
        ..BuildParams::default()
    };
    build
        .validate()
        .map_err(|e| AppError::usage(e.to_string()))?;
    Ok(build)
}

/// Reads `source`: the mesh (unscaled), its name for messages and records, the reader's
/// warnings.
pub fn read_mesh(source: &MeshSource) -> Result<(TriMesh, String, Vec<String>), AppError> {
    let path = match source {
        MeshSource::Given { mesh, name } => {
            check_mesh(mesh, name)?;
            return Ok((mesh.clone(), name.clone(), Vec::new()));
        }
        MeshSource::Path(p) => p,
    };
    read_surface(path).map_err(|e| match e {
        SurfaceError::Input(e) => AppError::Input(e),
        SurfaceError::Unknown(text) => AppError::usage(message![
            given(Opt::Mesh, &text),
            format!(
                ": no such file, and not a built-in surface (built-in: {})",
                SURFACE_NAMES.join(", ")
            )
        ]),
    })
}

/// Refuses a mesh given as arrays with a face naming a missing vertex or a coordinate that
/// is not finite.
fn check_mesh(mesh: &TriMesh, name: &str) -> Result<(), AppError> {
    if mesh.vertices.iter().any(|p| !p.is_finite()) {
        return Err(AppError::usage(format!(
            "{name}: a vertex coordinate is not finite"
        )));
    }
    let n = mesh.vertices.len();
    if let Some((k, f)) = mesh
        .faces
        .iter()
        .enumerate()
        .find(|(_, f)| f.iter().any(|&i| i as usize >= n))
    {
        return Err(AppError::usage(format!(
            "{name}: face {k} names vertex {}, but the mesh has {n} vertices",
            f.iter().copied().max().unwrap_or(0)
        )));
    }
    Ok(())
}

fn scaled_mesh(mut mesh: TriMesh, scale: f64) -> TriMesh {
    for v in &mut mesh.vertices {
        *v = *v * scale;
    }
    mesh
}

/// The paper's example `name`, with its own surface, scale and edge length.
fn example_inputs(spec: &InputSpec, name: &str, data: Option<&Path>) -> Result<Inputs, AppError> {
    for (opt, set) in [
        (Opt::Mesh, spec.mesh.is_some()),
        (Opt::Scale, spec.scale != 1.0),
        (Opt::EdgeLength, spec.edge_length.is_some()),
    ] {
        if set {
            return Err(AppError::usage(message![
                "a paper's example brings its own surface, scale and edge length: drop ",
                opt
            ]));
        }
    }
    let source = data_source(data)?;
    let ex = paper::load_from(name, &source, spec.supports.unwrap_or_default())?;
    let build = BuildParams {
        merge_joints_below: spec.merge_joints,
        ..ex.build.clone()
    };
    build
        .validate()
        .map_err(|e| AppError::usage(e.to_string()))?;
    Ok(Inputs {
        description: InputDescription {
            example: Some(ex.setup.name.to_string()),
            mesh: Some(format!("meshes/{}", ex.setup.mesh)),
            curve_files: ex
                .setup
                .curves
                .iter()
                .map(|(f, _)| format!("curves/{f}"))
                .collect(),
            scale: ex.setup.mesh_scale,
        },
        warnings: ex
            .warnings
            .iter()
            .map(|w| Message::from(w.to_string()))
            .collect(),
        example: Some(ExampleDefaults {
            name: ex.setup.name.to_string(),
            budget: ex.setup.budget_fraction,
            keep: ex.setup.keep.clone(),
            paper: ex.setup.paper,
        }),
        curves: ex.curves,
        mesh: Some(ex.mesh),
        build,
        groups: Vec::new(),
        specs: Vec::new(),
        file_units: None,
    })
}

/// Where the paper's files are read from: the folder `data` names (which must exist), or
/// the copies embedded in curvenet.
pub fn data_source(data: Option<&Path>) -> Result<paper::DataSource, AppError> {
    if let Some(dir) = data
        && !dir.is_dir()
    {
        return Err(AppError::usage(message![
            given(Opt::Data, dir.display()),
            ": no such folder (it should hold meshes/ and curves/; without it the paper's \
             files embedded in curvenet are used)"
        ]));
    }
    Ok(paper::DataSource::folder_or_embedded(data))
}

/// The demo's largest extent of a built-in surface (the reference's command-line scenes).
pub const GEODESIC_EXTENT: f64 = 4000.0;

/// `count` random geodesics traced on the built-in surface `surface`, scaled to
/// [`GEODESIC_EXTENT`].
fn geodesic_inputs(
    spec: &InputSpec,
    surface: &str,
    count: usize,
    seed: u32,
) -> Result<Inputs, AppError> {
    let mesh = builtin_surface(surface).ok_or_else(|| {
        AppError::usage(format!(
            "unknown built-in surface '{surface}' (known: {})",
            SURFACE_NAMES.join(", ")
        ))
    })?;
    let (mesh, _) = scale_to_extent(&mesh, GEODESIC_EXTENT);
    let traced = generate(&mesh, &Generator::Random { count, seed })
        .map_err(|e| AppError::usage(format!("builtin:{surface}: {e}")))?;
    if traced.curves.is_empty() {
        return Err(AppError::usage(format!(
            "builtin:{surface}: no geodesic could be traced"
        )));
    }
    let h = match spec.edge_length {
        Some(h) => h,
        None => pipeline::default_edge_length(&traced.curves)
            .ok_or_else(|| AppError::Failed("the traced curves have no length".into()))?,
    };
    let build = build_params(spec, h)?;
    Ok(Inputs {
        warnings: network_size_warning(&traced.curves, h, spec.edge_length.is_some(), 1.0)
            .into_iter()
            .collect(),
        curves: traced.curves,
        mesh: Some(mesh),
        build,
        description: InputDescription {
            example: Some(format!("demo:{surface}:{count}:{seed}")),
            mesh: Some(format!("builtin:{surface}")),
            curve_files: Vec::new(),
            scale: 1.0,
        },
        groups: Vec::new(),
        specs: Vec::new(),
        file_units: None,
        example: None,
    })
}

/// The warning about a very large network at edge length `h` (given by the user when
/// `given`, else the default), before it is built. (One too large to build is refused by the
/// build itself.)
pub fn network_size_warning(
    curves: &[Polyline],
    h: f64,
    given_h: bool,
    scale: f64,
) -> Option<Message> {
    let n = pipeline::large_network(curves, h)?;
    let mut pieces = vec![if given_h {
        given(Opt::EdgeLength, format!("{h:e}"))
    } else {
        Piece::from(format!("the default edge length {h:e}"))
    }];
    pieces.push(format!(" makes a large network, about {n:.0} vertices").into());
    if scale != 1.0 {
        pieces.extend([
            " (curves scaled by ".into(),
            given(Opt::Scale, scale),
            ")".into(),
        ]);
    }
    pieces.extend([
        ": its analysis takes minutes and gigabytes of memory (a larger ".into(),
        Opt::EdgeLength.into(),
        " makes it smaller)".into(),
    ]);
    Some(Message::new(pieces))
}

/// Refuses a scale that pushes coordinates out of the floating-point range, naming the first
/// curve (file and line) or the mesh it breaks.
fn check_scaled(
    curves: &[Polyline],
    mesh: Option<&TriMesh>,
    scale: f64,
    mesh_name: Option<&str>,
) -> Result<(), AppError> {
    if let Some((c, curve)) = curves
        .iter()
        .enumerate()
        .find(|(_, c)| c.points.iter().any(|p| !p.is_finite()))
    {
        return Err(AppError::usage(message![
            format!("{}: ", curve.origin),
            given(Opt::Scale, scale),
            format!(" makes the coordinates of curve {c} overflow; choose a smaller scale")
        ]));
    }
    // Points that still differ but whose distances underflow: the scale shrank the curve away.
    if let Some((c, curve)) = curves
        .iter()
        .enumerate()
        .find(|(_, c)| c.length() == 0.0 && c.points.windows(2).any(|w| w[0] != w[1]))
    {
        return Err(AppError::usage(message![
            format!("{}: ", curve.origin),
            given(Opt::Scale, fmt::length(scale)),
            format!(
                " makes curve {c} so small that its length underflows to 0; choose a larger \
                 scale"
            )
        ]));
    }
    if mesh.is_some_and(|m| m.vertices.iter().any(|p| !p.is_finite())) {
        return Err(AppError::usage(message![
            format!("{}: ", mesh_name.unwrap_or_default()),
            given(Opt::Scale, scale),
            " makes the mesh's coordinates overflow; choose a smaller scale"
        ]));
    }
    Ok(())
}

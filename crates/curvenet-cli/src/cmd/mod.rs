//! One module per subcommand, plus the option handling they share.

mod analyze;
pub(crate) mod bench;
mod compare;
mod demo;
mod example;
mod export;
mod greedy_run;
#[cfg(feature = "serve")]
mod serve;
mod simplify;
mod surface;
mod trace;
mod view;

use crate::args::{Cli, Command, InputArgs, PhysicalModeArgs, PhysicsArgs};
use crate::exit::usage;
use curvenet::io::{self, Polyline, TriMesh};
use curvenet::network::{BuildParams, checks};
use curvenet::physics::{PhysicalOptions, PhysicalParams};
use curvenet::rod::Material;
use curvenet::run_folder::InputDescription;
use curvenet::stability::{Objective, StabilityParams};
use curvenet::{paper, pipeline};

/// Runs the parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Analyze(a) => analyze::run(a),
        Command::Simplify(a) => simplify::run(a),
        Command::Example(a) => example::run(a),
        Command::Demo(a) => demo::run(a),
        Command::Trace(a) => trace::run(a),
        Command::Compare(a) => compare::run(a),
        Command::View(a) => view::run(a),
        Command::Export(a) => export::run(a),
        Command::Bench(a) => bench::run(a),
        #[cfg(feature = "serve")]
        Command::Serve(a) => serve::run(a),
    }
}

/// Opens `what` (a URL or a file) in the default browser without waiting for it; a failure
/// is a warning saying what to open by hand.
pub fn open_in_browser(what: &str) {
    if let Err(e) = open::that_detached(what) {
        eprintln!("warning: could not open a browser ({e}); open {what} in one");
    }
}

/// Where the paper's files are read from: the folder `--data` names (which must exist), or the
/// copies embedded in curvenet.
pub fn data_source(folder: Option<&std::path::Path>) -> anyhow::Result<paper::DataSource> {
    if let Some(dir) = folder
        && !dir.is_dir()
    {
        return Err(usage(format!(
            "--data {}: no such folder (it should hold meshes/ and curves/; without --data \
                 the paper's files embedded in curvenet are used)",
            dir.display()
        )));
    }
    Ok(paper::DataSource::folder_or_embedded(folder))
}

/// The physical mode from the options: its parameters (`None` in the paper's mode) and the
/// options the paper's model is built from. In the physical mode `--radius` and `--young`
/// describe the physical rods, so the paper's model (its `λ`, the searches' objective) keeps
/// its defaults and chooses as without the physical options. `file_units` and `specs` come
/// from the curve files.
pub fn physical_mode(
    physics: &PhysicsArgs,
    p: &PhysicalModeArgs,
    file_units: Option<&str>,
    specs: &[curvenet::material::CurveSpec],
) -> anyhow::Result<(Option<PhysicalParams>, PhysicsArgs)> {
    let options = physical_options(physics, p);
    let physical = options.resolve(file_units, specs).map_err(usage)?;
    let mut paper = physics.clone();
    let physical = physical.map(|mut pp| {
        paper.young = None;
        paper.radius = None;
        pp.frequencies = physics.eigen_count.clamp(1, 50);
        pp
    });
    Ok((physical, paper))
}

/// The physical mode's options as given (what a run folder records of them).
pub fn physical_options(physics: &PhysicsArgs, p: &PhysicalModeArgs) -> PhysicalOptions {
    PhysicalOptions {
        units: p.units.clone(),
        material: p.material.clone(),
        young: physics.young.clone(),
        density: p.density.clone(),
        strength: p.strength.clone(),
        radius: physics.radius.map(|r| r.to_string()),
        tube: p.tube.clone(),
        load: p.load.clone(),
        gravity: p.gravity.clone(),
    }
}

/// Stability parameters from the shared options (defaults where unset).
pub fn stability_params(p: &PhysicsArgs) -> anyhow::Result<StabilityParams> {
    let mut s = StabilityParams::default();
    let d = Material::default();
    s.material = Material {
        radius: p.radius.unwrap_or(d.radius),
        young: match &p.young {
            Some(t) => t.trim().parse().map_err(|_| {
                usage(format!(
                    "--young {t:?}: the paper's mode takes a plain number (default 1); a modulus \
                     with a unit such as 210GPa needs the physical mode (--units mm|cm|m and \
                     --material NAME)"
                ))
            })?,
            None => d.young,
        },
        anchor_weight: p.anchor_weight.unwrap_or(d.anchor_weight),
    };
    s.eigen = s.eigen.with_count(p.eigen_count);
    let m = &s.material;
    let (lo, hi) = curvenet::rod::STIFFNESS_RANGE;
    for (name, k, formula) in [
        ("stretching", m.ks(), "E π r²"),
        ("bending", m.kb(), "E π r⁴ / 4"),
    ] {
        if !(lo..=hi).contains(&k) {
            return Err(usage(format!(
                "--radius {:e} and --young {:e} give a {name} stiffness {formula} = {k:e}, out \
                 of the range the solvers handle ({lo:e} to {hi:e}); choose scene units where \
                 the radius is nearer 1",
                m.radius, m.young
            )));
        }
    }
    if !(lo..=hi).contains(&(2.0 * m.anchor_weight)) {
        return Err(usage(format!(
            "--anchor-weight {:e}: an anchor's stiffness 2µ must lie between {lo:e} and {hi:e}",
            m.anchor_weight
        )));
    }
    s.validate().map_err(usage)?;
    Ok(s)
}

/// Curves and build parameters from the input options.
pub struct Inputs {
    /// Scaled curves in id order.
    pub curves: Vec<Polyline>,
    /// Network construction.
    pub build: BuildParams,
    /// Reading warnings.
    pub warnings: Vec<String>,
    /// What was read.
    pub description: InputDescription,
    /// The mesh, scaled, if one was given.
    pub mesh: Option<curvenet::io::TriMesh>,
    /// The groups the curve files name (each curve's JSON `"group"`, in id order), as groups.
    pub groups: Vec<curvenet::constraints::Group>,
    /// Each curve's material, section and rest shape from the curve files (empty when no
    /// file says anything).
    pub specs: Vec<curvenet::material::CurveSpec>,
    /// The length unit the curve files declare (the first that does).
    pub file_units: Option<String>,
}

/// The user's inputs read (their warnings printed), with the physical mode they ask for and
/// the stability parameters maximising `objective`: where `analyze` and `simplify` start.
pub fn load_setup(
    input: &InputArgs,
    physics: &PhysicsArgs,
    physical: &PhysicalModeArgs,
    objective: Objective,
) -> anyhow::Result<(Inputs, Option<PhysicalParams>, StabilityParams)> {
    let inputs = load_inputs(input, physics)?;
    print_warnings(&inputs.warnings);
    let (physical, paper) = physical_mode(
        physics,
        physical,
        inputs.file_units.as_deref(),
        &inputs.specs,
    )?;
    let mut params = stability_params(&paper)?;
    params.objective = objective;
    Ok((inputs, physical, params))
}

/// Refuses the curve ids `option` names when the input (`n` curves) lacks one.
pub fn check_curve_ids(option: &str, ids: &[usize], n: usize) -> anyhow::Result<()> {
    match ids.iter().find(|&&c| c >= n) {
        Some(&bad) => Err(usage(format!(
            "{option} names curve {bad}, but the input has {n} curves (ids 0..{})",
            n.saturating_sub(1)
        ))),
        None => Ok(()),
    }
}

/// Reads and scales the inputs.
pub fn load_inputs(a: &InputArgs, p: &PhysicsArgs) -> anyhow::Result<Inputs> {
    let mut warnings = Vec::new();
    let mut mesh = None;
    if let Some(m) = &a.mesh {
        let file = surface::read_mesh_arg(m)?;
        warnings.extend(file.warnings);
        let mut tri = file.mesh;
        for v in &mut tri.vertices {
            *v = *v * a.scale;
        }
        mesh = Some(tri);
    }
    let mut curves = Vec::new();
    let (mut tags, mut origins) = (Vec::new(), Vec::new());
    let (mut specs, mut file_units) = (Vec::new(), None);
    for path in &a.curves {
        let f = io::read_curves(path)?;
        warnings.extend(f.warnings.iter().map(|w| w.to_string()));
        origins.extend(f.curves.iter().map(|c| c.origin.to_string()));
        tags.extend(
            f.groups
                .iter()
                .cloned()
                .chain(std::iter::repeat(None))
                .take(f.curves.len()),
        );
        if !f.specs.is_empty() {
            specs.resize(curves.len(), Default::default());
            specs.extend(f.specs);
        }
        file_units = file_units.or(f.units);
        curves.extend(f.curves);
    }
    let groups = curvenet::constraints::groups::groups_of_tags(&tags, &origins);
    pipeline::scale_curves(&mut curves, a.scale);
    check_scaled(&curves, mesh.as_ref(), a)?;
    let h = match a.edge_length {
        Some(h) => h,
        None => pipeline::default_edge_length(&curves).ok_or_else(|| {
            usage(
                "cannot choose the edge length: the curves' lengths are out of range; give \
                 --edge-length or another --scale",
            )
        })?,
    };
    warnings.extend(network_size_warning(
        &curves,
        h,
        a.edge_length.is_some(),
        a.scale,
    ));
    if let Some(m) = &mesh {
        let name = a
            .mesh
            .as_ref()
            .map_or_else(String::new, |p| p.display().to_string());
        warnings.extend(checks::mesh_warnings(m, &name));
        let far = checks::curves_far_from_mesh(&curves, m, checks::FAR_FROM_MESH);
        warnings.extend(checks::far_from_mesh_warning(&far, &name));
    }
    let build = BuildParams {
        edge_length: h,
        supports: p.supports.unwrap_or_default(),
        merge_joints_below: p.merge_joints,
        ..BuildParams::default()
    };
    build.validate().map_err(|e| usage(e.to_string()))?;
    let description = InputDescription {
        example: None,
        mesh: a.mesh.as_ref().map(|m| m.display().to_string()),
        curve_files: a.curves.iter().map(|c| c.display().to_string()).collect(),
        scale: a.scale,
    };
    Ok(Inputs {
        curves,
        build,
        warnings,
        description,
        mesh,
        groups,
        specs,
        file_units,
    })
}

/// The design constraints of the options, with `groups` (the curve files' own) after the
/// groups file's.
pub fn constraint_params(
    a: &crate::args::ConstraintArgs,
    groups: Vec<curvenet::constraints::Group>,
) -> anyhow::Result<curvenet::constraints::ConstraintParams> {
    use curvenet::constraints::{ConstraintParams, read_groups};
    let mut all = match &a.groups {
        Some(path) => read_groups(path)?,
        None => Vec::new(),
    };
    all.extend(groups);
    let p = ConstraintParams {
        groups: all,
        symmetry: a.symmetry.unwrap_or_default(),
        connected: a.connected,
        min_curves: a.min_curves,
        max_gap: a.max_gap,
        max_deviation: a.max_deviation,
        ..ConstraintParams::default()
    };
    p.validate().map_err(usage)?;
    Ok(p)
}

/// The warning about a very large network at edge length `h` (given as `--edge-length` when
/// `given`, else the default), before it is built. (One too large to build is refused by the
/// build itself.)
pub fn network_size_warning(
    curves: &[Polyline],
    h: f64,
    given: bool,
    scale: f64,
) -> Option<String> {
    let what = if given {
        format!("--edge-length {h:e}")
    } else {
        format!("the default edge length {h:e}")
    };
    let scaled = if scale == 1.0 {
        String::new()
    } else {
        format!(" (curves scaled by --scale {scale})")
    };
    pipeline::large_network(curves, h).map(|n| {
        format!(
            "{what} makes a large network, about {n:.0} vertices{scaled}: its analysis takes \
             minutes and gigabytes of memory (a larger --edge-length makes it smaller)"
        )
    })
}

/// Rejects a `--scale` that pushes coordinates out of the floating-point range, naming the first
/// curve (file and line) or the mesh it breaks.
fn check_scaled(curves: &[Polyline], mesh: Option<&TriMesh>, a: &InputArgs) -> anyhow::Result<()> {
    if let Some((c, curve)) = curves
        .iter()
        .enumerate()
        .find(|(_, c)| c.points.iter().any(|p| !p.is_finite()))
    {
        return Err(usage(format!(
            "{}: --scale {} makes the coordinates of curve {c} overflow; choose a smaller scale",
            curve.origin, a.scale
        )));
    }
    // Points that still differ but whose distances underflow: the scale shrank the curve away.
    if let Some((c, curve)) = curves
        .iter()
        .enumerate()
        .find(|(_, c)| c.length() == 0.0 && c.points.windows(2).any(|w| w[0] != w[1]))
    {
        return Err(usage(format!(
            "{}: --scale {} makes curve {c} so small that its length underflows to 0; choose \
             a larger scale",
            curve.origin,
            fmt_length(a.scale)
        )));
    }
    if mesh.is_some_and(|m| m.vertices.iter().any(|p| !p.is_finite())) {
        return Err(usage(format!(
            "{}: --scale {} makes the mesh's coordinates overflow; choose a smaller scale",
            a.mesh
                .as_ref()
                .map_or_else(String::new, |p| p.display().to_string()),
            a.scale
        )));
    }
    Ok(())
}

/// A length with seven significant digits (`curvenet::fmt::length`).
pub use curvenet::fmt::length as fmt_length;

/// Takes the lock of the run folder `dir` for `command` (`view`, `export`), which write into
/// it, shared with other such commands: refused while a run is writing there. A folder that cannot be locked (read-only, say)
/// is no run's either: the command goes on without the lock.
pub fn hold_run_folder(
    dir: &std::path::Path,
    command: &str,
) -> anyhow::Result<Option<curvenet::run_folder::folder::FolderLock>> {
    use curvenet::run_folder::folder::{FolderError, FolderLock};
    match FolderLock::acquire_shared(dir) {
        Ok(lock) => Ok(Some(lock)),
        Err(FolderError::Held(_)) => Err(usage(format!(
            "{}: a curvenet run is writing in this folder; wait for it to end before `curvenet \
             {command}`",
            dir.display()
        ))),
        Err(_) => Ok(None),
    }
}

/// Checks, before any work, that `path` (the value of `option`) can be written: not a folder,
/// in a folder that exists.
pub fn writable_file(option: &str, path: &std::path::Path) -> anyhow::Result<()> {
    if path.is_dir() {
        return Err(usage(format!(
            "{option} {}: is a folder; give a file name",
            path.display()
        )));
    }
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    if !parent.is_dir() {
        return Err(usage(format!(
            "{option} {}: the folder {} does not exist",
            path.display(),
            parent.display()
        )));
    }
    Ok(())
}

/// Prints warnings on stderr, one per line: `warning: …`, or as they are when they already read
/// `file:line: warning: …` (the findings of the readers).
pub fn print_warnings(warnings: &[String]) {
    for w in warnings {
        if w.contains(": warning: ") {
            eprintln!("{w}");
        } else {
            eprintln!("warning: {w}");
        }
    }
}

//! One module per subcommand, plus the option handling they share.

mod analyze;
pub(crate) mod bench;
mod compare;
mod demo;
mod example;
mod export;
mod greedy_run;
mod simplify;
mod surface;
mod trace;
mod view;

use crate::args::{Cli, Command, InputArgs, PhysicsArgs};
use crate::exit::usage;
use curvenet::io::{self, Polyline, TriMesh};
use curvenet::network::{BuildParams, checks};
use curvenet::pipeline;
use curvenet::rod::Material;
use curvenet::simplify::result::InputDescription;
use curvenet::stability::StabilityParams;

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
    s.eigen.count = p.eigen_count;
    s.eigen.max_basis = s
        .eigen
        .max_basis
        .max(p.eigen_count + 4 * s.eigen.block_size);
    s.validate().map_err(usage)?;
    let m = &s.material;
    for (name, k, formula) in [
        ("stretching", m.ks(), "E π r²"),
        ("bending", m.kb(), "E π r⁴ / 4"),
    ] {
        if !(k.is_finite() && k > f64::MIN_POSITIVE) {
            return Err(usage(format!(
                "--radius {:e} and --young {:e} give a {name} stiffness {formula} = {k:e}, out \
                 of floating-point range; choose scene units where the radius is nearer 1",
                m.radius, m.young
            )));
        }
    }
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
    /// Each curve's material, section and rest shape from the curve files (empty when no
    /// file says anything).
    pub specs: Vec<curvenet::material::CurveSpec>,
    /// The length unit the curve files declare (the first that does).
    pub file_units: Option<String>,
}

/// Reads and scales the inputs.
pub fn load_inputs(a: &InputArgs, p: &PhysicsArgs) -> anyhow::Result<Inputs> {
    if !(a.scale.is_finite() && a.scale > 0.0) {
        return Err(usage(format!(
            "--scale must be a positive number, got {}",
            a.scale
        )));
    }
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
    let (mut specs, mut file_units) = (Vec::new(), None);
    for path in &a.curves {
        let f = io::read_curves(path)?;
        warnings.extend(f.warnings.iter().map(|w| w.to_string()));
        if !f.specs.is_empty() {
            specs.resize(curves.len(), Default::default());
            specs.extend(f.specs);
        }
        file_units = file_units.or(f.units);
        curves.extend(f.curves);
    }
    pipeline::scale_curves(&mut curves, a.scale);
    check_scaled(&curves, mesh.as_ref(), a)?;
    let h = match a.edge_length {
        Some(h) if !(h.is_finite() && h > 0.0) => {
            return Err(usage(format!(
                "--edge-length must be a positive finite number (scene units), got {h}"
            )));
        }
        Some(h) => h,
        None => {
            let h = pipeline::median_segment_length(&curves);
            if !(h.is_finite() && h > 0.0) {
                return Err(usage(format!(
                    "cannot choose the edge length: the median input segment is {h:e} long \
                     (coordinates out of range); give --edge-length or another --scale"
                )));
            }
            h
        }
    };
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
        specs,
        file_units,
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

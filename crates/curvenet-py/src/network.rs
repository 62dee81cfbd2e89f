//! `curvenet._native.Network`: a set-up of the application layer ([`curvenet::app::Setup`])
//! with its network built, and the two long calls on it, `analyze` ([`app::analyze`]) and
//! `simplify` ([`app::execute`], written to a run folder as the command line writes it).
//! Everything here converts Python values and calls the library; no logic of a run is here.

use crate::arrays::{points, vector, xyz};
use crate::errors;
use crate::inputs::{curve_from_tuple, curve_tuple, mesh_from_tuple, mesh_tuple};
use crate::interrupt;
use curvenet::app::{
    self, AppError, CurveSource, GivenCurves, InputSpec, MeshSource, ModelOptions, Observer,
    RunSpec, Setup,
};
use curvenet::constraints::{ConstraintParams, Group};
use curvenet::physics::PhysicalOptions;
use curvenet::simplify::Budget;
use curvenet::simplify::greedy::IterationRecord;
use curvenet::words::{Message, Opt, Wording};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::Mutex;

/// Options as Python spells them: keyword arguments (`max_gap`, `max_gap=900`,
/// `resume=True`).
pub struct Keywords;

impl Wording for Keywords {
    fn option(&self, opt: Opt) -> String {
        match opt {
            Opt::Connected
            | Opt::LocalSearch
            | Opt::Certify
            | Opt::Resume
            | Opt::Force
            | Opt::Slide
            | Opt::FixedEnds => {
                format!("{}=True", opt.key())
            }
            _ => opt.key().to_string(),
        }
    }

    fn given(&self, opt: Opt, value: &str) -> String {
        format!("{}={value}", opt.key())
    }
}

/// An application-layer error as the package's exception.
pub fn raise(py: Python<'_>, e: AppError) -> PyErr {
    match &e {
        AppError::Input(i) => errors::input(py, i),
        e if e.is_input() => errors::usage(py, e.render(&Keywords)),
        e => errors::failed(py, e.render(&Keywords)),
    }
}

/// A rod network built from curves, with the model of its analysis.
#[pyclass(module = "curvenet._native", frozen)]
pub struct Network {
    setup: Setup,
}

/// The curves of `sources`: each a curve file's path (read here, with the groups, specs and
/// units it declares) or a curve tuple of the package's readers (arrays, `.3dm` objects).
fn given_curves(py: Python<'_>, sources: &Bound<'_, PyList>) -> PyResult<GivenCurves> {
    let mut given = GivenCurves::default();
    for item in sources.iter() {
        if let Ok(path) = item.extract::<PathBuf>() {
            let read = py.detach(|| given.read_file(&path));
            read.map_err(|e| errors::input(py, &e))?;
        } else {
            given.push(curve_from_tuple(&item)?);
        }
    }
    if given.curves.is_empty() {
        return Err(errors::usage(py, "no curves given"));
    }
    Ok(given)
}

#[pymethods]
impl Network {
    /// Reads and builds the network. Private: use `curvenet.load` or `curvenet.example`.
    #[new]
    #[pyo3(signature = (sources, mesh = None, scale = 1.0, edge_length = None, supports = None,
        merge_joints = None, radius = None, young = None, anchor_weight = None, eigen_count = 4,
        objective = "lambda", units = None, material = None, density = None, strength = None,
        tube = None, load = None, gravity = None, loads = None, deflection_limit = None,
        buckling_factor = None, supports_file = None, warnings = Vec::new(), example = None,
        data = None))]
    fn new(
        py: Python<'_>,
        sources: &Bound<'_, PyList>,
        mesh: Option<&Bound<'_, PyAny>>,
        scale: f64,
        edge_length: Option<f64>,
        supports: Option<&str>,
        merge_joints: Option<f64>,
        radius: Option<f64>,
        young: Option<String>,
        anchor_weight: Option<f64>,
        eigen_count: usize,
        objective: &str,
        units: Option<String>,
        material: Option<String>,
        density: Option<String>,
        strength: Option<String>,
        tube: Option<String>,
        load: Option<String>,
        gravity: Option<String>,
        loads: Option<PathBuf>,
        deflection_limit: Option<String>,
        buckling_factor: Option<String>,
        supports_file: Option<PathBuf>,
        warnings: Vec<String>,
        example: Option<String>,
        data: Option<PathBuf>,
    ) -> PyResult<Self> {
        let supports = supports
            .map(str::parse)
            .transpose()
            .map_err(|e: String| errors::usage(py, format!("supports: {e}")))?;
        let objective = objective
            .parse()
            .map_err(|e: String| errors::usage(py, format!("objective: {e}")))?;
        let curves = match example {
            Some(name) => CurveSource::Example { name, data },
            None => {
                let mut given = given_curves(py, sources)?;
                let mut w = warnings;
                w.append(&mut given.warnings);
                given.warnings = w;
                CurveSource::Given(given)
            }
        };
        let mesh = match mesh {
            None => None,
            Some(m) => match m.extract::<PathBuf>() {
                Ok(p) => Some(MeshSource::Path(p)),
                Err(_) => {
                    let (mesh, name) = mesh_from_tuple(py, m)?;
                    Some(MeshSource::Given { mesh, name })
                }
            },
        };
        let input = InputSpec {
            curves,
            mesh,
            scale,
            edge_length,
            merge_joints,
            supports,
            supports_file,
        };
        let model = ModelOptions {
            radius,
            young,
            anchor_weight,
            eigen_count,
            objective,
            physical: PhysicalOptions {
                units,
                material,
                density,
                strength,
                tube,
                load,
                gravity,
                loads: loads.map(|p| p.display().to_string()),
                deflection_limit,
                buckling_factor,
                ..PhysicalOptions::default()
            },
        };
        let setup = py
            .detach(|| {
                let mut setup = Setup::new(&input, &model)?;
                setup.build()?;
                Ok(setup)
            })
            .map_err(|e| raise(py, e))?;
        Ok(Network { setup })
    }

    /// Vertex positions of the drawn (rest) state, `(V, 3)`.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(py, &self.network().positions)
    }

    /// Per curve, its vertex indices in order (a closed curve does not repeat its first).
    #[getter]
    fn rods<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArray1<u32>>> {
        self.network()
            .rods
            .iter()
            .map(|r| vector(py, r.vertices.clone()))
            .collect()
    }

    /// Per curve, whether it is closed.
    #[getter]
    fn closed(&self) -> Vec<bool> {
        self.network().rods.iter().map(|r| r.closed).collect()
    }

    /// Per curve, its anchored (supported) vertices.
    #[getter]
    fn anchors<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArray1<u32>>> {
        self.network()
            .rods
            .iter()
            .map(|r| vector(py, r.anchors.clone()))
            .collect()
    }

    /// Per curve, its rest length (the material to cut).
    #[getter]
    fn rest_lengths<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.network().rest_lengths())
    }

    /// The joints: `(vertex, [curves])` pairs.
    #[getter]
    fn joints(&self) -> Vec<(u32, Vec<u32>)> {
        self.network()
            .joints
            .iter()
            .map(|j| (j.vertex, j.curves.clone()))
            .collect()
    }

    /// The edge length `h` the curves were resampled at.
    #[getter]
    fn edge_length(&self) -> f64 {
        self.setup.inputs.build.edge_length
    }

    /// The supports of open curves (`"clamped"` or `"pinned"`).
    #[getter]
    fn supports(&self) -> &'static str {
        self.setup.inputs.build.supports.name()
    }

    /// The input curves, scaled, as reader tuples.
    #[getter]
    fn curves<'py>(&self, py: Python<'py>) -> Vec<crate::inputs::CurveTuple<'py>> {
        self.setup
            .inputs
            .curves
            .iter()
            .map(|c| curve_tuple(py, c))
            .collect()
    }

    /// The surface mesh, scaled, as `(vertices, faces)`, or `None`.
    #[getter]
    fn mesh<'py>(&self, py: Python<'py>) -> Option<crate::inputs::MeshTuple<'py>> {
        self.setup.inputs.mesh.as_ref().map(|m| mesh_tuple(py, m))
    }

    /// Warnings found while reading and building.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.setup
            .inputs
            .warnings
            .iter()
            .chain(&self.setup.build_warnings())
            .map(|w| w.render(&Keywords))
            .collect()
    }

    /// Construction details (JSON text).
    #[getter]
    fn build_info(&self) -> String {
        serde_json::to_string(&self.setup.built().expect("built at load").1)
            .expect("build info serialises")
    }

    /// The example's budget fraction, keep list and the paper's figures (JSON text), or
    /// `None` for curves given by the user.
    #[getter]
    fn example(&self) -> Option<(f64, Vec<usize>, String)> {
        self.setup.inputs.example.as_ref().map(|e| {
            (
                e.budget,
                e.keep.clone(),
                serde_json::to_string(&e.paper).expect("figures serialise"),
            )
        })
    }

    /// Relaxes the network without the curves `remove` and analyses its equilibrium:
    /// `{report (JSON text, with "physical" in the physical mode), eigenvalues, mode (V, 3),
    /// displacement (V, 3)}`.
    #[pyo3(signature = (remove = Vec::new()))]
    fn analyze<'py>(&self, py: Python<'py>, remove: Vec<usize>) -> PyResult<Bound<'py, PyDict>> {
        let mut setup = self.setup.clone();
        let out = interrupt::run(py, None, |_, _| {
            app::analyze(&mut setup, &remove, &Keywords)
        })?
        .map_err(|e| raise(py, e))?;
        let d = PyDict::new(py);
        d.set_item("report", out.to_json())?;
        d.set_item(
            "eigenvalues",
            vector(py, out.analysis.spectrum.values.clone()),
        )?;
        d.set_item("mode", xyz(py, out.analysis.mode()))?;
        d.set_item("displacement", xyz(py, out.analysis.displacement.clone()))?;
        Ok(d)
    }

    /// Runs the simplification into the run folder `out` (as `curvenet simplify` does),
    /// calling `progress` with each iteration's record (JSON text). Returns the warnings and
    /// notes.
    #[pyo3(signature = (out, budget = None, budget_length = None, keep = None,
        groups_file = None, groups = Vec::new(), symmetry = None, connected = false,
        min_curves = None, max_gap = None, max_deviation = None, local_search = false,
        alternatives = 0, certify = false, certificate_nodes = None, pictures = true,
        resume = false, force = false, progress = None, slide = false, max_move = None,
        fixed_ends = false, pin = Vec::new(), slide_rounds = 0))]
    fn simplify(
        &self,
        py: Python<'_>,
        out: PathBuf,
        budget: Option<f64>,
        budget_length: Option<f64>,
        keep: Option<Vec<usize>>,
        groups_file: Option<PathBuf>,
        groups: Vec<Vec<usize>>,
        symmetry: Option<&str>,
        connected: bool,
        min_curves: Option<usize>,
        max_gap: Option<f64>,
        max_deviation: Option<f64>,
        local_search: bool,
        alternatives: usize,
        certify: bool,
        certificate_nodes: Option<usize>,
        pictures: bool,
        resume: bool,
        force: bool,
        progress: Option<&Bound<'_, PyAny>>,
        slide: bool,
        max_move: Option<String>,
        fixed_ends: bool,
        pin: Vec<usize>,
        slide_rounds: usize,
    ) -> PyResult<Vec<String>> {
        let slide = match slide {
            true => Some(slide_spec(
                py,
                &out,
                &out,
                max_move,
                fixed_ends,
                pin,
                slide_rounds,
            )?),
            false => None,
        };
        let budget = match (budget, budget_length) {
            (Some(_), Some(_)) => {
                return Err(errors::usage(py, "give budget or budget_length, not both"));
            }
            (f, l) => f.map(Budget::Fraction).or(l.map(Budget::Length)),
        };
        let symmetry = symmetry
            .map(str::parse)
            .transpose()
            .map_err(|e: String| errors::usage(py, format!("symmetry: {e}")))?;
        let spec = RunSpec {
            budget,
            keep,
            constraints: ConstraintParams {
                groups: groups
                    .into_iter()
                    .enumerate()
                    .map(|(k, mut curves)| {
                        curves.sort_unstable();
                        curves.dedup();
                        Group {
                            name: format!("groups[{k}]"),
                            curves,
                            origin: format!("groups[{k}]"),
                        }
                    })
                    .collect(),
                symmetry: symmetry.unwrap_or_default(),
                connected,
                min_curves,
                max_gap,
                max_deviation,
                ..ConstraintParams::default()
            },
            groups_file,
            local_search,
            alternatives,
            certify,
            certificate_nodes,
            pictures,
            resume,
            force,
            slide,
            ..RunSpec::new(out)
        };
        let mut setup = self.setup.clone();
        let ran = interrupt::run(py, progress, |cancel, tx| {
            let observer = Forward {
                tx,
                curves: setup.curve_count(),
                messages: Mutex::new(Vec::new()),
            };
            let outcome = app::execute(&mut setup, &spec, &observer, cancel);
            (outcome, observer.messages.into_inner().unwrap_or_default())
        })?;
        let (outcome, mut messages) = ran;
        let outcome = outcome.map_err(|e| raise(py, e))?;
        if outcome.already_complete {
            messages.push(format!(
                "note: {}: the run is already complete",
                outcome.folder.display()
            ));
        }
        Ok(messages)
    }
}

/// The slide of Python's keywords, from the run in `from` into `out`.
fn slide_spec(
    py: Python<'_>,
    from: &std::path::Path,
    out: &std::path::Path,
    max_move: Option<String>,
    fixed_ends: bool,
    pin: Vec<usize>,
    rounds: usize,
) -> PyResult<app::SlideSpec> {
    let d = app::SlideSpec::new(from, out);
    let max_move = match max_move {
        Some(m) => m.parse().map_err(|e: Message| {
            errors::usage(py, format!("max_move={m}: {}", e.render(&Keywords)))
        })?,
        None => d.max_move,
    };
    Ok(app::SlideSpec {
        max_move,
        fixed_ends,
        pin,
        rounds,
        ..d
    })
}

/// Slides the answer of the run in `from` on its surface into the run folder `out` (as
/// `curvenet slide` does). Returns the warnings and notes.
#[pyfunction]
#[pyo3(signature = (from, out, max_move = None, fixed_ends = false, pin = Vec::new(),
    pictures = true, force = false, slide_rounds = 0))]
#[allow(clippy::too_many_arguments)]
pub fn slide(
    py: Python<'_>,
    from: PathBuf,
    out: PathBuf,
    max_move: Option<String>,
    fixed_ends: bool,
    pin: Vec<usize>,
    pictures: bool,
    force: bool,
    slide_rounds: usize,
) -> PyResult<Vec<String>> {
    let spec = app::SlideSpec {
        pictures,
        force,
        ..slide_spec(py, &from, &out, max_move, fixed_ends, pin, slide_rounds)?
    };
    let ran = interrupt::run(py, None, |cancel, tx| {
        let observer = Forward {
            tx,
            curves: 0,
            messages: Mutex::new(Vec::new()),
        };
        let outcome = app::slide(&spec, &observer, cancel);
        (outcome, observer.messages.into_inner().unwrap_or_default())
    })?;
    let (outcome, messages) = ran;
    outcome.map_err(|e| raise(py, e))?;
    Ok(messages)
}

impl Network {
    fn network(&self) -> &curvenet::network::Network {
        &self.setup.built().expect("built at load").0
    }
}

/// The observer of a Python call: iterations to the progress channel (JSON text), warnings
/// and notes collected in Python's words.
struct Forward<'a> {
    tx: &'a interrupt::Progress,
    /// The network's curve count (an iteration's index is the curves it removed).
    curves: usize,
    messages: Mutex<Vec<String>>,
}

impl Forward<'_> {
    fn push(&self, text: String) {
        self.messages
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(text);
    }
}

impl Observer for Forward<'_> {
    fn warning(&self, w: &Message) {
        self.push(w.render(&Keywords));
    }

    fn note(&self, n: &Message) {
        self.push(format!("note: {}", n.render(&Keywords)));
    }

    fn iteration(&self, r: &IterationRecord, total: f64, budget: f64) {
        let mut msg = serde_json::to_value(r).unwrap_or_default();
        if let Some(o) = msg.as_object_mut() {
            o.insert(
                "iteration".into(),
                self.curves.saturating_sub(r.curves.len()).into(),
            );
            o.insert("budget".into(), budget.into());
            o.insert("total_length".into(), total.into());
        }
        let _ = self.tx.send(msg.to_string());
    }
}

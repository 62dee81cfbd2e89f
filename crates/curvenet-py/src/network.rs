//! `curvenet._native.Network`: a built rod network with its inputs and parameters, and the
//! two long calls on it, `analyze` (the pipeline's analysis) and `simplify` (the greedy,
//! written to a run folder as `curvenet simplify` writes it).

use crate::arrays::{points, vector, xyz};
use crate::errors;
use crate::inputs::{curve_from_tuple, curve_tuple, mesh_from_tuple, mesh_tuple};
use crate::interrupt;
use curvenet::io::{Polyline, TriMesh};
use curvenet::network::{BuildInfo, BuildParams, build_network, checks};
use curvenet::pipeline;
use curvenet::rod::{Material, Supports};
use curvenet::run_folder::{InputDescription, LocalSearchRecord, OutputWriter, RunSetup, folder};
use curvenet::simplify::greedy::IterationRecord;
use curvenet::simplify::local::{LocalParams, local_search};
use curvenet::simplify::{Budget, GreedyParams, SimplifyError, greedy};
use curvenet::stability::{Analyzer, StabilityParams};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// A rod network built from curves, with the parameters of its analysis.
#[pyclass(module = "curvenet._native", frozen)]
pub struct Network {
    curves: Vec<Polyline>,
    mesh: Option<TriMesh>,
    build: BuildParams,
    stability: StabilityParams,
    description: InputDescription,
    warnings: Vec<String>,
    network: curvenet::network::Network,
    info: BuildInfo,
}

/// Stability parameters as the command line makes them (defaults where unset), checked.
fn stability_params(
    radius: Option<f64>,
    young: Option<f64>,
    anchor_weight: Option<f64>,
    eigen_count: usize,
) -> Result<StabilityParams, String> {
    let mut s = StabilityParams::default();
    let d = Material::default();
    s.material = Material {
        radius: radius.unwrap_or(d.radius),
        young: young.unwrap_or(d.young),
        anchor_weight: anchor_weight.unwrap_or(d.anchor_weight),
    };
    s.eigen = s.eigen.with_count(eigen_count);
    s.validate()?;
    let m = &s.material;
    for (name, k) in [("stretching", m.ks()), ("bending", m.kb())] {
        if !(k.is_finite() && k > f64::MIN_POSITIVE) {
            return Err(format!(
                "radius {:e} and young {:e} give a {name} stiffness {k:e}, out of floating-point \
                 range; choose scene units where the radius is nearer 1",
                m.radius, m.young
            ));
        }
    }
    Ok(s)
}

/// Scales curves and mesh by `scale` and chooses the edge length, as the command line does.
fn scaled_inputs(
    curves: &mut [Polyline],
    mesh: Option<&mut TriMesh>,
    scale: f64,
    edge_length: Option<f64>,
) -> Result<f64, String> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(format!("scale must be a positive number, got {scale}"));
    }
    pipeline::scale_curves(curves, scale);
    if let Some((c, curve)) = curves
        .iter()
        .enumerate()
        .find(|(_, c)| c.points.iter().any(|p| !p.is_finite()))
    {
        return Err(format!(
            "{}: scale {scale} makes the coordinates of curve {c} overflow; choose a smaller \
             scale",
            curve.origin
        ));
    }
    if let Some(m) = mesh {
        for v in &mut m.vertices {
            *v = *v * scale;
        }
        if m.vertices.iter().any(|p| !p.is_finite()) {
            return Err(format!(
                "scale {scale} makes the mesh's coordinates overflow; choose a smaller scale"
            ));
        }
    }
    match edge_length {
        Some(h) if !(h.is_finite() && h > 0.0) => Err(format!(
            "edge_length must be a positive finite number (scene units), got {h}"
        )),
        Some(h) => Ok(h),
        None => {
            let h = pipeline::median_segment_length(curves);
            if h.is_finite() && h > 0.0 {
                Ok(h)
            } else {
                Err(format!(
                    "cannot choose the edge length: the median input segment is {h:e} long \
                     (coordinates out of range); give edge_length or another scale"
                ))
            }
        }
    }
}

/// The budget from a fraction or a length (exactly one).
fn budget_of(fraction: Option<f64>, length: Option<f64>) -> Result<Budget, String> {
    let b = match (fraction, length) {
        (Some(f), None) => Budget::Fraction(f),
        (None, Some(l)) => Budget::Length(l),
        (Some(_), Some(_)) => return Err("give budget or budget_length, not both".into()),
        (None, None) => return Err("give a budget: budget=FRACTION or budget_length=L".into()),
    };
    b.validate()?;
    Ok(b)
}

#[pymethods]
impl Network {
    /// Builds the network of `curves` (tuples from the readers). Private: use
    /// `curvenet.load`.
    #[new]
    #[pyo3(signature = (curves, mesh = None, mesh_name = None, scale = 1.0, edge_length = None,
        supports = "clamped", merge_joints = None, radius = None, young = None,
        anchor_weight = None, eigen_count = 4, warnings = Vec::new(), example = None,
        curve_files = Vec::new()))]
    fn new(
        py: Python<'_>,
        curves: &Bound<'_, PyList>,
        mesh: Option<&Bound<'_, PyAny>>,
        mesh_name: Option<String>,
        scale: f64,
        edge_length: Option<f64>,
        supports: &str,
        merge_joints: Option<f64>,
        radius: Option<f64>,
        young: Option<f64>,
        anchor_weight: Option<f64>,
        eigen_count: usize,
        mut warnings: Vec<String>,
        example: Option<String>,
        curve_files: Vec<String>,
    ) -> PyResult<Self> {
        let mut curves: Vec<Polyline> = curves
            .iter()
            .map(|t| curve_from_tuple(&t))
            .collect::<PyResult<_>>()?;
        if curves.is_empty() {
            return Err(errors::usage(py, "no curves given"));
        }
        let mut mesh = mesh.map(|m| mesh_from_tuple(py, m)).transpose()?;
        let supports: Supports = supports.parse().map_err(|e: String| errors::usage(py, e))?;
        let stability = stability_params(radius, young, anchor_weight, eigen_count)
            .map_err(|e| errors::usage(py, e))?;
        let h = scaled_inputs(&mut curves, mesh.as_mut(), scale, edge_length)
            .map_err(|e| errors::usage(py, e))?;
        let build = BuildParams {
            edge_length: h,
            supports,
            merge_joints_below: merge_joints,
            ..BuildParams::default()
        };
        build
            .validate()
            .map_err(|e| errors::usage(py, e.to_string()))?;
        let built = py.detach(|| {
            let mut found = Vec::new();
            if let Some(m) = &mesh {
                let name = mesh_name.clone().unwrap_or_default();
                found.extend(checks::mesh_warnings(m, &name));
                let far = checks::curves_far_from_mesh(&curves, m, checks::FAR_FROM_MESH);
                found.extend(checks::far_from_mesh_warning(&far, &name));
            }
            build_network(&curves, &build).map(|b| (b, found))
        });
        let ((network, info), found) = built.map_err(|e| errors::usage(py, e.to_string()))?;
        warnings.extend(found);
        Ok(Network {
            description: InputDescription {
                example,
                mesh: mesh_name,
                curve_files,
                scale,
            },
            curves,
            mesh,
            build,
            stability,
            warnings,
            network,
            info,
        })
    }

    /// Vertex positions of the drawn (rest) state, `(V, 3)`.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(py, &self.network.positions)
    }

    /// Per curve, its vertex indices in order (a closed curve does not repeat its first).
    #[getter]
    fn rods<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArray1<u32>>> {
        self.network
            .rods
            .iter()
            .map(|r| vector(py, r.vertices.clone()))
            .collect()
    }

    /// Per curve, whether it is closed.
    #[getter]
    fn closed(&self) -> Vec<bool> {
        self.network.rods.iter().map(|r| r.closed).collect()
    }

    /// Per curve, its anchored (supported) vertices.
    #[getter]
    fn anchors<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArray1<u32>>> {
        self.network
            .rods
            .iter()
            .map(|r| vector(py, r.anchors.clone()))
            .collect()
    }

    /// Per curve, its rest length (the material to cut).
    #[getter]
    fn rest_lengths<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.network.rest_lengths())
    }

    /// The joints: `(vertex, [curves])` pairs.
    #[getter]
    fn joints(&self) -> Vec<(u32, Vec<u32>)> {
        self.network
            .joints
            .iter()
            .map(|j| (j.vertex, j.curves.clone()))
            .collect()
    }

    /// The edge length `h` the curves were resampled at.
    #[getter]
    fn edge_length(&self) -> f64 {
        self.build.edge_length
    }

    /// The supports of open curves (`"clamped"` or `"pinned"`).
    #[getter]
    fn supports(&self) -> &'static str {
        self.build.supports.name()
    }

    /// The input curves, scaled, as reader tuples.
    #[getter]
    fn curves<'py>(&self, py: Python<'py>) -> Vec<crate::inputs::CurveTuple<'py>> {
        self.curves.iter().map(|c| curve_tuple(py, c)).collect()
    }

    /// The surface mesh, scaled, as `(vertices, faces)`, or `None`.
    #[getter]
    fn mesh<'py>(&self, py: Python<'py>) -> Option<crate::inputs::MeshTuple<'py>> {
        self.mesh.as_ref().map(|m| mesh_tuple(py, m))
    }

    /// Warnings found while reading and building.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// Construction details (JSON text).
    #[getter]
    fn build_info(&self) -> PyResult<String> {
        serde_json::to_string(&self.info)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))
    }

    /// Relaxes the network without the curves `remove` and analyses its equilibrium:
    /// `(report JSON, eigenvalues, mode (V, 3), displacement (V, 3))`.
    #[pyo3(signature = (remove = Vec::new()))]
    fn analyze<'py>(&self, py: Python<'py>, remove: Vec<usize>) -> PyResult<Bound<'py, PyDict>> {
        let n = self.curves.len();
        if let Some(&bad) = remove.iter().find(|&&c| c >= n) {
            return Err(errors::usage(
                py,
                format!(
                    "remove names curve {bad}, but the network has {n} curves (ids 0..{})",
                    n.saturating_sub(1)
                ),
            ));
        }
        let mut remove = remove;
        remove.sort_unstable();
        remove.dedup();
        if remove.len() >= n {
            return Err(errors::usage(
                py,
                "remove would remove every curve; nothing is left to analyse",
            ));
        }
        let out = interrupt::run(py, None, |_, _| {
            pipeline::analyze(
                &self.curves,
                &self.build,
                &self.stability,
                None,
                &remove,
                self.warnings.clone(),
            )
        })?
        .map_err(|e| errors::failed(py, e.to_string()))?;
        let d = PyDict::new(py);
        let report =
            serde_json::to_string(&out.report).map_err(|e| errors::failed(py, e.to_string()))?;
        d.set_item("report", report)?;
        d.set_item(
            "eigenvalues",
            vector(py, out.analysis.spectrum.values.clone()),
        )?;
        d.set_item("mode", xyz(py, out.analysis.mode()))?;
        d.set_item("displacement", xyz(py, out.analysis.displacement.clone()))?;
        Ok(d)
    }

    /// Runs the greedy into the run folder `out` (as `curvenet simplify` does), calling
    /// `progress` with each iteration's record (JSON text). Returns the warnings.
    #[pyo3(signature = (out, budget = None, budget_length = None, keep = Vec::new(),
        local_search = false, pictures = true, resume = false, force = false, progress = None))]
    fn simplify(
        &self,
        py: Python<'_>,
        out: PathBuf,
        budget: Option<f64>,
        budget_length: Option<f64>,
        keep: Vec<usize>,
        local_search: bool,
        pictures: bool,
        resume: bool,
        force: bool,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Vec<String>> {
        let budget = budget_of(budget, budget_length).map_err(|e| errors::usage(py, e))?;
        let params = GreedyParams {
            keep,
            ..GreedyParams::new(budget)
        };
        let stability = self.stability.clone();
        params
            .validate(self.curves.len())
            .map_err(|e| errors::usage(py, e))?;
        let job = Job {
            net: self,
            stability,
            params,
            out,
            local_search,
            pictures,
            resume,
            force,
        };
        let ran = interrupt::run(py, progress, |cancel, tx| job.run(cancel, tx))?;
        ran.map_err(|e| match e {
            JobError::Usage(m) => errors::usage(py, m),
            JobError::Failed(m) => errors::failed(py, m),
        })
    }
}

/// A greedy run of [`Network::simplify`].
struct Job<'a> {
    net: &'a Network,
    stability: StabilityParams,
    params: GreedyParams,
    out: PathBuf,
    local_search: bool,
    pictures: bool,
    resume: bool,
    /// Run into a non-empty folder that is not a curvenet run's.
    force: bool,
}

/// Why a [`Job`] failed.
enum JobError {
    /// The request was wrong (budget, folder, resume of another set-up).
    Usage(String),
    /// A computation failed.
    Failed(String),
}

impl Job<'_> {
    fn run(
        &self,
        cancel: &curvenet::cancel::Cancel,
        tx: &interrupt::Progress,
    ) -> Result<Vec<String>, JobError> {
        let start = Instant::now();
        let net = self.net;
        let network = net.network.clone();
        let n = network.rods.len();
        let total = network.total_length(&(0..n).collect::<Vec<_>>());
        let budget = self.params.budget.length(total);
        let mut warnings = Vec::new();
        // The folder as the command line claims it: locked for the run, a resumed run's stale
        // temporary files removed, a fresh run's earlier files removed once it starts.
        let resuming = self.resume && self.out.join("result.json").is_file();
        let (lock, fresh) = self.claim(resuming)?;
        if let Some(w) = &lock.warning {
            warnings.push(w.clone());
        }
        if budget >= total {
            warnings.push(format!(
                "the budget {} is not below the total length {}: nothing will be removed",
                curvenet::fmt::length(budget),
                curvenet::fmt::length(total)
            ));
        }
        let kept_length = network.total_length(&self.params.keep);
        if kept_length > budget {
            warnings.push(format!(
                "the keep list alone needs {}, more than the budget {}: the budget cannot be met",
                curvenet::fmt::length(kept_length),
                curvenet::fmt::length(budget)
            ));
        }
        if !net.info.isolated_curves.is_empty() {
            warnings.push(format!(
                "curves that cross nothing: {:?}",
                net.info.isolated_curves
            ));
        }
        let setup = RunSetup {
            input: net.description.clone(),
            build: net.build.clone(),
            stability: self.stability.clone(),
            greedy: self.params.clone(),
            network: net.info.clone(),
            total_length: total,
            constraints: Default::default(),
            physical: None,
        };
        let analyzer = Analyzer::new(network, self.stability.clone()).map_err(JobError::Usage)?;
        let network = analyzer.network();
        let (writer, resume_point) = if resuming {
            let (w, p) = OutputWriter::resume(&self.out, network, &setup, net.mesh.as_ref())
                .map_err(JobError::Usage)?;
            warnings.extend(w.warnings().iter().cloned());
            if p.is_none() && w.result().complete {
                return Ok(warnings);
            }
            (w, p)
        } else {
            if let Some(fresh) = fresh
                && let Some(note) = fresh.apply().map_err(|e| JobError::Usage(e.to_string()))?
            {
                warnings.push(note);
            }
            (
                OutputWriter::create(&self.out, network, setup, budget).map_err(JobError::Usage)?,
                None,
            )
        };
        if let Some(mesh) = &net.mesh {
            writer.write_mesh(mesh).map_err(JobError::Failed)?;
        }
        // The writer polls a flag; mirror the token into it from the progress path and from
        // the greedy's own polls (through `Cancelling`).
        let flag = Cancelling {
            cancel: cancel.clone(),
            flag: AtomicBool::new(false),
        };
        let progress = |r: &IterationRecord| {
            let k = n - r.curves.len();
            let msg = serde_json::json!({
                "iteration": k,
                "curves": r.curves,
                "length": r.length,
                "lambda": r.lambda,
                "zero_modes": r.zero_modes,
                "negative_modes": r.negative_modes,
                "removed": r.removed,
                "score": r.score,
                "budget": budget,
                "total_length": total,
            });
            let _ = tx.send(msg.to_string());
        };
        let poller = flag.watch();
        let mut writer = writer.with_cancel(&flag.flag).with_progress(&progress);
        let outcome = std::thread::scope(|s| {
            s.spawn(poller);
            let o = greedy(&analyzer, &self.params, None, resume_point, &mut writer);
            flag.done();
            o
        });
        let outcome = match outcome {
            Ok(o) => o,
            Err(SimplifyError::Cancelled) => {
                return Err(JobError::Failed(format!(
                    "cancelled: {} iteration(s) kept in {}; simplify again with resume=True to \
                     continue",
                    writer.result().iterations.len(),
                    self.out.display()
                )));
            }
            Err(e) => return Err(JobError::Failed(e.to_string())),
        };
        warnings.extend(curvenet::run_folder::unrelaxed(
            &outcome.iterations,
            analyzer.objective(),
        ));
        let local_start = Instant::now();
        if self.local_search {
            match local_search_of(&analyzer, &self.params, &outcome) {
                Ok(r) => writer.set_local_search(Some(r)),
                Err(e) => warnings.push(format!("no local search: {e}")),
            }
        }
        let timings = serde_json::json!({
            "total_seconds": start.elapsed().as_secs_f64(),
            "greedy": outcome.timings,
            "local_search_seconds": self.local_search.then(|| local_start.elapsed().as_secs_f64()),
            "threads": rayon_threads(),
        });
        writer
            .finish(&outcome, &timings)
            .map_err(JobError::Failed)?;
        if self.pictures {
            match curvenet::report::viewer::write_run_outputs(&self.out) {
                Ok(o) => warnings.extend(o.warnings),
                Err(e) => warnings.push(format!("pictures and viewer not written: {e}")),
            }
        }
        Ok(warnings)
    }
}

impl Job<'_> {
    /// Takes the run folder `out` (created when missing) as `curvenet simplify --out` does
    /// ([`folder::claim`], [`folder::fresh_start`]): its lock, held while the run writes, and
    /// for a fresh run what it removes first.
    fn claim(
        &self,
        resuming: bool,
    ) -> Result<(folder::FolderLock, Option<folder::FreshStart>), JobError> {
        let out = &self.out;
        if out.exists() && !out.is_dir() {
            return Err(JobError::Usage(format!(
                "out={}: is a file, not a folder; give a folder for the run's outputs",
                out.display()
            )));
        }
        std::fs::create_dir_all(out).map_err(|e| {
            JobError::Usage(format!(
                "out={}: cannot create the folder: {e}",
                out.display()
            ))
        })?;
        let said = |e: folder::FolderError| {
            JobError::Usage(match e {
                folder::FolderError::Held(dir) => format!(
                    "{}: another curvenet run is writing in this folder; wait for it to end or \
                     give another out",
                    dir.display()
                ),
                folder::FolderError::NotARun { dir, foreign } => format!(
                    "{}: the folder is not empty and is not a curvenet run's (it holds {}); give \
                     an empty or new folder, or force=True to run there anyway (the run's own \
                     files are replaced, the others kept)",
                    dir.display(),
                    foreign.join(", ")
                ),
                folder::FolderError::Io(m) => m,
            })
        };
        let claim = folder::claim(out, resuming).map_err(said)?;
        let fresh = if resuming {
            None
        } else {
            Some(folder::fresh_start(out, self.force).map_err(said)?)
        };
        Ok((claim.lock, fresh))
    }
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The flag the run folder's writer polls, set from the [`curvenet::cancel::Cancel`] token.
struct Cancelling {
    cancel: curvenet::cancel::Cancel,
    flag: AtomicBool,
}

impl Cancelling {
    /// A poller that copies the token into the flag until [`Self::done`].
    fn watch(&self) -> impl FnOnce() + Send + '_ {
        move || {
            while !self.flag.load(Ordering::Relaxed) {
                if self.cancel.is_cancelled() {
                    self.flag.store(true, Ordering::Relaxed);
                    return;
                }
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
        }
    }

    /// Stops the poller (also sets the flag: the run is over).
    fn done(&self) {
        self.flag.store(true, Ordering::Relaxed);
    }
}

/// The local search from the greedy's final network (when it is within the budget) and from
/// the best single curves, with the run's budget and keep list.
fn local_search_of(
    analyzer: &Analyzer,
    params: &GreedyParams,
    outcome: &curvenet::simplify::GreedyOutcome,
) -> Result<LocalSearchRecord, String> {
    let last = outcome.iterations.last().ok_or("no iteration")?;
    let local = LocalParams {
        keep: params.keep.clone(),
        ..LocalParams::new(params.budget)
    };
    let o = local_search(
        analyzer,
        &local,
        None,
        &last.curves,
        &curvenet::cancel::Cancel::never(),
    )
    .map_err(|e| e.to_string())?;
    LocalSearchRecord::new(&local, &o, &last.curves)
        .ok_or_else(|| "λ_eq could not be evaluated".to_string())
}

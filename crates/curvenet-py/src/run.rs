//! `curvenet._native.Run`: a run folder (of `curvenet simplify`/`example`, or of
//! `Network.simplify`) read with the library's run-folder reader.

use crate::arrays::{points, xyz};
use crate::errors;
use crate::network::Keywords;
use curvenet::report::ReportError;
use curvenet::report::export::{ExportFormat, export_files, write_exports};
use curvenet::run_folder::RunFolder;
use curvenet::run_folder::RunFolderError;
use curvenet::run_folder::network_polylines;
use numpy::PyArray2;
use pyo3::prelude::*;
use std::path::PathBuf;

/// A run folder, read and checked.
#[pyclass(module = "curvenet._native", frozen)]
pub struct Run {
    run: RunFolder,
}

impl Run {
    fn k(&self, py: Python<'_>, k: Option<usize>) -> PyResult<usize> {
        let k = k.unwrap_or_else(|| self.run.last_index());
        self.run
            .record(k)
            .map_err(|e| errors::usage(py, said(&e)))?;
        Ok(k)
    }
}

/// A run folder's error in the package's words (a missing network names its keyword).
fn said(e: &RunFolderError) -> String {
    match e {
        RunFolderError::Absent(m) | RunFolderError::Resume(m) => m.render(&Keywords),
        e => e.to_string(),
    }
}

/// An export's error in the package's words.
fn reported(e: &ReportError) -> String {
    match e {
        ReportError::RunFolder(e) => said(e),
        e => e.to_string(),
    }
}

/// An export's error as the package raises it: `InputError` for a structural export of a run
/// in the paper's mode, `CurvenetError` otherwise.
fn export_error(py: Python<'_>, e: &ReportError) -> PyErr {
    match e {
        ReportError::NotPhysical => errors::usage(py, reported(e)),
        e => errors::failed(py, reported(e)),
    }
}

#[pymethods]
impl Run {
    /// Opens the run folder `dir`.
    #[new]
    fn new(py: Python<'_>, dir: PathBuf) -> PyResult<Self> {
        let run = py
            .detach(|| RunFolder::open(&dir))
            .map_err(|e| errors::usage(py, said(&e)))?;
        Ok(Run { run })
    }

    /// The folder.
    #[getter]
    fn dir(&self) -> PathBuf {
        self.run.dir.clone()
    }

    /// `result.json` as JSON text (as the library reads it).
    #[getter]
    fn result_json(&self, py: Python<'_>) -> PyResult<String> {
        serde_json::to_string(&self.run.result).map_err(|e| errors::failed(py, e.to_string()))
    }

    /// Problems found while reading that did not stop it.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.run.warnings.clone()
    }

    /// Vertex positions of the network's drawn state, `(V, 3)`.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(py, &self.run.network.positions)
    }

    /// Number of curves of the network.
    #[getter]
    fn curve_count(&self) -> usize {
        self.run.network.rods.len()
    }

    /// Equilibrium displacements of iteration `k` (default: the last), `(V, 3)`.
    #[pyo3(signature = (k = None))]
    fn displacement<'py>(
        &self,
        py: Python<'py>,
        k: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let k = self.k(py, k)?;
        let u = self
            .run
            .displacement(k)
            .map_err(|e| errors::usage(py, said(&e)))?;
        Ok(xyz(py, u))
    }

    /// Worst-case mode of iteration `k` (default: the last), `(V, 3)`, unit norm.
    #[pyo3(signature = (k = None))]
    fn mode<'py>(&self, py: Python<'py>, k: Option<usize>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let k = self.k(py, k)?;
        let v = self.run.mode(k).map_err(|e| errors::usage(py, said(&e)))?;
        Ok(xyz(py, v))
    }

    /// The polylines of `curves` (rod vertices in order) at rest, or displaced by `u`
    /// (`(V, 3)`, e.g. an equilibrium displacement). Returns `[(points, closed)]`.
    #[pyo3(signature = (curves, u = None))]
    fn polylines<'py>(
        &self,
        py: Python<'py>,
        curves: Vec<usize>,
        u: Option<numpy::PyReadonlyArray2<'py, f64>>,
    ) -> PyResult<Vec<(Bound<'py, PyArray2<f64>>, bool)>> {
        let n = self.run.network.rods.len();
        if let Some(&c) = curves.iter().find(|&&c| c >= n) {
            return Err(errors::usage(
                py,
                format!("no curve {c}: the network has {n} curves"),
            ));
        }
        let u: Option<Vec<f64>> = match u {
            Some(a) => {
                let pts = crate::arrays::to_points(&a, "u")?;
                if pts.len() != self.run.network.positions.len() {
                    return Err(errors::usage(
                        py,
                        format!(
                            "u has {} rows, the network {} vertices",
                            pts.len(),
                            self.run.network.positions.len()
                        ),
                    ));
                }
                Some(pts.iter().flat_map(|p| [p.x, p.y, p.z]).collect())
            }
            None => None,
        };
        Ok(network_polylines(&self.run.network, &curves, u.as_deref())
            .iter()
            .map(|p| (points(py, &p.points), p.closed))
            .collect())
    }

    /// Writes iteration `k`'s files in `format` (obj, json, csv, network, structural, opensees,
    /// all) into the folder `out`; returns their paths.
    #[pyo3(signature = (out, format = "all", k = None))]
    fn export(
        &self,
        py: Python<'_>,
        out: PathBuf,
        format: &str,
        k: Option<usize>,
    ) -> PyResult<Vec<PathBuf>> {
        let format: ExportFormat = format.parse().map_err(|e: String| errors::usage(py, e))?;
        let k = self.k(py, k)?;
        py.detach(|| write_exports(&self.run, k, format, &out))
            .map_err(|e| export_error(py, &e))
    }

    /// The main file of `format` for iteration `k`, as `(name, text)`.
    #[pyo3(signature = (format, k = None))]
    fn export_text(
        &self,
        py: Python<'_>,
        format: &str,
        k: Option<usize>,
    ) -> PyResult<(String, String)> {
        let format: ExportFormat = format.parse().map_err(|e: String| errors::usage(py, e))?;
        let k = self.k(py, k)?;
        let files = export_files(&self.run, k, format).map_err(|e| export_error(py, &e))?;
        files
            .into_iter()
            .next()
            .ok_or_else(|| errors::failed(py, "nothing to export"))
    }
}

//! Reading inputs: curve and mesh files, point arrays, the paper's examples.

use crate::arrays::{points, to_points};
use crate::errors;
use curvenet::io::{self, InputWarning, PointCurve, Polyline, TriMesh};
use curvenet::paper;
use numpy::ndarray::Array2;
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::path::PathBuf;

/// One curve as Python sees it: `(points (n, 3), closed, label, file, line)`.
pub type CurveTuple<'py> = (
    Bound<'py, PyArray2<f64>>,
    bool,
    Option<String>,
    String,
    usize,
);

/// A curve to its Python tuple.
pub fn curve_tuple<'py>(py: Python<'py>, c: &Polyline) -> CurveTuple<'py> {
    (
        points(py, &c.points),
        c.closed,
        c.label.clone(),
        c.origin.file.clone(),
        c.origin.line,
    )
}

/// A curve from its Python tuple (already checked: it came from a reader).
pub fn curve_from_tuple(t: &Bound<'_, PyAny>) -> PyResult<Polyline> {
    let (pts, closed, label, file, line): (
        PyReadonlyArray2<'_, f64>,
        bool,
        Option<String>,
        String,
        usize,
    ) = t.extract()?;
    Ok(Polyline {
        points: to_points(&pts, "curve")?,
        closed,
        origin: io::Origin::new(file, line),
        label,
    })
}

/// A mesh as Python sees it: `(vertices (V, 3), faces (F, 3) uint32)`.
pub type MeshTuple<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>);

/// A mesh to its Python tuple.
pub fn mesh_tuple<'py>(py: Python<'py>, m: &TriMesh) -> MeshTuple<'py> {
    let flat: Vec<u32> = m.faces.iter().flatten().copied().collect();
    let faces = Array2::from_shape_vec((m.faces.len(), 3), flat).expect("3 indices per face");
    (
        points(py, &m.vertices),
        PyArray2::from_owned_array(py, faces),
    )
}

/// A mesh from `(vertices, faces, name)`: `faces` an int64 array (the Python layer converts
/// any integer dtype, refusing others), checked by the library when the set-up is read.
pub fn mesh_from_tuple(py: Python<'_>, t: &Bound<'_, PyAny>) -> PyResult<(TriMesh, String)> {
    let (v, f, name): (PyReadonlyArray2<'_, f64>, PyReadonlyArray2<'_, i64>, String) =
        t.extract()?;
    let vertices = to_points(&v, "mesh vertices")?;
    let f = f.as_array();
    if f.ncols() != 3 {
        return Err(errors::usage(
            py,
            format!(
                "{name}: faces: expected an (m, 3) array of vertex indices, got shape {:?}",
                f.shape()
            ),
        ));
    }
    let mut faces = Vec::with_capacity(f.nrows());
    for (k, r) in f.rows().into_iter().enumerate() {
        let mut face = [0u32; 3];
        for (slot, &i) in face.iter_mut().zip(r.iter()) {
            *slot = u32::try_from(i).map_err(|_| {
                errors::usage(
                    py,
                    format!(
                        "{name}: face {k} names vertex {i}, but the mesh has {} vertices",
                        vertices.len()
                    ),
                )
            })?;
        }
        faces.push(face);
    }
    Ok((TriMesh { vertices, faces }, name))
}

fn warning_texts(w: &[InputWarning]) -> Vec<String> {
    w.iter().map(ToString::to_string).collect()
}

/// Reads a curve file (`.txt`, `.obj`, `.json`): `([curve tuples], [warnings])`.
#[pyfunction]
pub fn read_curves<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(Vec<CurveTuple<'py>>, Vec<String>)> {
    let f = py
        .detach(|| io::read_curves(&path))
        .map_err(|e| errors::input(py, &e))?;
    let curves = f.curves.iter().map(|c| curve_tuple(py, c)).collect();
    Ok((curves, warning_texts(&f.warnings)))
}

/// Normalises curves given as point arrays like the file readers: `file` and each curve's
/// `line` (a 1-based position, 0 unknown) name it in messages; `closed[i]` is `True`,
/// `False` or `None` (closed when the last point repeats the first).
#[pyfunction]
#[pyo3(signature = (file, arrays, closed, labels, lines))]
pub fn curves_from_arrays<'py>(
    py: Python<'py>,
    file: String,
    arrays: Vec<PyReadonlyArray2<'py, f64>>,
    closed: Vec<Option<bool>>,
    labels: Vec<Option<String>>,
    lines: Vec<usize>,
) -> PyResult<(Vec<CurveTuple<'py>>, Vec<String>)> {
    let n = arrays.len();
    if closed.len() != n || labels.len() != n || lines.len() != n {
        return Err(errors::usage(
            py,
            "one closed flag, label and line per curve",
        ));
    }
    let mut curves = Vec::with_capacity(n);
    for (k, a) in arrays.iter().enumerate() {
        let pts = to_points(a, &format!("{file}: curve {k}"))?;
        curves.push(PointCurve {
            points: pts,
            closed: closed[k],
            label: labels[k].clone(),
            line: lines[k],
        });
    }
    let f = io::curves_from_points(&file, curves).map_err(|e| errors::input(py, &e))?;
    let out = f.curves.iter().map(|c| curve_tuple(py, c)).collect();
    Ok((out, warning_texts(&f.warnings)))
}

/// Reads a mesh: an OBJ file, or the name of a built-in surface (`builtin:NAME` or `NAME`
/// when no such file exists). Returns `((vertices, faces), description, [warnings])`.
#[pyfunction]
pub fn read_mesh<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyTuple>> {
    let text = path.to_string_lossy().to_string();
    let builtin = text.strip_prefix("builtin:");
    let (mesh, description, warnings) = if builtin.is_none() && path.exists() {
        let f = py
            .detach(|| io::read_mesh(&path))
            .map_err(|e| errors::input(py, &e))?;
        (f.mesh, text.clone(), warning_texts(&f.warnings))
    } else {
        let name = builtin.unwrap_or(&text);
        let mesh = curvenet::trace::surfaces::builtin_surface(name).ok_or_else(|| {
            errors::usage(
                py,
                format!(
                    "{text}: no such file, and not a built-in surface (built-in: {})",
                    curvenet::trace::surfaces::SURFACE_NAMES.join(", ")
                ),
            )
        })?;
        (mesh, format!("builtin:{name}"), Vec::new())
    };
    (mesh_tuple(py, &mesh), description, warnings).into_pyobject(py)
}

/// The names of the paper's examples.
#[pyfunction]
pub fn example_names() -> Vec<&'static str> {
    paper::NAMES.to_vec()
}

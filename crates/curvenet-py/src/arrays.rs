//! numpy arrays to and from the library's point and vector types.

use curvenet::geom::Vec3;
use numpy::ndarray::Array2;
use numpy::{PyArray1, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An `(n, 3)` array of points.
pub fn points<'py>(py: Python<'py>, pts: &[Vec3]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    xyz(py, flat)
}

/// A flat vector of `3·n` values as an `(n, 3)` array.
pub fn xyz(py: Python<'_>, flat: Vec<f64>) -> Bound<'_, PyArray2<f64>> {
    let n = flat.len() / 3;
    let a = Array2::from_shape_vec((n, 3), flat).expect("3·n values");
    PyArray2::from_owned_array(py, a)
}

/// A one-dimensional array.
pub fn vector<T: numpy::Element>(py: Python<'_>, v: Vec<T>) -> Bound<'_, PyArray1<T>> {
    PyArray1::from_vec(py, v)
}

/// Points from an `(n, 3)` array (`what` names it in the error).
pub fn to_points(a: &PyReadonlyArray2<'_, f64>, what: &str) -> PyResult<Vec<Vec3>> {
    let a = a.as_array();
    if a.ncols() != 3 {
        return Err(PyValueError::new_err(format!(
            "{what}: expected an (n, 3) array of points, got shape {:?}",
            a.shape()
        )));
    }
    Ok(a.rows()
        .into_iter()
        .map(|r| Vec3::new(r[0], r[1], r[2]))
        .collect())
}

//! The native half of the `curvenet` Python package (`curvenet._native`).
//!
//! The package's public API is the pure-Python layer in `python/curvenet/`; this module gives
//! it the library's application layer ([`curvenet::app`]: the set-up, the analysis, the
//! whole run) and the run-folder reader — with numpy arrays in and out, the GIL released during
//! every long computation ([`interrupt`]) and library errors raised as the package's exceptions
//! ([`errors`]). Structured records (the analysis report, the run's `result.json`) cross as
//! JSON text, so every field the library adds reaches Python without a change here.

mod arrays;
mod errors;
mod inputs;
mod interrupt;
mod network;
mod run;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(inputs::read_curves, m)?)?;
    m.add_function(wrap_pyfunction!(inputs::read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(inputs::curves_from_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(inputs::example_names, m)?)?;
    m.add_function(wrap_pyfunction!(network::slide, m)?)?;
    m.add_class::<network::Network>()?;
    m.add_class::<run::Run>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

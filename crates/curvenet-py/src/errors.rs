//! Library errors as the package's exceptions (defined in `curvenet/_errors.py`):
//! `InputError(ValueError)` for bad input, with `file` and `line` attributes; `Cancelled`
//! never reaches Python (a cancelled call raises the `KeyboardInterrupt` that cancelled it);
//! `CurvenetError(RuntimeError)` for a computation that failed.

use curvenet::io::InputError;
use pyo3::prelude::*;

fn raise<'py>(py: Python<'py>, class: &str, args: impl pyo3::call::PyCallArgs<'py>) -> PyErr {
    let made = py
        .import("curvenet._errors")
        .and_then(|m| m.getattr(class))
        .and_then(|c| c.call1(args));
    match made {
        Ok(e) => PyErr::from_value(e),
        Err(e) => e,
    }
}

/// `curvenet.InputError(message, file, line)`; the message is the CLI's `file:line: …`.
pub fn input(py: Python<'_>, e: &InputError) -> PyErr {
    raise(
        py,
        "InputError",
        (e.to_string(), e.file().to_string(), e.line()),
    )
}

/// `curvenet.InputError(message)` for a bad parameter or a bad file without a line.
pub fn usage(py: Python<'_>, message: impl Into<String>) -> PyErr {
    raise(
        py,
        "InputError",
        (message.into(), None::<String>, None::<usize>),
    )
}

/// `curvenet.CurvenetError(message)`: a computation that failed.
pub fn failed(py: Python<'_>, message: impl Into<String>) -> PyErr {
    raise(py, "CurvenetError", (message.into(),))
}

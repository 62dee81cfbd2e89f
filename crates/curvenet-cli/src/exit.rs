//! Mapping errors to exit codes and messages.

use curvenet::io::InputError;
use curvenet::network::build::BuildError;
use curvenet::paper::ExampleError;

/// An error that carries its exit code.
#[derive(Debug)]
pub struct ExitError {
    /// Process exit code.
    pub code: i32,
    /// Message for stderr.
    pub message: String,
}

impl std::fmt::Display for ExitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for ExitError {}

/// A usage or input error: exit code 2.
pub fn usage(message: impl Into<String>) -> anyhow::Error {
    ExitError {
        code: 2,
        message: message.into(),
    }
    .into()
}

/// Prints the error (if any) and returns the exit code.
pub fn report(result: anyhow::Result<()>) -> i32 {
    let Err(err) = result else { return 0 };
    let code = if let Some(e) = err.downcast_ref::<ExitError>() {
        e.code
    } else if err.downcast_ref::<InputError>().is_some()
        || err.downcast_ref::<BuildError>().is_some()
        || err.downcast_ref::<ExampleError>().is_some()
    {
        2
    } else {
        1
    };
    eprintln!("error: {err:#}");
    code
}

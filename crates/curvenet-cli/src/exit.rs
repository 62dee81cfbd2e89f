//! Mapping errors to exit codes and messages.

use curvenet::io::InputError;
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

/// The exit code of `err`: its own for an [`ExitError`] (the application layer's errors are
/// made one by `front::fail`), 2 for unreadable or malformed files and unknown examples, 1 for
/// everything else (internal errors).
pub fn code_of(err: &anyhow::Error) -> i32 {
    if let Some(e) = err.downcast_ref::<ExitError>() {
        return e.code;
    }
    let input =
        err.downcast_ref::<InputError>().is_some() || err.downcast_ref::<ExampleError>().is_some();
    if input { 2 } else { 1 }
}

/// The error and its causes on one line, `outer: cause: …`, leaving out a cause whose text the
/// line already holds (an [`InputError::Io`] shows its I/O error itself, and also lists it as
/// its source).
pub fn message_of(err: &anyhow::Error) -> String {
    let mut message = err.to_string();
    for cause in err.chain().skip(1) {
        let text = cause.to_string();
        if !message.contains(&text) {
            message.push_str(": ");
            message.push_str(&text);
        }
    }
    message
}

/// Prints the error (if any) and returns the exit code.
pub fn report(result: anyhow::Result<()>) -> i32 {
    let Err(err) = result else { return 0 };
    eprintln!("error: {}", message_of(&err));
    code_of(&err)
}

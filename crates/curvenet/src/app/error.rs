//! [`AppError`]: why a run, an analysis or a set-up stopped, in kinds each front end maps to
//! its own answer (the command line's exit codes, Python's exceptions, the server's status
//! codes), with messages that name options by their neutral key ([`crate::words`]).

use crate::io::InputError;
use crate::network::build::BuildError;
use crate::paper::ExampleError;
use crate::run_folder::RunFolderError;
use crate::stability::StabilityError;
use crate::words::{Message, Wording};
use std::path::PathBuf;

/// The stage a run was in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The greedy.
    Greedy,
    /// The local search after it.
    LocalSearch,
    /// The search for alternatives.
    Alternatives,
    /// The certificate.
    Certificate,
    /// Sliding the curves on the surface.
    Slide,
}

impl Stage {
    /// The stage as a user reads it: `the local search`.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Greedy => "the greedy",
            Stage::LocalSearch => "the local search",
            Stage::Alternatives => "the search for alternatives",
            Stage::Certificate => "the certificate",
            Stage::Slide => "sliding",
        }
    }
}

/// Why the application layer stopped.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// The request is wrong: an option's value, a combination of options, a folder; the
    /// message names the option. The command line exits 2, Python raises `InputError`, the
    /// server answers 4xx.
    #[error("{0}")]
    Usage(Message),
    /// A file is unreadable or malformed (the error names the file and line).
    #[error(transparent)]
    Input(#[from] InputError),
    /// No network can be built from the curves.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// A paper's example could not be loaded.
    #[error(transparent)]
    Example(#[from] ExampleError),
    /// A stage polled its cancellation token and stopped; what was recorded is kept.
    #[error("cancelled during {}", stage.name())]
    Cancelled {
        /// The stage that stopped.
        stage: Stage,
        /// The greedy's iterations kept in the run folder.
        kept: usize,
        /// The run folder.
        folder: PathBuf,
    },
    /// A computation or a write failed (not the user's doing).
    #[error("{0}")]
    Failed(String),
}

impl AppError {
    /// A usage error with `message`.
    pub fn usage(message: impl Into<Message>) -> Self {
        AppError::Usage(message.into())
    }

    /// Whether the user can fix it (exit 2, `InputError`, 4xx): every kind but
    /// [`AppError::Cancelled`] and [`AppError::Failed`].
    pub fn is_input(&self) -> bool {
        !matches!(self, AppError::Cancelled { .. } | AppError::Failed(_))
    }

    /// The message spelled by `words` (a front end's option names).
    pub fn render(&self, words: &dyn Wording) -> String {
        use crate::words::{Opt, message};
        match self {
            AppError::Usage(m) => m.render(words),
            AppError::Build(e) => e.message().render(words),
            AppError::Cancelled {
                stage,
                kept,
                folder,
            } => {
                if *stage == Stage::Slide {
                    return format!(
                        "cancelled while sliding: the best network so far is recorded in {}",
                        folder.display()
                    );
                }
                let what = match stage {
                    Stage::Greedy => format!("{kept} iteration(s) kept in {}", folder.display()),
                    _ => format!(
                        "during {}: the greedy's iterations are kept in {}",
                        stage.name(),
                        folder.display()
                    ),
                };
                message![
                    "cancelled: ",
                    what,
                    "; run again with ",
                    Opt::Resume,
                    " to continue"
                ]
                .render(words)
            }
            e => e.to_string(),
        }
    }
}

impl From<Message> for AppError {
    fn from(m: Message) -> Self {
        AppError::Usage(m)
    }
}

/// A run folder that cannot be resumed as asked, or lacks the network asked for, is a usage
/// error; one that cannot be read or written is a failure.
impl From<RunFolderError> for AppError {
    fn from(e: RunFolderError) -> Self {
        match e {
            RunFolderError::Resume(m) | RunFolderError::Absent(m) => AppError::Usage(m),
            e => AppError::Failed(e.to_string()),
        }
    }
}

/// Parameters the user set are a usage error; a computation that failed is not.
impl From<StabilityError> for AppError {
    fn from(e: StabilityError) -> Self {
        match e {
            StabilityError::Params(m) => AppError::Usage(m),
            e => AppError::Failed(e.to_string()),
        }
    }
}

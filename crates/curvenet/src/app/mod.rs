//! The application layer: what a *run* is, once, for every front end.
//!
//! A front end (the command line, the server, the Python package) only translates its
//! inputs into the specifications here and the outcomes back into its own output:
//!
//! - [`InputSpec`] (where the curves and the surface come from, the scale, the edge length,
//!   the supports) and [`ModelOptions`] (the material, the eigenvalues, the objective, the
//!   physical mode) → [`Setup`]: the inputs read and scaled, the default edge length chosen,
//!   the model resolved, the network built on demand, the warnings a user should read first;
//! - [`analyze`]: one structure's analysis and its reports (one JSON form);
//! - [`RunSpec`] (budget, keep list, design constraints, local search, alternatives,
//!   certificate, pictures, folder, resume, force) → [`execute`]: the whole simplification,
//!   recorded in its run folder, reporting to an [`Observer`] and stopped by a
//!   [`crate::cancel::Cancel`] token;
//! - [`AppError`]: typed errors whose messages name options by their neutral key
//!   ([`crate::words`]), which each front end spells its own way.

mod analyze;
pub mod draw;
pub mod end_frames;
mod ends;
mod error;
pub mod inputs;
mod model;
mod observer;
mod rounds;
mod run;
mod search;
mod setup;
mod slide;
mod summary;

pub use analyze::{AnalyzeOutcome, analyze};
pub use draw::{DrawEdit, DrawError, DrawParams, Drawing, Drawn, NewCurve};
pub use error::{AppError, Stage};
pub use inputs::{CurveSource, ExampleDefaults, GivenCurves, InputSpec, Inputs, MeshSource};
pub use model::{MAX_EIGEN_COUNT, Model, ModelOptions};
pub use observer::{Observer, Silent};
pub use run::{AfterSeconds, MAX_ALTERNATIVES, RunOutcome, RunSpec, execute};
pub use search::Search;
pub use setup::{Setup, check_curve_ids};
pub use slide::{MAX_SLIDE_ROUNDS, SlideOutcome, SlideSpec, slide};
pub use summary::{run_summary, slide_summary};

//! # curvenet
//!
//! Stability-aware simplification of curve networks (Neveu et al., SIGGRAPH 2022), done fast.
//!
//! The pipeline, one module per stage, data flowing one way:
//!
//! 1. [`io`]: meshes and curves in, results out (atomic writes);
//! 2. [`network`]: crossings, joints and resampling turn curves into a rod network;
//! 3. [`rod`]: the elastic energy of the network (stretching, bending, anchors);
//! 4. [`solve`]: sparse Cholesky, Newton equilibrium, shift-and-invert eigen solver;
//! 5. [`stability`]: the worst-case stability `λ` of a network or of any sub-structure;
//! 6. [`run_folder`]: the folder a simplification run writes as it goes, and reads back;
//! 7. [`report`]: the JSON objects and text of the command line, exports, pictures, viewer.
//!
//! [`constraints`] holds what a designer asks beyond the budget (groups, symmetry, a connected
//! structure, a number of curves, the surface's largest gap, the equilibrium's largest
//! deviation), tested on every subset the searches of [`simplify`] meet.
//!
//! [`trace`] generates curves on a mesh (geodesics, frame-field streamlines) and holds the
//! built-in surfaces; [`paper`] holds the paper's example set-ups, [`builtin`] scenes made in
//! code, [`pipeline`] the glue that runs the stages in order and [`experiments`] the harnesses
//! that measure the searches against each other.
//!
//! [`fmt`] prints computed numbers for people (significant digits, not fixed decimals).
//!
//! [`units`] and [`material`] describe the physical mode (the scene's length unit, materials,
//! cross-sections, rest shapes) at the bottom of the stack, beside [`geom`].
//!
//! See `ARCHITECTURE.md` at the repository root for the map and `docs/model.md` for the model.

pub mod app;
pub mod builtin;
pub mod cancel;
pub mod constraints;
pub mod experiments;
pub mod fmt;
pub mod geom;
pub mod io;
pub mod material;
pub mod network;
pub mod paper;
pub mod physics;
pub mod pipeline;
pub mod priority;
pub mod profile;
pub mod report;
pub mod rng;
pub mod rod;
pub mod run_folder;
pub mod run_layout;
pub mod simplify;
pub mod slide;
pub mod solve;
pub mod sparse;
pub mod stability;
pub mod trace;
pub mod units;
pub mod words;

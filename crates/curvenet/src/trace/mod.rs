//! Curves traced on a triangle mesh: geodesics shot from the boundary, frame-field
//! streamlines, the paper's generators and a few built-in surfaces.
//!
//! One file per role:
//!
//! | file | role |
//! |---|---|
//! | [`topology`] | edge–face adjacency, boundary loops (the reference's order), vertex fans |
//! | [`geodesic`] | straightest geodesics: edge unfolding, equal angles through vertices |
//! | [`from_point`] | a straightest geodesic from a point of the surface in a direction (drawing on the page) |
//! | [`field`] | smooth N-direction fields (N-RoSy, `z = e^{iNφ}` per face) aligned to the boundary |
//! | [`streamline`] | streamlines of such a field seeded along the boundary |
//! | [`generate`](mod@generate) | the paper's generators (hill, bunny, stadium, tent, command-line scenes) |
//! | [`surfaces`] | built-in surfaces made in code and [`surfaces::scale_to_extent`] |
//!
//! Everything is deterministic (no hash-map iteration, no parallel reductions) and no input
//! makes it panic: a mesh on which a curve cannot be traced gives a [`TraceError`] that says
//! why (a non-manifold edge on the path, no boundary, a degenerate triangle, a runaway curve…).
//!
//! Units: everything is in the mesh's own units. The paper's generators are defined on the
//! reference's meshes as the examples use them (hill, bunny and tent traced in file units).

pub mod field;
pub mod from_point;
pub mod generate;
pub mod geodesic;
pub mod streamline;
pub mod surfaces;
pub mod topology;
mod walk;

#[cfg(test)]
mod tests;

pub use field::{DirectionField, FieldOptions, smooth_field};
pub use from_point::{PointGeodesic, trace_geodesic_from};
pub use generate::{CurveRecord, GeneratedCurves, Generator, generate};
pub use geodesic::{GeodesicEnd, GeodesicPath, TraceOptions, trace_geodesic};
pub use streamline::{StreamlineOptions, StreamlineRecord, Streamlines, trace_streamlines};
pub use surfaces::{
    MAX_EXTENT, MIN_EXTENT, SURFACE_NAMES, SurfaceError, builtin_surface, check_extent,
    read_surface, scale_to_extent,
};
pub use topology::{BoundaryLoop, BoundaryPoint, MeshTopology};

/// Why a curve could not be traced (or a mesh cannot be used for tracing).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TraceError {
    /// The mesh itself is unusable: a face index out of range, a face repeating a vertex, a
    /// non-finite coordinate, no faces.
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
    /// The mesh has no boundary, so no curve can start on it.
    #[error("the mesh has no boundary: curves start and end on a boundary loop")]
    NoBoundary,
    /// A boundary loop index beyond the mesh's loops.
    #[error("boundary loop {index} does not exist (the mesh has {count} loop(s))")]
    LoopOutOfRange {
        /// The requested loop.
        index: usize,
        /// The number of loops.
        count: usize,
    },
    /// A parameter outside its domain (NaN, negative length, angle not in (0, π), …).
    #[error("invalid parameter {name} = {value}: expected {expected}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The accepted domain.
        expected: &'static str,
    },
    /// The curve reached an edge shared by more than two faces.
    #[error("non-manifold edge ({}, {}) on the path: it has {faces} faces", vertices[0], vertices[1])]
    NonManifoldEdge {
        /// The edge's vertices (sorted).
        vertices: [usize; 2],
        /// Number of faces on the edge.
        faces: usize,
    },
    /// The curve passed through a vertex whose faces do not form a single fan.
    #[error("non-manifold vertex {vertex} on the path: its faces do not form one fan")]
    NonManifoldVertex {
        /// The vertex.
        vertex: usize,
    },
    /// The curve entered a triangle of (numerically) zero area.
    #[error("degenerate (zero-area) face {face} on the path")]
    DegenerateFace {
        /// The face.
        face: usize,
    },
    /// The curve grew longer than the length cap without reaching the boundary.
    #[error("curve exceeded the length cap {cap} without reaching the boundary")]
    LengthCap {
        /// The cap.
        cap: f64,
    },
    /// The curve crossed more triangles than the step cap allows (a loop or a stall).
    #[error("curve crossed more than {steps} triangles without reaching the boundary")]
    StepCap {
        /// The cap.
        steps: usize,
    },
    /// The streamline reached a face where the field is singular (vanishing or with a
    /// non-zero index at one of its vertices).
    #[error("streamline reached a field singularity at face {face}")]
    Singularity {
        /// The face.
        face: usize,
    },
    /// The streamline could not continue: the field turns back across the edge just crossed.
    #[error("streamline stalled at face {face}: the field turns back")]
    Stalled {
        /// The face.
        face: usize,
    },
    /// The mesh cannot be oriented consistently (a Möbius strip or broken orientation), so a
    /// direction field cannot be transported across it.
    #[error("the mesh is not orientable: a direction field needs a consistent orientation")]
    NonOrientable,
    /// The sparse solver failed.
    #[error("field solver failed: {0}")]
    Solver(String),
    /// A generator with a rejection test ran out of attempts.
    #[error("generator accepted only {accepted} of {wanted} curves in {attempts} attempts")]
    GeneratorExhausted {
        /// Curves accepted.
        accepted: usize,
        /// Curves wanted.
        wanted: usize,
        /// Attempts made.
        attempts: usize,
    },
}

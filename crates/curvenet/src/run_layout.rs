//! Where a run folder keeps what: the one place that spells its files' names (at the bottom
//! of the stack, beside [`crate::fmt`], because the greedy's records name their mode files).
//!
//! - `result.json`, `network.json`, `timings.json`, `mesh.obj`: the record, the network, the
//!   times, the surface;
//! - `states/NNNN.bin` (iteration `NNNN`'s equilibrium displacements), `states/NNNN.modes.bin`
//!   (its low modes, for a resume), `modes/NNNN.bin` (its worst-case mode);
//! - `states/TAG.bin`, `modes/TAG.bin` for a recorded network that is not an iteration
//!   (`answer`, `alternative-N`); `states/carried.{0,1}.bin`, the carried test vectors.

/// Iteration `k`'s equilibrium displacements.
pub fn state_file(k: usize) -> String {
    format!("states/{k:04}.bin")
}

/// Iteration `k`'s low modes (what a resume starts from).
pub fn state_modes_file(k: usize) -> String {
    format!("states/{k:04}.modes.bin")
}

/// Iteration `k`'s worst-case mode.
pub fn mode_file(k: usize) -> String {
    format!("modes/{k:04}.bin")
}

/// The equilibrium of the recorded network `tag` (`answer`, `alternative-2`).
pub fn tagged_state_file(tag: &str) -> String {
    format!("states/{tag}.bin")
}

/// The worst-case mode of the recorded network `tag`.
pub fn tagged_mode_file(tag: &str) -> String {
    format!("modes/{tag}.bin")
}

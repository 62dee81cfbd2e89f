//! Where a run folder keeps what: the one place that spells its files' names (at the bottom
//! of the stack, beside [`crate::fmt`], because the greedy's records name their mode files).
//!
//! - `result.json`, `network.json`, `timings.json`, `mesh.obj`: the record, the network, the
//!   times, the surface;
//! - `states/NNNN.bin` (iteration `NNNN`'s equilibrium displacements), `states/NNNN.modes.bin`
//!   (its low modes, for a resume), `modes/NNNN.bin` (its worst-case mode);
//! - `states/TAG.bin`, `modes/TAG.bin` for a recorded network that is not an iteration
//!   (`answer`, `alternative-N`); `states/carried.{0,1}.bin`, the carried test vectors;
//! - `iterations/NNNN.obj`: iteration `NNNN`'s network at equilibrium;
//! - `rounds/K/local`, `rounds/K/slid`: a slid run's rounds, each a run folder.

/// The folder of a slid run's rounds (`rounds/K/local`, `rounds/K/slid`).
pub const ROUNDS: &str = "rounds";

/// Round `k`'s folder in a slid run (`rounds/K`; round 0 holds the first slide when a later
/// round's is the answer).
pub fn round_folder(k: usize) -> String {
    format!("{ROUNDS}/{k}")
}

/// The folder of the equilibria (and of the low modes and carried vectors a resume reads).
pub const STATES: &str = "states";

/// The folder of the worst-case modes.
pub const MODES: &str = "modes";

/// The folder of the iterations' networks at equilibrium.
pub const ITERATIONS: &str = "iterations";

/// The carried test vectors' files, one slot per parity of the iteration
/// (`run_folder::carried`).
pub const CARRIED_FILES: [&str; 2] = ["states/carried.0.bin", "states/carried.1.bin"];

/// The file holding the test vectors iteration `k` hands on.
pub fn carried_file(k: usize) -> &'static str {
    CARRIED_FILES[k % 2]
}

/// Iteration `k`'s network at equilibrium, one polyline per curve.
pub fn iteration_obj_file(k: usize) -> String {
    format!("{ITERATIONS}/{k:04}.obj")
}

/// Iteration `k`'s equilibrium displacements.
pub fn state_file(k: usize) -> String {
    format!("{STATES}/{k:04}.bin")
}

/// Iteration `k`'s low modes (what a resume starts from).
pub fn state_modes_file(k: usize) -> String {
    format!("{STATES}/{k:04}.modes.bin")
}

/// Iteration `k`'s worst-case mode.
pub fn mode_file(k: usize) -> String {
    format!("{MODES}/{k:04}.bin")
}

/// The equilibrium of the recorded network `tag` (`answer`, `alternative-2`).
pub fn tagged_state_file(tag: &str) -> String {
    format!("{STATES}/{tag}.bin")
}

/// The worst-case mode of the recorded network `tag`.
pub fn tagged_mode_file(tag: &str) -> String {
    format!("{MODES}/{tag}.bin")
}

//! Experiment harnesses: measurements that run the searches against each other, outside the
//! algorithm tree (they use [`crate::simplify`] like any caller).
//!
//! - [`compare`]: the paper's Fig. 10, greedy against exhaustive and random search on random
//!   networks (`curvenet compare`);
//! - [`bench`]: the greedy on the paper's examples, timed phase by phase (`curvenet bench`);
//! - [`worker`]: the bench's worker processes, one per run, ending with the bench.

pub mod bench;
pub mod compare;
pub mod worker;

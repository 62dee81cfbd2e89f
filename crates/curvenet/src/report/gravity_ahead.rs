//! The viewer's gravity deflections, solved while the greedy runs.
//!
//! The viewer page embeds the gravity deflection of every greedy iteration: one factorization
//! each, which after the search was the largest part of the wait between the search's end and
//! the finished run folder. The greedy leaves a two-core machine's cores idle part of the time
//! (its CPU time is about 1.5× its wall time on the paper's examples), so [`GravityAhead`]
//! solves each iteration's deflection as soon as it is recorded, on a thread of its own (with
//! a one-thread pool for its parallel parts) at the lowest priority ([`crate::priority`]): it
//! runs mostly when a core has nothing else to do. Each deflection is factored with the
//! structure's own symbolic analysis, handed over by the greedy (a structure holding a small
//! part of the network is factored on its own vertices, without analysing it again). When the
//! greedy ends, [`GravityAhead::finish`] takes what is solved, and the viewer
//! ([`super::viewer::write_run_outputs_with`]) solves the rest beside the pictures.
//!
//! The run never waits for this thread: while other programs keep every core busy it gets
//! little CPU time, and waiting for it (even for the one deflection it is solving) could stall
//! a run on a loaded machine. `finish` takes the deflections solved so far and leaves the
//! thread to stop after the one in hand, which is thrown away (the viewer solves it again, at
//! the run's own priority).
//!
//! The deflections are those the viewer solves from the run folder alone: the analyzer is
//! built from the network and stability settings the run writes to `network.json` and
//! `result.json` (their JSON round-trips every number exactly), and the displacements are the
//! ones written to `states/`, and the symbolic analysis is the one the viewer's analyzer
//! gives the same structure ([`Analyzer::symbolic_for`] is a pure function of it), so the page
//! is the same byte for byte whichever solved them (a test compares them).

use crate::network::Network;
use crate::priority::background_priority;
use crate::rod::ActiveSet;
use crate::solve::SymbolicFactor;
use crate::sparse::Pattern;
use crate::stability::{Analyzer, StabilityParams};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex, PoisonError};

/// One recorded iteration to solve: its index, curves, equilibrium displacement and the
/// structure's symbolic analysis (the greedy's, which the viewer's own would repeat).
type Job = (usize, Vec<usize>, Vec<f64>, Arc<SymbolicFactor>);

/// Gravity deflections solved ahead, by iteration: its curves and the deflection (`None`
/// when its structure is not positive definite).
#[derive(Clone, Debug, Default)]
pub struct Deflections(BTreeMap<usize, (Vec<usize>, Option<Vec<f64>>)>);

impl Deflections {
    /// The deflection solved for iteration `k` when it was solved for these `curves`.
    pub fn get(&self, k: usize, curves: &[usize]) -> Option<&Option<Vec<f64>>> {
        self.0
            .get(&k)
            .filter(|(c, _)| c.as_slice() == curves)
            .map(|(_, d)| d)
    }

    /// How many iterations were solved.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether none was.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// A thread solving the gravity deflections of a run's iterations as they are recorded.
/// Dropped without [`Self::finish`], it stops after the deflection it is solving.
pub struct GravityAhead {
    jobs: Option<mpsc::Sender<Job>>,
    solved: Arc<Mutex<Deflections>>,
    stop: Arc<AtomicBool>,
}

impl GravityAhead {
    /// Starts the thread for a run of `network` with the stability settings `stability`
    /// (what the run records), whose analyzer assembles its matrices on `pattern`. A thread
    /// that cannot start solves nothing ahead (the viewer then solves every deflection
    /// itself).
    pub fn start(network: Network, stability: StabilityParams, pattern: Pattern) -> Self {
        let (tx, rx) = mpsc::channel::<Job>();
        let stop = Arc::new(AtomicBool::new(false));
        let solved = Arc::new(Mutex::new(Deflections::default()));
        let (flag, into) = (Arc::clone(&stop), Arc::clone(&solved));
        // Detached: nothing ever waits for it (module docs).
        let _ = std::thread::Builder::new()
            .name("gravity-ahead".into())
            .spawn(move || solve_as_they_come(network, stability, &pattern, &rx, &flag, &into));
        GravityAhead {
            jobs: Some(tx),
            solved,
            stop,
        }
    }

    /// Queues iteration `k`: its curves, equilibrium displacement `u` and the structure's
    /// symbolic analysis (what [`Analyzer::symbolic_for`] gives it).
    pub fn submit(&self, k: usize, curves: &[usize], u: &[f64], symbolic: &Arc<SymbolicFactor>) {
        if let Some(tx) = &self.jobs {
            // The thread may have ended (the folder unreadable): nothing is solved ahead.
            let _ = tx.send((k, curves.to_vec(), u.to_vec(), symbolic.clone()));
        }
    }

    /// Gives the deflections solved so far, without waiting: the thread stops after the one it
    /// is solving, whose result is dropped.
    pub fn finish(mut self) -> Deflections {
        self.stop.store(true, Ordering::Relaxed);
        self.jobs = None;
        std::mem::take(&mut *self.solved.lock().unwrap_or_else(PoisonError::into_inner))
    }
}

impl Drop for GravityAhead {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// The thread's work: the run's analyzer, then each queued iteration in turn.
fn solve_as_they_come(
    network: Network,
    stability: StabilityParams,
    run_pattern: &Pattern,
    jobs: &mpsc::Receiver<Job>,
    stop: &AtomicBool,
    solved: &Mutex<Deflections>,
) {
    // All of the thread's work, its analyzer's model included, at the lowest priority.
    background_priority();
    let Ok(analyzer) = Analyzer::new(network, stability) else {
        return;
    };
    // The run's symbolic analyses fit these matrices only when the run's model has their
    // pattern (the physical mode's own model may not): else each structure is analysed here.
    let handed_fit = analyzer.model().pattern() == run_pattern;
    // Its own pool: the factorization's parallel parts stay off the greedy's threads.
    let Ok(pool) = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .thread_name(|_| "gravity-ahead-pool".into())
        .start_handler(|_| background_priority())
        .build()
    else {
        return;
    };
    while let Ok((k, curves, u, symbolic)) = jobs.recv() {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        let active = ActiveSet::from_curves(analyzer.curve_count(), &curves);
        let d = pool.install(|| {
            let solved = if handed_fit {
                analyzer.gravity_at_with(&active, &u, &symbolic)
            } else {
                analyzer.gravity_at(&active, &u)
            };
            solved.map(|(d, _)| d)
        });
        let mut solved = solved.lock().unwrap_or_else(PoisonError::into_inner);
        solved.0.insert(k, (curves, d));
    }
}

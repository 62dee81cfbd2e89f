//! [`Design`]: the one network being edited, its current structure and that structure's
//! stability, behind one lock.

use curvenet::rod::ActiveSet;
use curvenet::stability::{Analysis, Analyzer, CurveShare, StabilityError};
use serde::Serialize;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// Why an edit was refused.
#[derive(Debug, thiserror::Error)]
pub enum DesignError {
    /// A curve id the network does not have.
    #[error("unknown curve {curve}: the network has {count} curves (ids 0..{last})", last = .count.saturating_sub(1))]
    UnknownCurve {
        /// The id asked for.
        curve: usize,
        /// Curves in the network.
        count: usize,
    },
    /// The edit would leave no curve.
    #[error("the structure would have no curves left; keep at least one")]
    Empty,
    /// The analysis itself failed (the eigen solver).
    #[error("the analysis failed: {0}")]
    Analysis(StabilityError),
}

/// Whether a structure holds its shape, in words a designer reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Every computed eigenvalue is positive: the equilibrium is stable.
    Stable,
    /// Some eigenvalues are zero to round-off: the structure is a mechanism.
    Mechanism,
    /// Some eigenvalues are negative: the equilibrium is unstable.
    Unstable,
}

/// The stability of one structure: what `GET /api/state` answers.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// The kept curves, ascending.
    pub curves: Vec<usize>,
    /// `λ_eq`: the smallest eigenvalue of the Hessian at the structure's equilibrium.
    pub lambda: f64,
    /// Eigenvalues within the zero threshold (mechanisms).
    pub zero_modes: usize,
    /// Eigenvalues below it (unstable directions).
    pub negative_modes: usize,
    /// Total rest length of the kept curves.
    pub length: f64,
    /// Stable, a mechanism, or unstable.
    pub status: Status,
    /// The smallest eigenvalues, ascending.
    pub eigenvalues: Vec<f64>,
    /// Whether the equilibrium solve converged (when not, `λ` is measured where it stopped).
    pub converged: bool,
    /// Curves carrying the worst-case mode, largest share first (at most eight).
    pub mode_curves: Vec<CurveShare>,
}

/// One evaluated structure: its summary and the vectors a drawing needs.
#[derive(Debug)]
pub struct Evaluated {
    /// The numbers.
    pub summary: Summary,
    /// Displacements from the rest state at equilibrium (3 per vertex).
    pub displacement: Vec<f64>,
    /// The worst-case mode: the unit eigenvector of `λ` (3 per vertex).
    pub mode: Vec<f64>,
}

/// The answer to an edit: the new structure's summary and the server-side time it took.
#[derive(Clone, Debug)]
pub struct Edited {
    /// The structure after the edit.
    pub summary: Summary,
    /// Time spent computing it.
    pub elapsed: Duration,
}

/// The network being designed: its analyzer (one energy model and symbolic analysis for
/// every structure) and the current structure. Every read and edit takes the one lock, so
/// concurrent clients see the edits in some order, each state whole.
#[derive(Debug)]
pub struct Design {
    analyzer: Analyzer,
    current: Mutex<Arc<Evaluated>>,
}

impl Design {
    /// The design of `analyzer`'s network, starting from the structure of `curves`.
    ///
    /// # Errors
    ///
    /// An unknown or empty set of curves, or a failed analysis.
    pub fn new(analyzer: Analyzer, curves: &[usize]) -> Result<Self, DesignError> {
        let active = checked_set(&analyzer, curves)?;
        let first = evaluate(&analyzer, &active)?;
        Ok(Design {
            analyzer,
            current: Mutex::new(Arc::new(first)),
        })
    }

    /// The analyzer (the network, its model and parameters).
    pub fn analyzer(&self) -> &Analyzer {
        &self.analyzer
    }

    /// The current structure.
    pub fn current(&self) -> Arc<Evaluated> {
        self.lock().clone()
    }

    /// Makes the structure of `curves` (in any order, repeats ignored) the current one.
    ///
    /// # Errors
    ///
    /// An unknown id, an empty set or a failed analysis; the current structure is then
    /// unchanged.
    pub fn set(&self, curves: &[usize]) -> Result<Edited, DesignError> {
        let active = checked_set(&self.analyzer, curves)?;
        let mut current = self.lock();
        let start = Instant::now();
        let next = Arc::new(evaluate(&self.analyzer, &active)?);
        let elapsed = start.elapsed();
        *current = next.clone();
        Ok(Edited {
            summary: next.summary.clone(),
            elapsed,
        })
    }

    /// Removes `curve` from the current structure, or restores it when it was removed.
    ///
    /// # Errors
    ///
    /// As [`Self::set`].
    pub fn toggle(&self, curve: usize) -> Result<Edited, DesignError> {
        let count = self.analyzer.curve_count();
        if curve >= count {
            return Err(DesignError::UnknownCurve { curve, count });
        }
        let mut current = self.lock();
        let mut curves = current.summary.curves.clone();
        match curves.binary_search(&curve) {
            Ok(i) => {
                curves.remove(i);
            }
            Err(i) => curves.insert(i, curve),
        }
        let active = checked_set(&self.analyzer, &curves)?;
        let start = Instant::now();
        let next = Arc::new(evaluate(&self.analyzer, &active)?);
        let elapsed = start.elapsed();
        *current = next.clone();
        Ok(Edited {
            summary: next.summary.clone(),
            elapsed,
        })
    }

    /// The lock on the current structure (a panic elsewhere leaves the last whole state).
    fn lock(&self) -> MutexGuard<'_, Arc<Evaluated>> {
        self.current.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The set of `curves`, every id checked.
fn checked_set(analyzer: &Analyzer, curves: &[usize]) -> Result<ActiveSet, DesignError> {
    let count = analyzer.curve_count();
    if let Some(&curve) = curves.iter().find(|&&c| c >= count) {
        return Err(DesignError::UnknownCurve { curve, count });
    }
    if curves.is_empty() {
        return Err(DesignError::Empty);
    }
    Ok(analyzer.set(curves))
}

/// Relaxes and analyses `active` the way `curvenet analyze` does.
fn evaluate(analyzer: &Analyzer, active: &ActiveSet) -> Result<Evaluated, DesignError> {
    let analysis = analyzer.analyze(active, None).map_err(|e| match e {
        StabilityError::Empty => DesignError::Empty,
        e => DesignError::Analysis(e),
    })?;
    Ok(evaluated(analyzer, active, analysis))
}

/// The summary and vectors of `analysis` of `active`.
fn evaluated(analyzer: &Analyzer, active: &ActiveSet, analysis: Analysis) -> Evaluated {
    let curves = active.curves();
    let sp = &analysis.spectrum;
    let status = if sp.negative_modes > 0 {
        Status::Unstable
    } else if sp.zero_modes > 0 {
        Status::Mechanism
    } else {
        Status::Stable
    };
    let summary = Summary {
        length: analyzer.total_length(&curves),
        lambda: sp.lambda(),
        zero_modes: sp.zero_modes,
        negative_modes: sp.negative_modes,
        status,
        eigenvalues: sp.values.clone(),
        converged: analysis.newton.converged,
        mode_curves: analysis.mode_curves.iter().take(8).copied().collect(),
        curves,
    };
    let mode = analysis.mode();
    Evaluated {
        summary,
        displacement: analysis.displacement,
        mode,
    }
}

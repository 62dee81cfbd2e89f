//! [`Design`]: the one network being edited, its current structure and that structure's
//! stability, behind one lock.
//!
//! Edits are warm: each is analysed from the current structure's equilibrium and modes
//! ([`Analyzer::analyze_edit`], which falls back to the drawn state when the warm answer is
//! not a stable equilibrium), and every structure analysed is kept in a cache bounded by
//! memory ([`Cache`]), so a set seen before (a restored curve, an undo) is answered at once.
//!
//! In the physical mode (an analyzer [`Analyzer::with_physical`]) each structure also gets its
//! physical analysis ([`analyze_physical`]: frequencies, deflections, stresses), cached with
//! it. The gravity deflection of a structure is computed when it is first asked for
//! ([`Evaluated::gravity`]), not with the edit.

use crate::cache::Cache;
use curvenet::physics::{PhysicalReport, analyze_physical};
use curvenet::rod::ActiveSet;
use curvenet::stability::{
    Analysis, Analyzer, CurveShare, EDIT_PAIRS, EditFrom, EditStart, GravityDeflection, Spectrum,
    StabilityError,
};
use serde::Serialize;
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};
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
    /// The physical analysis failed.
    #[error("the physical analysis failed: {0}")]
    Physical(String),
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

impl Status {
    /// The status as a word: `stable`, `mechanism`, `unstable` (as the API spells it).
    pub fn word(self) -> &'static str {
        match self {
            Status::Stable => "stable",
            Status::Mechanism => "mechanism",
            Status::Unstable => "unstable",
        }
    }
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
    /// The two smallest eigenvalues, ascending (`λ` and the next: how isolated `λ` is).
    pub eigenvalues: Vec<f64>,
    /// Whether the equilibrium solve converged (when not, `λ` is measured where it stopped).
    pub converged: bool,
    /// Curves carrying the worst-case mode, largest share first (at most eight).
    pub mode_curves: Vec<CurveShare>,
    /// In the physical mode, the structure's physical analysis (`analyze --json`'s
    /// `physical` object): frequencies, deflections, stresses, utilisation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub physical: Option<PhysicalReport>,
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
    /// The spectrum: the next edit's eigen solve starts from its vectors.
    spectrum: Spectrum,
    /// The gravity deflection, once asked for.
    gravity: OnceLock<Option<(Vec<f64>, GravityDeflection)>>,
}

impl Evaluated {
    /// The deflection under the analyzer's gravity load, `H u = f` at the equilibrium (3 per
    /// vertex), with the library's summary of it (largest displacement, where, compliance);
    /// `None` when the Hessian is not positive definite. Computed on first use.
    pub fn gravity(&self, analyzer: &Analyzer) -> Option<(&[f64], &GravityDeflection)> {
        self.gravity
            .get_or_init(|| {
                let active = analyzer.set(&self.summary.curves);
                analyzer.gravity_at(&active, &self.displacement)
            })
            .as_ref()
            .map(|(u, summary)| (u.as_slice(), summary))
    }

    /// Bytes of memory it holds (what the cache counts; the gravity deflection counted
    /// whether or not it was computed).
    pub fn bytes(&self) -> usize {
        let floats = 2 * self.displacement.len()
            + self.mode.len()
            + self.spectrum.vectors.nrows() * self.spectrum.vectors.ncols();
        8 * floats + 64 * self.summary.eigenvalues.len() + 8 * self.summary.curves.len() + 512
    }
}

/// Where an edit's answer came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Source {
    /// The cache: the set was analysed before.
    Cache,
    /// Relaxed from the previous structure's equilibrium.
    Warm,
    /// Relaxed from the drawn state (the first structure, or a warm answer that was not a
    /// stable equilibrium: docs/serve.md, *Warm edits*).
    Drawn,
}

impl From<EditFrom> for Source {
    fn from(f: EditFrom) -> Self {
        match f {
            EditFrom::Warm => Source::Warm,
            EditFrom::Drawn => Source::Drawn,
        }
    }
}

/// The answer to an edit: the new structure's summary, the server-side time it took and
/// where it came from.
#[derive(Clone, Debug)]
pub struct Edited {
    /// The structure after the edit.
    pub summary: Summary,
    /// Time spent computing it.
    pub elapsed: Duration,
    /// The cache, a warm start or the drawn state.
    pub source: Source,
    /// The structure itself (its equilibrium, its mode).
    pub structure: Arc<Evaluated>,
}

/// The current structure and the cache of every structure analysed, under one lock.
#[derive(Debug)]
struct Store {
    current: Arc<Evaluated>,
    cache: Cache<Vec<usize>, Evaluated>,
}

/// The network being designed: its analyzer (one energy model and symbolic analysis for
/// every structure), the current structure and the structures analysed so far. Every read
/// and edit takes the one lock, so concurrent clients see the edits in some order, each state
/// whole.
#[derive(Debug)]
pub struct Design {
    analyzer: Analyzer,
    store: Mutex<Store>,
}

/// Memory the cache of analysed structures may hold by default.
pub const CACHE_BYTES: usize = 512 << 20;

impl Design {
    /// The design of `analyzer`'s network, starting from the structure of `curves` (analysed
    /// from the drawn state), with a cache of [`CACHE_BYTES`].
    ///
    /// # Errors
    ///
    /// An unknown or empty set of curves, or a failed analysis.
    pub fn new(analyzer: Analyzer, curves: &[usize]) -> Result<Self, DesignError> {
        Self::with_cache(analyzer, curves, CACHE_BYTES)
    }

    /// [`Self::new`] with a cache of at most `cache_bytes` (the current structure is kept
    /// whatever the bound).
    ///
    /// # Errors
    ///
    /// As [`Self::new`].
    pub fn with_cache(
        analyzer: Analyzer,
        curves: &[usize],
        cache_bytes: usize,
    ) -> Result<Self, DesignError> {
        let active = checked_set(&analyzer, curves)?;
        let analysis = analyzer.analyze(&active, None).map_err(design_error)?;
        let first = Arc::new(evaluated(&analyzer, &active, analysis)?);
        let mut cache = Cache::new(cache_bytes);
        cache.insert(first.summary.curves.clone(), first.clone(), first.bytes());
        Ok(Design {
            analyzer,
            store: Mutex::new(Store {
                current: first,
                cache,
            }),
        })
    }

    /// The analyzer (the network, its model and parameters).
    pub fn analyzer(&self) -> &Analyzer {
        &self.analyzer
    }

    /// The total rest length of the whole network.
    pub fn total_length(&self) -> f64 {
        let all: Vec<usize> = (0..self.analyzer.curve_count()).collect();
        self.analyzer.total_length(&all)
    }

    /// The current structure.
    pub fn current(&self) -> Arc<Evaluated> {
        self.lock().current.clone()
    }

    /// Structures in the cache and the bytes they hold.
    pub fn cached(&self) -> (usize, usize) {
        let store = self.lock();
        (store.cache.len(), store.cache.bytes())
    }

    /// Makes the structure of `curves` (in any order, repeats ignored) the current one.
    ///
    /// # Errors
    ///
    /// An unknown id, an empty set or a failed analysis; the current structure is then
    /// unchanged.
    pub fn set(&self, curves: &[usize]) -> Result<Edited, DesignError> {
        let active = checked_set(&self.analyzer, curves)?;
        let mut store = self.lock();
        self.edit(&mut store, &active)
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
        let mut store = self.lock();
        let mut curves = store.current.summary.curves.clone();
        match curves.binary_search(&curve) {
            Ok(i) => {
                curves.remove(i);
            }
            Err(i) => curves.insert(i, curve),
        }
        let active = checked_set(&self.analyzer, &curves)?;
        self.edit(&mut store, &active)
    }

    /// Makes `active` current: from the cache when it was analysed before, else analysed
    /// from the current structure.
    fn edit(&self, store: &mut Store, active: &ActiveSet) -> Result<Edited, DesignError> {
        let start = Instant::now();
        let key = active.curves();
        let (next, source) = match store.cache.get(&key) {
            Some(hit) => (hit, Source::Cache),
            None => {
                let cur = nearest(store, &key);
                let from = EditStart {
                    active: &self.analyzer.set(&cur.summary.curves),
                    displacement: &cur.displacement,
                    modes: cur.spectrum.vectors.as_ref(),
                };
                let edit = self
                    .analyzer
                    .analyze_edit(active, from)
                    .map_err(design_error)?;
                let next = Arc::new(evaluated(&self.analyzer, active, edit.analysis)?);
                store.cache.insert(key, next.clone(), next.bytes());
                (next, edit.start.into())
            }
        };
        let elapsed = start.elapsed();
        store.current = Arc::clone(&next);
        Ok(Edited {
            summary: next.summary.clone(),
            elapsed,
            source,
            structure: next,
        })
    }

    /// The lock on the store (a panic elsewhere leaves the last whole state).
    fn lock(&self) -> MutexGuard<'_, Store> {
        self.store.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The analysed structure an edit to `target` starts from: the one missing the fewest of
/// `target`'s curves, then holding the fewest others, the current one on a tie. A restored
/// curve so starts, when it can, from a structure that held it (the equilibrium before its
/// removal), where its vertices' displacements are known: restricting an equilibrium to a
/// sub-structure is a far better start than extending one.
fn nearest(store: &Store, target: &[usize]) -> Arc<Evaluated> {
    let distance = |e: &Evaluated| {
        let have = &e.summary.curves;
        let missing = target
            .iter()
            .filter(|c| have.binary_search(c).is_err())
            .count();
        (missing, have.len() + missing - target.len())
    };
    let mut best = (distance(&store.current), store.current.clone());
    for e in store.cache.values() {
        let d = distance(e);
        if d < best.0 {
            best = (d, e.clone());
        }
    }
    best.1
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

/// The design's error for a failed analysis.
fn design_error(e: StabilityError) -> DesignError {
    match e {
        StabilityError::Empty => DesignError::Empty,
        e => DesignError::Analysis(e),
    }
}

/// The summary and vectors of `analysis` of `active`, with its physical analysis in the
/// physical mode.
fn evaluated(
    analyzer: &Analyzer,
    active: &ActiveSet,
    analysis: Analysis,
) -> Result<Evaluated, DesignError> {
    // The full analysis, with the load cases given to the server.
    let physical = match analyzer.physical_with_loads() {
        Some(p) => Some(
            analyze_physical(analyzer.network(), p, active)
                .map_err(|e| DesignError::Physical(e.to_string()))?,
        ),
        None => None,
    };
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
        eigenvalues: sp.values.iter().take(EDIT_PAIRS).copied().collect(),
        converged: analysis.newton.converged,
        mode_curves: analysis.mode_curves.iter().take(8).copied().collect(),
        curves,
        physical,
    };
    let mode = analysis.mode();
    Ok(Evaluated {
        summary,
        displacement: analysis.displacement,
        mode,
        spectrum: analysis.spectrum,
        gravity: OnceLock::new(),
    })
}

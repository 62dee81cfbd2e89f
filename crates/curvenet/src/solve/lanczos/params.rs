//! The parameters, statistics, results and errors of [`super::largest_eigenpairs`].

use faer::Mat;

/// Parameters of [`super::largest_eigenpairs`].
#[derive(Clone, Debug, PartialEq)]
pub struct BlockLanczosParams {
    /// Number of wanted eigenpairs (the largest eigenvalues of the operator). Default 4.
    pub nev: usize,
    /// Width of the Krylov blocks, at least 1. Eigenvalues of multiplicity up to
    /// `block_size` are reliably found. Default 3.
    pub block_size: usize,
    /// Maximum number of Krylov basis columns before a thick restart; must exceed
    /// `nev + block_size` unless it is at least `n`. The pending (not yet applied) block is
    /// stored on top of these. Default 60.
    pub max_basis: usize,
    /// Convergence tolerance: every wanted pair must satisfy
    /// `‖Op·y − μ·y‖ ≤ tol·|μ_max|`, with `μ_max` the Ritz value of largest magnitude
    /// (the pairs after the first: see [`Self::trailing_tol`]).
    /// Must be positive and finite. Default `1e-10`.
    pub tol: f64,
    /// The tolerance of the wanted pairs after the first, when they need less accuracy than
    /// the first (never below `tol`); `None`: `tol` for every pair. Default `None`.
    pub trailing_tol: Option<f64>,
    /// Maximum number of thick restarts before giving up with
    /// [`LanczosError::NotConverged`]. Default 50.
    pub max_restarts: usize,
    /// Seed of the deterministic random start and injection vectors. Default 0.
    pub seed: u64,
}

impl Default for BlockLanczosParams {
    fn default() -> Self {
        BlockLanczosParams {
            nev: 4,
            block_size: 3,
            max_basis: 60,
            tol: 1e-10,
            trailing_tol: None,
            max_restarts: 50,
            seed: 0,
        }
    }
}

impl BlockLanczosParams {
    /// The tolerance of wanted pair `j` (0: the first).
    pub fn tolerance(&self, j: usize) -> f64 {
        match self.trailing_tol {
            Some(t) if j > 0 => t.max(self.tol),
            _ => self.tol,
        }
    }

    /// Checks the parameters for an operator of dimension `n`.
    ///
    /// Requires `n ≥ 1`, `1 ≤ nev ≤ n`, `block_size ≥ 1`, a positive finite `tol`, and
    /// `max_basis > nev + block_size` unless `max_basis ≥ n` (the whole space fits in the
    /// basis, so no restart is ever needed).
    pub fn validate(&self, n: usize) -> Result<(), LanczosError> {
        let fail = |msg: String| Err(LanczosError::InvalidParams(msg));
        if n == 0 {
            return fail("operator dimension n must be at least 1".into());
        }
        if self.nev == 0 {
            return fail("nev must be at least 1".into());
        }
        if self.nev > n {
            return fail(format!(
                "nev = {} exceeds the operator dimension n = {n}",
                self.nev
            ));
        }
        if self.block_size == 0 {
            return fail("block_size must be at least 1".into());
        }
        if self.max_basis <= self.nev.saturating_add(self.block_size) && self.max_basis < n {
            return fail(format!(
                "max_basis = {} must exceed nev + block_size = {} + {} (or be at least n = {n})",
                self.max_basis, self.nev, self.block_size
            ));
        }
        if !(self.tol.is_finite() && self.tol > 0.0) {
            return fail(format!("tol = {} must be positive and finite", self.tol));
        }
        if let Some(t) = self.trailing_tol.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return fail(format!("trailing_tol = {t} must be positive and finite"));
        }
        Ok(())
    }
}

/// Statistics of a [`super::largest_eigenpairs`] run.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockLanczosInfo {
    /// Number of thick restarts performed.
    pub restarts: usize,
    /// Number of operator applications, counted per column.
    pub applications: usize,
    /// Number of wanted pairs that met the tolerance.
    pub converged: usize,
    /// Residual norms `‖Op·y − μ·y‖` of the returned pairs (from the Lanczos relation,
    /// which full reorthogonalisation keeps accurate to rounding).
    pub residuals: Vec<f64>,
}

/// Eigenpairs returned by [`super::largest_eigenpairs`].
#[derive(Clone, Debug)]
pub struct EigenPairs {
    /// Eigenvalues `μ` of the operator, in descending order.
    pub values: Vec<f64>,
    /// The matching eigenvectors, `n × nev`, orthonormal columns; each column's entry of
    /// largest magnitude (the first one on ties) is positive.
    pub vectors: Mat<f64>,
    /// Run statistics.
    pub info: BlockLanczosInfo,
}

/// Errors of [`super::largest_eigenpairs`].
#[derive(Debug, thiserror::Error)]
pub enum LanczosError {
    /// The parameters, dimension or warm start are unusable; nothing was computed.
    #[error("invalid Lanczos parameters: {0}")]
    InvalidParams(String),
    /// The operator (or the warm start) produced NaN or infinite values.
    #[error("non-finite values: {0}")]
    NonFinite(String),
    /// The Krylov basis could not be extended with new directions before `nev` Ritz
    /// pairs existed (not expected in practice: needs random vectors to fail repeatedly).
    #[error("block Lanczos breakdown: {0}")]
    Breakdown(String),
    /// faer's dense symmetric eigensolver failed on the projected matrix.
    #[error("dense eigensolver failed: {0}")]
    DenseEigen(String),
    /// The tolerance was not met within `max_restarts`; the best approximations found
    /// (with their residuals in `info`) are attached.
    #[error(
        "block Lanczos did not converge: {}/{} pairs after {} restarts and {} applications",
        .0.info.converged, .0.values.len(), .0.info.restarts, .0.info.applications
    )]
    NotConverged(Box<EigenPairs>),
}

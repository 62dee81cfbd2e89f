//! Sparse symmetric matrices stored as their upper triangle in compressed columns.
//!
//! [`Pattern`] is the fixed sparsity pattern the energy model assembles every Hessian into and
//! the solvers factor; the values live beside it in a plain slice (one per stored entry), so
//! one pattern serves every matrix of a network.

/// The upper-triangular sparsity pattern of a symmetric matrix, in compressed columns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pattern {
    /// Number of rows and columns.
    pub n: usize,
    /// Column pointers (`n + 1` entries).
    pub col_ptr: Vec<usize>,
    /// Row indices, ascending within each column.
    pub row_idx: Vec<usize>,
    /// Slot of each diagonal entry.
    pub diag: Vec<usize>,
}

impl Pattern {
    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// The pattern as a faer symbolic matrix.
    pub fn symbolic(&self) -> faer::sparse::SymbolicSparseColMatRef<'_, usize> {
        faer::sparse::SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        )
    }

    /// `y = A x` for the symmetric matrix whose upper triangle `values` holds.
    pub fn sym_matvec(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for j in 0..self.n {
            let xj = x[j];
            let mut acc = 0.0;
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[k];
                let a = values[k];
                if i == j {
                    acc += a * xj;
                } else {
                    acc += a * x[i];
                    y[i] += a * xj;
                }
            }
            y[j] += acc;
        }
    }

    /// [`Pattern::sym_matvec`] for `K` vectors at once, stored interleaved (`x[i][c]`:
    /// coordinate `i` of vector `c`): one pass over the matrix instead of `K`. Each vector's
    /// result is the same, bit for bit, as `sym_matvec`'s.
    pub fn sym_matvec_many<const K: usize>(
        &self,
        values: &[f64],
        x: &[[f64; K]],
        y: &mut [[f64; K]],
    ) {
        y.iter_mut().for_each(|v| *v = [0.0; K]);
        for j in 0..self.n {
            let xj = x[j];
            let mut acc = [0.0; K];
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[k];
                let a = values[k];
                if i == j {
                    for c in 0..K {
                        acc[c] += a * xj[c];
                    }
                } else {
                    let xi = x[i];
                    let yi = &mut y[i];
                    for c in 0..K {
                        acc[c] += a * xi[c];
                        yi[c] += a * xj[c];
                    }
                }
            }
            for c in 0..K {
                y[j][c] += acc[c];
            }
        }
    }

    /// The principal sub-pattern of the coordinates `keep` selects (`keep.len() == n`): the
    /// pattern itself, for each of its stored entries the slot of the same entry in `self`,
    /// and for each of its coordinates the coordinate in `self`.
    pub fn principal(&self, keep: &[bool]) -> (Pattern, Vec<usize>, Vec<usize>) {
        assert_eq!(keep.len(), self.n, "one flag per coordinate");
        let dofs: Vec<usize> = (0..self.n).filter(|&j| keep[j]).collect();
        let mut new_of = vec![usize::MAX; self.n];
        for (i, &d) in dofs.iter().enumerate() {
            new_of[d] = i;
        }
        let mut col_ptr = Vec::with_capacity(dofs.len() + 1);
        let mut row_idx = Vec::new();
        let mut slots = Vec::new();
        let mut diag = Vec::with_capacity(dofs.len());
        col_ptr.push(0);
        for &j in &dofs {
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[k];
                if keep[i] {
                    if i == j {
                        diag.push(row_idx.len());
                    }
                    // Rows stay ascending: `new_of` is increasing.
                    row_idx.push(new_of[i]);
                    slots.push(k);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let sub = Pattern {
            n: dofs.len(),
            col_ptr,
            row_idx,
            diag,
        };
        (sub, slots, dofs)
    }

    /// The 1-norm of the symmetric matrix (largest absolute column sum).
    pub fn sym_norm1(&self, values: &[f64]) -> f64 {
        let mut col = vec![0.0; self.n];
        for j in 0..self.n {
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[k];
                let a = values[k].abs();
                col[j] += a;
                if i != j {
                    col[i] += a;
                }
            }
        }
        col.into_iter().fold(0.0, f64::max)
    }
}

/// The tridiagonal matrix `tridiag(−1, d, −1)` of size `n`: its pattern and upper-triangle
/// values (the solvers' unit tests).
#[cfg(test)]
pub(crate) fn tridiagonal(n: usize, d: f64) -> (Pattern, Vec<f64>) {
    let mut col_ptr = vec![0];
    let (mut row_idx, mut diag, mut values) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..n {
        if j > 0 {
            row_idx.push(j - 1);
            values.push(-1.0);
        }
        diag.push(row_idx.len());
        row_idx.push(j);
        values.push(d);
        col_ptr.push(row_idx.len());
    }
    let pattern = Pattern {
        n,
        col_ptr,
        row_idx,
        diag,
    };
    (pattern, values)
}

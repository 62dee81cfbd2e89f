//! The triangular substitutions on a [`Plan`]'s schedule, bit-identical to faer's
//! sequential supernodal ones.

use super::{Plan, Task};
use faer::linalg::matmul::matmul_with_conj;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place_with_conj, solve_upper_triangular_in_place_with_conj,
};
use faer::reborrow::{IntoConst, Reborrow, ReborrowMut};
use faer::{Accum, Conj, MatMut, MatRef, Par};
use std::ops::Range;

/// A forward substitution's updates to rows beyond a task's own, in the order the sequential
/// substitution would subtract them: for each record `(supernode, column, first)`, the
/// supernode's pattern rows from `first` on receive the next values.
#[derive(Default)]
struct Deferred {
    records: Vec<(usize, usize, usize)>,
    values: Vec<f64>,
}

/// Read-only rows above a task in the backward substitution (their final values): for each
/// right-hand side, segments `(first row, values)` in ascending rows, covering every row from
/// the first segment's on.
#[derive(Clone, Default)]
struct Above<'a> {
    columns: Vec<Vec<(usize, &'a [f64])>>,
}

impl<'a> Above<'a> {
    /// `self` with the rows of `x` (from row `c0`) in front.
    fn below(&self, x: MatRef<'a, f64>, c0: usize) -> Above<'a> {
        let columns = (0..x.ncols())
            .map(|j| {
                let slice = x
                    .col(j)
                    .try_as_col_major()
                    .expect("column-major storage")
                    .as_slice();
                let mut segs = vec![(c0, slice)];
                if let Some(rest) = self.columns.get(j) {
                    segs.extend_from_slice(rest);
                }
                segs
            })
            .collect();
        Above { columns }
    }

    /// Writes the values of rows `rows` (ascending, all above the task) of column `j` into
    /// `out`.
    fn gather(&self, j: usize, rows: &[usize], out: &mut [f64]) {
        let mut at = 0;
        for &(start, values) in &self.columns[j] {
            let n = rows[at..].partition_point(|&r| r < start + values.len());
            for (o, &r) in out[at..at + n].iter_mut().zip(&rows[at..at + n]) {
                *o = values[r - start];
            }
            at += n;
            if at == rows.len() {
                return;
            }
        }
        assert_eq!(at, rows.len(), "rows above the task are covered");
    }
}

impl Plan {
    /// Solves `L Lᵀ X = B` in place (`x`: `B` in the factor's order) with `l` the factor's
    /// values, independent subtrees in parallel. Each supernode runs the same dense operations
    /// (faer's kernels, `Par::Seq`) as faer's sequential supernodal solve, and every entry
    /// receives its updates in the same order (a subtree's updates to rows above it are
    /// deferred and applied in the sequential order once its siblings are done), so the result
    /// is bit-identical to faer's on any number of threads.
    pub(crate) fn solve_in_place(&self, l: &[f64], mut x: MatMut<'_, f64>) {
        assert_eq!(x.nrows(), self.n, "right-hand side of the factor's size");
        assert_eq!(l.len(), self.len_val(), "factor values of the plan's size");
        let mut deferred = Deferred::default();
        self.forward(&self.solve_root, l, x.rb_mut(), 0, &mut deferred);
        debug_assert!(
            deferred.records.is_empty(),
            "no row lies beyond the last supernode"
        );
        self.backward(&self.solve_root, l, x, 0, &Above::default());
    }

    /// `x` (rows from `c0` on) split into the rows of each of `parts` (consecutive, the first
    /// starting at `c0`): each part with its rows and its first row.
    fn split_rows<'t, 'x>(
        &self,
        parts: &'t [Task],
        x: MatMut<'x, f64>,
        c0: usize,
    ) -> Vec<(&'t Task, MatMut<'x, f64>, usize)> {
        let mut jobs = Vec::with_capacity(parts.len());
        let mut rest = x;
        let mut start = c0;
        for p in parts {
            let r = p.range();
            let (head, next) = rest.split_at_row_mut(self.col(r.end) - self.col(r.start));
            jobs.push((p, head, start));
            start = self.col(r.end);
            rest = next;
        }
        jobs
    }

    /// Forward substitution over `task`, whose rows `x` holds (from row `c0`); updates to rows
    /// beyond them go to `out`.
    fn forward(
        &self,
        task: &Task,
        l: &[f64],
        mut x: MatMut<'_, f64>,
        c0: usize,
        out: &mut Deferred,
    ) {
        match task {
            Task::Seq(range) => self.forward_seq(range.clone(), l, x, c0, out),
            Task::Fork { parts, tail } => {
                let jobs = self.split_rows(parts, x.rb_mut(), c0);
                use rayon::prelude::*;
                let deferred: Vec<Deferred> = jobs
                    .into_par_iter()
                    .map(|(p, xp, start)| {
                        let mut d = Deferred::default();
                        self.forward(p, l, xp, start, &mut d);
                        d
                    })
                    .collect();
                for d in &deferred {
                    let mut values = &d.values[..];
                    for &(s, j, first) in &d.records {
                        let rows = &self.node(s).pattern[first..];
                        let (v, rest) = values.split_at(rows.len());
                        values = rest;
                        self.subtract(x.rb_mut(), c0, s, j, first, v, out);
                    }
                }
                self.forward_seq(tail.clone(), l, x, c0, out);
            }
        }
    }

    fn forward_seq(
        &self,
        range: Range<usize>,
        l: &[f64],
        mut x: MatMut<'_, f64>,
        c0: usize,
        out: &mut Deferred,
    ) {
        let k = x.ncols();
        let mut buf: Vec<f64> = Vec::new();
        for s in range {
            let node = self.node(s);
            let (top, bot) = self.block(l, s).split_at_row(node.ncols);
            let mut x_top = x.rb_mut().subrows_mut(node.start - c0, node.ncols);
            solve_lower_triangular_in_place_with_conj(top, Conj::No, x_top.rb_mut(), Par::Seq);
            let p = node.pattern.len();
            if buf.len() < p * k {
                buf.resize(p * k, 0.0);
            }
            let mut tmp = MatMut::from_column_major_slice_mut(&mut buf[..p * k], p, k);
            matmul_with_conj(
                tmp.rb_mut(),
                Accum::Replace,
                bot,
                Conj::No,
                x_top.rb(),
                Conj::No,
                1.0,
                Par::Seq,
            );
            for j in 0..k {
                self.subtract(x.rb_mut(), c0, s, j, 0, &buf[j * p..(j + 1) * p], out);
            }
        }
    }

    /// Subtracts `v` from column `j` of the rows `pattern[first..]` of supernode `s`: those of
    /// `x` (rows from `c0` on) in place, the others deferred to `out`, in order.
    #[allow(clippy::too_many_arguments)]
    fn subtract(
        &self,
        x: MatMut<'_, f64>,
        c0: usize,
        s: usize,
        j: usize,
        first: usize,
        v: &[f64],
        out: &mut Deferred,
    ) {
        let c1 = c0 + x.nrows();
        let rows = &self.node(s).pattern[first..];
        let near = rows.partition_point(|&r| r < c1);
        let xs = column(x, j);
        for (&i, &v) in rows[..near].iter().zip(&v[..near]) {
            xs[i - c0] -= v;
        }
        if near < rows.len() {
            out.records.push((s, j, first + near));
            out.values.extend_from_slice(&v[near..]);
        }
    }

    /// Backward substitution over `task`, whose rows `x` holds (from row `c0`); the rows
    /// beyond them are final and read from `above`.
    fn backward(
        &self,
        task: &Task,
        l: &[f64],
        mut x: MatMut<'_, f64>,
        c0: usize,
        above: &Above<'_>,
    ) {
        match task {
            Task::Seq(range) => self.backward_seq(range.clone(), l, x, c0, above),
            Task::Fork { parts, tail } => {
                self.backward_seq(tail.clone(), l, x.rb_mut(), c0, above);
                let parts_end = parts.last().map_or(tail.start, |p| p.range().end);
                let split = self.col(parts_end) - c0;
                let (mut lower, upper) = x.split_at_row_mut(split);
                let inner = if upper.nrows() > 0 {
                    above.below(upper.into_const(), c0 + split)
                } else {
                    above.clone()
                };
                let jobs = self.split_rows(parts, lower.rb_mut(), c0);
                use rayon::prelude::*;
                jobs.into_par_iter()
                    .for_each(|(p, xp, start)| self.backward(p, l, xp, start, &inner));
            }
        }
    }

    fn backward_seq(
        &self,
        range: Range<usize>,
        l: &[f64],
        mut x: MatMut<'_, f64>,
        c0: usize,
        above: &Above<'_>,
    ) {
        let c1 = c0 + x.nrows();
        let k = x.ncols();
        let mut buf: Vec<f64> = Vec::new();
        for s in range.rev() {
            let node = self.node(s);
            let (top, bot) = self.block(l, s).split_at_row(node.ncols);
            let p = node.pattern.len();
            if buf.len() < p * k {
                buf.resize(p * k, 0.0);
            }
            let (near, far) = node
                .pattern
                .split_at(node.pattern.partition_point(|&r| r < c1));
            for j in 0..k {
                let xs = column(x.rb_mut(), j);
                let (t_near, t_far) = buf[j * p..(j + 1) * p].split_at_mut(near.len());
                for (t, &i) in t_near.iter_mut().zip(near) {
                    *t = xs[i - c0];
                }
                if !far.is_empty() {
                    above.gather(j, far, t_far);
                }
            }
            let tmp = MatRef::from_column_major_slice(&buf[..p * k], p, k);
            let mut x_top = x.rb_mut().subrows_mut(node.start - c0, node.ncols);
            // The conjugations faer's substitution passes (no-ops on reals), so that the
            // kernels, hence the bits, are the same.
            matmul_with_conj(
                x_top.rb_mut(),
                Accum::Add,
                bot.transpose(),
                Conj::Yes,
                tmp.rb(),
                Conj::No,
                -1.0,
                Par::Seq,
            );
            solve_upper_triangular_in_place_with_conj(
                top.transpose(),
                Conj::Yes,
                x_top.rb_mut(),
                Par::Seq,
            );
        }
    }
}

/// Column `j` of `x` as a slice (faer's matrices here are column-major).
fn column(x: MatMut<'_, f64>, j: usize) -> &mut [f64] {
    x.col_mut(j)
        .try_as_col_major_mut()
        .expect("column-major storage")
        .as_slice_mut()
}

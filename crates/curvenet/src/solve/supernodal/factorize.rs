//! The numeric factorization on a [`Plan`]'s schedule: independent subtrees as rayon tasks,
//! each supernode by the same dense operations whatever the schedule.

use super::{Node, Plan, Task};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{
    LltError, LltRegularization, cholesky_in_place, cholesky_in_place_scratch,
};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};

/// A reference factor's values and the supernodes whose values differ from it.
type CopyFrom<'a> = Option<(&'a [f64], &'a [bool])>;

/// Nodes at least this wide, updated by at least this many descendants, take their updates in
/// two column halves run in parallel.
const SPLIT_MIN_COLS: usize = 48;
const SPLIT_MIN_UPDATES: usize = 32;

/// The column splitting an `nrows × ncols` lower trapezoid into two parts of equal area.
pub(super) fn balanced_split(ncols: usize, nrows: usize) -> usize {
    let area = |x: usize| {
        // Entries on or below the diagonal in columns `0..x`.
        (x * nrows) as f64 - (x * x.saturating_sub(1)) as f64 / 2.0
    };
    let half = area(ncols) / 2.0;
    let mut split = (1..ncols).find(|&x| area(x) >= half).unwrap_or(ncols / 2);
    split = split.clamp(1, ncols - 1);
    split
}

/// What a supernode's updates read: its geometry, its descendants' values and the position
/// of its pattern's rows.
struct Update<'a> {
    plan: &'a Plan,
    node: &'a Node<'a>,
    base: usize,
    head: &'a [f64],
    g2l: &'a [usize],
}

impl Update<'_> {
    /// Subtracts from `cols` (the node's columns `range`, column-major) the contributions of
    /// the descendants `upd`, in order.
    fn apply(&self, upd: &[usize], cols: &mut [f64], range: Range<usize>, tmp: &mut Vec<f64>) {
        let plan = self.plan;
        let node = self.node;
        let nrows = node.nrows();
        let (c_lo, c_hi) = (node.start + range.start, node.start + range.end);
        let s_end = node.start + node.ncols;
        for &d in upd {
            let dn = plan.node(d);
            let off = plan.val_ptr[d] - self.base;
            let ld = MatRef::from_column_major_slice(
                &self.head[off..off + (plan.val_ptr[d + 1] - plan.val_ptr[d])],
                dn.nrows(),
                dn.ncols,
            );
            let start = dn.pattern.partition_point(|&r| r < c_lo);
            let rows = &dn.pattern[start..];
            let width = rows.partition_point(|&r| r < c_hi);
            if width == 0 {
                continue;
            }
            let mid = rows.partition_point(|&r| r < s_end);
            let m = rows.len();
            let below = ld.subrows(dn.ncols + start, m);
            let at = ld.subrows(dn.ncols + start, width);
            // `matmul` overwrites the product: grow the buffer, never clear it.
            if tmp.len() < m * width {
                tmp.resize(m * width, 0.0);
            }
            let mut t = MatMut::from_column_major_slice_mut(&mut tmp[..m * width], m, width);
            matmul(
                t.rb_mut(),
                Accum::Replace,
                below,
                at.transpose(),
                1.0,
                Par::Seq,
            );
            for c in 0..width {
                let col = rows[c] - c_lo;
                let dst = &mut cols[col * nrows..(col + 1) * nrows];
                let src = t.rb().col(c);
                for r in c..mid {
                    dst[rows[r] - node.start] -= src[r];
                }
                for r in mid..m {
                    dst[self.g2l[rows[r]]] -= src[r];
                }
            }
        }
    }
}

impl Plan {
    /// Factors the matrix whose upper-triangle values (in the pattern and order given to
    /// [`Plan::new`]) are `a` into `l` (of [`Plan::len_val`] values, faer's layout). On a
    /// non-positive pivot returns `Err(column)` (permuted order): one failing column — with
    /// several failing subtrees, which one is reported depends on the schedule.
    pub(crate) fn factorize(&self, a: &[f64], l: &mut [f64]) -> Result<(), usize> {
        assert_eq!(l.len(), self.len_val(), "factor storage of the plan's size");
        let abort = AtomicBool::new(false);
        self.run(&self.root, a, l, None, &abort)
    }

    /// [`Plan::factorize`] of a matrix that differs from the one `reference` holds the factor
    /// of only in the supernodes `changed` ([`Plan::changed_supernodes`]): the other
    /// supernodes' values are copied from `reference`, the changed ones computed as
    /// [`Plan::factorize`] would, so the factor is bit-identical to a whole factorization.
    pub(crate) fn factorize_partial(
        &self,
        a: &[f64],
        l: &mut [f64],
        reference: &[f64],
        changed: &[bool],
    ) -> Result<(), usize> {
        assert_eq!(l.len(), self.len_val(), "factor storage of the plan's size");
        assert_eq!(
            reference.len(),
            self.len_val(),
            "reference of the plan's size"
        );
        let abort = AtomicBool::new(false);
        self.run(&self.root, a, l, Some((reference, changed)), &abort)
    }

    /// Runs `task` on `l`, the values of the task's supernodes (starting at its first);
    /// with `reuse`, unchanged supernodes are copied from the reference factor.
    fn run(
        &self,
        task: &Task,
        a: &[f64],
        l: &mut [f64],
        reuse: CopyFrom<'_>,
        abort: &AtomicBool,
    ) -> Result<(), usize> {
        if let Some((reference, changed)) = reuse {
            let r = task.range();
            if !changed[r.clone()].iter().any(|&c| c) {
                l.copy_from_slice(&reference[self.val_ptr[r.start]..self.val_ptr[r.end]]);
                return Ok(());
            }
        }
        match task {
            Task::Seq(range) => self.run_seq(range.clone(), range.start, a, l, reuse, abort),
            Task::Fork { parts, tail } => {
                let lo = task.range().start;
                let mut jobs = Vec::with_capacity(parts.len());
                let mut rest = &mut *l;
                for p in parts {
                    let r = p.range();
                    let (head, tail_vals) =
                        rest.split_at_mut(self.val_ptr[r.end] - self.val_ptr[r.start]);
                    jobs.push((p, head));
                    rest = tail_vals;
                }
                use rayon::prelude::*;
                let results: Vec<Result<(), usize>> = jobs
                    .into_par_iter()
                    .map(|(p, vals)| self.run(p, a, vals, reuse, abort))
                    .collect();
                results.into_iter().collect::<Result<(), usize>>()?;
                self.run_seq(tail.clone(), lo, a, l, reuse, abort)
            }
        }
    }

    /// Factors supernodes `range` in order; `l` holds the values from supernode `lo` on, and
    /// every descendant of the range lies in `lo..`.
    fn run_seq(
        &self,
        range: Range<usize>,
        lo: usize,
        a: &[f64],
        l: &mut [f64],
        reuse: CopyFrom<'_>,
        abort: &AtomicBool,
    ) -> Result<(), usize> {
        if range.is_empty() {
            return Ok(());
        }
        let mut g2l = vec![0usize; self.n];
        let mut tmp: Vec<f64> = Vec::new();
        let mut mem = MemBuffer::new(cholesky_in_place_scratch::<f64>(
            self.max_cols,
            Par::Seq,
            Default::default(),
        ));
        let base = self.val_ptr[lo];
        for s in range {
            if abort.load(Ordering::Relaxed) {
                return Err(self.begin[s]);
            }
            let (head, rest) = l.split_at_mut(self.val_ptr[s] - base);
            let block = &mut rest[..self.val_ptr[s + 1] - self.val_ptr[s]];
            if let Some((reference, changed)) = reuse
                && !changed[s]
            {
                block.copy_from_slice(&reference[self.val_ptr[s]..self.val_ptr[s + 1]]);
                continue;
            }
            if let Err(col) =
                self.factor_node(s, base, head, block, a, &mut g2l, &mut tmp, &mut mem)
            {
                abort.store(true, Ordering::Relaxed);
                return Err(col);
            }
        }
        Ok(())
    }

    /// Factors supernode `s` into `block`; `head` holds the values of the supernodes from the
    /// one at offset `base` up to `s` (all of `s`'s descendants).
    #[allow(clippy::too_many_arguments)]
    fn factor_node(
        &self,
        s: usize,
        base: usize,
        head: &[f64],
        block: &mut [f64],
        a: &[f64],
        g2l: &mut [usize],
        tmp: &mut Vec<f64>,
        mem: &mut MemBuffer,
    ) -> Result<(), usize> {
        let node = self.node(s);
        let (ncols, nrows) = (node.ncols, node.nrows());
        block.fill(0.0);
        for k in self.a_ptr[s]..self.a_ptr[s + 1] {
            block[self.a_dst[k]] += a[self.a_src[k]];
        }
        for (i, &r) in node.pattern.iter().enumerate() {
            g2l[r] = ncols + i;
        }
        let upd = &self.upd[self.upd_ptr[s]..self.upd_ptr[s + 1]];
        let ctx = Update {
            plan: self,
            node: &node,
            base,
            head,
            g2l,
        };
        if ncols >= SPLIT_MIN_COLS && upd.len() >= SPLIT_MIN_UPDATES {
            // Columns left of `split` and right of it take their updates independently; the
            // split is a function of the node only (never of the threads), and balances the
            // lower trapezoid's area.
            let split = balanced_split(ncols, nrows);
            let (left, right) = block.split_at_mut(split * nrows);
            rayon::join(
                || ctx.apply(upd, left, 0..split, &mut Vec::new()),
                || ctx.apply(upd, right, split..ncols, &mut Vec::new()),
            );
        } else {
            ctx.apply(upd, block, 0..ncols, tmp);
        }
        let ls = MatMut::from_column_major_slice_mut(block, nrows, ncols);
        let (mut top, mut bot) = ls.split_at_row_mut(ncols);
        match cholesky_in_place(
            top.rb_mut(),
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(mem),
            Default::default(),
        ) {
            Ok(_) => {}
            Err(LltError::NonPositivePivot { index }) => return Err(index + node.start),
        }
        solve_lower_triangular_in_place(top.rb(), bot.rb_mut().transpose_mut(), Par::Seq);
        Ok(())
    }
}

//! Numeric supernodal Cholesky on faer's symbolic analysis, with independent subtrees of the
//! elimination tree factored in parallel.
//!
//! faer's own numeric factorization visits the supernodes one after the other (left-looking)
//! and can parallelize only inside a supernode's dense blocks; on our matrices these blocks are
//! small, and its parallel mode is slower than the sequential one (docs/benchmarks.md). But
//! supernodes in disjoint subtrees of the elimination tree never touch each other: a
//! supernode reads only the finished columns of its own descendants. [`Plan`] splits the tree
//! into such subtrees once per symbolic analysis; [`Plan::factorize`] runs them as rayon
//! tasks, then the supernodes above them in order.
//!
//! The factor has faer's storage layout (faer solves with it), and each supernode is computed
//! by the same sequence of dense operations (faer's kernels, `Par::Seq`) whatever the thread
//! count or the schedule, so the values are bit-identical on one and on many threads.
//!
//! The input is scattered straight from the model's upper-triangle values into `L` through a
//! map computed once (faer permutes the matrix into a lower-triangle copy first).
//!
//! [`Plan::solve_in_place`] runs the two triangular substitutions on the same kind of schedule
//! (coarser: a substitution reads each value once). The backward one parallelizes as is: a
//! supernode reads only its ancestors' final values. The forward one scatters each
//! supernode's update into its ancestors' rows, which sibling subtrees share; a subtree
//! applies the updates to its own rows at once and defers those to rows above it, which are
//! applied in the sequential order once its siblings are done. Each row thus receives the
//! same updates in the same order, from the same dense operations, as in faer's sequential
//! substitution: the solution is bit-identical to it. The deferred updates make it about 10%
//! slower where no core is free, so only callers that leave the cores idle (Newton's steps)
//! use it.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{
    LltError, LltRegularization, cholesky_in_place, cholesky_in_place_scratch,
};
use faer::linalg::matmul::{matmul, matmul_with_conj};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_lower_triangular_in_place_with_conj,
    solve_upper_triangular_in_place_with_conj,
};
use faer::reborrow::{IntoConst, Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::{Accum, Conj, MatMut, MatRef, Par};
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};

/// Subtrees lighter than `1 / GRAIN_PARTS` of the whole factorization's work are not split.
const GRAIN_PARTS: f64 = 48.0;

/// Factorizations estimated below this many flops run as one sequential task.
const MIN_PARALLEL_FLOPS: f64 = 2.0e6;

/// Substitutions' subtrees lighter than `1 / SOLVE_GRAIN_PARTS` of the whole are not split.
const SOLVE_GRAIN_PARTS: f64 = 4.0;

/// Factors with fewer stored values than this are substituted in one sequential task.
const MIN_PARALLEL_SOLVE_VALUES: f64 = 2.0e5;

/// Tasks nested deeper than this are not split further.
const MAX_DEPTH: usize = 48;

/// How the supernodes are scheduled: a sequential range, or independent subtrees (run in
/// parallel) followed by the supernodes above them.
#[derive(Debug)]
enum Task {
    /// Supernodes `range`, in order.
    Seq(Range<usize>),
    /// `parts` cover consecutive ranges of supernodes, independent of each other; `tail`
    /// follows them and depends on all of them.
    Fork {
        parts: Vec<Task>,
        tail: Range<usize>,
    },
}

impl Task {
    /// The sequential parts of the schedule (1 if it has no fork).
    fn sequential_parts(&self) -> usize {
        match self {
            Task::Seq(_) => 1,
            Task::Fork { parts, .. } => parts.iter().map(Task::sequential_parts).sum(),
        }
    }

    /// The supernodes the task covers (a contiguous range in postorder).
    fn range(&self) -> Range<usize> {
        match self {
            Task::Seq(r) => r.clone(),
            Task::Fork { parts, tail } => {
                let start = parts.first().map_or(tail.start, |p| p.range().start);
                // The root's fork has an empty tail (`0..0`): it ends with its last part.
                let end = if tail.is_empty() {
                    parts.last().map_or(tail.end, |p| p.range().end)
                } else {
                    tail.end
                };
                start..end
            }
        }
    }
}

/// The numeric factorization plan of one supernodal symbolic analysis.
#[derive(Debug)]
pub(crate) struct Plan {
    /// Dimension.
    n: usize,
    /// First column of each supernode (`n_super + 1` entries).
    begin: Vec<usize>,
    /// Offset of each supernode's block in the factor values (`n_super + 1` entries).
    val_ptr: Vec<usize>,
    /// Each supernode's off-diagonal row pattern: `rows[pat_ptr[s]..pat_ptr[s + 1]]`.
    pat_ptr: Vec<usize>,
    rows: Vec<usize>,
    /// Parent of each supernode in the elimination tree.
    parent: Vec<Option<usize>>,
    /// Estimated work of each supernode's factorization (`c·r²`: its columns update
    /// everything below them).
    work: Vec<f64>,
    /// Supernodes whose columns update supernode `s`, ascending: `upd[upd_ptr[s]..]`.
    upd_ptr: Vec<usize>,
    upd: Vec<usize>,
    /// Input entries of supernode `s`: slot in the model's values and offset in the block.
    a_ptr: Vec<usize>,
    a_src: Vec<usize>,
    a_dst: Vec<usize>,
    /// Widest supernode (columns), for the dense Cholesky's scratch.
    max_cols: usize,
    /// The factorization's schedule.
    root: Task,
    /// The substitutions' schedule: coarser, as a substitution does far less work per
    /// supernode than the factorization (`c·r` against `c·r²`) and a task costs the same.
    solve_root: Task,
}

/// Supernode `s`'s geometry.
struct Node<'a> {
    start: usize,
    ncols: usize,
    pattern: &'a [usize],
}

impl Node<'_> {
    fn nrows(&self) -> usize {
        self.ncols + self.pattern.len()
    }
}

impl Plan {
    /// A plan for `sym` (supernodal analysis of a matrix of dimension `n` permuted by
    /// `perm_inv`: new index of each original one), for input values stored as the upper
    /// triangle `col_ptr`/`row_idx` in the original order. `None` if the supernodes are not in
    /// a postorder of their elimination tree (the layout this schedule relies on).
    pub(crate) fn new(
        sym: &SymbolicSupernodalCholesky<usize>,
        perm_inv: Option<&[usize]>,
        col_ptr: &[usize],
        row_idx: &[usize],
    ) -> Option<Plan> {
        let n = sym.nrows();
        let ns = sym.n_supernodes();
        let mut begin: Vec<usize> = sym.supernode_begin().to_vec();
        begin.push(n);
        let val_ptr = sym.col_ptr_for_val().to_vec();
        let mut pat_ptr = Vec::with_capacity(ns + 1);
        let mut rows = Vec::new();
        pat_ptr.push(0);
        for s in 0..ns {
            rows.extend_from_slice(sym.supernode(s).pattern());
            pat_ptr.push(rows.len());
        }
        // Elimination tree of the supernodes and its postorder property.
        let (super_of, parent) = supernode_tree(sym);
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); ns];
        for (s, p) in parent.iter().enumerate() {
            if let &Some(p) = p {
                if p <= s {
                    return None;
                }
                children[p].push(s);
            }
        }
        let mut first: Vec<usize> = (0..ns).collect();
        let mut size = vec![1usize; ns];
        for s in 0..ns {
            if let Some(p) = parent[s] {
                first[p] = first[p].min(first[s]);
                size[p] += size[s];
            }
        }
        if (0..ns).any(|s| s + 1 - first[s] != size[s]) {
            return None;
        }
        // Updates: d updates every supernode its pattern reaches.
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        for d in 0..ns {
            let mut last = usize::MAX;
            for &r in &rows[pat_ptr[d]..pat_ptr[d + 1]] {
                let s = super_of[r];
                if s != last {
                    pairs.push((s, d));
                    last = s;
                }
            }
        }
        let (upd_ptr, upd) = bucket(ns, pairs);
        // Input scatter map.
        let mut entries: Vec<(usize, (usize, usize))> = Vec::new();
        for j in 0..n {
            for (k, &i) in row_idx
                .iter()
                .enumerate()
                .take(col_ptr[j + 1])
                .skip(col_ptr[j])
            {
                let (pi, pj) = match perm_inv {
                    Some(p) => (p[i], p[j]),
                    None => (i, j),
                };
                let (row, col) = (pi.max(pj), pi.min(pj));
                let s = super_of[col];
                let ncols = begin[s + 1] - begin[s];
                let pattern = &rows[pat_ptr[s]..pat_ptr[s + 1]];
                let local_row = if row < begin[s + 1] {
                    row - begin[s]
                } else {
                    ncols + pattern.binary_search(&row).ok()?
                };
                let dst = (col - begin[s]) * (ncols + pattern.len()) + local_row;
                entries.push((s, (k, dst)));
            }
        }
        let (a_ptr, a) = bucket(ns, entries);
        let (a_src, a_dst) = a.into_iter().unzip();
        // Work per subtree: each supernode's columns update everything below them.
        let work: Vec<f64> = (0..ns)
            .map(|s| {
                let c = (begin[s + 1] - begin[s]) as f64;
                let r = c + (pat_ptr[s + 1] - pat_ptr[s]) as f64;
                c * r * r
            })
            .collect();
        let mut subtree = work.clone();
        for s in 0..ns {
            if let Some(p) = parent[s] {
                let w = subtree[s];
                subtree[p] += w;
            }
        }
        let total: f64 = (0..ns)
            .filter(|&s| parent[s].is_none())
            .map(|s| subtree[s])
            .sum();
        let roots: Vec<usize> = (0..ns).filter(|&s| parent[s].is_none()).collect();
        let tree = Tree {
            children: &children,
            first: &first,
            subtree: &subtree,
            grain: if total < MIN_PARALLEL_FLOPS {
                f64::INFINITY
            } else {
                total / GRAIN_PARTS
            },
        };
        let root = tree.fork(&roots, 0..0, 0);
        // The substitutions' work per subtree: each supernode reads its block once.
        let mut solve_subtree: Vec<f64> = (0..ns)
            .map(|s| {
                ((begin[s + 1] - begin[s])
                    * (pat_ptr[s + 1] - pat_ptr[s] + begin[s + 1] - begin[s]))
                    as f64
            })
            .collect();
        for s in 0..ns {
            if let Some(p) = parent[s] {
                let w = solve_subtree[s];
                solve_subtree[p] += w;
            }
        }
        let solve_total: f64 = roots.iter().map(|&s| solve_subtree[s]).sum();
        let solve_root = Tree {
            children: &children,
            first: &first,
            subtree: &solve_subtree,
            grain: if solve_total < MIN_PARALLEL_SOLVE_VALUES {
                f64::INFINITY
            } else {
                solve_total / SOLVE_GRAIN_PARTS
            },
        }
        .fork(&roots, 0..0, 0);
        let max_cols = (0..ns).map(|s| begin[s + 1] - begin[s]).max().unwrap_or(0);
        Some(Plan {
            n,
            parent,
            work,
            begin,
            val_ptr,
            pat_ptr,
            rows,
            upd_ptr,
            upd,
            a_ptr,
            a_src,
            a_dst,
            max_cols,
            root,
            solve_root,
        })
    }

    /// Number of tasks that may run in parallel (sequential parts of forks), 1 if none.
    pub(crate) fn parallel_tasks(&self) -> usize {
        self.root.sequential_parts()
    }

    /// [`Plan::parallel_tasks`] of the substitutions' schedule.
    pub(crate) fn parallel_solve_tasks(&self) -> usize {
        self.solve_root.sequential_parts()
    }

    /// The supernodes whose values change when the matrix changes only in entries whose row
    /// and column both lie in `cols` (permuted order): those holding one of `cols`, and their
    /// ancestors (every supernode reads its descendants' values). The others keep their
    /// values, which [`Plan::factorize_partial`] copies.
    pub(crate) fn changed_supernodes(&self, cols: &[usize]) -> Vec<bool> {
        let ns = self.begin.len() - 1;
        let mut changed = vec![false; ns];
        for &c in cols {
            let mut s = Some(self.begin.partition_point(|&b| b <= c) - 1);
            while let Some(x) = s {
                if changed[x] {
                    break;
                }
                changed[x] = true;
                s = self.parent[x];
            }
        }
        changed
    }

    /// The share of a factorization's work in supernodes `changed`.
    pub(crate) fn work_share(&self, changed: &[bool]) -> f64 {
        let total: f64 = self.work.iter().sum();
        let part: f64 = self
            .work
            .iter()
            .zip(changed)
            .filter(|(_, c)| **c)
            .map(|(w, _)| w)
            .sum();
        part / total.max(f64::MIN_POSITIVE)
    }

    /// Number of stored factor values.
    pub(crate) fn len_val(&self) -> usize {
        *self.val_ptr.last().unwrap_or(&0)
    }

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

    fn node(&self, s: usize) -> Node<'_> {
        Node {
            start: self.begin[s],
            ncols: self.begin[s + 1] - self.begin[s],
            pattern: &self.rows[self.pat_ptr[s]..self.pat_ptr[s + 1]],
        }
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

    /// The first column of supernode `s` (or `n` for `s` = the number of supernodes).
    fn col(&self, s: usize) -> usize {
        self.begin[s]
    }

    /// The factor block of supernode `s`.
    fn block<'l>(&self, l: &'l [f64], s: usize) -> MatRef<'l, f64> {
        let node = self.node(s);
        MatRef::from_column_major_slice(
            &l[self.val_ptr[s]..self.val_ptr[s + 1]],
            node.nrows(),
            node.ncols,
        )
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

/// A reference factor's values and the supernodes whose values differ from it.
type CopyFrom<'a> = Option<(&'a [f64], &'a [bool])>;

/// Nodes at least this wide, updated by at least this many descendants, take their updates in
/// two column halves run in parallel.
const SPLIT_MIN_COLS: usize = 48;
const SPLIT_MIN_UPDATES: usize = 32;

/// The column splitting an `nrows × ncols` lower trapezoid into two parts of equal area.
fn balanced_split(ncols: usize, nrows: usize) -> usize {
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

/// The ordering `perm_fwd` (original index of each new one; identity if `None`) with the
/// supernodes of `sym` (its analysis) renumbered in a postorder of their elimination tree,
/// children in ascending order: the same factor up to a symmetric permutation, with the same
/// fill, but every subtree's supernodes consecutive, as [`Plan`] needs. `None` if they
/// already are.
pub(crate) fn postordered(
    sym: &SymbolicSupernodalCholesky<usize>,
    perm_fwd: Option<&[usize]>,
) -> Option<Vec<usize>> {
    let n = sym.nrows();
    let ns = sym.n_supernodes();
    let begin = sym.supernode_begin();
    let end = sym.supernode_end();
    let (_, parent) = supernode_tree(sym);
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); ns];
    let mut roots = Vec::new();
    for (s, p) in parent.into_iter().enumerate() {
        match p {
            Some(p) => children[p].push(s),
            None => roots.push(s),
        }
    }
    // Iterative depth-first postorder.
    let mut order = Vec::with_capacity(ns);
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for &r in &roots {
        stack.push((r, 0));
        while let Some((s, next)) = stack.pop() {
            if let Some(&c) = children[s].get(next) {
                stack.push((s, next + 1));
                stack.push((c, 0));
            } else {
                order.push(s);
            }
        }
    }
    if order.iter().enumerate().all(|(i, &s)| i == s) {
        return None;
    }
    let mut fwd = Vec::with_capacity(n);
    for &s in &order {
        for col in begin[s]..end[s] {
            fwd.push(perm_fwd.map_or(col, |p| p[col]));
        }
    }
    Some(fwd)
}

/// The elimination tree of `sym`'s supernodes: the supernode of each column, and each
/// supernode's parent (the supernode of its first off-diagonal row; `None` for roots).
fn supernode_tree(sym: &SymbolicSupernodalCholesky<usize>) -> (Vec<usize>, Vec<Option<usize>>) {
    let (begin, end) = (sym.supernode_begin(), sym.supernode_end());
    let mut super_of = vec![0usize; sym.nrows()];
    for s in 0..sym.n_supernodes() {
        super_of[begin[s]..end[s]].fill(s);
    }
    let parent = (0..sym.n_supernodes())
        .map(|s| sym.supernode(s).pattern().first().map(|&r| super_of[r]))
        .collect();
    (super_of, parent)
}

/// Groups `(key, value)` pairs by key (`0..n`), keeping their order within a key.
fn bucket<T: Copy>(n: usize, pairs: Vec<(usize, T)>) -> (Vec<usize>, Vec<T>) {
    let mut ptr = vec![0usize; n + 1];
    for &(k, _) in &pairs {
        ptr[k + 1] += 1;
    }
    for k in 0..n {
        ptr[k + 1] += ptr[k];
    }
    let mut next = ptr.clone();
    let mut out: Vec<Option<T>> = vec![None; pairs.len()];
    for (k, v) in pairs {
        out[next[k]] = Some(v);
        next[k] += 1;
    }
    (
        ptr,
        out.into_iter()
            .map(|v| v.expect("every slot filled"))
            .collect(),
    )
}

/// The elimination tree, for building the schedule.
struct Tree<'a> {
    children: &'a [Vec<usize>],
    first: &'a [usize],
    subtree: &'a [f64],
    grain: f64,
}

impl Tree<'_> {
    /// The task for the subtree rooted at `r`.
    fn task(&self, r: usize, depth: usize) -> Task {
        let whole = self.first[r]..r + 1;
        if self.subtree[r] < self.grain || depth >= MAX_DEPTH {
            return Task::Seq(whole);
        }
        // Walk down the chain of single children: those supernodes run after the fork.
        let mut b = r;
        while self.children[b].len() == 1 {
            b = self.children[b][0];
        }
        if self.children[b].is_empty() {
            return Task::Seq(whole);
        }
        self.fork(&self.children[b], b..r + 1, depth + 1)
    }

    /// Independent subtrees `roots` (consecutive in postorder) followed by `tail`; runs of
    /// light subtrees are merged into one sequential part.
    fn fork(&self, roots: &[usize], tail: Range<usize>, depth: usize) -> Task {
        let mut parts: Vec<Task> = Vec::new();
        let mut light: Option<Range<usize>> = None;
        for &c in roots {
            let range = self.first[c]..c + 1;
            if self.subtree[c] < self.grain {
                light = Some(match light {
                    Some(l) => l.start..range.end,
                    None => range,
                });
                continue;
            }
            if let Some(l) = light.take() {
                parts.push(Task::Seq(l));
            }
            parts.push(self.task(c, depth));
        }
        if let Some(l) = light {
            parts.push(Task::Seq(l));
        }
        if parts.len() == 1 && tail.is_empty() {
            return parts.pop().expect("one part");
        }
        Task::Fork { parts, tail }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balanced_split_halves_the_trapezoid() {
        for (ncols, nrows) in [
            (2, 2),
            (3, 10),
            (48, 48),
            (100, 100),
            (100, 400),
            (423, 423),
        ] {
            let split = balanced_split(ncols, nrows);
            assert!((1..ncols).contains(&split), "{ncols}×{nrows}: {split}");
            let area = |a: usize, b: usize| (a..b).map(|c| nrows - c).sum::<usize>();
            let (left, right) = (area(0, split), area(split, ncols));
            // Within one column of an even split.
            assert!(
                left.abs_diff(right) <= 2 * nrows,
                "{ncols}×{nrows}: {left} vs {right}"
            );
        }
    }

    #[test]
    fn bucket_groups_by_key_keeping_order() {
        let (ptr, vals) = bucket(3, vec![(2, 'a'), (0, 'b'), (2, 'c'), (0, 'd')]);
        assert_eq!(ptr, vec![0, 2, 2, 4]);
        assert_eq!(vals, vec!['b', 'd', 'a', 'c']);
    }
}

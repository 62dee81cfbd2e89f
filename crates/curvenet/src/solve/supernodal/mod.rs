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
//! substitution: the solution is bit-identical to it. The deferred updates cost extra work
//! where no core is free, so only callers that leave the cores idle (Newton's steps) use it.

mod factorize;
mod plan;
mod substitute;

pub(crate) use plan::postordered;

use faer::MatRef;
use std::ops::Range;

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

    fn node(&self, s: usize) -> Node<'_> {
        Node {
            start: self.begin[s],
            ncols: self.begin[s + 1] - self.begin[s],
            pattern: &self.rows[self.pat_ptr[s]..self.pat_ptr[s + 1]],
        }
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
}

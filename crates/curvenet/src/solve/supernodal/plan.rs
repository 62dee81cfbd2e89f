//! Building a [`Plan`]: the supernodes' layout and elimination tree, who updates whom, the
//! input's scatter map, and the schedules of independent subtrees.

use super::{Plan, Task};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use std::ops::Range;

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
        let (super_of, parent) = supernode_tree(sym);
        let (children, first) = postorder_tree(&parent)?;
        let layout = Layout {
            begin: &begin,
            pat_ptr: &pat_ptr,
            rows: &rows,
            super_of: &super_of,
        };
        let (upd_ptr, upd) = layout.updates();
        let (a_ptr, a) = layout.scatter_map(perm_inv, col_ptr, row_idx)?;
        let (a_src, a_dst) = a.into_iter().unzip();
        let roots: Vec<usize> = (0..ns).filter(|&s| parent[s].is_none()).collect();
        let schedule = |work: &[f64], min_parallel: f64, parts: f64| {
            let mut subtree = work.to_vec();
            for s in 0..ns {
                if let Some(p) = parent[s] {
                    let w = subtree[s];
                    subtree[p] += w;
                }
            }
            let total: f64 = roots.iter().map(|&s| subtree[s]).sum();
            let tree = Tree {
                children: &children,
                first: &first,
                subtree: &subtree,
                grain: if total < min_parallel {
                    f64::INFINITY
                } else {
                    total / parts
                },
            };
            tree.fork(&roots, 0..0, 0)
        };
        // Work per supernode: its columns update everything below them (`c·r²`); a
        // substitution reads its block once (`c·r`).
        let work = layout.work(|c, r| c * r * r);
        let root = schedule(&work, MIN_PARALLEL_FLOPS, GRAIN_PARTS);
        let solve_work = layout.work(|c, r| c * r);
        let solve_root = schedule(&solve_work, MIN_PARALLEL_SOLVE_VALUES, SOLVE_GRAIN_PARTS);
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
}

/// The supernodes' columns and off-diagonal row patterns (`n_super + 1` pointers each) and
/// the supernode of each column.
struct Layout<'a> {
    begin: &'a [usize],
    pat_ptr: &'a [usize],
    rows: &'a [usize],
    super_of: &'a [usize],
}

impl Layout<'_> {
    fn supernodes(&self) -> usize {
        self.begin.len() - 1
    }

    /// Who updates whom: each supernode's updating descendants (every supernode its pattern
    /// reaches), ascending, bucketed by the updated one.
    fn updates(&self) -> (Vec<usize>, Vec<usize>) {
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        for d in 0..self.supernodes() {
            let mut last = usize::MAX;
            for &r in &self.rows[self.pat_ptr[d]..self.pat_ptr[d + 1]] {
                let s = self.super_of[r];
                if s != last {
                    pairs.push((s, d));
                    last = s;
                }
            }
        }
        bucket(self.supernodes(), pairs)
    }

    /// The input's scatter map: for every stored entry of the upper triangle
    /// `col_ptr`/`row_idx` (original order, permuted by `perm_inv`), its supernode, its slot
    /// in the input values and its offset in the supernode's block. `None` if an entry falls
    /// outside the supernodes' patterns.
    #[allow(clippy::type_complexity)]
    fn scatter_map(
        &self,
        perm_inv: Option<&[usize]>,
        col_ptr: &[usize],
        row_idx: &[usize],
    ) -> Option<(Vec<usize>, Vec<(usize, usize)>)> {
        let begin = self.begin;
        let mut entries: Vec<(usize, (usize, usize))> = Vec::new();
        for j in 0..col_ptr.len() - 1 {
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
                let s = self.super_of[col];
                let ncols = begin[s + 1] - begin[s];
                let pattern = &self.rows[self.pat_ptr[s]..self.pat_ptr[s + 1]];
                let local_row = if row < begin[s + 1] {
                    row - begin[s]
                } else {
                    ncols + pattern.binary_search(&row).ok()?
                };
                let dst = (col - begin[s]) * (ncols + pattern.len()) + local_row;
                entries.push((s, (k, dst)));
            }
        }
        Some(bucket(self.supernodes(), entries))
    }

    /// `cost(columns, rows)` of every supernode (rows: its columns and pattern together).
    fn work(&self, cost: impl Fn(f64, f64) -> f64) -> Vec<f64> {
        (0..self.supernodes())
            .map(|s| {
                let c = (self.begin[s + 1] - self.begin[s]) as f64;
                let r = c + (self.pat_ptr[s + 1] - self.pat_ptr[s]) as f64;
                cost(c, r)
            })
            .collect()
    }
}

/// The children of each supernode and the first supernode of each subtree; `None` unless
/// the supernodes are in a postorder of their tree (every subtree's supernodes consecutive,
/// each before its parent).
fn postorder_tree(parent: &[Option<usize>]) -> Option<(Vec<Vec<usize>>, Vec<usize>)> {
    let ns = parent.len();
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
    Some((children, first))
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
    use crate::solve::supernodal::factorize::balanced_split;

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

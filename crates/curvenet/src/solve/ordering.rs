//! Fill-reducing orderings of the Hessian's pattern.
//!
//! The pattern is made of 3×3 blocks, one per pair of vertices that share a term, so orderings
//! are computed on the vertex graph and expanded to the three coordinates of each vertex.
//!
//! - **AMD** (faer's approximate minimum degree): fast, good on small networks.
//! - **Nested dissection** (METIS `NodeND`, with the `metis` feature): on large networks it
//!   leaves far less fill in the Cholesky factor than AMD (the paper's: `docs/benchmarks.md`),
//!   which makes every factorization and solve cheaper.
//!
//! Either ordering is then renumbered in a [`postorder`] of its elimination tree (same fill;
//! faer merges more supernodes, and the subtree-parallel factorization needs it).
//!
//! [`SymbolicFactor::new`](super::SymbolicFactor::new) tries both on networks large enough for
//! it to matter and keeps the one with less fill; METIS runs with its default, fixed seed, so
//! the choice is deterministic.

use crate::sparse::Pattern;

/// Which ordering a symbolic factorization used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OrderingKind {
    /// Approximate minimum degree.
    Amd,
    /// Nested dissection (METIS).
    NestedDissection,
}

/// The vertex graph of a 3×3-block pattern in compressed form (`xadj`, `adjncy`), without
/// self loops.
pub fn vertex_graph(pattern: &Pattern) -> (Vec<usize>, Vec<usize>) {
    let nv = pattern.n / 3;
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); nv];
    for j in 0..nv {
        let col = 3 * j;
        for k in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
            let r = pattern.row_idx[k];
            if r.is_multiple_of(3) && r / 3 != j {
                adj[j].push(r / 3);
                adj[r / 3].push(j);
            }
        }
    }
    let mut xadj = Vec::with_capacity(nv + 1);
    let mut adjncy = Vec::new();
    xadj.push(0);
    for mut a in adj {
        a.sort_unstable();
        a.dedup();
        adjncy.extend(a);
        xadj.push(adjncy.len());
    }
    (xadj, adjncy)
}

/// Expands a vertex permutation (`perm[new] = old`) to the coordinates: `(forward, inverse)`.
pub fn expand(vertex_perm: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let n = 3 * vertex_perm.len();
    let mut fwd = Vec::with_capacity(n);
    for &v in vertex_perm {
        fwd.extend([3 * v, 3 * v + 1, 3 * v + 2]);
    }
    let mut inv = vec![0; n];
    for (i, &s) in fwd.iter().enumerate() {
        inv[s] = i;
    }
    (fwd, inv)
}

/// Held while METIS orders a graph: one ordering at a time in the process. METIS keeps its
/// random number generator (seeded afresh by every call) and its signal handlers in global
/// state, so two orderings at once interleave one generator and give orderings that depend on
/// the timing (seen: the same structure analysed on two threads at once factored with
/// different fill-reducing orderings, run to run).
#[cfg(feature = "metis")]
static METIS: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// A nested-dissection vertex ordering (`perm[new] = old`) from METIS, or `None` when METIS
/// is not built in or fails. The same pattern gives the same ordering, whatever else runs.
#[cfg(feature = "metis")]
pub fn nested_dissection(pattern: &Pattern) -> Option<Vec<usize>> {
    use metis_sys::idx_t;
    let (xadj, adjncy) = vertex_graph(pattern);
    let nv = xadj.len() - 1;
    if nv == 0
        || adjncy.is_empty()
        || nv > idx_t::MAX as usize
        || adjncy.len() > idx_t::MAX as usize
    {
        return None;
    }
    let mut xadj: Vec<idx_t> = xadj.iter().map(|&x| x as idx_t).collect();
    let mut adjncy: Vec<idx_t> = adjncy.iter().map(|&x| x as idx_t).collect();
    let mut n = nv as idx_t;
    let mut options = [0 as idx_t; metis_sys::METIS_NOPTIONS as usize];
    let mut perm = vec![0 as idx_t; nv];
    let mut iperm = vec![0 as idx_t; nv];
    let _one_at_a_time = METIS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    #[allow(unsafe_code)]
    // SAFETY: every pointer refers to a live, correctly sized buffer: `options` has
    // METIS_NOPTIONS entries, `xadj` nv + 1, `adjncy` xadj[nv], `perm` and `iperm` nv; the
    // graph is symmetric without self loops, as METIS requires; the vertex weights are null
    // (unweighted), which METIS accepts. METIS does not keep the pointers after returning.
    // The lock keeps every other METIS call of the process out meanwhile.
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        metis_sys::METIS_NodeND(
            &mut n,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return None;
    }
    let perm: Vec<usize> = perm.into_iter().map(|p| p as usize).collect();
    // A permutation, or nothing.
    let mut seen = vec![false; nv];
    for &p in &perm {
        if p >= nv || std::mem::replace(&mut seen[p], true) {
            return None;
        }
    }
    Some(perm)
}

/// Without the `metis` feature there is no nested dissection.
#[cfg(not(feature = "metis"))]
pub fn nested_dissection(_pattern: &Pattern) -> Option<Vec<usize>> {
    None
}

/// The ordering `fwd` (`fwd[new] = old`) renumbered in a postorder of the elimination tree of
/// the pattern it permutes (children in ascending order): the same fill, but every subtree's
/// columns consecutive, which keeps the supernodes of faer's analysis in postorder (as the
/// subtree-parallel factorization needs) and the factorization's memory accesses local.
pub fn postorder(pattern: &Pattern, fwd: &[usize]) -> Vec<usize> {
    let n = pattern.n;
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    // Entries above the diagonal of the permuted matrix, by column: (row < col).
    let mut count = vec![0usize; n + 1];
    for j in 0..n {
        for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
            if i != j {
                count[inv[i].max(inv[j]) + 1] += 1;
            }
        }
    }
    for k in 0..n {
        count[k + 1] += count[k];
    }
    let mut next = count.clone();
    let mut rows = vec![0usize; count[n]];
    for j in 0..n {
        for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
            if i != j {
                let col = inv[i].max(inv[j]);
                rows[next[col]] = inv[i].min(inv[j]);
                next[col] += 1;
            }
        }
    }
    // Elimination tree (Liu's algorithm with path compression).
    const NONE: usize = usize::MAX;
    let mut parent = vec![NONE; n];
    let mut ancestor = vec![NONE; n];
    for k in 0..n {
        for &i0 in &rows[count[k]..count[k + 1]] {
            let mut i = i0;
            while i != NONE && i < k {
                let up = ancestor[i];
                ancestor[i] = k;
                if up == NONE {
                    parent[i] = k;
                }
                i = up;
            }
        }
    }
    // Depth-first postorder, children ascending.
    let mut head = vec![NONE; n];
    let mut sibling = vec![NONE; n];
    for k in (0..n).rev() {
        if parent[k] != NONE {
            sibling[k] = head[parent[k]];
            head[parent[k]] = k;
        }
    }
    let mut order = Vec::with_capacity(n);
    let mut stack = Vec::new();
    for root in (0..n).filter(|&k| parent[k] == NONE) {
        stack.push(root);
        while let Some(&top) = stack.last() {
            let child = head[top];
            if child == NONE {
                order.push(top);
                stack.pop();
            } else {
                head[top] = sibling[child];
                stack.push(child);
            }
        }
    }
    order.into_iter().map(|new| fwd[new]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expansion_is_a_permutation_of_coordinates() {
        let (fwd, inv) = expand(&[2, 0, 1]);
        assert_eq!(fwd, vec![6, 7, 8, 0, 1, 2, 3, 4, 5]);
        for (i, &f) in fwd.iter().enumerate() {
            assert_eq!(inv[f], i);
        }
    }

    /// A path 0 – 1 – … – 9 plus a few chords, as a symmetric pattern (upper triangle).
    fn small_pattern() -> Pattern {
        pattern_of(
            10,
            &[
                (0, 1),
                (1, 2),
                (2, 3),
                (3, 4),
                (4, 5),
                (5, 6),
                (6, 7),
                (7, 8),
                (8, 9),
                (0, 5),
                (2, 7),
            ],
        )
    }

    /// The pattern (upper triangle) of an `n × n` symmetric matrix with a diagonal and the
    /// entries `(i, j)`, `i < j`.
    fn pattern_of(n: usize, entries: &[(usize, usize)]) -> Pattern {
        let mut cols: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
        for &(i, j) in entries {
            cols[j].push(i);
        }
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut diag = Vec::new();
        for mut c in cols {
            c.sort_unstable();
            let j = col_ptr.len() - 1;
            diag.push(row_idx.len() + c.iter().position(|&r| r == j).expect("diagonal"));
            row_idx.extend(c);
            col_ptr.push(row_idx.len());
        }
        Pattern {
            n,
            col_ptr,
            row_idx,
            diag,
        }
    }

    /// Stored entries of the (simplicial) Cholesky factor of `pattern` in the order `fwd`.
    fn fill(pattern: &Pattern, fwd: &[usize]) -> usize {
        use faer::sparse::linalg::cholesky::*;
        let mut inv = vec![0; fwd.len()];
        for (i, &f) in fwd.iter().enumerate() {
            inv[f] = i;
        }
        factorize_symbolic_cholesky(
            pattern.symbolic(),
            faer::Side::Upper,
            SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(fwd, &inv, pattern.n)),
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold:
                    faer::sparse::linalg::SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .expect("analysis")
        .len_val()
    }

    #[test]
    fn postorder_keeps_the_fill_and_makes_subtrees_consecutive() {
        let p = small_pattern();
        for fwd in [
            (0..10).collect::<Vec<_>>(),
            vec![9, 0, 8, 1, 7, 2, 6, 3, 5, 4],
            vec![4, 6, 1, 9, 0, 3, 8, 2, 7, 5],
        ] {
            let post = postorder(&p, &fwd);
            let mut sorted = post.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..10).collect::<Vec<_>>(), "a permutation");
            assert_eq!(fill(&p, &post), fill(&p, &fwd), "same fill");
            // Postordered: renumbering again changes nothing.
            assert_eq!(postorder(&p, &post), post);
        }
    }

    /// The pattern of a network of `side × side` vertices in a grid (three coordinates each,
    /// coupled within a vertex and with its grid neighbours).
    #[cfg(feature = "metis")]
    fn grid_pattern(side: usize) -> Pattern {
        let mut entries = Vec::new();
        let mut couple = |a: usize, b: usize| {
            for k in 0..3 {
                for l in 0..3 {
                    let (i, j) = (3 * a + k, 3 * b + l);
                    if i < j {
                        entries.push((i, j));
                    }
                }
            }
        };
        for r in 0..side {
            for c in 0..side {
                let v = r * side + c;
                couple(v, v);
                if c + 1 < side {
                    couple(v, v + 1);
                }
                if r + 1 < side {
                    couple(v, v + side);
                }
            }
        }
        pattern_of(3 * side * side, &entries)
    }

    #[cfg(feature = "metis")]
    #[test]
    fn orderings_made_at_once_on_several_threads_are_the_ordering_made_alone() {
        let pattern = grid_pattern(60);
        let alone = nested_dissection(&pattern).expect("METIS orders a grid");
        let at_once: Vec<Vec<usize>> = std::thread::scope(|s| {
            let runs: Vec<_> = (0..4)
                .map(|_| {
                    s.spawn(|| {
                        (0..4)
                            .map(|_| nested_dissection(&pattern).expect("ordered"))
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            runs.into_iter()
                .flat_map(|r| r.join().expect("no panic"))
                .collect()
        });
        for (k, o) in at_once.iter().enumerate() {
            assert!(o == &alone, "ordering {k} made beside others differs");
        }
    }
}

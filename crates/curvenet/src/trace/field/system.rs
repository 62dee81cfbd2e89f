//! The smoothness energy's links between faces and the sparse solve for the free faces'
//! values, `K_FF z_F = −K_FC z_C` over the reals (two unknowns per face), followed by the
//! normalisation steps of [`FieldOptions::iterations`].

use super::spd::SpdSolver;
use super::{FieldOptions, angle_in};
use crate::geom::Vec3;
use crate::trace::TraceError;
use crate::trace::topology::MeshTopology;
use faer::sparse::Triplet;
use std::collections::VecDeque;

/// An interior manifold edge between usable faces `f` and `g`: its weight `w_E` and the
/// transport `r_fg = c + i s`.
pub(super) struct Link {
    f: usize,
    g: usize,
    w: f64,
    c: f64,
    s: f64,
}

/// The links of every interior manifold edge between non-degenerate faces.
pub(super) fn links(topo: &MeshTopology, frames: &[(Vec3, Vec3)], n: f64) -> Vec<Link> {
    let mut links = Vec::new();
    for e in 0..topo.edge_count() {
        let fs = topo.edge_faces(e);
        if fs.len() != 2 || topo.is_degenerate(fs[0]) || topo.is_degenerate(fs[1]) {
            continue;
        }
        let (f, g) = (fs[0], fs[1]);
        let [a, b] = topo.edge(e);
        let ev = topo.position(b) - topo.position(a);
        let rot = n * (angle_in(frames[f], ev) - angle_in(frames[g], ev));
        let w = ev.norm2() / (topo.face_area(f) + topo.face_area(g));
        links.push(Link {
            f,
            g,
            w,
            c: rot.cos(),
            s: rot.sin(),
        });
    }
    links
}

/// Faces connected through links to a constrained face (the others stay zero: singular).
pub(super) fn reached(nf: usize, links: &[Link], constrained: &[bool]) -> Vec<bool> {
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); nf];
    for l in links {
        adj[l.f].push(l.g);
        adj[l.g].push(l.f);
    }
    let mut reached = constrained.to_vec();
    let mut queue: VecDeque<usize> = (0..nf).filter(|&f| constrained[f]).collect();
    while let Some(f) = queue.pop_front() {
        for &g in &adj[f] {
            if !reached[g] {
                reached[g] = true;
                queue.push_back(g);
            }
        }
    }
    reached
}

/// Solves for the values of the free reached faces, writing them into `values`.
pub(super) fn solve_free(
    topo: &MeshTopology,
    options: &FieldOptions,
    links: &[Link],
    constrained: &[bool],
    reached: &[bool],
    values: &mut [(f64, f64)],
) -> Result<(), TraceError> {
    let nf = topo.face_count();
    let mut index = vec![usize::MAX; nf];
    let mut free = 0usize;
    for f in 0..nf {
        if reached[f] && !constrained[f] {
            index[f] = free;
            free += 1;
        }
    }
    if free == 0 {
        return Ok(());
    }
    let (triplets, rhs) = assemble(links, &index, constrained, values, free);
    let mut solution = SpdSolver::new(2 * free, &triplets)?.solve(rhs.clone())?;
    if options.iterations > 0 && options.penalty > 0.0 {
        solution = normalise(topo, options, &index, free, &triplets, &rhs, solution)?;
    }
    for f in 0..nf {
        if index[f] != usize::MAX {
            values[f] = (solution[2 * index[f]], solution[2 * index[f] + 1]);
        }
    }
    Ok(())
}

/// The upper triangle of `K_FF` (duplicates summed) and `−K_FC z_C`.
fn assemble(
    links: &[Link],
    index: &[usize],
    constrained: &[bool],
    values: &[(f64, f64)],
    free: usize,
) -> (Vec<Triplet<usize, usize, f64>>, Vec<f64>) {
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(6 * links.len());
    let mut rhs = vec![0.0f64; 2 * free];
    // Block of −w r (rows f, columns g): [[−wc, ws], [−ws, −wc]].
    for l in links {
        let blk = [[-l.w * l.c, l.w * l.s], [-l.w * l.s, -l.w * l.c]];
        let (fi, gi) = (index[l.f], index[l.g]);
        if fi != usize::MAX {
            triplets.push(Triplet::new(2 * fi, 2 * fi, l.w));
            triplets.push(Triplet::new(2 * fi + 1, 2 * fi + 1, l.w));
        }
        if gi != usize::MAX {
            triplets.push(Triplet::new(2 * gi, 2 * gi, l.w));
            triplets.push(Triplet::new(2 * gi + 1, 2 * gi + 1, l.w));
        }
        match (fi != usize::MAX, gi != usize::MAX) {
            (true, true) => {
                for r in 0..2 {
                    for c in 0..2 {
                        // Upper triangle: row index below column index.
                        if fi < gi {
                            triplets.push(Triplet::new(2 * fi + r, 2 * gi + c, blk[r][c]));
                        } else {
                            triplets.push(Triplet::new(2 * gi + c, 2 * fi + r, blk[r][c]));
                        }
                    }
                }
            }
            (true, false) if constrained[l.g] => {
                let (x, y) = values[l.g];
                rhs[2 * fi] -= blk[0][0] * x + blk[0][1] * y;
                rhs[2 * fi + 1] -= blk[1][0] * x + blk[1][1] * y;
            }
            (false, true) if constrained[l.f] => {
                // Block of −w r̄ (rows g, columns f) is the transpose.
                let (x, y) = values[l.f];
                rhs[2 * gi] -= blk[0][0] * x + blk[1][0] * y;
                rhs[2 * gi + 1] -= blk[0][1] * x + blk[1][1] * y;
            }
            _ => {}
        }
    }
    (triplets, rhs)
}

/// Ginzburg–Landau-like normalisation: repeatedly pulls the field towards unit length,
/// `(K + λM) z = b + λ M z/|z|`, with M the face areas over their mean.
fn normalise(
    topo: &MeshTopology,
    options: &FieldOptions,
    index: &[usize],
    free: usize,
    triplets: &[Triplet<usize, usize, f64>],
    rhs: &[f64],
    mut solution: Vec<f64>,
) -> Result<Vec<f64>, TraceError> {
    let nf = topo.face_count();
    let mean_area = (0..nf)
        .filter(|&f| index[f] != usize::MAX)
        .map(|f| topo.face_area(f))
        .sum::<f64>()
        / free as f64;
    let mass: Vec<f64> = (0..nf)
        .filter(|&f| index[f] != usize::MAX)
        .map(|f| options.penalty * topo.face_area(f) / mean_area)
        .collect();
    let mut shifted = triplets.to_vec();
    for (i, &m) in mass.iter().enumerate() {
        shifted.push(Triplet::new(2 * i, 2 * i, m));
        shifted.push(Triplet::new(2 * i + 1, 2 * i + 1, m));
    }
    let flow = SpdSolver::new(2 * free, &shifted)?;
    for _ in 0..options.iterations {
        let mut b = rhs.to_vec();
        for (i, &m) in mass.iter().enumerate() {
            let (x, y) = (solution[2 * i], solution[2 * i + 1]);
            let r = x.hypot(y);
            if r > 0.0 {
                b[2 * i] += m * x / r;
                b[2 * i + 1] += m * y / r;
            }
        }
        solution = flow.solve(b)?;
    }
    Ok(solution)
}

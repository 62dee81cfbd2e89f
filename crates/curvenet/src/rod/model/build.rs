//! Building an [`EnergyModel`]: the terms of every rod, the Hessian's block pattern over the
//! vertices they couple, and each term's block positions in it.

use super::twist::{self, ClampTwistTerm, FrameTerm, TwistDof};
use super::{AnchorTerm, BendTerm, ClampTerm, EnergyModel, RodTerms, STRAIGHT, StretchTerm};
use crate::geom::Vec3;
use crate::material::RestShape;
use crate::rod::terms::{self, RestBend};
use crate::rod::{ClampRule, Material, ModelRules, Network, Rod, RodStiffness};
use crate::sparse::Pattern;

impl EnergyModel {
    /// Collects the terms of `network` with `material` (every rod alike, straight at rest)
    /// and builds the Hessian pattern.
    pub fn new(network: &Network, material: &Material) -> Self {
        let rods = vec![RodStiffness::from(material); network.rods.len()];
        Self::with_rods(network, &rods, material.anchor_weight)
    }

    /// Collects the terms of `network`, rod `i` with the stiffnesses and rest shape
    /// `rods[i]`, anchors of weight `anchor_weight`, and builds the Hessian pattern (the
    /// paper's rules).
    pub fn with_rods(network: &Network, rods: &[RodStiffness], anchor_weight: f64) -> Self {
        Self::with_rules(network, rods, anchor_weight, ModelRules::PAPER)
    }

    /// [`Self::with_rods`] under `rules` (the paper's or the physical mode's).
    pub fn with_rules(
        network: &Network,
        rods: &[RodStiffness],
        anchor_weight: f64,
        rules: ModelRules,
    ) -> Self {
        assert_eq!(rods.len(), network.rods.len(), "one stiffness per rod");
        let n_vertices = network.positions.len();
        let terms = collect_terms(network, rods, rules);
        let curve_vertices = network
            .rods
            .iter()
            .map(|r| {
                let mut v = r.vertices.clone();
                v.sort_unstable();
                v.dedup();
                v
            })
            .collect();
        let lower = vertex_adjacency(n_vertices, &terms.stretch, &terms.bend, &terms.frame);
        let pos = |a: u32, b: u32| -> u32 {
            let (i, j) = if a <= b { (a, b) } else { (b, a) };
            lower[j as usize]
                .binary_search(&i)
                .expect("pattern holds every term") as u32
        };
        let stretch_pos = terms
            .stretch
            .iter()
            .map(|t| block_positions(&t.v, pos))
            .collect();
        let bend_pos = terms
            .bend
            .iter()
            .map(|t| block_positions(&t.v, pos))
            .collect();
        let clamp_pos = terms
            .clamp
            .iter()
            .map(|t| block_positions(&t.v, pos))
            .collect();
        let frame_coords: Vec<[usize; 11]> = terms.frame.iter().map(|t| t.coordinates()).collect();
        let clamp_coords: Vec<[usize; 7]> =
            terms.twist_clamp.iter().map(|t| t.coordinates()).collect();
        let pattern = twist::with_twist_columns(
            block_pattern(&lower),
            n_vertices,
            terms.twists.len(),
            frame_coords
                .iter()
                .map(|c| &c[..])
                .chain(clamp_coords.iter().map(|c| &c[..])),
        );
        let frame_slots = frame_coords
            .iter()
            .map(|c| twist::term_slots(&pattern, c))
            .collect();
        let twist_clamp_slots = clamp_coords
            .iter()
            .map(|c| twist::term_slots(&pattern, c))
            .collect();
        let mu = anchor_weight;
        // A loose vertex's diagonal: the stiffest scale in the model, far above the low
        // spectrum that stability is about. (ks / rest is monotone in rest, so with one ks
        // this is exactly ks over the shortest edge.)
        let stiffest = terms
            .stretch
            .iter()
            .map(|t| t.ks / t.rest)
            .fold(f64::NEG_INFINITY, f64::max);
        let loose_diagonal = if stiffest.is_finite() {
            stiffest.max(2.0 * mu)
        } else {
            1.0
        };
        EnergyModel {
            n_vertices,
            mu,
            stretch: terms.stretch,
            bend: terms.bend,
            bend_rest: terms.bend_rest,
            clamp: terms.clamp,
            frame: terms.frame,
            frame_slots,
            twist_clamp: terms.twist_clamp,
            twist_clamp_slots,
            twists: terms.twists,
            anchor: terms.anchor,
            rods: terms.rods,
            vertex_curves: network.vertex_curves(),
            curve_vertices,
            pattern,
            stretch_pos,
            bend_pos,
            clamp_pos,
            loose_diagonal,
            load: Vec::new(),
            pressure: None,
        }
    }
}

/// Every term of a network, grouped by rod.
struct Terms {
    stretch: Vec<StretchTerm>,
    bend: Vec<BendTerm>,
    bend_rest: Vec<RestBend>,
    clamp: Vec<ClampTerm>,
    frame: Vec<FrameTerm>,
    twist_clamp: Vec<ClampTwistTerm>,
    twists: Vec<TwistDof>,
    anchor: Vec<AnchorTerm>,
    rods: Vec<RodTerms>,
}

/// The stretching term of every edge, the bending term of every interior vertex (every vertex
/// of a closed rod), the clamps ([`ClampRule::EndTangent`]) and the anchor of every supported
/// vertex, rod after rod, rod `i` with the stiffnesses and rest shape `stiffness[i]`.
fn collect_terms(network: &Network, stiffness: &[RodStiffness], rules: ModelRules) -> Terms {
    let p = &network.positions;
    let mut t = Terms {
        stretch: Vec::new(),
        bend: Vec::new(),
        bend_rest: Vec::new(),
        clamp: Vec::new(),
        frame: Vec::new(),
        twist_clamp: Vec::new(),
        twists: Vec::new(),
        anchor: Vec::new(),
        rods: Vec::with_capacity(network.rods.len()),
    };
    for (c, (rod, k)) in network.rods.iter().zip(stiffness).enumerate() {
        let (s0, b0, a0) = (t.stretch.len(), t.bend.len(), t.anchor.len());
        let (c0, f0, tc0) = (t.clamp.len(), t.frame.len(), t.twist_clamp.len());
        // A pre-bent rod drawn straight bends as a straight one: its twist decouples.
        let framed = rules.twist
            && k.rest == RestShape::PreBent
            && !rod.is_drawn_straight(&network.positions);
        if framed {
            twist::collect_rod(
                c,
                network,
                k,
                &mut t.frame,
                &mut t.twist_clamp,
                &mut t.twists,
            );
        }
        let m = rod.vertices.len();
        let ne = rod.edge_count();
        for j in 0..ne {
            let (a, b) = rod.edge(j);
            t.stretch.push(StretchTerm {
                v: [a, b],
                rest: rod.rest_lengths[j],
                ks: k.ks,
                e: p[b as usize] - p[a as usize],
            });
        }
        let centers = if framed {
            0..0
        } else if rod.closed {
            0..m
        } else {
            1..m.saturating_sub(1)
        };
        for i in centers {
            let (prev, next) = ((i + ne - 1) % ne, i % ne);
            let v0 = rod.vertices[(i + m - 1) % m];
            let v1 = rod.vertices[i];
            let v2 = rod.vertices[(i + 1) % m];
            let x1 = p[v1 as usize];
            let (r0, r1) = (rod.rest_lengths[prev], rod.rest_lengths[next]);
            let (a, b) = (p[v0 as usize] - x1, p[v2 as usize] - x1);
            let rest = match k.rest {
                RestShape::Straight => STRAIGHT,
                RestShape::PreBent => {
                    t.bend_rest.push(terms::rest_bend(-a, b, r0, r1));
                    (t.bend_rest.len() - 1) as u32
                }
            };
            t.bend.push(BendTerm {
                v: [v0, v1, v2],
                rest,
                r0,
                r1,
                kb: k.kb,
                a,
                b,
            });
        }
        let released = match rules.clamp {
            ClampRule::TwoVertices => Vec::new(),
            ClampRule::EndTangent => clamp_ends(rod, k, p, &mut t.clamp),
        };
        for &v in &rod.anchors {
            if !released.contains(&v) {
                t.anchor.push(AnchorTerm {
                    v,
                    offset: Vec3::ZERO,
                    axes: rod.anchor_weights(v),
                });
            }
        }
        t.rods.push(RodTerms {
            kb: k.kb,
            stretch: s0..t.stretch.len(),
            bend: b0..t.bend.len(),
            clamp: c0..t.clamp.len(),
            frame: f0..t.frame.len(),
            twist_clamp: tc0..t.twist_clamp.len(),
            anchor: a0..t.anchor.len(),
        });
    }
    t
}

/// The physical mode's clamps of `rod` (stiffness `k`, drawn positions `p`), pushed onto
/// `clamps`: an end is clamped when its vertex and the next are anchored (the paper's clamp,
/// as the network records it); its clamp term holds the end's tangent, and the next vertex's
/// anchor is released (returned), unless it is the other end's vertex.
fn clamp_ends(rod: &Rod, k: &RodStiffness, p: &[Vec3], clamps: &mut Vec<ClampTerm>) -> Vec<u32> {
    let m = rod.vertices.len();
    let ends = [rod.vertices[0], rod.vertices[m.saturating_sub(1)]];
    let mut released = Vec::new();
    for at_start in [true, false] {
        // The end, its neighbour and the next one along the rod, and the end edge.
        let idx = |k: usize| if at_start { k } else { m - 1 - k };
        if !rod.is_clamped_at(at_start) {
            continue;
        }
        let (v0, v1) = (rod.vertices[idx(0)], rod.vertices[idx(1)]);
        let edge = if at_start { 0 } else { m - 2 };
        let rest = rod.rest_lengths[edge];
        let x2 = (m > 2).then(|| p[rod.vertices[idx(2)] as usize]);
        let (x0, x1) = (p[v0 as usize], p[v1 as usize]);
        clamps.push(ClampTerm {
            v: [v0, v1],
            rest,
            kb: k.kb,
            e: x1 - x0,
            shape: terms::clamp_rest(x0, x1, x2, rest, k.rest == RestShape::PreBent),
        });
        if !ends.contains(&v1) {
            released.push(v1);
        }
    }
    released
}

/// For each vertex `j`, the vertices `i ≤ j` sharing a term with it (itself included),
/// ascending.
fn vertex_adjacency(
    n_vertices: usize,
    stretch: &[StretchTerm],
    bend: &[BendTerm],
    frame: &[FrameTerm],
) -> Vec<Vec<u32>> {
    let mut lower: Vec<Vec<u32>> = (0..n_vertices as u32).map(|j| vec![j]).collect();
    let mut link = |a: u32, b: u32| {
        let (i, j) = if a <= b { (a, b) } else { (b, a) };
        lower[j as usize].push(i);
    };
    for t in stretch {
        link(t.v[0], t.v[1]);
    }
    for v in bend.iter().map(|t| t.v).chain(frame.iter().map(|t| t.v)) {
        link(v[0], v[1]);
        link(v[0], v[2]);
        link(v[1], v[2]);
    }
    for l in &mut lower {
        l.sort_unstable();
        l.dedup();
    }
    lower
}

/// The upper-triangle pattern over `3·V` coordinates with a dense 3×3 block for every pair of
/// adjacent vertices (`lower`: [`vertex_adjacency`]).
fn block_pattern(lower: &[Vec<u32>]) -> Pattern {
    let n = 3 * lower.len();
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::new();
    let mut diag = Vec::with_capacity(n);
    col_ptr.push(0);
    for (j, nbrs) in lower.iter().enumerate() {
        for b in 0..3 {
            for &i in nbrs {
                let i = i as usize;
                let rows = if i == j { 0..b + 1 } else { 0..3 };
                for a in rows {
                    if i == j && a == b {
                        diag.push(row_idx.len());
                    }
                    row_idx.push(3 * i + a);
                }
            }
            col_ptr.push(row_idx.len());
        }
    }
    Pattern {
        n,
        col_ptr,
        row_idx,
        diag,
    }
}

/// `pos[p][q]`: the position of the 3×3 block of local vertices `(p, q)` of a term over
/// vertices `v` among the blocks of the larger global vertex's column.
fn block_positions<const K: usize>(v: &[u32; K], pos: impl Fn(u32, u32) -> u32) -> [[u32; K]; K] {
    let mut p = [[0u32; K]; K];
    for (x, row) in p.iter_mut().enumerate() {
        for (y, slot) in row.iter_mut().enumerate() {
            *slot = pos(v[x], v[y]);
        }
    }
    p
}

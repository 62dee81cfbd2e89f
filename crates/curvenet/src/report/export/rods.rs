//! What the exports and the viewer say about one rod: arc lengths, end supports, the joints
//! along it.

use crate::geom::Vec3;
use crate::network::{Network, Rod};

/// Arc length (rest lengths) of every vertex position along `rod`, from its first vertex.
pub fn arc_lengths(rod: &Rod) -> Vec<f64> {
    let mut s = Vec::with_capacity(rod.vertices.len());
    let mut acc = 0.0;
    for i in 0..rod.vertices.len() {
        s.push(acc);
        if let Some(l) = rod.rest_lengths.get(i) {
            acc += l;
        }
    }
    s
}

/// Support of one end of an open rod ([`Rod::end_support`]): `clamped`, `pinned`, a support
/// given per end by its name (`free`, or e.g. `yz fixed; rotation held`), `none` for an end
/// nothing holds without per-end supports (and for closed rods).
pub fn end_support(rod: &Rod, at_start: bool) -> String {
    match rod.end_support(at_start) {
        Some(s) if s.is_support() || rod.ends.is_some() => s.name(),
        _ => "none".into(),
    }
}

/// A rod's supports as one word: the end supports if both ends agree, else `start/end`.
pub fn rod_supports(rod: &Rod) -> String {
    let (a, b) = (end_support(rod, true), end_support(rod, false));
    if a == b { a } else { format!("{a}/{b}") }
}

/// A joint along a rod in the kept structure.
#[derive(Clone, Debug, PartialEq)]
pub struct RodJoint {
    /// Index along the rod.
    pub index: usize,
    /// Arc length (rest) from the rod's first vertex.
    pub s: f64,
    /// The network vertex.
    pub vertex: u32,
    /// Rest position.
    pub position: Vec3,
    /// The other kept rods meeting there (the rod's own id when it crosses itself).
    pub meets: Vec<usize>,
}

/// The joints along `curve` with the rods of `kept` met there, in order along the rod.
pub fn rod_joints(net: &Network, curve: usize, kept: &[usize]) -> Vec<RodJoint> {
    let rod = &net.rods[curve];
    let s = arc_lengths(rod);
    let mut at_vertex: std::collections::HashMap<u32, Vec<usize>> = Default::default();
    for &c in kept {
        for &v in &net.rods[c].vertices {
            let list = at_vertex.entry(v).or_default();
            list.push(c);
        }
    }
    let mut out = Vec::new();
    for (i, &v) in rod.vertices.iter().enumerate() {
        let Some(list) = at_vertex.get(&v) else {
            continue;
        };
        let mut meets: Vec<usize> = list.iter().copied().filter(|&c| c != curve).collect();
        // A self-crossing: the rod passes the vertex twice.
        if list.iter().filter(|&&c| c == curve).count() > 1 {
            meets.push(curve);
        }
        meets.sort_unstable();
        meets.dedup();
        if meets.is_empty() {
            continue;
        }
        out.push(RodJoint {
            index: i,
            s: s[i],
            vertex: v,
            position: net.positions[v as usize],
            meets,
        });
    }
    out
}

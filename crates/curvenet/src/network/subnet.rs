//! The network made of some of a network's curves.

use super::{Joint, Network, Rod};

impl Network {
    /// The network of `curves` alone: their rods with the same rest lengths and anchors, and
    /// only the vertices they use, renumbered in order of first use: the structure of `curves`
    /// (`docs/model.md`, *Stability*) with the loose vertices deleted. Returns the network and, for each of its
    /// vertices, the vertex it was in `self`.
    pub fn sub_network(&self, curves: &[usize]) -> (Network, Vec<u32>) {
        let mut new_index = vec![u32::MAX; self.positions.len()];
        let mut old_of = Vec::new();
        let mut map = |v: u32, old_of: &mut Vec<u32>| -> u32 {
            let slot = &mut new_index[v as usize];
            if *slot == u32::MAX {
                *slot = old_of.len() as u32;
                old_of.push(v);
            }
            *slot
        };
        let rods: Vec<Rod> = curves
            .iter()
            .map(|&c| {
                let r = &self.rods[c];
                Rod {
                    vertices: r.vertices.iter().map(|&v| map(v, &mut old_of)).collect(),
                    closed: r.closed,
                    rest_lengths: r.rest_lengths.clone(),
                    anchors: r.anchors.iter().map(|&v| map(v, &mut old_of)).collect(),
                    ends: r.ends,
                    frames: r.frames,
                }
            })
            .collect();
        let positions = old_of.iter().map(|&v| self.positions[v as usize]).collect();
        let mut joints = Vec::new();
        for j in &self.joints {
            let v = new_index[j.vertex as usize];
            if v == u32::MAX {
                continue;
            }
            let kept: Vec<u32> = curves
                .iter()
                .enumerate()
                .filter(|(_, c)| j.curves.contains(&(**c as u32)))
                .map(|(i, _)| i as u32)
                .collect();
            let passes = rods
                .iter()
                .map(|r| r.vertices.iter().filter(|&&x| x == v).count())
                .sum::<usize>();
            if passes >= 2 {
                joints.push(Joint {
                    vertex: v,
                    curves: kept,
                });
            }
        }
        joints.sort_by_key(|j| j.vertex);
        (
            Network {
                positions,
                rods,
                joints,
                supports: self.supports,
            },
            old_of,
        )
    }
}

/// The connected parts of `curves` (ids below `curve_count`), where each item of `links` lists
/// curves that share a vertex: each part ascending, the parts in order of their smallest
/// curve. Curves outside `curves` never connect anything.
pub fn curve_components<L, I>(curve_count: usize, curves: &[usize], links: L) -> Vec<Vec<usize>>
where
    L: IntoIterator<Item = I>,
    I: IntoIterator<Item = usize>,
{
    let mut on = vec![false; curve_count];
    for &c in curves {
        on[c] = true;
    }
    let mut uf = super::crossings::UnionFind::new(curve_count);
    for link in links {
        let mut first = None;
        for c in link.into_iter().filter(|&c| on[c]) {
            match first {
                None => first = Some(c),
                Some(f) => uf.union(f, c),
            }
        }
    }
    let mut sorted: Vec<usize> = curves.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let mut parts: Vec<Vec<usize>> = Vec::new();
    let mut root_part = std::collections::HashMap::new();
    for c in sorted {
        let i = *root_part.entry(uf.find(c)).or_insert_with(|| {
            parts.push(Vec::new());
            parts.len() - 1
        });
        parts[i].push(c);
    }
    parts
}

#[cfg(test)]
mod tests {
    use crate::geom::Vec3;
    use crate::io::Polyline;
    use crate::network::{BuildParams, build_network};

    fn line(a: Vec3, b: Vec3) -> Polyline {
        Polyline::straight(a, b, 20)
    }

    #[test]
    fn keeps_the_chosen_rods_and_their_vertices_only() {
        let curves = vec![
            line(Vec3::new(-10.0, 0.0, 0.0), Vec3::new(10.0, 0.0, 0.0)),
            line(Vec3::new(0.0, -10.0, 0.0), Vec3::new(0.0, 10.0, 0.0)),
            line(Vec3::new(5.0, -10.0, 1.0), Vec3::new(5.0, 10.0, 1.0)),
        ];
        let (net, _) = build_network(
            &curves,
            &BuildParams {
                edge_length: 2.0,
                ..Default::default()
            },
        )
        .expect("builds");
        let (sub, old) = net.sub_network(&[0, 2]);
        assert_eq!(sub.rods.len(), 2);
        assert_eq!(
            sub.vertex_count(),
            net.rods[0].vertices.len() + net.rods[2].vertices.len()
        );
        assert!(sub.joints.is_empty(), "curves 0 and 2 do not meet");
        for (i, r) in sub.rods.iter().enumerate() {
            let orig = &net.rods[[0, 2][i]];
            assert_eq!(r.rest_lengths, orig.rest_lengths);
            for (&a, &b) in r.vertices.iter().zip(&orig.vertices) {
                assert_eq!(old[a as usize], b);
                assert_eq!(sub.positions[a as usize], net.positions[b as usize]);
            }
        }
        let (both, _) = net.sub_network(&[0, 1]);
        assert_eq!(both.joints.len(), 1);
        assert_eq!(both.joints[0].curves, vec![0, 1]);
    }
}

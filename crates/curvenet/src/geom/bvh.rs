//! A bounding-volume hierarchy over axis-aligned boxes: the one spatial index of the crate.
//!
//! Crossing detection asks it for the segment boxes that overlap a box
//! ([`Bvh::overlapping`]), the overlap check for the boxes that hold a point
//! ([`Bvh::containing`]), and the point-to-mesh distance for the nearest item by a distance of
//! its own ([`Bvh::nearest`]).
//!
//! The tree splits at the median of the box centres along their widest axis, down to
//! [`Bvh::LEAF`] items per leaf. Ties are broken by item index and children are visited left
//! first, so the tree and the order in which queries report items depend only on the boxes.
//! Written here rather than taken from a library: the three queries fit in a page, and the
//! crossings they feed must come out in the same order on every machine.

use super::{Aabb, Vec3};

/// A bounding-volume hierarchy over boxes; item `i` is the `i`-th box given to [`Bvh::new`].
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    boxes: Vec<Aabb>,
    nodes: Vec<Node>,
    items: Vec<u32>,
}

/// A node: a leaf holds `items[start..end]`, an inner node two children.
#[derive(Clone, Copy, Debug)]
struct Node {
    bbox: Aabb,
    start: u32,
    end: u32,
    children: Option<(u32, u32)>,
}

impl Bvh {
    /// Items per leaf.
    pub const LEAF: usize = 4;

    /// Builds the tree over `boxes`.
    pub fn new(boxes: Vec<Aabb>) -> Bvh {
        let mut items: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * boxes.len() / Self::LEAF + 1);
        if !boxes.is_empty() {
            build_node(&boxes, &mut items, 0, boxes.len(), &mut nodes);
        }
        Bvh {
            boxes,
            nodes,
            items,
        }
    }

    /// The box of item `i`.
    pub fn item_box(&self, i: u32) -> &Aabb {
        &self.boxes[i as usize]
    }

    /// Calls `f` for every item whose box overlaps `q` (boundaries included).
    pub fn overlapping(&self, q: &Aabb, f: impl FnMut(u32)) {
        self.visit(|b| b.overlaps(q), f);
    }

    /// Calls `f` for every item whose box holds `p` (boundary included).
    pub fn containing(&self, p: Vec3, f: impl FnMut(u32)) {
        self.visit(|b| b.contains(p), f);
    }

    /// Depth-first walk of the nodes whose box passes `keep`, left child first; `f` gets the
    /// leaves' items whose own box passes it.
    fn visit(&self, keep: impl Fn(&Aabb) -> bool, mut f: impl FnMut(u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if !keep(&node.bbox) {
                continue;
            }
            match node.children {
                Some((l, r)) => {
                    stack.push(r);
                    stack.push(l);
                }
                None => {
                    for &i in &self.items[node.start as usize..node.end as usize] {
                        if keep(&self.boxes[i as usize]) {
                            f(i);
                        }
                    }
                }
            }
        }
    }

    /// The item nearest to `p` by `dist` (a distance at least the distance from `p` to the
    /// item's box), among items closer than `limit`; the search ends at the first item found
    /// closer than `stop_below`. `None` when no item is closer than `limit`.
    pub fn nearest(
        &self,
        p: Vec3,
        limit: f64,
        stop_below: f64,
        mut dist: impl FnMut(u32) -> f64,
    ) -> Option<(f64, u32)> {
        let mut best: Option<(f64, u32)> = None;
        let mut bound = limit;
        let mut stack: Vec<(f64, u32)> = Vec::with_capacity(64);
        if let Some(root) = self.nodes.first() {
            stack.push((root.bbox.distance_to(p), 0));
        }
        while let Some((d, n)) = stack.pop() {
            // `!(d < bound)` also drops NaN distances.
            if !(d < bound) {
                continue;
            }
            let node = &self.nodes[n as usize];
            match node.children {
                Some((l, r)) => {
                    let dl = self.nodes[l as usize].bbox.distance_to(p);
                    let dr = self.nodes[r as usize].bbox.distance_to(p);
                    // The nearer child is searched first (pushed last).
                    if dl <= dr {
                        stack.push((dr, r));
                        stack.push((dl, l));
                    } else {
                        stack.push((dl, l));
                        stack.push((dr, r));
                    }
                }
                None => {
                    for &i in &self.items[node.start as usize..node.end as usize] {
                        let di = dist(i);
                        if di < bound {
                            bound = di;
                            best = Some((di, i));
                            if di < stop_below {
                                return best;
                            }
                        }
                    }
                }
            }
        }
        best
    }
}

/// Builds the node over `items[start..end]` and its subtree; returns its index.
fn build_node(
    boxes: &[Aabb],
    items: &mut [u32],
    start: usize,
    end: usize,
    nodes: &mut Vec<Node>,
) -> u32 {
    let mut bbox = Aabb::EMPTY;
    let mut centres = Aabb::EMPTY;
    for &i in &items[start..end] {
        let b = boxes[i as usize];
        bbox.add(b.min);
        bbox.add(b.max);
        centres.add((b.min + b.max) * 0.5);
    }
    let id = nodes.len() as u32;
    nodes.push(Node {
        bbox,
        start: start as u32,
        end: end as u32,
        children: None,
    });
    if end - start <= Bvh::LEAF {
        return id;
    }
    let ext = centres.extent();
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = (start + end) / 2;
    let key = |i: u32| {
        let b = boxes[i as usize];
        b.min[axis] + b.max[axis]
    };
    items[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
        key(a).total_cmp(&key(b)).then(a.cmp(&b))
    });
    let left = build_node(boxes, items, start, mid, nodes);
    let right = build_node(boxes, items, mid, end, nodes);
    nodes[id as usize].children = Some((left, right));
    id
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(x: f64, y: f64, z: f64) -> Aabb {
        Aabb::of_points(&[Vec3::new(x, y, z), Vec3::new(x + 1.0, y + 1.0, z + 1.0)])
    }

    #[test]
    fn queries_match_brute_force() {
        let mut rng = crate::rng::SplitMix64::new(3);
        let boxes: Vec<Aabb> = (0..300)
            .map(|_| {
                unit_box(
                    20.0 * rng.next_f64(),
                    20.0 * rng.next_f64(),
                    5.0 * rng.next_f64(),
                )
            })
            .collect();
        let bvh = Bvh::new(boxes.clone());
        for _ in 0..100 {
            let p = Vec3::new(
                22.0 * rng.next_f64() - 1.0,
                22.0 * rng.next_f64() - 1.0,
                7.0 * rng.next_f64() - 1.0,
            );
            let mut got = Vec::new();
            bvh.containing(p, |i| got.push(i as usize));
            got.sort_unstable();
            let want: Vec<usize> = (0..boxes.len()).filter(|&i| boxes[i].contains(p)).collect();
            assert_eq!(got, want);
            let q = unit_box(p.x, p.y, p.z);
            let mut got = Vec::new();
            bvh.overlapping(&q, |i| got.push(i as usize));
            got.sort_unstable();
            let want: Vec<usize> = (0..boxes.len())
                .filter(|&i| boxes[i].overlaps(&q))
                .collect();
            assert_eq!(got, want);
            let centre = |i: u32| {
                let b = boxes[i as usize];
                p.dist((b.min + b.max) * 0.5)
            };
            let (d, _) = bvh.nearest(p, f64::INFINITY, -1.0, centre).unwrap();
            let brute = (0..boxes.len() as u32)
                .map(centre)
                .fold(f64::INFINITY, f64::min);
            assert_eq!(d, brute);
        }
        assert!(
            Bvh::new(Vec::new())
                .nearest(Vec3::ZERO, 1.0, 0.0, |_| 0.0)
                .is_none()
        );
    }
}

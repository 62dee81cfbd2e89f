//! The faces' orientation, tangent frames and boundary constraints of the direction field.

use super::angle_in;
use crate::geom::Vec3;
use crate::trace::TraceError;
use crate::trace::topology::MeshTopology;
use std::collections::VecDeque;

/// Orientation signs (+1 / −1) making adjacent faces agree, by breadth-first search.
pub(super) fn orient(topo: &MeshTopology) -> Result<Vec<i8>, TraceError> {
    let nf = topo.face_count();
    let mut sign = vec![0i8; nf];
    let faces = topo.faces();
    // +1 when edge e runs a → b (sorted order) in face f.
    let runs_forward = |f: usize, e: usize| -> bool {
        let [a, b] = topo.edge(e);
        let t = faces[f];
        (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b)
    };
    let mut queue = VecDeque::new();
    for seed in 0..nf {
        if sign[seed] != 0 {
            continue;
        }
        sign[seed] = 1;
        queue.push_back(seed);
        while let Some(f) = queue.pop_front() {
            for e in topo.face_edges(f) {
                let fs = topo.edge_faces(e);
                if fs.len() != 2 {
                    continue;
                }
                let g = if fs[0] == f { fs[1] } else { fs[0] };
                let same = runs_forward(f, e) != runs_forward(g, e);
                let want = if same { sign[f] } else { -sign[f] };
                if sign[g] == 0 {
                    sign[g] = want;
                    queue.push_back(g);
                } else if sign[g] != want {
                    return Err(TraceError::NonOrientable);
                }
            }
        }
    }
    Ok(sign)
}

/// Per-face tangent frame `(x_f, y_f)`: `x_f` along the face's first edge, `y_f = n_f × x_f`
/// with the normal oriented by `sign`.
pub(super) fn face_frames(topo: &MeshTopology, sign: &[i8]) -> Vec<(Vec3, Vec3)> {
    (0..topo.face_count())
        .map(|f| {
            let [a, b, _] = topo.face_points(f);
            let x = (b - a).normalized();
            let nrm = topo.face_normal(f) * f64::from(sign[f]);
            (x, nrm.cross(x))
        })
        .collect()
}

/// The boundary constraints: per face its value `z_f` (unit where constrained, zero elsewhere)
/// and whether it is constrained. A face's value is the normalised sum of `e^{iN ang}` over its
/// boundary edges; a corner whose edges disagree for this `N` (a sum near zero) stays free.
pub(super) fn boundary_values(
    topo: &MeshTopology,
    frames: &[(Vec3, Vec3)],
    n: f64,
) -> (Vec<(f64, f64)>, Vec<bool>) {
    let nf = topo.face_count();
    let mut values = vec![(0.0f64, 0.0f64); nf];
    let mut constrained = vec![false; nf];
    for f in 0..nf {
        if topo.is_degenerate(f) {
            continue;
        }
        let (mut re, mut im, mut count) = (0.0, 0.0, 0usize);
        for e in topo.face_edges(f) {
            if topo.is_boundary_edge(e) {
                let [a, b] = topo.edge(e);
                let ang = n * angle_in(frames[f], topo.position(b) - topo.position(a));
                re += ang.cos();
                im += ang.sin();
                count += 1;
            }
        }
        let m = f64::hypot(re, im);
        if count > 0 && m > 1e-6 * count as f64 {
            values[f] = (re / m, im / m);
            constrained[f] = true;
        }
    }
    (values, constrained)
}

//! Every paper example's curves lie on its mesh as loaded: the mesh is what the pictures, the
//! viewer and the surface constraints (`--max-gap`) use, so a mesh at another scale than its
//! curves draws them as a speck and measures gaps against the wrong surface.
//!
//! For the examples whose curves come from files (roof, kagome, tower, shell, arched shell),
//! the farthest curve point from its nearest mesh vertex must stay within 5 % of the mesh's
//! bounding-box diagonal. (Brute force over the vertices: a few seconds in release.)

use curvenet::geom::Vec3;
use curvenet::rod::Supports;

/// Largest distance from a curve point to its nearest mesh vertex, and the mesh's diagonal.
fn farthest_point(name: &str) -> (f64, f64) {
    let ex = curvenet::paper::load_embedded(name, Supports::Clamped).expect("example loads");
    let verts = &ex.mesh.vertices;
    let mut lo = verts[0];
    let mut hi = verts[0];
    for v in verts {
        lo = Vec3::new(lo.x.min(v.x), lo.y.min(v.y), lo.z.min(v.z));
        hi = Vec3::new(hi.x.max(v.x), hi.y.max(v.y), hi.z.max(v.z));
    }
    let farthest = ex
        .curves
        .iter()
        .flat_map(|c| c.points.iter())
        .map(|&p| {
            verts
                .iter()
                .map(|&v| p.dist(v))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    (farthest, lo.dist(hi))
}

#[test]
fn every_examples_curves_lie_on_its_mesh() {
    for name in ["roof", "kagome", "tower", "shell", "arcshell"] {
        let (farthest, diagonal) = farthest_point(name);
        println!(
            "{name}: farthest curve point {farthest:.3} from the mesh, diagonal {diagonal:.3} \
             ({:.2} %)",
            100.0 * farthest / diagonal
        );
        assert!(
            farthest <= 0.05 * diagonal,
            "{name}: a curve point lies {farthest:.3} from the nearest mesh vertex, more than 5 % \
             of the mesh's diagonal {diagonal:.3}: the mesh and the curves are not at one scale"
        );
    }
}

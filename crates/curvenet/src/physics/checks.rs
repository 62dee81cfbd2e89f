//! Warnings of the physical mode: curves that would break when bent into shape, units that
//! imply absurd dimensions, and deflections larger than the structure.

use super::stress::Stresses;
use crate::geom::Aabb;
use crate::material::Physical;
use crate::rod::Network;
use crate::words::{Message, Opt, given, message};

/// A network this many metres across or more (kilometres) is probably drawn in another unit:
/// no rod structure of any material spans a kilometre.
pub const MAX_EXTENT_M: f64 = 1_000.0;
/// A network less than this many metres across is probably drawn in another unit.
pub const MIN_EXTENT_M: f64 = 0.01;
/// Rods thicker than this share of the median curve length are columns, not rods.
pub const MAX_DIAMETER_SHARE: f64 = 0.1;
/// Curves longer than this many outer radii are as slack as cables.
pub const MAX_SLENDERNESS: f64 = 1e4;

/// One warning per curve whose assembly stress exceeds its strength, worst first: "curve 12
/// would break when bent: 480 MPa > 355 MPa (steel) near joint 57 at (x, y, z)".
pub fn overstress_warnings(
    stresses: &Stresses,
    network: &Network,
    physical: &Physical,
) -> Vec<String> {
    stresses
        .overstressed()
        .into_iter()
        .map(|c| {
            let p = network.positions[c.vertex];
            let material = &physical.curve_material(c.curve).name;
            format!(
                "curve {} would break when bent: {:.0} MPa > {:.0} MPa ({material}, utilisation \
                 {:.2}) {} at ({:.1}, {:.1}, {:.1})",
                c.curve,
                c.combined_mpa,
                c.strength_mpa,
                c.utilisation(),
                near_joint(network, c.curve, c.vertex),
                p.x,
                p.y,
                p.z
            )
        })
        .collect()
}

/// "at joint J" when `vertex` is a joint, else "near joint J" (the nearest joint on the
/// curve), or "" when the curve has none.
pub fn near_joint(network: &Network, curve: usize, vertex: usize) -> String {
    let at = network.positions[vertex];
    let nearest = network
        .joints
        .iter()
        .enumerate()
        .filter(|(_, j)| j.curves.contains(&(curve as u32)))
        .map(|(k, j)| {
            (
                k,
                j.vertex as usize,
                at.dist(network.positions[j.vertex as usize]),
            )
        })
        .min_by(|a, b| a.2.total_cmp(&b.2));
    match nearest {
        Some((k, v, _)) if v == vertex => format!("at joint {k}"),
        Some((k, _, _)) => format!("near joint {k}"),
        None => String::new(),
    }
}

/// Warnings when the scene's unit and the sections imply absurd dimensions, saying what they
/// imply.
pub fn units_warnings(network: &Network, physical: &Physical) -> Vec<Message> {
    let mut out = Vec::new();
    if network.positions.is_empty() {
        return out;
    }
    let u = physical.units;
    let m = u.metres();
    let extent = Aabb::of_points(&network.positions).largest_extent() * m;
    if !(MIN_EXTENT_M..MAX_EXTENT_M).contains(&extent) {
        out.push(message![
            "with ",
            given(Opt::Units, u),
            format!(
                " the network is {} across: are the coordinates in {u}?",
                metres(extent)
            )
        ]);
    }
    let mut lengths = network.rest_lengths();
    lengths.sort_by(f64::total_cmp);
    let median = lengths.get(lengths.len() / 2).copied().unwrap_or(0.0);
    let r = (0..network.rods.len())
        .map(|c| physical.curve_section(c).outer_radius())
        .fold(0.0, f64::max);
    if 2.0 * r > MAX_DIAMETER_SHARE * median {
        out.push(message![
            "with ",
            given(Opt::Units, u),
            format!(
                " the rods are up to {} thick on curves {} long (median): check ",
                metres(2.0 * r * m),
                metres(median * m)
            ),
            Opt::Units,
            " and the section"
        ]);
    }
    let r_min = (0..network.rods.len())
        .map(|c| physical.curve_section(c).outer_radius())
        .fold(f64::INFINITY, f64::min);
    if median > MAX_SLENDERNESS * r_min {
        out.push(message![
            "with ",
            given(Opt::Units, u),
            format!(
                " rods {} thick span curves {} long (median): as slack as cables, check ",
                metres(2.0 * r_min * m),
                metres(median * m)
            ),
            Opt::Units,
            " and the section"
        ]);
    }
    out
}

/// Warnings when a deflection of the structure `active` is larger than the structure itself
/// (a linear deflection that size means nothing: the units, the material or the section are
/// wrong): `self_weight` and `load` are its largest self-weight and worst-case-load
/// deflections, scene units.
pub fn deflection_warnings(
    network: &Network,
    physical: &Physical,
    active: &crate::rod::ActiveSet,
    self_weight: Option<f64>,
    load: Option<f64>,
) -> Vec<Message> {
    let held = super::loads::held_vertices(network, active);
    let points: Vec<_> = network
        .positions
        .iter()
        .zip(&held)
        .filter(|(_, h)| **h)
        .map(|(p, _)| *p)
        .collect();
    if points.is_empty() {
        return Vec::new();
    }
    let u = physical.units;
    let m = u.metres();
    let size = Aabb::of_points(&points).largest_extent();
    let load_words = format!(
        "the worst-case load of {} kN/m",
        crate::fmt::significant(physical.load_n_per_m / 1e3, 4)
    );
    [
        ("its own weight".to_string(), self_weight),
        (load_words, load),
    ]
    .into_iter()
    .filter_map(|(what, d)| Some((what, d?)))
    .filter(|(_, d)| *d > size)
    .map(|(what, d)| {
        message![
            format!(
                "under {what} the structure deflects by {}, more than its size ({} \
                     across): a linear deflection this large means nothing; check ",
                metres(d * m),
                metres(size * m)
            ),
            Opt::Units,
            ", the material and the section"
        ]
    })
    .collect()
}

/// A length in metres, written in a readable unit.
fn metres(x: f64) -> String {
    if x >= 1000.0 {
        format!("{:.1} km", x / 1000.0)
    } else if x >= 1.0 {
        format!("{x:.2} m")
    } else if x >= 0.01 {
        format!("{:.1} cm", x * 100.0)
    } else {
        format!("{:.2} mm", x * 1000.0)
    }
}

//! The points table and the fabrication table (CSV) of a recorded network.

use super::num;
use super::rods::{arc_lengths, end_support, rod_joints};
use crate::network::Network;
use crate::report::ReportError;
use crate::run_folder::{RunFolder, Which, positions_at};
use std::fmt::Write as _;

/// CSV of every network vertex of the curves of iteration `k` (any [`Which`]): arc length
/// along the curve, rest and equilibrium positions.
pub fn points_csv(run: &RunFolder, which: impl Into<Which>) -> Result<String, ReportError> {
    let which = which.into();
    let rec = run.network_of(which)?;
    let net = &run.network;
    let eq = positions_at(net, Some(&run.displacement_of(which)?));
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# curvenet export: {}, {} curves; one row per network vertex along each curve (scene units)",
        rec.what,
        rec.curves.len()
    );
    if let Some(w) = &rec.unstable {
        let _ = writeln!(out, "# {}", super::unstable_header(w));
    }
    let _ = writeln!(
        out,
        "# s = arc length at rest from the curve's first vertex; a closed curve does not repeat its first point"
    );
    out.push_str("curve,point,vertex,closed,s,x_rest,y_rest,z_rest,x_eq,y_eq,z_eq\n");
    for &c in &rec.curves {
        let rod = &net.rods[c];
        let s = arc_lengths(rod);
        for (i, &v) in rod.vertices.iter().enumerate() {
            let p = net.positions[v as usize];
            let q = eq[v as usize];
            let _ = writeln!(
                out,
                "{c},{i},{v},{},{},{},{},{},{},{},{}",
                rod.closed,
                num(s[i]),
                num(p.x),
                num(p.y),
                num(p.z),
                num(q.x),
                num(q.y),
                num(q.z)
            );
        }
    }
    Ok(out)
}

/// The fabrication table of iteration `k` (any [`Which`]): one row per kept rod.
pub fn fabrication_csv(run: &RunFolder, which: impl Into<Which>) -> Result<String, ReportError> {
    let rec = run.network_of(which.into())?;
    let what = format!("{} of {}", rec.what, run.dir.display());
    let table = fabrication_table(&run.network, &what, &rec.curves, rec.length);
    Ok(super::with_unstable_header(table, rec.unstable.as_deref()))
}

/// The fabrication table of the structure `curves` of `net`, of total rest length `length`
/// (`what` names it in the header): one row per kept rod.
pub fn fabrication_table(net: &Network, what: &str, curves: &[usize], length: f64) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# curvenet fabrication table: {what}, {} rods, total rest length {}; scene units",
        curves.len(),
        num(length)
    );
    out.push_str(
        "# cut_length = rest_length: rods are straight at rest and their rest length is the sum of the rest\n\
         # edge lengths; no allowance is added for joints, overlaps or end fixings\n\
         # joints: 's:a+b' entries separated by ';' = arc length s along the rod (from its first vertex, at rest)\n\
         # and the ids of the kept rods that meet there (the rod's own id where it crosses itself)\n\
         # start_support/end_support: pinned (end vertex anchored), clamped (end vertex and its neighbour), none\n",
    );
    out.push_str(
        "curve,rest_length,cut_length,closed,vertices,joint_count,joints,start_support,end_support\n",
    );
    for &c in curves {
        let rod = &net.rods[c];
        let joints = rod_joints(net, c, curves);
        let cells: Vec<String> = joints
            .iter()
            .map(|j| {
                let ids: Vec<String> = j.meets.iter().map(usize::to_string).collect();
                format!("{}:{}", num(j.s), ids.join("+"))
            })
            .collect();
        let l = rod.rest_length();
        let _ = writeln!(
            out,
            "{c},{},{},{},{},{},{},{},{}",
            num(l),
            num(l),
            rod.closed,
            rod.vertices.len(),
            joints.len(),
            cells.join(";"),
            end_support(rod, true),
            end_support(rod, false)
        );
    }
    out
}

//! Reading a run's output folder and exporting its networks for other tools.
//!
//! [`RunFolder::open`] reads and checks a folder written by
//! [`crate::simplify::result::OutputWriter`] (`result.json`, `network.json`, the optional
//! `mesh.obj`, and per iteration `states/KKKK.bin` and the mode file): every index, length and
//! number is checked, so a missing or corrupt folder gives a clear error naming the file, never
//! a panic.
//!
//! Exports of one recorded iteration `K` (the final one by default):
//!
//! | function | file | content |
//! |---|---|---|
//! | [`curves_obj`] | `curves_KKKK.obj`, `curves_KKKK_rest.obj` | OBJ polylines (`v` + `l`, closed curves repeat their first index; `o curve N` names), at equilibrium or at rest |
//! | [`curves_json`] | `curves_KKKK.json`, `curves_KKKK_equilibrium.json` | curvenet-curves JSON ([`crate::io::read_curves`] reads it back) at rest or at equilibrium; each curve's label is `id=N; rest_length=L; closed=B; supports=S` |
//! | [`points_csv`] | `points_KKKK.csv` | one row per network vertex of every kept curve: arc length, rest and equilibrium positions |
//! | [`fabrication_csv`] | `fabrication_KKKK.csv` | one row per kept rod: rest (= cut) length, the joints along it (arc length and the rods met there), end supports |
//! | [`network_json`] | `network_KKKK.json` | the kept structure at network resolution (`"format": "curvenet-network"`): rest positions, rods with vertex lists, rest lengths and anchors, supports, material, equilibrium displacements; [`load_network`] reads it back |
//!
//! The network file holds everything the energy depends on, bit for bit (numbers in Rust's
//! shortest round-trip form), so analysing the loaded network gives the `λ` of the exported
//! structure again with no resampling. Its vertices are the kept rods' vertices in their
//! original order, renumbered from 0; its rods are the kept curves in ascending id order,
//! renumbered from 0, each with its original `id`.

use crate::geom::Vec3;
use crate::io::{self, Origin, Polyline, TriMesh};
use crate::network::{Joint, Network, Rod};
use crate::rod::{Material, Supports};
use crate::simplify::greedy::IterationRecord;
use crate::simplify::result::{ResultFile, read_f64_file};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A run's output folder, read and checked.
#[derive(Clone, Debug)]
pub struct RunFolder {
    /// The folder.
    pub dir: PathBuf,
    /// `result.json`.
    pub result: ResultFile,
    /// `network.json`.
    pub network: Network,
    /// `mesh.obj`, when the folder has a readable one.
    pub mesh: Option<TriMesh>,
    /// Problems that did not stop the reading (an unreadable `mesh.obj`, …).
    pub warnings: Vec<String>,
}

impl RunFolder {
    /// Reads `dir/result.json`, `dir/network.json` and (if present) `dir/mesh.obj`, and checks
    /// that they agree. Side files of the iterations are read on demand.
    pub fn open(dir: &Path) -> Result<RunFolder, String> {
        if !dir.is_dir() {
            return Err(format!(
                "{}: not a folder (expected the output folder of a run, holding result.json)",
                dir.display()
            ));
        }
        let result = ResultFile::read(dir)?;
        let net_path = dir.join("network.json");
        let text = std::fs::read_to_string(&net_path)
            .map_err(|e| format!("{}: {e}", net_path.display()))?;
        let network: Network = serde_json::from_str(&text)
            .map_err(|e| format!("{}:{}: {e}", net_path.display(), e.line()))?;
        check_network(&network).map_err(|e| format!("{}: {e}", net_path.display()))?;
        let n = network.rods.len();
        if result.iterations.is_empty() {
            return Err(format!(
                "{}: no iteration recorded yet",
                dir.join("result.json").display()
            ));
        }
        for (k, it) in result.iterations.iter().enumerate() {
            if it.curves.is_empty() {
                return Err(format!(
                    "{}: iteration {k} has no curves",
                    dir.join("result.json").display()
                ));
            }
            if let Some(&c) = it.curves.iter().chain(it.removed.iter()).find(|&&c| c >= n) {
                return Err(format!(
                    "{}: iteration {k} names curve {c}, but network.json has {n} curves",
                    dir.join("result.json").display()
                ));
            }
        }
        let mut warnings = Vec::new();
        let mesh_path = dir.join("mesh.obj");
        let mesh = if mesh_path.is_file() {
            match io::read_mesh(&mesh_path) {
                Ok(m) if !m.mesh.faces.is_empty() => Some(m.mesh),
                Ok(_) => {
                    warnings.push(format!("{}: no faces; ignored", mesh_path.display()));
                    None
                }
                Err(e) => {
                    warnings.push(format!("{e}; the surface is left out"));
                    None
                }
            }
        } else {
            None
        };
        if !result.complete {
            warnings.push(format!(
                "{}: the run is not complete; showing the {} iteration(s) recorded",
                dir.display(),
                result.iterations.len()
            ));
        }
        Ok(RunFolder {
            dir: dir.to_path_buf(),
            result,
            network,
            mesh,
            warnings,
        })
    }

    /// Number of recorded iterations.
    pub fn iteration_count(&self) -> usize {
        self.result.iterations.len()
    }

    /// Index of the last recorded iteration (the final network of a complete run).
    pub fn last_index(&self) -> usize {
        self.result.iterations.len() - 1
    }

    /// The iteration the run's pictures and viewer show first: the answer's when it is one of
    /// the greedy's iterations, else the last.
    pub fn shown_index(&self) -> usize {
        self.result
            .answer
            .as_ref()
            .and_then(|a| a.iteration)
            .filter(|&k| k < self.iteration_count())
            .unwrap_or_else(|| self.last_index())
    }

    /// The record of iteration `k`.
    pub fn record(&self, k: usize) -> Result<&IterationRecord, String> {
        self.result.iterations.get(k).ok_or_else(|| {
            format!(
                "{}: no iteration {k} (the run recorded iterations 0 to {})",
                self.dir.display(),
                self.last_index()
            )
        })
    }

    fn vector_file(&self, rel: &str) -> Result<Vec<f64>, String> {
        let path = self.dir.join(rel);
        let v = read_f64_file(&path)?;
        if v.len() != self.network.dofs() {
            return Err(format!(
                "{}: {} values, expected 3·V = {} for network.json",
                path.display(),
                v.len(),
                self.network.dofs()
            ));
        }
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(format!("{}: value {i} is not finite", path.display()));
        }
        Ok(v)
    }

    /// Equilibrium displacements of iteration `k` (`states/KKKK.bin`, 3·V values).
    pub fn displacement(&self, k: usize) -> Result<Vec<f64>, String> {
        self.record(k)?;
        self.vector_file(&format!("states/{k:04}.bin"))
    }

    /// Worst-case mode of iteration `k` (its `mode_file`, 3·V values).
    pub fn mode(&self, k: usize) -> Result<Vec<f64>, String> {
        let rec = self.record(k)?;
        self.vector_file(&rec.mode_file)
    }
}

/// Checks that a network is consistent: finite positions, indices in range, one positive
/// rest length per edge, enough vertices per rod. Everything the energy model indexes.
pub fn check_network(net: &Network) -> Result<(), String> {
    let nv = net.positions.len();
    if nv == 0 || net.rods.is_empty() {
        return Err("the network has no vertices or no rods".into());
    }
    if let Some(i) = net.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("position of vertex {i} is not finite"));
    }
    for (c, rod) in net.rods.iter().enumerate() {
        let m = rod.vertices.len();
        let min = if rod.closed { 3 } else { 2 };
        if m < min {
            return Err(format!("rod {c} has {m} vertices (at least {min} needed)"));
        }
        let edges = if rod.closed { m } else { m - 1 };
        if rod.rest_lengths.len() != edges {
            return Err(format!(
                "rod {c} has {} rest lengths for {edges} edges",
                rod.rest_lengths.len()
            ));
        }
        if let Some(j) = rod
            .rest_lengths
            .iter()
            .position(|&l| !(l.is_finite() && l > 0.0))
        {
            return Err(format!(
                "rod {c}: rest length of edge {j} is {} (must be positive and finite)",
                rod.rest_lengths[j]
            ));
        }
        if let Some(&v) = rod
            .vertices
            .iter()
            .chain(&rod.anchors)
            .find(|&&v| v as usize >= nv)
        {
            return Err(format!(
                "rod {c} names vertex {v}, but the network has {nv} vertices"
            ));
        }
        if let Some(&v) = rod.anchors.iter().find(|v| !rod.vertices.contains(v)) {
            return Err(format!("rod {c} anchors vertex {v}, which is not on it"));
        }
        if let Some(j) = (0..edges).find(|&j| {
            let (a, b) = rod.edge(j);
            a == b
        }) {
            return Err(format!("rod {c}: edge {j} joins a vertex to itself"));
        }
    }
    for (j, joint) in net.joints.iter().enumerate() {
        if joint.vertex as usize >= nv {
            return Err(format!("joint {j} names vertex {}", joint.vertex));
        }
        if let Some(&c) = joint.curves.iter().find(|&&c| c as usize >= net.rods.len()) {
            return Err(format!("joint {j} names curve {c}"));
        }
    }
    Ok(())
}

/// Positions of all vertices at displacements `u` (`None`: the rest state).
pub fn positions_at(net: &Network, u: Option<&[f64]>) -> Vec<Vec3> {
    net.positions
        .iter()
        .enumerate()
        .map(|(i, &p)| match u {
            Some(u) => p + Vec3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]),
            None => p,
        })
        .collect()
}

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

/// Support of one end of an open rod: `clamped` when the end vertex and its neighbour are
/// anchored, `pinned` when only the end vertex is, `none` otherwise (and for closed rods).
pub fn end_support(rod: &Rod, at_start: bool) -> &'static str {
    let m = rod.vertices.len();
    if rod.closed || m < 2 {
        return "none";
    }
    let (end, next) = if at_start {
        (rod.vertices[0], rod.vertices[1])
    } else {
        (rod.vertices[m - 1], rod.vertices[m - 2])
    };
    match (rod.anchors.contains(&end), rod.anchors.contains(&next)) {
        (true, true) => "clamped",
        (true, false) => "pinned",
        _ => "none",
    }
}

/// A rod's supports as one word: the end supports if both ends agree, else `start/end`.
pub fn rod_supports(rod: &Rod) -> String {
    let (a, b) = (end_support(rod, true), end_support(rod, false));
    if a == b {
        a.to_string()
    } else {
        format!("{a}/{b}")
    }
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

fn num(v: f64) -> String {
    format!("{v:?}")
}

fn label(net: &Network, c: usize) -> String {
    let rod = &net.rods[c];
    format!(
        "id={c}; rest_length={}; closed={}; supports={}",
        num(rod.rest_length()),
        rod.closed,
        rod_supports(rod)
    )
}

fn polylines(net: &Network, curves: &[usize], pos: &[Vec3], labels: bool) -> Vec<Polyline> {
    curves
        .iter()
        .map(|&c| {
            let rod = &net.rods[c];
            Polyline {
                points: rod.vertices.iter().map(|&v| pos[v as usize]).collect(),
                closed: rod.closed,
                origin: Origin::new("network", 0),
                label: Some(if labels {
                    label(net, c)
                } else {
                    format!("curve {c}")
                }),
            }
        })
        .collect()
}

/// OBJ polylines of the curves of iteration `k`: at equilibrium (`rest = false`) or in the
/// designed rest state. One `o curve N` object and one `l` record per curve.
pub fn curves_obj(run: &RunFolder, k: usize, rest: bool) -> Result<String, String> {
    let rec = run.record(k)?;
    let pos = if rest {
        positions_at(&run.network, None)
    } else {
        positions_at(&run.network, Some(&run.displacement(k)?))
    };
    let mut out = format!(
        "# curvenet export: iteration {k}, {} curves, {} state, scene units\n",
        rec.curves.len(),
        if rest {
            "rest (designed)"
        } else {
            "equilibrium"
        }
    );
    out.push_str(&io::curves_to_obj(&polylines(
        &run.network,
        &rec.curves,
        &pos,
        false,
    )));
    Ok(out)
}

/// curvenet-curves JSON of the curves of iteration `k`, at rest or at equilibrium; labels
/// carry `id`, `rest_length`, `closed` and `supports`.
pub fn curves_json(run: &RunFolder, k: usize, rest: bool) -> Result<String, String> {
    let rec = run.record(k)?;
    let pos = if rest {
        positions_at(&run.network, None)
    } else {
        positions_at(&run.network, Some(&run.displacement(k)?))
    };
    Ok(io::curves_to_json(&polylines(
        &run.network,
        &rec.curves,
        &pos,
        true,
    )))
}

/// Parses a label written by [`curves_json`] into `(id, rest_length, closed, supports)`.
pub fn parse_curve_label(label: &str) -> Option<(usize, f64, bool, String)> {
    let mut id = None;
    let mut len = None;
    let mut closed = None;
    let mut supports = None;
    for part in label.split(';') {
        let (k, v) = part.trim().split_once('=')?;
        match k {
            "id" => id = v.parse().ok(),
            "rest_length" => len = v.parse().ok(),
            "closed" => closed = v.parse().ok(),
            "supports" => supports = Some(v.to_string()),
            _ => {}
        }
    }
    Some((id?, len?, closed?, supports?))
}

/// CSV of every network vertex of the curves of iteration `k`: arc length along the curve,
/// rest and equilibrium positions.
pub fn points_csv(run: &RunFolder, k: usize) -> Result<String, String> {
    let rec = run.record(k)?;
    let net = &run.network;
    let eq = positions_at(net, Some(&run.displacement(k)?));
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# curvenet export: iteration {k}, {} curves; one row per network vertex along each curve (scene units)",
        rec.curves.len()
    );
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

/// The fabrication table of iteration `k`: one row per kept rod.
pub fn fabrication_csv(run: &RunFolder, k: usize) -> Result<String, String> {
    let rec = run.record(k)?;
    Ok(fabrication_table(
        run,
        &format!("iteration {k}"),
        &rec.curves,
        rec.length,
    ))
}

/// The fabrication table of the run's answer (the network to build), `None` when the run
/// has none.
pub fn answer_fabrication_csv(run: &RunFolder) -> Option<String> {
    let a = run.result.answer.as_ref()?;
    let what = match a.iteration {
        Some(k) => format!("the answer (iteration {k})"),
        None => format!("the answer (the {}'s network)", a.source.replace('_', " ")),
    };
    Some(fabrication_table(run, &what, &a.curves, a.length))
}

/// The fabrication table of the network `curves` of `run` (`what` names it in the header).
fn fabrication_table(run: &RunFolder, what: &str, curves: &[usize], length: f64) -> String {
    let net = &run.network;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# curvenet fabrication table: {what} of {}, {} rods, total rest length {}; scene units",
        run.dir.display(),
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

/// The value of `format` in a network file.
pub const NETWORK_FORMAT: &str = "curvenet-network";
/// The network file version this module reads and writes.
pub const NETWORK_VERSION: u32 = 1;

/// One rod of a network file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NetworkFileRod {
    /// The curve's id in the run the file was exported from.
    pub id: usize,
    /// Closed rod (an edge joins the last vertex to the first).
    pub closed: bool,
    /// Vertex indices along the rod (into `positions`).
    pub vertices: Vec<u32>,
    /// Rest length of each edge.
    pub rest_lengths: Vec<f64>,
    /// Anchored vertices (their targets are their rest positions).
    pub anchors: Vec<u32>,
}

/// A network file (`"format": "curvenet-network"`): a structure at network resolution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NetworkFile {
    /// Always [`NETWORK_FORMAT`].
    pub format: String,
    /// Always [`NETWORK_VERSION`].
    pub version: u32,
    /// Where the structure came from (free text).
    #[serde(default)]
    pub source: Option<String>,
    /// The iteration of the run it was exported from.
    #[serde(default)]
    pub iteration: Option<usize>,
    /// `λ_eq` recorded by the run for this structure.
    #[serde(default)]
    pub lambda: Option<f64>,
    /// The supports the anchors were chosen with.
    pub supports: Supports,
    /// Material constants of the run.
    pub material: Material,
    /// Rest positions.
    pub positions: Vec<Vec3>,
    /// Rods, rod `i` being curve `i` of the loaded network.
    pub rods: Vec<NetworkFileRod>,
    /// Equilibrium displacements, one `[dx, dy, dz]` per vertex, when known.
    #[serde(default)]
    pub equilibrium: Option<Vec<[f64; 3]>>,
}

impl NetworkFile {
    /// The structure of curves `curves` of `net`, renumbered compactly (vertices in their
    /// original order, rods in ascending id order).
    pub fn from_structure(
        net: &Network,
        curves: &[usize],
        material: Material,
        displacement: Option<&[f64]>,
    ) -> NetworkFile {
        let mut curves = curves.to_vec();
        curves.sort_unstable();
        curves.dedup();
        let mut used = vec![false; net.positions.len()];
        for &c in &curves {
            for &v in &net.rods[c].vertices {
                used[v as usize] = true;
            }
        }
        let mut new_index = vec![u32::MAX; used.len()];
        let mut positions = Vec::new();
        let mut equilibrium = displacement.map(|_| Vec::new());
        for (v, &u) in used.iter().enumerate() {
            if u {
                new_index[v] = positions.len() as u32;
                positions.push(net.positions[v]);
                if let (Some(eq), Some(d)) = (equilibrium.as_mut(), displacement) {
                    eq.push([d[3 * v], d[3 * v + 1], d[3 * v + 2]]);
                }
            }
        }
        let rods = curves
            .iter()
            .map(|&c| {
                let r = &net.rods[c];
                NetworkFileRod {
                    id: c,
                    closed: r.closed,
                    vertices: r.vertices.iter().map(|&v| new_index[v as usize]).collect(),
                    rest_lengths: r.rest_lengths.clone(),
                    anchors: r.anchors.iter().map(|&v| new_index[v as usize]).collect(),
                }
            })
            .collect();
        NetworkFile {
            format: NETWORK_FORMAT.into(),
            version: NETWORK_VERSION,
            source: None,
            iteration: None,
            lambda: None,
            supports: net.supports,
            material,
            positions,
            rods,
            equilibrium,
        }
    }

    /// The file as JSON text: one position or rod per line.
    pub fn to_json(&self) -> String {
        let mut out = String::from("{\n");
        let _ = writeln!(out, "  \"format\": {},", j(&self.format));
        let _ = writeln!(out, "  \"version\": {},", self.version);
        if let Some(s) = &self.source {
            let _ = writeln!(out, "  \"source\": {},", j(s));
        }
        if let Some(k) = self.iteration {
            let _ = writeln!(out, "  \"iteration\": {k},");
        }
        if let Some(l) = self.lambda {
            let _ = writeln!(out, "  \"lambda\": {},", j(&l));
        }
        let _ = writeln!(out, "  \"supports\": {},", j(&self.supports));
        let _ = writeln!(out, "  \"material\": {},", j(&self.material));
        out.push_str("  \"positions\": [");
        for (i, p) in self.positions.iter().enumerate() {
            out.push_str(if i == 0 { "\n    " } else { ",\n    " });
            out.push_str(&j(p));
        }
        out.push_str("\n  ],\n  \"rods\": [");
        for (i, r) in self.rods.iter().enumerate() {
            out.push_str(if i == 0 { "\n    " } else { ",\n    " });
            out.push_str(&j(r));
        }
        out.push_str("\n  ]");
        if let Some(eq) = &self.equilibrium {
            out.push_str(",\n  \"equilibrium\": [");
            for (i, c) in eq.iter().enumerate() {
                out.push_str(if i == 0 { "\n    " } else { ",\n    " });
                out.push_str(&j(c));
            }
            out.push_str("\n  ]");
        }
        out.push_str("\n}\n");
        out
    }

    /// The equilibrium displacements as a flat vector `[dx0, dy0, dz0, dx1, …]` (3 per vertex).
    pub fn equilibrium_vector(&self) -> Option<Vec<f64>> {
        self.equilibrium
            .as_ref()
            .map(|e| e.iter().flatten().copied().collect())
    }

    /// Checks the file and builds the network it describes (joints recomputed from the shared
    /// vertices).
    pub fn to_network(&self) -> Result<Network, String> {
        if self.format != NETWORK_FORMAT {
            return Err(format!(
                "\"format\" is \"{}\", expected \"{NETWORK_FORMAT}\"",
                self.format
            ));
        }
        if self.version != NETWORK_VERSION {
            return Err(format!(
                "unsupported version {} (this reader supports {NETWORK_VERSION})",
                self.version
            ));
        }
        self.material.validate()?;
        let rods: Vec<Rod> = self
            .rods
            .iter()
            .map(|r| Rod {
                vertices: r.vertices.clone(),
                closed: r.closed,
                rest_lengths: r.rest_lengths.clone(),
                anchors: r.anchors.clone(),
            })
            .collect();
        let mut net = Network {
            positions: self.positions.clone(),
            rods,
            joints: Vec::new(),
            supports: self.supports,
        };
        check_network(&net)?;
        if let Some(eq) = &self.equilibrium {
            if eq.len() != net.positions.len() {
                return Err(format!(
                    "\"equilibrium\" has {} displacements for {} vertices",
                    eq.len(),
                    net.positions.len()
                ));
            }
            if eq.iter().flatten().any(|x| !x.is_finite()) {
                return Err("\"equilibrium\" holds a non-finite value".into());
            }
        }
        net.joints = joints_of(&net);
        Ok(net)
    }
}

/// Joints of a network: every vertex that two rods share or that one rod passes twice.
pub fn joints_of(net: &Network) -> Vec<Joint> {
    let mut passes = vec![0usize; net.positions.len()];
    for rod in &net.rods {
        for &v in &rod.vertices {
            passes[v as usize] += 1;
        }
    }
    net.vertex_curves()
        .into_iter()
        .enumerate()
        .filter(|&(v, _)| passes[v] > 1)
        .map(|(v, curves)| Joint {
            vertex: v as u32,
            curves,
        })
        .collect()
}

/// The kept structure of iteration `k` as a network file (with its equilibrium).
pub fn network_file(run: &RunFolder, k: usize) -> Result<NetworkFile, String> {
    let rec = run.record(k)?;
    let u = run.displacement(k)?;
    let mut f = NetworkFile::from_structure(
        &run.network,
        &rec.curves,
        run.result.setup.stability.material,
        Some(&u),
    );
    f.source = Some(format!("{} iteration {k}", run.dir.display()));
    f.iteration = Some(k);
    f.lambda = Some(rec.lambda);
    Ok(f)
}

/// [`network_file`] as JSON text.
pub fn network_json(run: &RunFolder, k: usize) -> Result<String, String> {
    Ok(network_file(run, k)?.to_json())
}

/// Reads a network file and checks it. See [`load_network`] for the network alone.
pub fn read_network_file(path: &Path) -> Result<NetworkFile, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse_network_file(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Parses and checks the text of a network file.
pub fn parse_network_file(text: &str) -> Result<NetworkFile, String> {
    let f: NetworkFile =
        serde_json::from_str(text).map_err(|e| format!("line {}: {e}", e.line()))?;
    f.to_network()?;
    Ok(f)
}

/// Loads the network of a network file written by [`network_json`] (no resampling: the
/// vertices, rest lengths and anchors are used as they are). Rod `i` of the result is the
/// file's rod `i`; the file's material is in [`read_network_file`]'s result.
pub fn load_network(path: &Path) -> Result<Network, String> {
    let f = read_network_file(path)?;
    f.to_network()
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Formats of `curvenet export`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// OBJ polylines at equilibrium and at rest.
    Obj,
    /// curvenet-curves JSON at rest and at equilibrium.
    Json,
    /// The points table and the fabrication table.
    Csv,
    /// The network file.
    Network,
    /// All of the above.
    All,
}

impl std::str::FromStr for ExportFormat {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Ok(match s {
            "obj" => ExportFormat::Obj,
            "json" => ExportFormat::Json,
            "csv" => ExportFormat::Csv,
            "network" => ExportFormat::Network,
            "all" => ExportFormat::All,
            _ => {
                return Err(format!(
                    "unknown export format '{s}' (expected obj, json, csv, network or all)"
                ));
            }
        })
    }
}

/// The files of `format` for iteration `k`: `(file name, content)` pairs, each format's main
/// file first (OBJ at equilibrium, JSON at rest, the fabrication table, the network file).
pub fn export_files(
    run: &RunFolder,
    k: usize,
    format: ExportFormat,
) -> Result<Vec<(String, String)>, String> {
    use ExportFormat::*;
    run.record(k)?;
    let mut out = Vec::new();
    if matches!(format, Obj | All) {
        out.push((format!("curves_{k:04}.obj"), curves_obj(run, k, false)?));
        out.push((format!("curves_{k:04}_rest.obj"), curves_obj(run, k, true)?));
    }
    if matches!(format, Json | All) {
        out.push((format!("curves_{k:04}.json"), curves_json(run, k, true)?));
        out.push((
            format!("curves_{k:04}_equilibrium.json"),
            curves_json(run, k, false)?,
        ));
    }
    if matches!(format, Csv | All) {
        out.push((format!("fabrication_{k:04}.csv"), fabrication_csv(run, k)?));
        out.push((format!("points_{k:04}.csv"), points_csv(run, k)?));
    }
    if matches!(format, Network | All) {
        out.push((format!("network_{k:04}.json"), network_json(run, k)?));
    }
    Ok(out)
}

/// Writes the files of `format` for iteration `k` into the folder `out` (created if needed);
/// returns their paths.
pub fn write_exports(
    run: &RunFolder,
    k: usize,
    format: ExportFormat,
    out: &Path,
) -> Result<Vec<PathBuf>, String> {
    let files = export_files(run, k, format)?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut paths = Vec::new();
    for (name, text) in files {
        let p = out.join(name);
        io::write_atomic(&p, text.as_bytes()).map_err(|e| format!("{}: {e}", p.display()))?;
        paths.push(p);
    }
    Ok(paths)
}

/// Compact JSON of a value (numbers in the shortest round-trip form).
fn j<T: Serialize + ?Sized>(v: &T) -> String {
    serde_json::to_string(v).unwrap_or_else(|_| "null".into())
}

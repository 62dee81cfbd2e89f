//! The network file (`"format": "curvenet-network"`): a structure at network resolution that
//! loads back bit for bit.
//!
//! It holds everything the energy depends on, bit for bit (numbers in Rust's shortest
//! round-trip form), so analysing the loaded network gives the `λ` of the exported structure
//! again with no resampling. Its vertices are the kept rods' vertices in their original order,
//! renumbered from 0; its rods are the kept curves in ascending id order, renumbered from 0,
//! each with its original `id`.

use crate::geom::Vec3;
use crate::material::EndSupport;
use crate::network::{Joint, Network, Rod};
use crate::report::ReportError;
use crate::rod::{Material, Supports};
use crate::run_folder::{RunFolder, Which, check_network};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

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
    /// The supports of its start and end when given per end (which translations its anchors
    /// fix; a held rotation anchors the end's neighbour too).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ends: Option<[EndSupport; 2]>,
    /// The surface's directions at its ends where a support fixes a translation along one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<[crate::material::EndFrame; 2]>,
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
    /// What the run's searches maximised, when not the paper's `λ_eq`: `frequency`, with
    /// which `lambda` holds `μ_min` of the mass-metric problem.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objective: Option<String>,
    /// `λ_eq` recorded by the run for this structure (`μ_min` under `objective` frequency).
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
                    ends: r.ends,
                    frames: r.frames,
                }
            })
            .collect();
        NetworkFile {
            format: NETWORK_FORMAT.into(),
            version: NETWORK_VERSION,
            source: None,
            iteration: None,
            objective: None,
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
        if let Some(o) = &self.objective {
            let _ = writeln!(out, "  \"objective\": {},", j(o));
        }
        if let Some(l) = self.lambda {
            let _ = writeln!(out, "  \"lambda\": {},", j(&l));
        }
        let _ = writeln!(out, "  \"supports\": {},", j(&self.supports));
        let _ = writeln!(out, "  \"material\": {},", j(&self.material));
        // One list item a line.
        let list = |name: &str, items: Vec<String>| {
            let body: Vec<String> = items.iter().map(|i| format!("\n    {i}")).collect();
            format!("  \"{name}\": [{}\n  ]", body.join(","))
        };
        let mut lists = vec![
            list("positions", self.positions.iter().map(j).collect()),
            list("rods", self.rods.iter().map(j).collect()),
        ];
        if let Some(eq) = &self.equilibrium {
            lists.push(list("equilibrium", eq.iter().map(j).collect()));
        }
        out.push_str(&lists.join(",\n"));
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
    pub fn to_network(&self) -> Result<Network, ReportError> {
        if self.format != NETWORK_FORMAT {
            return Err(format!(
                "\"format\" is \"{}\", expected \"{NETWORK_FORMAT}\"",
                self.format
            )
            .into());
        }
        if self.version != NETWORK_VERSION {
            return Err(format!(
                "unsupported version {} (this reader supports {NETWORK_VERSION})",
                self.version
            )
            .into());
        }
        self.material.validate().map_err(|e| e.to_string())?;
        let rods: Vec<Rod> = self
            .rods
            .iter()
            .map(|r| Rod {
                vertices: r.vertices.clone(),
                closed: r.closed,
                rest_lengths: r.rest_lengths.clone(),
                anchors: r.anchors.clone(),
                ends: r.ends,
                frames: r.frames,
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
                )
                .into());
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
pub fn network_file(run: &RunFolder, which: impl Into<Which>) -> Result<NetworkFile, ReportError> {
    let which = which.into();
    let rec = run.network_of(which)?;
    let u = run.displacement_of(which)?;
    let mut f = NetworkFile::from_structure(
        &run.network,
        &rec.curves,
        run.result.setup.stability.material,
        Some(&u),
    );
    let unstable = rec
        .unstable
        .as_ref()
        .map_or_else(String::new, |w| format!(" ({})", super::unstable_header(w)));
    f.source = Some(format!("{} {}{unstable}", run.dir.display(), rec.what));
    f.iteration = rec.iteration;
    let objective = run.result.setup.stability.objective;
    f.objective = (!objective.is_lambda()).then(|| objective.name().to_string());
    f.lambda = Some(rec.lambda);
    Ok(f)
}

/// [`network_file`] as JSON text.
pub fn network_json(run: &RunFolder, which: impl Into<Which>) -> Result<String, ReportError> {
    Ok(network_file(run, which)?.to_json())
}

/// Reads a network file and checks it. See [`load_network`] for the network alone.
pub fn read_network_file(path: &Path) -> Result<NetworkFile, ReportError> {
    read_checked(path).map(|(f, _)| f)
}

/// Parses and checks the text of a network file.
pub fn parse_network_file(text: &str) -> Result<NetworkFile, ReportError> {
    parse_checked(text).map(|(f, _)| f)
}

/// Loads the network of a network file written by [`network_json`] (no resampling: the
/// vertices, rest lengths and anchors are used as they are). Rod `i` of the result is the
/// file's rod `i`; the file's material is in [`read_network_file`]'s result.
pub fn load_network(path: &Path) -> Result<Network, ReportError> {
    read_checked(path).map(|(_, n)| n)
}

/// A network file and its network (building the network is the file's check), errors
/// prefixed with the path.
fn read_checked(path: &Path) -> Result<(NetworkFile, Network), ReportError> {
    let text = std::fs::read_to_string(path).map_err(|e| ReportError::io(path, e))?;
    parse_checked(&text).map_err(|e| format!("{}: {e}", path.display()).into())
}

fn parse_checked(text: &str) -> Result<(NetworkFile, Network), ReportError> {
    let f: NetworkFile =
        serde_json::from_str(text).map_err(|e| format!("line {}: {e}", e.line()))?;
    if let Some(d) = crate::io::duplicate_key(text) {
        return Err(format!("line {}: {}", d.line, d.describe()).into());
    }
    let network = f.to_network()?;
    Ok((f, network))
}

/// Compact JSON of a value (numbers in the shortest round-trip form).
fn j<T: Serialize + ?Sized>(v: &T) -> String {
    serde_json::to_string(v).unwrap_or_else(|_| "null".into())
}

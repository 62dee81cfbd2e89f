//! Reports: the JSON objects of docs/formats.md and their text renderings.
//!
//! - [`AnalysisReport`]: what `curvenet analyze` and `example --analyze-only` print.
//! - [`UnitsNote`]: what the material constants mean against the scene's size.
//! - [`export`]: OBJ / JSON / CSV / fabrication exports of a run folder
//!   ([`crate::run_folder::RunFolder`]); the reloadable network file ([`export::load_network`]).
//! - [`render`], [`plot`]: software-rasterised pictures (`final.png`, `mode.png`, `lambda.png`).
//! - [`viewer`]: the self-contained WebGL viewer page (`curvenet view`) and
//!   [`viewer::write_run_outputs`], called after every greedy run.
//! - [`gravity_ahead`]: the viewer's gravity deflections, solved while the greedy runs.

pub mod export;
pub mod gravity_ahead;
pub mod plot;
pub mod render;
pub mod viewer;

use crate::fmt;
use crate::network::{BuildInfo, EdgeLengthStats, Network};
use crate::rod::{ActiveSet, Material};
use crate::run_folder::RunFolderError;
use crate::stability::{Analysis, CurveShare, GravityDeflection, NewtonSummary, Objective};
use crate::words::{Opt, Recorded, Wording, message};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Why an export, a picture or the viewer could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The run folder could not be read, or lacks the network asked for.
    #[error(transparent)]
    RunFolder(#[from] RunFolderError),
    /// A file could not be read or written: its path and the system's reason.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        error: std::io::Error,
    },
    /// A network file holds what no export writes (the message names the file and line), or
    /// a picture could not be encoded.
    #[error("{0}")]
    Invalid(String),
    /// A structural export of a run in the paper's mode, which has no material.
    #[error(
        "the run is in the paper's model, which has no material or units: a structural model \
         needs a run in the physical mode (the scene's length unit, a material and a section)"
    )]
    NotPhysical,
}

impl ReportError {
    /// The message spelled by `words` (a front end's option names).
    pub fn render(&self, words: &dyn crate::words::Wording) -> String {
        match self {
            ReportError::RunFolder(e) => e.render(words),
            e => e.to_string(),
        }
    }

    /// Whether the error is the input's: the run folder read is missing a file, damaged (a
    /// state truncated, a record malformed) or lacks the network asked for ([`RunFolderError::
    /// is_input`]); writing the outputs failing is not.
    pub fn is_input(&self) -> bool {
        match self {
            ReportError::RunFolder(e) => e.is_input(),
            ReportError::Io { .. } | ReportError::Invalid(_) => false,
            ReportError::NotPhysical => true,
        }
    }

    /// `path` could not be read or written.
    pub fn io(path: &Path, error: std::io::Error) -> Self {
        ReportError::Io {
            path: path.to_path_buf(),
            error,
        }
    }
}

impl From<String> for ReportError {
    fn from(message: String) -> Self {
        ReportError::Invalid(message)
    }
}

impl From<crate::run_folder::InvalidNetwork> for ReportError {
    fn from(e: crate::run_folder::InvalidNetwork) -> Self {
        ReportError::Invalid(e.0)
    }
}

impl From<&str> for ReportError {
    fn from(message: &str) -> Self {
        ReportError::Invalid(message.to_string())
    }
}

/// The rod radius against the scene: what the units imply.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UnitsNote {
    /// Rod radius.
    pub radius: f64,
    /// Median curve rest length.
    pub median_curve_length: f64,
    /// `median_curve_length / radius`.
    pub slenderness: f64,
    /// A warning when the ratio is outside what rods of a gridshell look like.
    pub warning: Option<String>,
}

impl UnitsNote {
    /// Compares the material's radius with the curves' lengths; the warning names the radius
    /// option as `words` spell it.
    pub fn new(network: &Network, material: &Material, words: &dyn Wording) -> Self {
        let mut lengths = network.rest_lengths();
        lengths.sort_by(f64::total_cmp);
        let median = lengths.get(lengths.len() / 2).copied().unwrap_or(0.0);
        let slenderness = median / material.radius;
        let extreme = if slenderness < 20.0 {
            Some(("large", " (rods are usually 100–10000× longer than thick)"))
        } else {
            (slenderness > 1e6).then_some(("tiny", ""))
        };
        let warning = if let Some((size, usual)) = extreme {
            Some(message![
                format!(
                    "rod radius {} is {size} against the median curve length {}: slenderness \
                     {}{usual}; check the scene's units or set ",
                    material.radius,
                    fmt::length(median),
                    fmt::significant(slenderness, 4)
                ),
                Opt::Radius
            ])
        } else {
            // The median is fine; a single curve may still be a stub against the rod's
            // thickness.
            network
                .rods
                .iter()
                .enumerate()
                .map(|(c, r)| (c, r.rest_length()))
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .filter(|&(_, l)| l < 4.0 * material.radius)
                .map(|(c, l)| {
                    message![
                        format!(
                            "curve {c} is only {l:.4e} long, less than twice the rod's diameter \
                             {}: a stub, not a rod; check it or set ",
                            2.0 * material.radius
                        ),
                        Opt::Radius
                    ]
                })
        }
        .map(|m| m.render(words));
        UnitsNote {
            radius: material.radius,
            median_curve_length: median,
            slenderness,
            warning,
        }
    }
}

/// Where the worst-case mode of `analysis` moves most, in words: `; it moves most at vertex V
/// (x, y, z) on curve(s) a, b` (its rest position, the curves through it); `None` when no mode
/// was computed.
fn mode_peak(network: &Network, analysis: &Analysis) -> Option<String> {
    let vectors = &analysis.spectrum.vectors;
    if vectors.ncols() == 0 || vectors.nrows() != network.dofs() {
        return None;
    }
    let vertex = (0..network.vertex_count())
        .map(|v| {
            let a = (0..3).map(|k| vectors[(3 * v + k, 0)].powi(2)).sum::<f64>();
            (v, a)
        })
        .filter(|(_, a)| a.is_finite())
        .max_by(|x, y| x.1.total_cmp(&y.1).then(y.0.cmp(&x.0)))?
        .0;
    let curves: Vec<String> = network
        .rods
        .iter()
        .enumerate()
        .filter(|(_, r)| r.vertices.contains(&(vertex as u32)))
        .map(|(c, _)| c.to_string())
        .collect();
    let p = network.positions[vertex];
    Some(format!(
        "; it moves most at vertex {vertex} ({:.4e}, {:.4e}, {:.4e}) on curve(s) {}",
        p.x,
        p.y,
        p.z,
        curves.join(", ")
    ))
}

/// The object printed by `analyze --json` (docs/formats.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AnalysisReport {
    /// Curves in the network (before removal).
    pub curve_count: usize,
    /// Vertices.
    pub vertices: usize,
    /// Joints.
    pub joints: usize,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Rest edge lengths.
    pub edge_length: EdgeLengthStats,
    /// Supports.
    pub supports: String,
    /// The equilibrium solve.
    pub newton: NewtonSummary,
    /// What `lambda` and `eigenvalues` are: absent for the paper's `λ_eq`; `frequency`:
    /// the mass-metric problem's `H v = μ M v` (the number the frequency objective maximises).
    #[serde(default, skip_serializing_if = "Objective::is_lambda")]
    pub objective: Objective,
    /// `λ_eq` of the analysed structure (`μ_min` under the frequency objective).
    pub lambda: f64,
    /// Under the frequency objective, the first natural frequency `√μ_min / 2π` (Hz in the
    /// physical mode); absent otherwise and when the structure is not stable.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_frequency: Option<f64>,
    /// The smallest eigenvalues, ascending.
    pub eigenvalues: Vec<f64>,
    /// Eigenvalues within the zero threshold (mechanisms).
    pub zero_modes: usize,
    /// Eigenvalues below it (unstable directions).
    pub negative_modes: usize,
    /// `‖Hv − λv‖ / ‖H‖₁` per eigenpair.
    pub residuals: Vec<f64>,
    /// The zero threshold `C·ε·‖H‖₁`.
    pub zero_threshold: f64,
    /// Curves removed before the analysis.
    pub removed: Vec<usize>,
    /// Curves in the analysed structure.
    pub curves: usize,
    /// Total rest length of the analysed structure.
    pub length: f64,
    /// Curves carrying the worst-case mode (largest shares).
    pub mode_curves: Vec<CurveShare>,
    /// Deflection under gravity (absent when the structure is not positive definite).
    pub gravity: Option<GravityDeflection>,
    /// What the material constants mean against the scene.
    pub units: UnitsNote,
    /// Construction details.
    pub build: BuildInfo,
    /// Warnings (also printed on stderr).
    pub warnings: Vec<String>,
    /// The analysis is the paper's model's beside a physical one (the physical mode): the
    /// text says its figures are the paper's model's, not physical.
    #[serde(skip)]
    pub beside_physical: bool,
    /// The scene's length unit beside a physical analysis (`mm`, `cm`, `m`): the text's
    /// lengths carry it.
    #[serde(skip)]
    pub length_unit: Option<String>,
}

impl AnalysisReport {
    /// The report of an analysis whose spectrum is `objective`'s (the analyzer's): under the
    /// frequency objective `lambda` is `μ_min` and the first frequency is added when the
    /// structure is stable.
    pub fn with_objective(mut self, objective: Objective) -> Self {
        self.objective = objective;
        let stable = self.zero_modes == 0 && self.negative_modes == 0 && self.lambda > 0.0;
        self.first_frequency = (objective == Objective::Frequency && stable)
            .then(|| self.lambda.sqrt() / (2.0 * std::f64::consts::PI));
        self
    }

    /// In the physical mode the paper's model keeps its default radius as a stand-in: the
    /// units note is that of the real section's outer radius `radius` (scene units) instead,
    /// without the paper model's warning (the physical analysis checks the section against
    /// the scene); the text's lengths carry the scene's `unit` and the paper's figures say
    /// they are the paper's model's.
    pub fn use_physical_radius(&mut self, network: &Network, radius: f64, unit: &str) {
        self.beside_physical = true;
        self.length_unit = Some(unit.to_string());
        if let Some(w) = self.units.warning.take() {
            self.warnings.retain(|x| *x != w);
        }
        let material = Material {
            radius,
            ..Material::default()
        };
        self.units = UnitsNote::new(network, &material, &Recorded);
        self.units.warning = None;
    }

    /// Assembles the report of `analysis` of structure `active` of `network`; its own and
    /// the build's warnings name options as `words` spell them.
    pub fn new(
        network: &Network,
        build: &BuildInfo,
        material: &Material,
        active: &ActiveSet,
        analysis: &Analysis,
        mut warnings: Vec<String>,
        words: &dyn Wording,
    ) -> Self {
        let curves = active.curves();
        let removed: Vec<usize> = (0..network.rods.len())
            .filter(|&c| !active.contains(c))
            .collect();
        let units = UnitsNote::new(network, material, words);
        if let Some(w) = &units.warning {
            warnings.push(w.clone());
        }
        let sp = &analysis.spectrum;
        if !analysis.newton.converged {
            warnings.push(format!(
                "equilibrium not reached: Newton stopped ({}) after {} iterations at relative \
                 gradient {:.3e}; λ is measured where it stopped",
                analysis.newton.stop, analysis.newton.iterations, analysis.newton.grad_rel
            ));
        }
        if sp.unconverged > 0 {
            warnings.push(format!(
                "the eigen solver converged only {} of the {} requested eigenpairs within its \
                 restarts; λ and the eigenvalues listed are the converged ones",
                sp.values.len(),
                sp.values.len() + sp.unconverged
            ));
        }
        let top: Vec<String> = analysis
            .mode_curves
            .iter()
            .take(5)
            .map(|c| c.curve.to_string())
            .collect();
        let unstable = sp.zero_modes > 0 || sp.negative_modes > 0;
        let place = unstable
            .then(|| mode_peak(network, analysis))
            .flatten()
            .unwrap_or_default();
        if sp.zero_modes > 0 {
            warnings.push(format!(
                "the structure has {} zero mode(s) (a mechanism): |λ| ≤ {:.3e}; the mode lives \
                 mostly on curves {}{place}",
                sp.zero_modes,
                sp.zero_threshold,
                top.join(", ")
            ));
        }
        if sp.negative_modes > 0 {
            warnings.push(format!(
                "the equilibrium is unstable: {} negative mode(s), λ = {:.6e}; mostly on curves \
                 {}{place}",
                sp.negative_modes,
                sp.lambda(),
                top.join(", ")
            ));
        }
        warnings.extend(build.warnings.iter().map(|w| w.render(words)));
        AnalysisReport {
            curve_count: network.rods.len(),
            vertices: network.vertex_count(),
            joints: network.joints.len(),
            dofs: network.dofs(),
            edge_length: network.edge_length_stats(),
            supports: network.supports.name().to_string(),
            newton: analysis.newton.summary(),
            objective: Objective::Lambda,
            lambda: sp.lambda(),
            first_frequency: None,
            eigenvalues: sp.values.clone(),
            zero_modes: sp.zero_modes,
            negative_modes: sp.negative_modes,
            residuals: sp.residuals.clone(),
            zero_threshold: sp.zero_threshold,
            length: network.total_length(&curves),
            curves: curves.len(),
            removed,
            mode_curves: analysis.mode_curves.iter().take(8).copied().collect(),
            gravity: analysis.gravity.clone(),
            units,
            build: build.clone(),
            warnings,
            beside_physical: false,
            length_unit: None,
        }
    }

    /// A human-readable rendering.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let b = &self.build;
        let unit = self.length_unit.as_deref();
        let sig = |x: f64| match unit {
            Some(u) => format!("{} {u}", fmt::significant(x, 4)),
            None => fmt::significant(x, 4),
        };
        let _ = writeln!(
            s,
            "network: {} curves, {} vertices, {} joints ({} crossings, {} self-crossings, up to {} curves at a joint), {} dofs",
            self.curve_count,
            self.vertices,
            self.joints,
            b.crossings,
            b.self_crossings,
            b.max_curves_at_joint,
            self.dofs
        );
        let e = &self.edge_length;
        let _ = writeln!(
            s,
            "edge lengths: min {} / median {} / max {}   (crossing tolerance {:.3e}..{:.3e}{})",
            sig(e.min),
            sig(e.median),
            sig(e.max),
            b.min_tolerance,
            b.max_tolerance,
            unit.map_or_else(String::new, |u| format!(" {u}"))
        );
        let _ = writeln!(
            s,
            "structure: {} curves, rest length {}{}; supports {}",
            self.curves,
            fmt::length_in(self.length, unit),
            if self.removed.is_empty() {
                String::new()
            } else {
                format!(" (removed {:?})", self.removed)
            },
            self.supports
        );
        let n = &self.newton;
        // Beside a physical analysis the paper's λ_eq and its spectrum are the paper's
        // model's (E = 1, r = 2, µ = 500), not physical figures: labelled so.
        let paper = if self.beside_physical && self.objective == Objective::Lambda {
            " (the paper's model)"
        } else {
            ""
        };
        let _ = writeln!(
            s,
            "equilibrium{paper}: {} Newton iterations, {}, relative gradient {:.3e}",
            n.iterations, n.stop, n.grad_rel
        );
        match self.objective {
            Objective::Lambda => {
                let model = if paper.is_empty() {
                    ""
                } else {
                    ", the paper's model"
                };
                let _ = writeln!(s, "lambda (λ_eq{model}): {:.6e}", self.lambda);
            }
            Objective::Frequency => {
                let f = self
                    .first_frequency
                    .map_or_else(|| "none (not stable)".to_string(), |f| format!("{f:.6e}"));
                let _ = writeln!(
                    s,
                    "objective frequency: μ_min {:.6e} (H v = μ M v); first natural frequency \
                     √μ_min / 2π {f}",
                    self.lambda
                );
            }
        }
        let _ = writeln!(
            s,
            "eigenvalues{paper}: {}",
            self.eigenvalues
                .iter()
                .map(|v| format!("{v:.6e}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        let _ = writeln!(
            s,
            "modes{paper}: {} zero, {} negative (threshold {:.3e}); relative residuals ≤ {:.2e}",
            self.zero_modes,
            self.negative_modes,
            self.zero_threshold,
            self.residuals.iter().copied().fold(0.0, f64::max)
        );
        let _ = writeln!(
            s,
            "worst-case mode{paper} lives on curves: {}",
            self.mode_curves
                .iter()
                .take(5)
                .map(|c| format!("{} ({:.1}%)", c.curve, 100.0 * c.share))
                .collect::<Vec<_>>()
                .join(", ")
        );
        let gravity = self.gravity.as_ref().map_or_else(
            || "not computed (structure not positive definite)".to_string(),
            |g| {
                format!(
                    "max {:.4e} at vertex {}, compliance {:.4e}",
                    g.max_displacement, g.vertex, g.compliance
                )
            },
        );
        let model = if self.beside_physical {
            " (the paper's model, in its own units: not a physical deflection)"
        } else {
            ""
        };
        let _ = writeln!(s, "gravity deflection{model}: {gravity}");
        let _ = writeln!(
            s,
            "units: radius {} vs median curve length {} (slenderness {})",
            match unit {
                Some(u) => format!("{} {u}", fmt::significant(self.units.radius, 4)),
                None => self.units.radius.to_string(),
            },
            fmt::length_in(self.units.median_curve_length, unit),
            fmt::significant(self.units.slenderness, 4)
        );
        s
    }
}

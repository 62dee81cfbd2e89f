//! The physical analysis of one structure: its rods' stiffnesses from materials and sections,
//! rigid supports, the equilibrium the rods are bent into, and what a structural designer
//! reads off it (natural frequencies, deflections, stresses, utilisation).
//!
//! The steps, all in the scene's consistent unit system (N, ℓ, s):
//! 1. the energy with `k_s = E A`, `k_b = E I` per rod, each rod straight or pre-bent at rest,
//!    anchors scaled to stay rigid next to the stiffest rod
//!    ([`crate::rod::physical::rigid_anchor_weight`]), clamps that hold the end vertex
//!    and its tangent, and pre-bent rods that carry their twist (`G J`) through a material
//!    frame, one twist unknown per edge ([`crate::rod::ModelRules::PHYSICAL`]);
//! 2. Newton's method from the drawn state to the equilibrium the rods are bent into;
//! 3. the lowest pairs of `H v = μ M v` (`M` the lumped mass matrix, with the twists'
//!    rotational inertia), solved as
//!    `M^{-1/2} H M^{-1/2} ṽ = μ ṽ`: the natural frequencies `√μ / 2π`, zero and negative
//!    modes judged in the identity metric ([`super::inertia`]);
//! 4. the lowest pair of `H v = μ_L Λ v` (`Λ` the lumped lengths): the worst-case
//!    distributed load of the given intensity and its largest deflection
//!    ([`super::loads::worst_load_deflection`]);
//! 5. the self-weight deflection, linearised at the equilibrium: `H u = M g`;
//! 6. the stresses of the equilibrium ([`super::stress::assembly_stresses`]) and the warnings
//!    (curves that would break when bent, units that imply absurd dimensions).
//!
//! An unstable equilibrium (a zero or negative `μ`) has no frequency and no linear
//! deflection: those numbers are absent and a warning says why.

use super::cases::Loads;
use super::checks::{deflection_warnings, near_joint, overstress_warnings, units_warnings};
use super::deviation::largest_deviation;
use super::inertia::{ModeSigns, classify};
use super::loaded::{LoadCaseReport, LoadedStructure};
use super::loads::{
    frequencies_hz, held_vertices, lumped_lengths, max_displacement, self_weight,
    worst_load_deflection,
};
use super::stress::{CurveStress, StressAt, assembly_stresses};
use crate::material::{Physical, PhysicalMaterial, RestShape};
use crate::rod::mass::{inverse_sqrt_with_twists, lumped_masses, scale_hessian, twist_masses};
use crate::rod::physical::{
    masses_per_length, physical_rods, rigid_anchor_weight, twist_masses_per_length,
};
use crate::rod::{ActiveSet, EnergyModel, ModelRules, Network};
use crate::solve::eigen::{
    EigenOptions, EigenParams, MAX_EIGEN_COUNT, Spectrum, smallest_eigenpairs,
};
use crate::solve::{
    Backend, Cholesky, Equilibrium, NewtonInfo, NewtonParams, NewtonSummary, SolverTuning,
    SymbolicFactor,
};
use crate::words::Message;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// What a physical analysis needs beyond the network.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicalParams {
    /// Units, materials, sections and loads.
    pub physical: Physical,
    /// Each curve's rest shape (straight where shorter).
    pub rest: Vec<RestShape>,
    /// How many natural frequencies to report.
    pub frequencies: usize,
    /// What an equilibrium is.
    pub newton: NewtonParams,
    /// Load cases and combinations to analyse (none: none).
    pub loads: Option<Loads>,
    /// The load cases' deflection limit.
    pub deflection_limit: Option<DeflectionLimit>,
    /// The smallest acceptable critical load factor of a load case (default 1).
    pub buckling_factor: f64,
}

/// A load case's deflection limit: a fraction of the span or a length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DeflectionLimit {
    /// The span over this number (`span/250`): see [`span`].
    SpanOver(f64),
    /// A length, scene units.
    Length(f64),
}

impl DeflectionLimit {
    /// The limit on the structure `active` of `network`, scene units.
    pub fn on(self, network: &Network, active: &ActiveSet) -> f64 {
        match self {
            DeflectionLimit::Length(l) => l,
            DeflectionLimit::SpanOver(d) => span(network, active) / d,
        }
    }
}

/// The span of the structure `active`: the largest distance between two of its supported
/// curve ends; a structure held at one point only is a cantilever, whose span is twice its
/// reach from that point (the usual convention for a cantilever's limit); one held nowhere
/// has its largest extent.
pub fn span(network: &Network, active: &ActiveSet) -> f64 {
    let rods = || {
        (network.rods.iter().enumerate())
            .filter(|(c, _)| active.contains(*c))
            .map(|(_, r)| r)
    };
    let p = |v: u32| network.positions[v as usize];
    let mut held: Vec<u32> = rods()
        .flat_map(|r| {
            let ends = match (r.vertices.first(), r.vertices.last()) {
                (Some(&a), Some(&b)) if !r.closed => vec![a, b],
                _ => Vec::new(),
            };
            ends.into_iter().filter(|v| r.anchors.contains(v))
        })
        .collect();
    held.sort_unstable();
    held.dedup();
    let all = || rods().flat_map(|r| r.vertices.iter().copied());
    let widest = |points: &[u32]| {
        let mut best = 0.0_f64;
        for (i, &a) in points.iter().enumerate() {
            for &b in &points[i + 1..] {
                best = best.max((p(a) - p(b)).norm());
            }
        }
        best
    };
    match held.len() {
        0 => {
            let mut v: Vec<u32> = all().collect();
            v.sort_unstable();
            v.dedup();
            widest(&v)
        }
        1 => {
            2.0 * all()
                .map(|v| (p(v) - p(held[0])).norm())
                .fold(0.0, f64::max)
        }
        _ => widest(&held),
    }
}

impl PhysicalParams {
    /// The analysis of `physical` with straight rods, four frequencies and the default
    /// equilibrium tolerance.
    pub fn new(physical: Physical) -> Self {
        PhysicalParams {
            physical,
            rest: Vec::new(),
            frequencies: 4,
            newton: NewtonParams::default(),
            loads: None,
            deflection_limit: None,
            buckling_factor: 1.0,
        }
    }

    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), Message> {
        self.physical.validate()?;
        if !(1..=MAX_EIGEN_COUNT).contains(&self.frequencies) {
            return Err(format!(
                "the number of frequencies must lie in 1..={MAX_EIGEN_COUNT}, got {}",
                self.frequencies
            )
            .into());
        }
        if !(self.buckling_factor.is_finite() && self.buckling_factor > 0.0) {
            return Err(format!(
                "the required critical load factor must be a positive number, got {}",
                self.buckling_factor
            )
            .into());
        }
        self.newton.validate()
    }
}

/// The largest utilisation (combined stress over strength) and where it occurs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Utilisation {
    /// Combined outer-fibre stress over the material's strength (above 1: the rod breaks).
    pub value: f64,
    /// The curve.
    pub curve: usize,
    /// The vertex.
    pub vertex: usize,
    /// "at joint J" or "near joint J" (empty when the curve has no joint).
    pub near: String,
    /// The combined stress there, MPa.
    pub stress_mpa: f64,
    /// The curve's strength, MPa.
    pub strength_mpa: f64,
}

/// A largest deflection and where it occurs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Deflection {
    /// The largest vertex displacement, scene units.
    pub max: f64,
    /// The vertex.
    pub vertex: usize,
}

/// The physical answers about one structure (`analyze --json`'s `physical` object).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicalReport {
    /// The scene's length unit (`mm`, `cm`, `m`).
    pub units: String,
    /// The run's material (curves may override it).
    pub material: PhysicalMaterial,
    /// The run's section, in words.
    pub section: String,
    /// The structure's mass, kg.
    pub mass_kg: f64,
    /// The anchor weight `µ` used (scene units, N/ℓ): rigid next to the rods.
    pub anchor_weight: f64,
    /// The solve of the equilibrium the rods are bent into.
    pub equilibrium: NewtonSummary,
    /// No zero or negative mode among the computed ones.
    pub stable: bool,
    /// Zero modes (mechanisms) among the computed ones.
    pub zero_modes: usize,
    /// Negative modes among the computed ones.
    pub negative_modes: usize,
    /// The lowest eigenvalue `μ` of `H v = μ M v`, s⁻².
    pub mu_min: f64,
    /// The first natural frequency, Hz (absent when unstable).
    pub first_frequency_hz: Option<f64>,
    /// The lowest natural frequencies, Hz (`null` for a zero or negative mode).
    pub frequencies_hz: Vec<Option<f64>>,
    /// Intensity of the worst-case distributed load, N/m.
    pub load_n_per_m: f64,
    /// The largest deflection under the worst-case distributed load of that intensity, scene
    /// units (absent when unstable).
    pub load_max_deflection: Option<Deflection>,
    /// Gravity, m/s².
    pub gravity_m_s2: [f64; 3],
    /// The largest deflection under self-weight, scene units (linearised at the
    /// equilibrium; absent when unstable).
    pub self_weight_max_deflection: Option<f64>,
    /// Where it occurs.
    pub self_weight_vertex: Option<usize>,
    /// The largest deviation of a vertex from its designed place once the rods are bent
    /// into shape and carry their own weight (the equilibrium's displacement plus the
    /// self-weight deflection), scene units: what `--max-deviation` bounds in the physical
    /// mode ([`super::deviation`]; absent when unstable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_deviation: Option<Deflection>,
    /// The largest bending stress `E r κ` of the assembly (the equilibrium the rods were
    /// bent into), MPa.
    pub assembly_max_bending_stress_mpa: f64,
    /// Where it occurs.
    pub assembly_max_bending_stress_at: Option<StressAt>,
    /// The largest axial stress of the assembly, MPa.
    pub assembly_max_axial_stress_mpa: f64,
    /// Where it occurs (its curve).
    pub assembly_max_axial_stress_at: Option<StressAt>,
    /// The largest utilisation and where it occurs.
    pub max_utilisation: Option<Utilisation>,
    /// Every curve's largest stresses.
    pub curves: Vec<CurveStress>,
    /// What the structure does under each load case and combination of the loads file.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub load_cases: Vec<LoadCaseReport>,
    /// Curves that would break when bent, units that look wrong, instability.
    pub warnings: Vec<Message>,
}

/// The physical numbers of one structure as a search records them per iteration
/// (result.json's `physical` of each iteration; [`PhysicalReport`] is the whole analysis).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicalSummary {
    /// The scene's length unit (`mm`, `cm` or `m`): the deflections' unit (absent in runs
    /// recorded before it was).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<String>,
    /// No zero or negative mode among the computed ones.
    pub stable: bool,
    /// The structure's mass, kg.
    pub mass_kg: f64,
    /// The lowest eigenvalue `μ` of `H v = μ M v`, s⁻².
    pub mu_min: f64,
    /// The first natural frequency, Hz (absent when unstable).
    pub first_frequency_hz: Option<f64>,
    /// The largest deflection under the worst-case distributed load, scene units (absent
    /// when unstable).
    pub load_max_deflection: Option<f64>,
    /// The largest deflection under self-weight, scene units (absent when unstable).
    pub self_weight_max_deflection: Option<f64>,
    /// The largest deviation of a vertex from its designed place under self-weight, scene
    /// units ([`PhysicalReport::max_deviation`]; absent when unstable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_deviation: Option<f64>,
    /// The largest bending stress of the assembly, MPa.
    pub assembly_max_bending_stress_mpa: f64,
    /// The largest axial stress of the assembly, MPa.
    pub assembly_max_axial_stress_mpa: f64,
    /// The largest utilisation (stress over strength; above 1 a rod breaks).
    pub max_utilisation: Option<f64>,
    /// The curves whose assembly stress exceeds their strength, ascending.
    pub overstressed_curves: Vec<usize>,
    /// Its load cases (a run given a loads file records them for the networks it offers to
    /// build: the answer and the alternatives).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub load_cases: Vec<super::loaded::LoadCaseReport>,
}

impl PhysicalReport {
    /// What a search records of this analysis per iteration.
    pub fn summary(&self) -> PhysicalSummary {
        PhysicalSummary {
            units: Some(self.units.clone()),
            stable: self.stable,
            mass_kg: self.mass_kg,
            mu_min: self.mu_min,
            first_frequency_hz: self.first_frequency_hz,
            load_max_deflection: self.load_max_deflection.map(|d| d.max),
            self_weight_max_deflection: self.self_weight_max_deflection,
            max_deviation: self.max_deviation.map(|d| d.max),
            assembly_max_bending_stress_mpa: self.assembly_max_bending_stress_mpa,
            assembly_max_axial_stress_mpa: self.assembly_max_axial_stress_mpa,
            max_utilisation: self.max_utilisation.as_ref().map(|u| u.value),
            overstressed_curves: self
                .curves
                .iter()
                .filter(|c| c.utilisation() > 1.0)
                .map(|c| c.curve)
                .collect(),
            load_cases: self.load_cases.clone(),
        }
    }
}

/// Why a physical analysis failed.
#[derive(Debug, thiserror::Error)]
pub enum PhysicsError {
    /// Bad parameters.
    #[error("invalid physical parameters: {0}")]
    Params(Message),
    /// The eigen solver failed.
    #[error(transparent)]
    Eigen(#[from] crate::solve::eigen::EigenError),
}

/// The physical analysis of the structure `active` of `network` (see the module's docs).
pub fn analyze_physical(
    network: &Network,
    params: &PhysicalParams,
    active: &ActiveSet,
) -> Result<PhysicalReport, PhysicsError> {
    params.validate().map_err(PhysicsError::Params)?;
    let phys = &params.physical;
    let n = network.rods.len();
    let rods = physical_rods(phys, n, &params.rest);
    let anchor_weight = rigid_anchor_weight(network, &rods);
    let model = EnergyModel::with_rules(network, &rods, anchor_weight, ModelRules::PHYSICAL);
    debug_assert_eq!(
        model.dofs(),
        3 * network.vertex_count() + model.twist_count()
    );
    let symbolic = SymbolicFactor::new(model.pattern(), Backend::default());
    let mut u = vec![0.0; model.dofs()];
    let relaxed = Equilibrium {
        model: &model,
        active,
        symbolic: &symbolic,
        params: &params.newton,
        tuning: &SolverTuning::default(),
    }
    .relax(&mut u, None);
    let held = held_vertices(network, active);
    let at = AtEquilibrium {
        model: &model,
        symbolic: &symbolic,
        hess: &relaxed.hess,
        keep: model.coordinate_mask(active),
        network,
        active,
        held: &held,
        phys,
    };

    // Natural frequencies: H v = μ M v, the twists with their rotational inertia.
    let masses = lumped_masses(network, &masses_per_length(phys, n), active);
    let twist_inertia = twist_masses(
        network,
        model.twist_dofs(),
        &twist_masses_per_length(phys, n),
    );
    let mass_scale = inverse_sqrt_with_twists(&masses, &twist_inertia);
    let count = params
        .frequencies
        .min(at.keep.iter().filter(|&&k| k).count().max(1));
    let modes = at.lowest(&mass_scale, count)?;
    let signs = at.classify(&modes, &mass_scale);
    let stable = signs.stable();
    let frequencies = frequencies_hz(&modes.values, &signs.positive);
    let mut warnings: Vec<Message> = solve_warnings(&relaxed.info, &signs, &modes)
        .into_iter()
        .map(Message::from)
        .collect();
    let (load_max_deflection, sag) = if stable {
        (Some(at.worst_load()?), at.self_weight())
    } else {
        (None, None)
    };
    let vertices = 3 * network.vertex_count();
    let self_weight_deflection = sag.as_ref().map(|w| max_displacement(w, &held));
    let max_deviation = sag.as_ref().map(|w| {
        let (vertex, max) = largest_deviation(&u[..vertices], w, &held);
        Deflection { max, vertex }
    });

    let stresses = assembly_stresses(network, phys, &params.rest, active, &u, Some(&model));
    warnings.extend(
        overstress_warnings(&stresses, network, phys)
            .into_iter()
            .map(Message::from),
    );
    warnings.extend(units_warnings(network, phys));
    warnings.extend(deflection_warnings(
        network,
        phys,
        active,
        self_weight_deflection.map(|d| d.1),
        load_max_deflection.map(|d| d.max),
    ));
    let max_utilisation = stresses.max_utilisation().map(|c| Utilisation {
        value: c.utilisation(),
        curve: c.curve,
        vertex: c.vertex,
        near: near_joint(network, c.curve, c.vertex),
        stress_mpa: c.combined_mpa,
        strength_mpa: c.strength_mpa,
    });
    let load_cases = match &params.loads {
        Some(loads) => {
            let cases = loads
                .forces(network, phys, active)
                .map_err(PhysicsError::Params)?;
            let mut loaded_model = model.clone();
            let structure = LoadedStructure {
                network,
                active,
                physical: phys,
                rest: &params.rest,
                held: &held,
                u0: &u,
                h0: &relaxed.hess,
                symbolic: &symbolic,
                newton: &params.newton,
                deflection_limit: params.deflection_limit.map(|d| d.on(network, active)),
                required_factor: params.buckling_factor,
            };
            let reports: Vec<LoadCaseReport> = cases
                .iter()
                .map(|c| structure.analyze(&mut loaded_model, c))
                .collect();
            for r in reports.iter().filter(|r| !r.passes) {
                warnings.push(Message::from(format!(
                    "load case {} does not pass: {}",
                    r.name,
                    r.failures.join("; ")
                )));
            }
            reports
        }
        None => Vec::new(),
    };
    let bending = stresses.max_bending();
    let axial = stresses.max_axial();
    let mass_kg = phys.units.mass_to_kg(
        masses
            .iter()
            .zip(&held)
            .filter(|(_, h)| **h)
            .map(|(m, _)| m)
            .sum(),
    );
    Ok(PhysicalReport {
        units: phys.units.symbol().to_string(),
        material: phys.material.clone(),
        section: phys.section.describe_in(phys.units.symbol()),
        mass_kg,
        anchor_weight,
        equilibrium: relaxed.info.summary(),
        stable,
        zero_modes: signs.zero,
        negative_modes: signs.negative,
        mu_min: modes.lambda(),
        first_frequency_hz: frequencies.first().copied().flatten(),
        frequencies_hz: frequencies,
        load_n_per_m: phys.load_n_per_m,
        load_max_deflection,
        gravity_m_s2: phys.gravity,
        self_weight_max_deflection: self_weight_deflection.map(|d| d.1),
        self_weight_vertex: self_weight_deflection.map(|d| d.0),
        max_deviation,
        assembly_max_bending_stress_mpa: bending.map_or(0.0, |s| s.mpa),
        assembly_max_bending_stress_at: bending,
        assembly_max_axial_stress_mpa: axial.map_or(0.0, |s| s.mpa),
        assembly_max_axial_stress_at: axial,
        max_utilisation,
        curves: stresses.curves,
        load_cases,
        warnings,
    })
}

/// The warnings of the analysis's solves: an unstable structure (zero or negative modes
/// among `modes`) and an equilibrium not reached.
fn solve_warnings(newton: &NewtonInfo, signs: &ModeSigns, modes: &Spectrum) -> Vec<String> {
    let mut warnings = Vec::new();
    if !signs.stable() {
        warnings.push(format!(
            "the structure is not stable in the physical mode ({} zero and {} negative modes \
             among the {} lowest; μ_min = {:.3e} s⁻²): it has no natural frequency and no \
             linear deflection",
            signs.zero,
            signs.negative,
            modes.values.len(),
            modes.lambda()
        ));
    }
    if !newton.converged {
        warnings.push(format!(
            "the equilibrium was not reached in the physical mode ({} after {} iterations, \
             |∇E| / g₀ = {:.1e}): its numbers are those of the last state",
            newton.stop, newton.iterations, newton.grad_rel
        ));
    }
    warnings
}

/// The structure at its equilibrium: the energy's Hessian there and the coordinates the
/// structure holds (those of its vertices, three per vertex), with the network, its active
/// curves and the physical parameters.
struct AtEquilibrium<'a> {
    model: &'a EnergyModel,
    symbolic: &'a Arc<SymbolicFactor>,
    hess: &'a [f64],
    keep: Vec<bool>,
    network: &'a Network,
    active: &'a ActiveSet,
    /// The vertices of the structure.
    held: &'a [bool],
    phys: &'a Physical,
}

impl AtEquilibrium<'_> {
    /// The `count` lowest pairs of `H v = μ D v` for the lumped diagonal metric `D`
    /// (`inv_sqrt`: `D^{-1/2}`, one value per coordinate), solved as
    /// `D^{-1/2} H D^{-1/2} ṽ = μ ṽ`: the vectors are the `ṽ`.
    fn lowest(&self, inv_sqrt: &[f64], count: usize) -> Result<Spectrum, PhysicsError> {
        let mut scaled = self.hess.to_vec();
        scale_hessian(self.model.pattern(), &mut scaled, inv_sqrt);
        let eigen = EigenParams::default().with_count(count);
        let options = EigenOptions {
            keep: Some(&self.keep),
            ..EigenOptions::default()
        };
        let found = smallest_eigenpairs(
            self.symbolic,
            self.model.pattern(),
            &scaled,
            &eigen,
            options,
        )?;
        Ok(found
            .expect("a shift below zero always gives pairs")
            .spectrum)
    }

    /// The signs of `modes` (pairs in the metric `D^{-1/2}` = `inv_sqrt`), judged in the
    /// identity metric.
    fn classify(&self, modes: &Spectrum, inv_sqrt: &[f64]) -> ModeSigns {
        classify(
            modes,
            self.model.pattern(),
            self.hess,
            inv_sqrt,
            &self.keep,
            EigenParams::default().zero_factor,
        )
    }

    /// The largest deflection under the worst-case distributed load of the run's intensity:
    /// the lowest pair of `H v = μ_L Λ v` (`Λ` the lumped lengths; a twist unknown's, its
    /// edge's length times `J / (A r²)`, the mass metric's ratio: a twisting section's
    /// weight in the metric, which a force-per-length load does not load), `v = Λ^{-1/2} ṽ`.
    fn worst_load(&self) -> Result<Deflection, PhysicsError> {
        let lengths = lumped_lengths(self.network, self.active);
        let n = self.network.rods.len();
        let ratio: Vec<f64> = twist_masses_per_length(self.phys, n)
            .iter()
            .zip(masses_per_length(self.phys, n))
            .map(|(t, m)| t / m)
            .collect();
        let twists = twist_masses(self.network, self.model.twist_dofs(), &ratio);
        let s = inverse_sqrt_with_twists(&lengths, &twists);
        let pair = self.lowest(&s, 1)?;
        let vertices = 3 * self.network.vertex_count();
        let v: Vec<f64> = (0..vertices).map(|i| s[i] * pair.vectors[(i, 0)]).collect();
        let (vertex, max) = worst_load_deflection(
            pair.lambda(),
            &v,
            &lengths,
            self.held,
            self.phys.load_scene(),
        );
        Ok(Deflection { max, vertex })
    }

    /// The self-weight deflection, linearised at the equilibrium (`H u = M g`): three
    /// displacements per vertex (`None` when `H` does not factorize).
    fn self_weight(&self) -> Option<Vec<f64>> {
        let factor =
            Cholesky::factorize(self.symbolic, self.model.pattern(), self.hess, 0.0, None).ok()?;
        let mut w = self_weight(self.network, self.phys, self.active);
        let vertices = w.len();
        w.resize(self.model.dofs(), 0.0);
        factor.solve_vec(&mut w);
        w.truncate(vertices);
        Some(w)
    }
}

impl PhysicalReport {
    /// The report as text lines for `analyze`'s summary (computed numbers with their
    /// significant digits: a tiny scene's stresses and masses do not print as zeros).
    pub fn to_text(&self) -> String {
        use crate::fmt::significant as sig;
        let u = &self.units;
        let mut s = String::new();
        let mut line = |l: String| {
            s.push_str(&l);
            s.push('\n');
        };
        line(format!(
            "physical: {} (E {} GPa, ρ {} kg/m³, strength {} MPa), {}, units {u}, mass {} kg",
            self.material.name,
            sig(self.material.young_pa / 1e9, 4),
            sig(self.material.density_kg_m3, 4),
            sig(self.material.strength_pa / 1e6, 4),
            self.section,
            sig(self.mass_kg, 4)
        ));
        line(format!(
            "  stable: {} (zero modes {}, negative modes {}), μ_min {:.6e} s⁻²",
            if self.stable { "yes" } else { "NO" },
            self.zero_modes,
            self.negative_modes,
            self.mu_min
        ));
        let freqs: Vec<String> = self
            .frequencies_hz
            .iter()
            .map(|f| f.map_or("none".into(), |f| sig(f, 5)))
            .collect();
        line(format!("  natural frequencies (Hz): {}", freqs.join(", ")));
        match self.load_max_deflection {
            Some(d) => line(format!(
                "  worst-case load {} kN/m: max deflection {:.4e} {u} at vertex {}",
                sig(self.load_n_per_m / 1e3, 4),
                d.max,
                d.vertex
            )),
            None => line("  worst-case load: no linear deflection (unstable)".into()),
        }
        match (self.self_weight_max_deflection, self.self_weight_vertex) {
            (Some(d), Some(v)) => line(format!(
                "  self-weight max deflection {d:.4e} {u} at vertex {v}"
            )),
            _ => line("  self-weight: no linear deflection (unstable)".into()),
        }
        if let Some(d) = self.max_deviation {
            line(format!(
                "  deviation from the design under self-weight (equilibrium and sag): max \
                 {:.4e} {u} at vertex {}",
                d.max, d.vertex
            ));
        }
        line(format!(
            "  assembly stress: bending max {} MPa, axial max {} MPa",
            sig(self.assembly_max_bending_stress_mpa, 4),
            sig(self.assembly_max_axial_stress_mpa, 4)
        ));
        if let Some(m) = &self.max_utilisation {
            line(format!(
                "  max utilisation {} ({} MPa / {} MPa) on curve {} {} (vertex {})",
                sig(m.value, 3),
                sig(m.stress_mpa, 4),
                sig(m.strength_mpa, 4),
                m.curve,
                m.near,
                m.vertex
            ));
        }
        for c in &self.load_cases {
            line(format!("  {}", c.to_text(u)));
        }
        s
    }
}

//! The parameters of every stability computation, the material budget of the searches'
//! problems, and the speed-only [`Tuning`] apart.

use crate::rod::Material;
use crate::solve::eigen::EigenParams;
use crate::solve::{Backend, NewtonParams, SolverTuning};
use crate::words::Message;
use serde::{Deserialize, Serialize};

/// Parameters of every stability computation.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StabilityParams {
    /// Material constants.
    pub material: Material,
    /// Equilibrium solver.
    pub newton: NewtonParams,
    /// Eigen solver (the analyses' spectra; the searches derive their presets from it,
    /// [`super::presets`]).
    pub eigen: EigenParams,
    /// Gravity load for the deflection report.
    pub gravity: GravityParams,
    /// What the searches maximise (recorded only when it is not the paper's `λ_eq`).
    #[serde(skip_serializing_if = "Objective::is_lambda")]
    pub objective: Objective,
    /// Knobs that change only the work (and round-off), never what is computed.
    pub tuning: Tuning,
}

impl StabilityParams {
    /// Checks every part.
    pub fn validate(&self) -> Result<(), Message> {
        self.tuning.validate()?;
        self.material.validate()?;
        self.newton.validate()?;
        self.eigen.validate()?;
        self.gravity.validate()
    }

    /// These parameters with `technique` switched off (for benchmarks: see [`Technique`]).
    pub fn without(mut self, technique: Technique) -> Self {
        self.tuning = self.tuning.without(technique);
        self
    }
}

/// What every search maximises.
///
/// - [`Objective::Lambda`] (the paper): `λ_eq`, the smallest eigenvalue of the Hessian at
///   equilibrium in the identity metric.
/// - [`Objective::Frequency`]: `μ_min`, the smallest eigenvalue of `H v = μ M v` with the
///   lumped mass matrix `M` (each vertex `ρ A` times half its adjacent rest edges), solved as
///   `M^{-1/2} H M^{-1/2}`. The first natural frequency is `√μ_min / 2π`. In the physical mode
///   `H` is the structure's own (per-rod `E A`, `E I`, rigid anchors) and `ρ A` the rods'; in
///   the paper's mode the paper's `H` with unit density (`ρ A = π r²`), so the objective needs
///   no material. Unlike `λ_eq`, which scales with the edge length, `μ_min` converges as the
///   edges shrink.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// The paper's `λ_eq`.
    #[default]
    Lambda,
    /// The first natural frequency: `μ_min` of the mass-metric problem.
    Frequency,
}

impl Objective {
    /// The paper's objective.
    pub fn is_lambda(&self) -> bool {
        *self == Objective::Lambda
    }

    /// The name a user writes (`--objective`) and `result.json` records.
    pub fn name(self) -> &'static str {
        match self {
            Objective::Lambda => "lambda",
            Objective::Frequency => "frequency",
        }
    }

    /// The symbol of the value the searches maximise, as summaries, pictures and the viewer
    /// show it: `λ_eq`, or `μ_min` (the mass-metric problem's smallest eigenvalue).
    pub fn value_symbol(self) -> &'static str {
        match self {
            Objective::Lambda => "λ_eq",
            Objective::Frequency => "μ_min",
        }
    }

    /// The symbol of a removal candidate's score: `λ_fix`, or `μ_fix`.
    pub fn score_symbol(self) -> &'static str {
        match self {
            Objective::Lambda => "λ_fix",
            Objective::Frequency => "μ_fix",
        }
    }
}

impl std::str::FromStr for Objective {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "lambda" => Ok(Objective::Lambda),
            "frequency" => Ok(Objective::Frequency),
            _ => Err(format!(
                "unknown objective {s:?}; one of lambda (the paper's λ_eq), frequency (the first \
                 natural frequency)"
            )),
        }
    }
}

/// Gravity load: a weight per unit rest length on every vertex, along `direction`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GravityParams {
    /// Weight per unit length.
    pub weight_per_length: f64,
    /// Direction of the load (normalised on use).
    pub direction: [f64; 3],
}

impl Default for GravityParams {
    fn default() -> Self {
        GravityParams {
            weight_per_length: 1.0,
            direction: [0.0, 0.0, -1.0],
        }
    }
}

impl GravityParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), Message> {
        let d = self.direction;
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let weight_ok = self.weight_per_length.is_finite() && self.weight_per_length >= 0.0;
        if !(weight_ok && n > 0.0 && n.is_finite()) {
            return Err(
                "gravity needs a finite non-negative weight and a non-zero direction".into(),
            );
        }
        Ok(())
    }
}

/// The material budget `V`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Budget {
    /// A fraction of the total rest length of all curves, in `(0, 1]`.
    Fraction(f64),
    /// An absolute rest length.
    Length(f64),
}

impl Budget {
    /// The budget as a length, for a network of total rest length `total`.
    pub fn length(self, total: f64) -> f64 {
        match self {
            Budget::Fraction(f) => f * total,
            Budget::Length(l) => l,
        }
    }

    /// Checks the value.
    pub fn validate(self) -> Result<(), Message> {
        match self {
            Budget::Fraction(f) if !(f > 0.0 && f <= 1.0) => {
                Err(format!("budget fraction must lie in (0, 1], got {f}").into())
            }
            Budget::Length(l) if !(l > 0.0 && l.is_finite()) => {
                Err(format!("budget length must be a positive number, got {l}").into())
            }
            _ => Ok(()),
        }
    }
}

/// Speed-only knobs of the stability computations and of the greedy's candidate search.
///
/// None of them changes what is computed: the same removals, the same values up to the
/// round-off of a different path (which factorization starts a Newton solve, which vector
/// starts an eigen solve). They are recorded with a run's set-up, so a resumed run takes the
/// same path. Every default was measured (`docs/benchmarks.md`); [`Technique`] names the
/// techniques a benchmark can switch off.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Tuning {
    /// A structure holding at most this share of the network's vertices is factored on its
    /// own vertices only ([`super::Analyzer::symbolic_for`]); 0 factors every structure on
    /// the whole pattern.
    pub restrict_share: f64,
    /// Low modes computed per greedy iteration: the subspace of the candidates' bounds.
    pub modes: usize,
    /// Each greedy iteration starts from the previous one's low modes, symbolic analysis and
    /// winning factorization (the equilibrium is the start either way).
    pub warm_start: bool,
    /// Skip the candidates whose bound shows they cannot win.
    pub prune: bool,
    /// Candidates evaluated together once a score is known (fixed, so the search is the same
    /// on any number of threads).
    pub batch: usize,
    /// Once a score is known, each further candidate's `H − σI` is factored with `σ` the
    /// best score minus the tie tolerance: a failed factorization proves the candidate cannot
    /// win (Sylvester's inertia), a successful one is the shift-and-invert operator of its
    /// eigen solve.
    pub inertia: bool,
    /// The first candidate of an iteration is scored about this share of its refined bound
    /// when the factorization there succeeds; 0 scores it about zero.
    pub first_shift: f64,
    /// The preconditioner's shift is the first guess instead when it lies between that guess
    /// and this share of the bound.
    pub preconditioner_guess: f64,
    /// Failed first guesses after which a candidate is scored about zero.
    pub max_guesses: u8,
    /// The inertia tests about one shift copy the supernodes a candidate cannot reach from a
    /// factorization of `H_A − σI` (the same factors).
    pub reuse: bool,
    /// ... when that saves at least this many factorizations' work (it costs one).
    pub reuse_min_saving: f64,
    /// While an iteration's first candidate is scored (one core mostly idle), refine the
    /// bounds of the next candidates its score is unlikely to prune.
    pub ahead: bool,
    /// At most this many.
    pub first_ahead: usize,
    /// A first score's solves per solve of the structure's spectrum (the budget of
    /// [`Self::ahead`]).
    pub first_score_cost: f64,
    /// Candidates refined ahead have a plain bound above this share of the first one's.
    pub ahead_share: f64,
    /// When the next candidates lack a refined bound, those of this many batches are refined
    /// together.
    pub refine_ahead: usize,
    /// Hand each candidate's best test vector to the next iteration, whose bound extends the
    /// plain Rayleigh–Ritz bound with it and whose refinement starts from it.
    pub carry: bool,
    /// The carried vectors are used in an iteration when the previous one settled at least
    /// this many candidates by an inertia test or by a carried vector's bound; 0 always.
    pub carry_after: usize,
    /// A negative best score serves as the inertia test's shift only beyond this many times
    /// its spectrum's zero-mode threshold (otherwise the test runs at the band's lower edge
    /// and only decides).
    pub negative_floor: f64,
    /// Factors storing more values than this solve an eigen block one column per core
    /// instead of in one pass (beyond the caches one pass for two columns costs nearly two).
    /// A function of the structure's size only, so results never depend on the threads.
    pub large_factor_values: usize,
    /// A greedy spectrum is computed about this share of the expected `λ_eq` when the
    /// factorization there proves it lies below every eigenvalue.
    pub spectrum_shift: f64,
    /// The solvers' own knobs: the factorization backend and Newton's techniques.
    pub solver: SolverTuning,
}

impl Default for Tuning {
    fn default() -> Self {
        Tuning {
            restrict_share: 0.85,
            modes: 2,
            warm_start: true,
            prune: true,
            batch: 2,
            inertia: true,
            first_shift: 0.8,
            preconditioner_guess: 0.95,
            max_guesses: 2,
            reuse: true,
            reuse_min_saving: 5.0,
            ahead: true,
            first_ahead: 10,
            first_score_cost: 1.6,
            ahead_share: 0.95,
            refine_ahead: 2,
            carry: true,
            carry_after: 2,
            negative_floor: 10.0,
            large_factor_values: 4_000_000,
            spectrum_shift: 0.9,
            solver: SolverTuning::default(),
        }
    }
}

impl Tuning {
    /// Checks the knobs.
    pub fn validate(&self) -> Result<(), Message> {
        let share = |name: &str, v: f64, open_top: bool| -> Result<(), Message> {
            let ok = v >= 0.0 && if open_top { v < 1.0 } else { v <= 1.0 };
            let range = if open_top { "[0, 1)" } else { "[0, 1]" };
            if ok {
                Ok(())
            } else {
                Err(format!("{name} must lie in {range}, got {v}").into())
            }
        };
        self.solver.validate()?;
        share("restrict_share", self.restrict_share, false)?;
        share("first shift", self.first_shift, true)?;
        share("preconditioner_guess", self.preconditioner_guess, false)?;
        share("ahead_share", self.ahead_share, false)?;
        share("spectrum_shift", self.spectrum_shift, true)?;
        if self.modes == 0 || self.batch == 0 || self.refine_ahead == 0 {
            return Err("modes, batch and refine_ahead must be at least 1".into());
        }
        let positive = [
            ("reuse_min_saving", self.reuse_min_saving),
            ("first_score_cost", self.first_score_cost),
            ("negative_floor", self.negative_floor),
        ];
        if let Some((name, v)) = positive.iter().find(|(_, v)| !(v.is_finite() && *v >= 0.0)) {
            return Err(format!("{name} must be a finite non-negative number, got {v}").into());
        }
        Ok(())
    }

    /// These knobs with `technique` switched off.
    pub fn without(mut self, technique: Technique) -> Self {
        match technique {
            Technique::Prune => self.prune = false,
            Technique::Warm => self.warm_start = false,
            Technique::Restrict => self.restrict_share = 0.0,
            Technique::FirstShift => self.first_shift = 0.0,
            Technique::Reuse => self.reuse = false,
            Technique::Ahead => self.ahead = false,
            Technique::Carry => self.carry = false,
            Technique::Inertia => self.inertia = false,
            Technique::Subtrees => self.solver.backend = Backend::Faer,
            Technique::FloorNear => self.solver.floor_near = 1.0,
            Technique::QuadraticChord => self.solver.chord_below = 0.0,
            Technique::Escape => self.solver.escape_doublings = 0,
        }
        self
    }
}

/// A speed technique a benchmark can switch off ([`StabilityParams::without`]), by the name
/// `bench --off` takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Technique {
    /// Pruning candidates by their bounds ([`Tuning::prune`]).
    Prune,
    /// Warm starts between greedy iterations ([`Tuning::warm_start`]).
    Warm,
    /// Factorizations restricted to a structure's vertices ([`Tuning::restrict_share`]).
    Restrict,
    /// The first candidate scored about a shift ([`Tuning::first_shift`]).
    FirstShift,
    /// Inertia tests copying a reference factorization ([`Tuning::reuse`]).
    Reuse,
    /// Refining bounds beside the first score ([`Tuning::ahead`]).
    Ahead,
    /// Test vectors carried between iterations ([`Tuning::carry`]).
    Carry,
    /// Inertia tests ([`Tuning::inertia`]).
    Inertia,
    /// The subtree-parallel factorization and substitutions (faer's sequential ones instead:
    /// [`SolverTuning::backend`]).
    Subtrees,
    /// The early round-off floor of Newton's method ([`SolverTuning::floor_near`]).
    FloorNear,
    /// Chord steps in Newton's quadratic phase ([`SolverTuning::chord_below`]).
    QuadraticChord,
    /// Extended steps escaping saddles ([`SolverTuning::escape_doublings`]).
    Escape,
}

impl Technique {
    /// Every technique, in the order benchmarks list them.
    pub const ALL: [Technique; 12] = [
        Technique::Prune,
        Technique::Warm,
        Technique::Restrict,
        Technique::FirstShift,
        Technique::Reuse,
        Technique::Ahead,
        Technique::Carry,
        Technique::Inertia,
        Technique::Subtrees,
        Technique::FloorNear,
        Technique::QuadraticChord,
        Technique::Escape,
    ];

    /// The name `bench --off` takes.
    pub fn name(self) -> &'static str {
        // In the order of the variants (and of `ALL`).
        const NAMES: [&str; 12] = [
            "prune",
            "warm",
            "restrict",
            "first-shift",
            "reuse",
            "ahead",
            "carry",
            "inertia",
            "subtrees",
            "floor-near",
            "quadratic-chord",
            "escape",
        ];
        NAMES[self as usize]
    }
}

impl std::str::FromStr for Technique {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Technique::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Technique::ALL.iter().map(|t| t.name()).collect();
                format!("unknown technique {s:?}; one of {}", names.join(", "))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_outside_their_range_are_rejected() {
        let mut t = Tuning::default();
        assert!(t.validate().is_ok());
        for bad in [1.0, 1.5, -0.1, f64::NAN, f64::INFINITY] {
            t.first_shift = bad;
            let e = t.validate().expect_err("rejected").to_string();
            assert!(e.contains("first shift must lie in [0, 1)"), "{e}");
        }
        t.first_shift = 0.0;
        assert!(t.validate().is_ok(), "0 switches it off");
        t.restrict_share = 1.5;
        assert!(t.validate().is_err());
    }

    #[test]
    fn objectives_parse_by_name() {
        assert_eq!("lambda".parse::<Objective>(), Ok(Objective::Lambda));
        assert_eq!("frequency".parse::<Objective>(), Ok(Objective::Frequency));
        let e = "freq".parse::<Objective>().expect_err("unknown");
        assert!(e.contains("one of lambda"), "{e}");
        // The paper's objective is not written into a run's set-up.
        let json = serde_json::to_string(&StabilityParams::default()).expect("serializes");
        assert!(!json.contains("objective"), "{json}");
    }

    #[test]
    fn budgets() {
        assert_eq!(Budget::Fraction(0.25).length(200.0), 50.0);
        assert_eq!(Budget::Length(30.0).length(200.0), 30.0);
        assert!(Budget::Fraction(0.0).validate().is_err());
        assert!(Budget::Fraction(1.5).validate().is_err());
        assert!(Budget::Length(-1.0).validate().is_err());
        assert!(Budget::Length(f64::NAN).validate().is_err());
    }

    #[test]
    fn techniques_parse_by_name_and_switch_their_knob_off() {
        for t in Technique::ALL {
            assert_eq!(t.name().parse::<Technique>(), Ok(t));
            assert_ne!(Tuning::default().without(t), Tuning::default(), "{t:?}");
        }
        let e = "pruning".parse::<Technique>().expect_err("unknown");
        assert!(e.contains("prune, warm"), "{e}");
    }
}

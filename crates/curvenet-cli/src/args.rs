//! Command-line arguments (clap derive). Subcommand and option names are fixed: scripts rely on them.
//! Every numeric option is checked while it is parsed ([`crate::values`]).

use crate::values::{
    budget_fraction, count, extent, open_fraction, physical, port, positive, seconds, young,
};
use clap::{Args, Parser, Subcommand};
use curvenet::app::MAX_EIGEN_COUNT;
use curvenet::constraints::SymmetryOption;
use curvenet::rod::Supports;
use curvenet::slide::MaxMove;
use curvenet::stability::{Objective, Technique};
use curvenet::words::Opt;
use std::path::PathBuf;
use std::str::FromStr;

/// `--force`'s help (`simplify`, `example`, `demo`).
const FORCE: &str = "Run into a non-empty folder that is not a curvenet run's (the run's own files \
    are replaced, the others kept). A curvenet run's folder needs no --force: a fresh run there \
    removes the earlier run's files first";

/// Stability-aware simplification of curve networks.
#[derive(Debug, Parser)]
#[command(name = "curvenet", version, about, propagate_version = true)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Build a network from a mesh and curves, relax it and report its worst-case stability.
    Analyze(AnalyzeArgs),
    /// Simplify a network to a material budget with the greedy (paper Algorithm 1).
    Simplify(SimplifyArgs),
    /// Run one of the paper's examples (docs/model.md, "The paper's examples") from its input files.
    ///
    /// The examples' meshes and curves are those published with the paper's implementation,
    /// embedded in curvenet under the authors' MIT licence (Copyright (c) 2022 wwwnev):
    /// `curvenet example --license` prints it.
    Example(ExampleArgs),
    /// Run the whole pipeline on a built-in scene: no input files needed.
    Demo(DemoArgs),
    /// Time the greedy on the paper's examples and print a table.
    Bench(BenchArgs),
    /// Generate curves on a mesh: random geodesics or frame-field streamlines (docs/model.md, "Curve generation").
    Trace(TraceArgs),
    /// Greedy against exhaustive and random search on random networks (paper Fig. 10).
    Compare(CompareArgs),
    /// Write the interactive viewer (one self-contained HTML page) and the pictures of a run.
    View(ViewArgs),
    /// Export a recorded network of a run (OBJ, JSON, CSV, fabrication table, network file).
    Export(ExportArgs),
    /// Slide a run's answer on its surface to raise the objective, into a run of its own.
    Slide(SlideCmdArgs),
    /// Serve a network over a local JSON API: remove and restore curves, see λ follow.
    #[cfg(feature = "serve")]
    Serve(ServeArgs),
}

/// `curvenet serve`.
#[cfg(feature = "serve")]
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// One of the paper's examples instead of input files: hill, roof, kagome, stadium, tower,
    /// shell, bunny, tent, arcshell.
    #[arg(long, conflicts_with_all = ["curves", "mesh", "scale", "edge_length"])]
    pub example: Option<String>,
    /// Folder holding the paper's data (`meshes/`, `curves/`) for `--example`, instead of the
    /// copies embedded in curvenet.
    #[arg(long, requires = "example")]
    pub data: Option<PathBuf>,
    /// The output folder of a run (holding result.json) instead of input files: its network,
    /// its material, and its greedy iterations to step through; serving starts on its answer.
    #[arg(long, value_name = "DIR", conflicts_with_all = [
        "example", "curves", "mesh", "scale", "edge_length",
        "supports", "supports_file", "radius", "young", "anchor_weight", "merge_joints",
        "eigen_count", "objective",
    ])]
    pub run: Option<PathBuf>,
    /// Inputs (instead of --example or --run).
    #[command(flatten)]
    pub input: InputArgs,
    /// Curves removed at the start (comma-separated ids).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub remove: Vec<usize>,
    /// Address to listen on. Anything but a loopback address makes the server reachable
    /// from other machines.
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    /// Port to listen on (0: any free port).
    #[arg(long, default_value_t = 8765, value_parser = port, allow_hyphen_values = true)]
    pub port: u16,
    /// Open the page in the default browser once the server answers.
    #[arg(long, conflicts_with = "bench")]
    pub open: bool,
    /// The folder whose run folders the page may load (default: the current folder); a run
    /// folder outside it is refused.
    #[arg(long, value_name = "DIR", conflicts_with = "bench")]
    pub runs: Option<PathBuf>,
    /// Measure instead of serving: a fixed sequence of single-curve removals and restores,
    /// each edit's time at the server printed beside a cold analysis of the same structure
    /// (docs/serve.md, *Benchmark*).
    #[arg(long)]
    pub bench: bool,
    /// Curves the benchmark removes (each is restored later).
    #[arg(long = "bench-removals", default_value_t = 12, requires = "bench", value_parser = count(1, 1000), allow_hyphen_values = true)]
    pub bench_removals: usize,
    /// Material and solver options.
    #[command(flatten)]
    pub physics: PhysicsArgs,
    /// The physical mode (every state also gives its physical numbers).
    #[command(flatten)]
    pub physical: PhysicalModeArgs,
}

/// `curvenet view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Output folder of a run (holding result.json).
    pub dir: PathBuf,
    /// The HTML file to write (default DIR/viewer.html).
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// Do not compute the gravity deflection of every iteration.
    #[arg(long = "no-gravity")]
    pub no_gravity: bool,
    /// Do not (re)write final.png, mode.png and lambda.png.
    #[arg(long = "no-pictures")]
    pub no_pictures: bool,
}

/// `curvenet export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// Output folder of a run (holding result.json).
    pub dir: PathBuf,
    /// Iteration to export (default: the final one).
    #[arg(long, allow_hyphen_values = true, conflicts_with_all = ["answer", "alternative"])]
    pub iteration: Option<usize>,
    /// Export the answer (the network to build) instead of an iteration.
    #[arg(long, conflicts_with = "alternative")]
    pub answer: bool,
    /// Export the N-th alternative (from 1) of a run made with --alternatives.
    #[arg(long, value_name = "N", value_parser = count(1, 100), allow_hyphen_values = true)]
    pub alternative: Option<usize>,
    /// obj, json, csv (points and fabrication table), network (reloadable network file),
    /// structural (a physical run's neutral structural JSON), opensees (its OpenSeesPy script,
    /// which prints its frequencies and self-weight deflection) or all.
    #[arg(long, default_value = "all")]
    pub format: String,
    /// Folder for the files (default DIR/export). With one format, a path with an extension
    /// writes only that format's main file: the OBJ at equilibrium, the JSON at rest, the
    /// fabrication table, the network file, the structural JSON or the OpenSeesPy script.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `curvenet slide`.
#[derive(Debug, Args)]
pub struct SlideCmdArgs {
    /// The run folder whose answer slides.
    pub dir: PathBuf,
    /// The slid run's folder.
    #[arg(long)]
    pub out: PathBuf,
    #[arg(long, help = FORCE)]
    pub force: bool,
    #[command(flatten)]
    pub sliding: SlideArgs,
}

/// How far the curves may slide (`docs/model.md`, "Sliding").
#[derive(Debug, Args, Clone)]
pub struct SlideArgs {
    /// How far a point of a curve may move: a length, or a percentage of the surface's diagonal.
    #[arg(long = "max-move", value_name = "D", default_value = "5%", value_parser = |s: &str| s.parse::<MaxMove>().map_err(|m| m.to_string()), allow_hyphen_values = true)]
    pub max_move: MaxMove,
    /// Keep every curve end where it is (else ends on the surface's boundary slide along it).
    #[arg(long = "fixed-ends")]
    pub fixed_ends: bool,
    /// Curves that do not move (comma-separated ids).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub pin: Vec<usize>,
    /// Then N rounds of a local search with the slid curves in place and a slide (rounds/K/).
    #[arg(long = "slide-rounds", value_name = "N", default_value_t = 0, value_parser = count(0, 100), allow_hyphen_values = true)]
    pub slide_rounds: usize,
}

/// `curvenet compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Numbers of curves N, comma-separated, each 2 to 30 (exhaustive search is exponential).
    #[arg(long, value_delimiter = ',', default_value = "10,12,14,16", value_parser = count(2, 30), allow_hyphen_values = true)]
    pub sizes: Vec<usize>,
    /// Random networks per size.
    #[arg(long, default_value_t = 10, value_parser = count(1, 10_000), allow_hyphen_values = true)]
    pub instances: usize,
    /// Budget as a fraction of each network's total length, in (0, 1].
    #[arg(long, default_value_t = 0.3, value_parser = budget_fraction, allow_hyphen_values = true)]
    pub budget: f64,
    /// Base seed.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub seed: u32,
    /// Surfaces to trace on: mesh files, names of the paper's simple surfaces (1wave, 2waves,
    /// half_sphere, sine_disk, leaf) or built-in surfaces (hill, tent, stadium, shell, dome,
    /// saddle, wave).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1wave,2waves,half_sphere,sine_disk,leaf"
    )]
    pub surfaces: Vec<String>,
    /// Folder holding the paper's data (`meshes/`) to read the simple surfaces from instead of
    /// the copies embedded in curvenet.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Write the full report (every instance) as JSON.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write the summary table as Markdown.
    #[arg(long)]
    pub markdown: Option<PathBuf>,
    /// Time limit of the exact λ_fix solver per network, seconds.
    #[arg(long = "exact-time-limit", default_value_t = 60.0, value_parser = seconds, allow_hyphen_values = true)]
    pub exact_time_limit: f64,
    /// Instead of the sizes' table: N networks drawn afresh (8–18 curves, budgets 0.1–0.5,
    /// the surfaces in rotation, each its own seed), the greedy and the greedy + local search
    /// against the exact optimum (exhaustive search over the connected feasible subsets, on
    /// networks of at most 20000 of them; the others are listed as skipped).
    #[arg(long, value_name = "N", value_parser = count(1, 10_000), allow_hyphen_values = true, conflicts_with_all = ["sizes", "instances", "budget", "exact_time_limit"])]
    pub fresh: Option<usize>,
    /// Instead of the sizes' table: what each design constraint costs. On the paper's examples
    /// (--examples) and on N random geodesic networks (8–12 curves, budgets 0.2–0.4; 0: none),
    /// the answer of greedy + local search with no constraint and with each constraint alone
    /// (symmetry auto, pairs of curves as groups, connected, a largest gap of 30% of the
    /// surface's extent, a largest deviation of 0.1% of it, at least 3 curves): its λ_eq, its
    /// time, and whether the unconstrained answer (and on the random networks, the
    /// unconstrained optimum) breaks the constraint.
    #[arg(long = "constraints", value_name = "N", value_parser = count(0, 10_000), allow_hyphen_values = true, conflicts_with_all = ["sizes", "instances", "budget", "exact_time_limit", "fresh"])]
    pub constraints: Option<usize>,
    /// With --constraints: the paper's examples to measure, comma-separated (`none`: only
    /// random networks).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "roof,tower,shell,arcshell,kagome",
        requires = "constraints"
    )]
    pub examples: Vec<String>,
    /// What the searches maximise: lambda (the paper's λ_eq) or frequency (the first natural
    /// frequency, μ_min of the mass metric); frequency needs --fresh (the sizes' table also
    /// runs the rounded relaxation and the exact λ_fix solver, which bound λ_fix only).
    #[arg(long, default_value = "lambda", value_parser = Objective::from_str)]
    pub objective: Objective,
}

/// `curvenet trace`.
#[derive(Debug, Args)]
pub struct TraceArgs {
    /// Surface: an OBJ file or a built-in surface name (hill, tent, stadium, shell, dome,
    /// saddle, wave).
    #[arg(long)]
    pub mesh: PathBuf,
    /// Number of random geodesics (the reference's command-line scenes: loop 0,
    /// t ~ U[0,1], θ ~ U[π/6, 5π/6]).
    #[arg(long, conflicts_with = "field", value_parser = count(1, 100_000), allow_hyphen_values = true)]
    pub geodesics: Option<usize>,
    /// Seed of the reference's rand() for the geodesics.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub seed: u32,
    /// Trace streamlines of a smooth 2- or 3-direction field instead of geodesics.
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=3), allow_hyphen_values = true)]
    pub field: Option<u32>,
    /// Seeds along the boundary for streamlines.
    #[arg(long, default_value_t = 40, value_parser = count(1, 100_000), allow_hyphen_values = true)]
    pub seeds: usize,
    /// Scale the mesh so its largest extent is this (the reference's scenes: 4000); 0 keeps it.
    #[arg(long, default_value_t = 4000.0, value_parser = extent, allow_hyphen_values = true)]
    pub extent: f64,
    /// Output curve file (.json, .obj or .txt).
    #[arg(long)]
    pub out: PathBuf,
    /// Also write the (scaled) mesh as OBJ.
    #[arg(long = "mesh-out")]
    pub mesh_out: Option<PathBuf>,
}

/// `curvenet bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Examples to run (comma-separated).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "tower,arcshell,roof,shell,kagome"
    )]
    pub examples: Vec<String>,
    /// Folder holding the paper's data (`meshes/`, `curves/`) to read instead of the copies
    /// embedded in curvenet.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Techniques to switch off, to measure what each contributes (comma-separated; the
    /// answer must stay the same): prune, warm, restrict, first-shift, reuse, ahead, carry,
    /// inertia, subtrees, floor-near, quadratic-chord, escape.
    #[arg(long, value_delimiter = ',', value_parser = Technique::from_str)]
    pub off: Vec<Technique>,
    /// Low modes per iteration (the candidates' bound subspace; default: the greedy's).
    #[arg(long, value_parser = count(1, 64), allow_hyphen_values = true)]
    pub modes: Option<usize>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = count(1, 1024), allow_hyphen_values = true)]
    pub threads: Option<usize>,
    /// Runs of each example, in rounds (every example once per round, so the machine's drift
    /// touches them alike); each row is the run with the median wall time, with the fastest
    /// and slowest beside it. The runs must agree bit for bit (removals and every `λ_eq`).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1000), allow_hyphen_values = true)]
    pub repeat: u32,
    /// Print the rows as JSON lines too.
    #[arg(long)]
    pub json: bool,
    /// The reference implementation's times measured on this machine, a JSON object of
    /// seconds by example (`{"tower": 103.8}`): the table shows them and the ratio. Without
    /// it, no ratio is shown.
    #[arg(long, value_name = "FILE")]
    pub reference: Option<PathBuf>,
    /// Run the one example given once, in this process, and print its JSON row only (the
    /// bench runs every run so, in a fresh process of its own).
    #[arg(long, hide = true)]
    pub worker: bool,
}

/// `curvenet demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Built-in surface to trace curves on (hill, tent, stadium, shell, dome, saddle, wave).
    #[arg(long, default_value = "dome")]
    pub surface: String,
    /// Number of random geodesics traced on it.
    #[arg(long, default_value_t = 24, value_parser = count(1, 10_000), allow_hyphen_values = true)]
    pub geodesics: usize,
    /// Seed of the geodesics.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub seed: u32,
    /// Target edge length h (the surface's largest extent is 4000).
    #[arg(long = "edge-length", default_value_t = 100.0, value_parser = positive, allow_hyphen_values = true)]
    pub edge_length: f64,
    /// Output folder.
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    #[arg(long, help = FORCE)]
    pub force: bool,
    /// Budget as a fraction of the total length, in (0, 1].
    #[arg(long, default_value_t = 0.3, value_parser = budget_fraction, allow_hyphen_values = true)]
    pub budget: f64,
    /// What runs after the greedy.
    #[command(flatten)]
    pub after: AfterGreedyArgs,
    /// Design constraints. Without any, the demo on the dome designs with its own: --connected
    /// and --max-gap 900 (22.5% of the surface's extent), left out with a note on networks
    /// where nothing can meet them (other surfaces run without constraints).
    #[command(flatten)]
    pub constraints: ConstraintArgs,
    /// Run the demo without its default constraints (the paper's problem alone).
    #[arg(long, conflicts_with_all = ["groups", "symmetry", "connected", "min_curves", "max_gap", "max_deviation"])]
    pub unconstrained: bool,
    /// Material and solver options.
    #[command(flatten)]
    pub physics: PhysicsArgs,
}

/// Material, solver and objective options shared by every command that analyses a network.
#[derive(Debug, Args, Clone)]
pub struct PhysicsArgs {
    /// Supports of open curves.
    #[arg(long, value_parser = Supports::from_str)]
    pub supports: Option<Supports>,
    /// Supports per curve end, by point or curve and end, overriding --supports (formats.md).
    #[arg(long = "supports-file")]
    pub supports_file: Option<PathBuf>,
    /// Rod radius (scene units; default 2).
    #[arg(long, value_parser = positive, allow_hyphen_values = true)]
    pub radius: Option<f64>,
    /// Young's modulus: a positive number in the paper's mode (default 1); with a stress unit
    /// in the physical mode (`--units`/`--material`, e.g. `210GPa`), overriding the material's.
    #[arg(long, value_parser = young, allow_hyphen_values = true)]
    pub young: Option<String>,
    /// Anchor weight µ (an anchor is a spring of stiffness 2µ; default 500).
    #[arg(long = "anchor-weight", value_parser = positive, allow_hyphen_values = true)]
    pub anchor_weight: Option<f64>,
    /// Number of smallest eigenvalues to report (1 to 100).
    #[arg(long = "eigen-count", default_value_t = 4, value_parser = count(1, MAX_EIGEN_COUNT as u64), allow_hyphen_values = true)]
    pub eigen_count: usize,
    /// Merge joints closer than this fraction of h, in (0, 1) (off by default; docs/model.md, "Numerical hazards").
    #[arg(long = "merge-joints", value_parser = open_fraction, allow_hyphen_values = true)]
    pub merge_joints: Option<f64>,
    /// What every search maximises and an analysis reports: lambda (the paper's λ_eq, the
    /// smallest eigenvalue of the Hessian at equilibrium) or frequency (the first natural
    /// frequency: μ_min of H v = μ M v with the lumped mass; in the paper's mode with unit
    /// density). See docs/units.md.
    #[arg(long, default_value = "lambda", value_parser = Objective::from_str)]
    pub objective: Objective,
}

/// Input files and network construction, shared by `analyze` and `simplify`.
#[derive(Debug, Args, Clone)]
pub struct InputArgs {
    /// Surface mesh: an OBJ file or a built-in surface name (hill, tent, stadium, shell,
    /// dome, saddle, wave); optional, used for reports and pictures.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// Curve files (.txt reference format, .obj polylines, .json); repeat for several files.
    /// Curve ids follow the loading order.
    #[arg(long)]
    pub curves: Vec<PathBuf>,
    /// Scale applied to the mesh and the curves.
    #[arg(long, default_value_t = 1.0, value_parser = positive, allow_hyphen_values = true)]
    pub scale: f64,
    /// Target edge length h (scene units, after scaling). Default: the median curve's length
    /// over 50, and no less than the total length over 100,000 (about 100,000 edges at most).
    #[arg(long = "edge-length", value_parser = positive, allow_hyphen_values = true)]
    pub edge_length: Option<f64>,
}

/// Budget, keep list and output of a greedy run.
#[derive(Debug, Args, Clone)]
pub struct GreedyArgs {
    /// Budget as a fraction of the total rest length of all curves, in (0, 1].
    #[arg(long, conflicts_with = "budget_length", value_parser = budget_fraction, allow_hyphen_values = true)]
    pub budget: Option<f64>,
    /// Budget as an absolute rest length (scene units).
    #[arg(long = "budget-length", value_parser = positive, allow_hyphen_values = true)]
    pub budget_length: Option<f64>,
    /// Curves never to remove (comma-separated ids).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub keep: Vec<usize>,
    /// Continue an interrupted run in the output folder.
    #[arg(long)]
    pub resume: bool,
    #[arg(long, help = FORCE)]
    pub force: bool,
    /// What runs after the greedy.
    #[command(flatten)]
    pub after: AfterGreedyArgs,
    /// Design constraints.
    #[command(flatten)]
    pub constraints: ConstraintArgs,
}

/// Design constraints every search honours (`docs/constraints.md`). Distances are in scene
/// units (after `--scale`).
#[derive(Debug, Args, Clone, Default)]
pub struct ConstraintArgs {
    /// Groups of curves kept or removed together: a text file, one group per line
    /// (`NAME: 0 1 4-7`); the JSON curve format's `"group"` fields add theirs.
    #[arg(long, value_name = "FILE")]
    pub groups: Option<PathBuf>,
    /// Keep the network symmetric: `rotate:N` (orbits under the rotation of order N about the
    /// detected axis kept or removed whole), `mirror`, `auto` (the largest symmetry found that
    /// leaves a choice within the budget) or `none`.
    #[arg(long, value_parser = SymmetryOption::from_str)]
    pub symmetry: Option<SymmetryOption>,
    /// The kept curves form one connected structure.
    #[arg(long)]
    pub connected: bool,
    /// Keep at least this many curves.
    #[arg(long = "min-curves", value_parser = count(1, 1_000_000), allow_hyphen_values = true)]
    pub min_curves: Option<usize>,
    /// No point of the surface farther than D from a kept curve (needs the mesh).
    #[arg(long = "max-gap", value_name = "D", value_parser = positive, allow_hyphen_values = true)]
    pub max_gap: Option<f64>,
    /// No vertex of the kept network farther than D from its designed place at equilibrium
    /// (the answer is chosen among networks that meet it); with --units, the physical model's
    /// under self-weight, in those units.
    #[arg(long = "max-deviation", value_name = "D", value_parser = positive, allow_hyphen_values = true)]
    pub max_deviation: Option<f64>,
}

/// What `demo`, `example` and `simplify` do after the greedy: the local search, the
/// alternatives and the certificate.
#[derive(Debug, Args, Clone)]
pub struct AfterGreedyArgs {
    /// After the greedy, compute a certificate of the answer: an upper bound no network
    /// within the budget can exceed on the stability at fixed geometry (λ_fix, at the full
    /// network's equilibrium), and how close the answer comes to it. Often the run's longest
    /// step, and loose on large networks.
    #[arg(long)]
    pub certify: bool,
    /// With --certify: branch and bound nodes spent tightening the certificate's bound
    /// (default: about 1e6 / unknowns, e.g. 220 on the demo, 60 on the tower; 0: the
    /// relaxation's bound only; at most 100000).
    #[arg(long = "certificate-nodes", value_parser = count(0, 100_000), allow_hyphen_values = true)]
    pub certificate_nodes: Option<usize>,
    /// After the greedy, run the local search from its final network (when within the
    /// budget), from the three stiffest single curves that fit the budget and, under
    /// --min-curves or --max-gap, from the three best networks grown to meet them (add / drop
    /// / swap moves with part steps, then variable-depth chains; `λ_eq` relaxed from the
    /// drawn state) and record its best network in result.json next to the greedy's
    /// (`local_search`).
    #[arg(long = "local-search")]
    pub local_search: bool,
    /// Record up to K alternatives to the answer: the best further stable networks within the
    /// budget and the constraints, by decreasing λ_eq, each distinct from the answer and from
    /// the others (the curves in one and not the other total at least 5% of the budget) and
    /// none a better network with curves added. Runs the local search (the networks it
    /// evaluated are where they come from); each is written as alternative-N.obj and
    /// alternative-N.csv and can be picked in the viewer. 0 (the default): none. At most 100.
    #[arg(long, value_name = "K", default_value_t = 0, value_parser = count(0, 100), allow_hyphen_values = true)]
    pub alternatives: usize,
    /// Then slide the answer's curves on the surface into the run folder's slide/ (see slide).
    #[arg(long)]
    pub slide: bool,
    #[command(flatten)]
    pub sliding: SlideArgs,
}

/// `curvenet analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// Inputs.
    #[command(flatten)]
    pub input: InputArgs,
    /// Curves to remove before the analysis (comma-separated ids).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub remove: Vec<usize>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Material and solver options.
    #[command(flatten)]
    pub physics: PhysicsArgs,
    /// The physical mode.
    #[command(flatten)]
    pub physical: PhysicalModeArgs,
}

/// The physical mode: given `--units` or `--material`, `analyze` also reports the structure
/// in physical terms (frequencies in Hz, deflections in scene units, stresses in MPa) with
/// `--radius` (scene units) or `--tube` as the rods' section, and `simplify`/`example` record
/// them for every iteration. See docs/units.md.
#[derive(Debug, Args, Clone, Default)]
pub struct PhysicalModeArgs {
    /// The scene's length unit: mm, cm or m (turns on the physical mode).
    #[arg(long, value_parser = physical(Opt::Units), allow_hyphen_values = true)]
    pub units: Option<String>,
    /// Material preset: steel, aluminium, gfrp, timber (turns on the physical mode).
    #[arg(long, value_parser = physical(Opt::Material), allow_hyphen_values = true)]
    pub material: Option<String>,
    /// Density with its unit, overriding the material's (e.g. 7850kg/m3).
    #[arg(long, value_parser = physical(Opt::Density), allow_hyphen_values = true)]
    pub density: Option<String>,
    /// Strength (yield or failure stress) with its unit, overriding the material's (e.g.
    /// 355MPa).
    #[arg(long, value_parser = physical(Opt::Strength), allow_hyphen_values = true)]
    pub strength: Option<String>,
    /// A round tube section instead of a solid one: outer diameter x wall (e.g. 60x4, scene
    /// units, or 60mmx4mm).
    #[arg(long, value_parser = physical(Opt::Tube), allow_hyphen_values = true)]
    pub tube: Option<String>,
    /// Intensity of the worst-case distributed load (default 1kN/m).
    #[arg(long, value_parser = physical(Opt::Load), allow_hyphen_values = true)]
    pub load: Option<String>,
    /// Gravity in m/s2: a magnitude along -z (default 9.81) or gx,gy,gz.
    #[arg(long, value_parser = physical(Opt::Gravity), allow_hyphen_values = true)]
    pub gravity: Option<String>,
    /// Load cases and combinations (JSON: self-weight, line loads, point loads, factored
    /// combinations; docs/units.md): each is followed as a nonlinear equilibrium, with its
    /// deflection, utilisation and critical load factor.
    #[arg(long, value_name = "FILE")]
    pub loads: Option<std::path::PathBuf>,
    /// The load cases' deflection limit: span/N (e.g. span/250) or a length (e.g. 20mm).
    #[arg(long, value_name = "LIMIT", allow_hyphen_values = true)]
    pub deflection_limit: Option<String>,
    /// The smallest acceptable critical load factor of a load case (default 1).
    #[arg(long, value_name = "FACTOR", allow_hyphen_values = true)]
    pub buckling_factor: Option<String>,
}

/// `curvenet simplify`.
#[derive(Debug, Args)]
pub struct SimplifyArgs {
    /// Inputs.
    #[command(flatten)]
    pub input: InputArgs,
    /// Budget and keep list.
    #[command(flatten)]
    pub greedy: GreedyArgs,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
    /// Material and solver options.
    #[command(flatten)]
    pub physics: PhysicsArgs,
    /// The physical mode (every iteration also records its physical numbers).
    #[command(flatten)]
    pub physical: PhysicalModeArgs,
}

/// `curvenet example`.
#[derive(Debug, Args)]
pub struct ExampleArgs {
    /// Example name: hill, roof, kagome, stadium, tower, shell, bunny, tent, arcshell.
    #[arg(required_unless_present = "license")]
    pub name: Option<String>,
    /// Print the licence and copyright of the paper's example data embedded in curvenet (MIT,
    /// Copyright (c) 2022 wwwnev) and exit.
    #[arg(long, exclusive = true)]
    pub license: bool,
    /// Folder holding the paper's data (`meshes/`, `curves/`) to read instead of the copies
    /// embedded in curvenet.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Output folder (default `out/NAME`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Only build and analyse the full network; do not simplify.
    #[arg(long = "analyze-only")]
    pub analyze_only: bool,
    /// Budget as a fraction of the total length, in (0, 1] (default: the example's).
    #[arg(long, value_parser = budget_fraction, allow_hyphen_values = true)]
    pub budget: Option<f64>,
    /// Continue an interrupted run in the output folder.
    #[arg(long)]
    pub resume: bool,
    #[arg(long, help = FORCE)]
    pub force: bool,
    /// What runs after the greedy.
    #[command(flatten)]
    pub after: AfterGreedyArgs,
    /// Design constraints.
    #[command(flatten)]
    pub constraints: ConstraintArgs,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Material and solver options.
    #[command(flatten)]
    pub physics: PhysicsArgs,
    /// The physical mode (every iteration also records its physical numbers).
    #[command(flatten)]
    pub physical: PhysicalModeArgs,
}

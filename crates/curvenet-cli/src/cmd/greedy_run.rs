//! Running the greedy from the command line: output folder, progress bar, signals, summary.

use super::{fmt_length, print_warnings};
use crate::args::GreedyArgs;
use crate::exit::{ExitError, usage};
use crate::signals::{self, Stage};
use curvenet::cancel::Cancel;
use curvenet::constraints::answer::{Answer, NoAnswer, choose};
use curvenet::constraints::{ConstraintError, ConstraintParams, Constraints};
use curvenet::io::{Polyline, TriMesh};
use curvenet::network::{BuildInfo, BuildParams, Network, build_network};
use curvenet::physics::PhysicalParams;
use curvenet::rod::ActiveSet;
use curvenet::run_folder::answer::{NetworkState, alternative_offers};
use curvenet::run_folder::folder::{FolderError, FolderLock, FreshStart, claim, fresh_start};
use curvenet::run_folder::schema::objective_name;
use curvenet::run_folder::{
    InputDescription, LocalSearchRecord, OutputWriter, ResultFile, RunSetup, evaluated_offer,
    greedy_offers, measure_greedy_deviations, read_f64_file, summary,
};
use curvenet::simplify::certificate::{
    Certificate, CertifyParams, certificate, tighten_certificate,
};
use curvenet::simplify::exhaustive::SubsetScore;
use curvenet::simplify::greedy::{IterationRecord, ResumePoint};
use curvenet::simplify::local::{LocalParams, local_search};
use curvenet::simplify::{Budget, GreedyOutcome, GreedyParams, SimplifyError, StopReason, greedy};
use curvenet::stability::fixed::FixedProblem;
use curvenet::stability::{Analyzer, Objective, Prepare, Preset, StabilityParams, Warm};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Everything a greedy run needs.
pub struct GreedyJob {
    pub curves: Vec<Polyline>,
    pub build: BuildParams,
    pub stability: StabilityParams,
    /// The physical mode's parameters: every iteration also records its physical numbers.
    pub physical: Option<PhysicalParams>,
    /// The physical mode's options as given (`None` in the paper's mode), recorded in the
    /// set-up a resumed run must match.
    pub physical_options: Option<curvenet::physics::PhysicalOptions>,
    pub input: InputDescription,
    pub budget: Budget,
    pub keep: Vec<usize>,
    pub out: PathBuf,
    pub resume: bool,
    /// Run into a non-empty folder that is not a curvenet run's.
    pub force: bool,
    /// Compute the fixed-geometry certificate of the result after the greedy.
    pub certificate: bool,
    /// Branch and bound nodes spent tightening the certificate (None: by network size).
    pub certificate_nodes: Option<usize>,
    /// Run the local search from the greedy's final network and record its answer.
    pub local_search: bool,
    /// Alternatives to record beside the answer (0: none).
    pub alternatives: usize,
    /// The surface, in scene units, written next to the result when known.
    pub mesh: Option<TriMesh>,
    /// Design constraints every search honours.
    pub constraints: ConstraintParams,
    /// The constraints are the command's own defaults, not the user's (`demo`): when nothing
    /// can meet them on this network, a note says so and the run goes on without them.
    pub default_constraints: bool,
}

/// The budget from the options, or `default` (a fraction) when none is given.
pub fn budget_of(a: &GreedyArgs, default: Option<f64>) -> anyhow::Result<Budget> {
    let b = match (a.budget, a.budget_length, default) {
        (Some(f), _, _) => Budget::Fraction(f),
        (None, Some(l), _) => Budget::Length(l),
        (None, None, Some(f)) => Budget::Fraction(f),
        (None, None, None) => {
            return Err(usage(
                "give a budget: --budget FRACTION or --budget-length L",
            ));
        }
    };
    b.validate().map_err(usage)?;
    Ok(b)
}

/// Builds the network, runs the greedy into `job.out` and prints a summary.
pub fn run_greedy(job: GreedyJob) -> anyhow::Result<()> {
    let start = Instant::now();
    let objective = job.stability.objective;
    if job.certificate && objective != Objective::Lambda {
        return Err(usage(format!(
            "--certify with --objective {}: the certificate bounds λ_fix, the paper's \
             objective at the full network's equilibrium, and its relaxation does not model \
             the mass metric of the first natural frequency (it changes with the set of \
             curves); drop --certify, or use --objective lambda",
            objective.name()
        )));
    }
    // Held to the end of the run: another run into the folder is refused meanwhile.
    let (_lock, fresh) = output_folder(&job.out, job.resume, job.force)?;
    let (network, info) = build_network(&job.curves, &job.build)?;
    let n = network.rods.len();
    let params = GreedyParams {
        keep: job.keep.clone(),
        ..GreedyParams::new(job.budget)
    };
    params.validate(n).map_err(usage)?;
    let total = network.total_length(&(0..n).collect::<Vec<_>>());
    let budget = job.budget.length(total);
    print_warnings(&start_warnings(&network, &info, &job.keep, budget, total));
    let (constraints, constraint_params) = constraints_of(&network, &job, budget)?;
    let setup = RunSetup {
        input: job.input,
        build: job.build.clone(),
        stability: job.stability.clone(),
        greedy: params.clone(),
        network: info.clone(),
        total_length: total,
        constraints: constraint_params,
        physical: job.physical_options.clone(),
    };
    let mut analyzer = Analyzer::new(network, job.stability).map_err(usage)?;
    if let Some(p) = job.physical {
        analyzer = analyzer.with_physical(p).map_err(usage)?;
    }
    let Some((writer, resume_point)) = open_writer(
        &job.out,
        job.resume,
        fresh.as_ref(),
        analyzer.network(),
        setup,
        job.mesh.as_ref(),
        budget,
    )?
    else {
        return Ok(());
    };

    // The greedy polls the signal flag through its writer; the stages after it poll the token.
    let bar = progress_bar();
    let progress = |r: &IterationRecord| show_progress(&bar, r, total, budget);
    if let Some(mesh) = &job.mesh {
        writer.write_mesh(mesh).map_err(failure)?;
    }
    let mut writer = writer.with_cancel(signals::flag()).with_progress(&progress);
    let stage = Stage::start();
    let outcome = greedy(
        &analyzer,
        &params,
        Some(&constraints),
        resume_point,
        &mut writer,
    );
    drop(stage);
    bar.finish_and_clear();
    let outcome =
        outcome.map_err(|e| greedy_error(e, writer.result().iterations.len(), &job.out))?;
    print_warnings(&curvenet::run_folder::unrelaxed(
        &outcome.iterations,
        analyzer.objective(),
    ));
    print_warnings(&curvenet::run_folder::unstable(
        &outcome.iterations,
        analyzer.objective(),
    ));
    print_warnings(budget_unmet(&outcome, budget).as_slice());
    let after = AfterGreedy {
        local_search: job.local_search,
        alternatives: job.alternatives,
        certificate: job.certificate,
        certificate_nodes: job.certificate_nodes,
    };
    let seconds = after.run(
        &analyzer,
        &params,
        &constraints,
        &outcome,
        &mut writer,
        &job.out,
    )?;
    let timings = serde_json::json!({
        "total_seconds": start.elapsed().as_secs_f64(),
        "greedy": outcome.timings,
        "certificate_seconds": job.certificate.then_some(seconds.certificate),
        "local_search_seconds": job.local_search.then_some(seconds.local_search),
        "alternatives_seconds": (job.alternatives > 0).then_some(seconds.alternatives),
        "threads": rayon::current_num_threads(),
    });
    writer.finish(&outcome, &timings).map_err(failure)?;
    write_pictures(&job.out);
    print_run_summary(writer.result(), seconds, start, &job.out);
    Ok(())
}

/// The warnings of a run's set-up that let it go on: a budget that removes nothing or that
/// the keep list alone exceeds, curves that cross nothing.
fn start_warnings(
    network: &Network,
    info: &BuildInfo,
    keep: &[usize],
    budget: f64,
    total: f64,
) -> Vec<String> {
    let mut warnings = Vec::new();
    if budget >= total {
        warnings.push(format!(
            "the budget {} is not below the total length {}: nothing will be removed",
            fmt_length(budget),
            fmt_length(total)
        ));
    }
    let kept_length = network.total_length(keep);
    if kept_length > budget {
        warnings.push(format!(
            "the keep list alone needs {}, more than the budget {}: the budget cannot be met",
            fmt_length(kept_length),
            fmt_length(budget)
        ));
    }
    if !info.isolated_curves.is_empty() {
        warnings.push(format!(
            "curves that cross nothing: {}",
            list(&info.isolated_curves)
        ));
    }
    warnings
}

/// The run's design constraints, their notes printed, and the settings in force. Infeasible
/// combinations stop the run here, before any work, saying why (the command's own default
/// constraints are dropped instead, with a note). Without design constraints a budget nothing
/// meets is only a warning ([`start_warnings`]): the greedy runs as ever.
fn constraints_of(
    network: &Network,
    job: &GreedyJob,
    budget: f64,
) -> anyhow::Result<(Constraints, ConstraintParams)> {
    let mut params = job.constraints.clone();
    let constraints = if params.is_default() {
        Constraints::none(network, budget, &job.keep)
    } else {
        match Constraints::new(network, job.mesh.as_ref(), &params, budget, &job.keep) {
            Ok(c) => c,
            Err(e) if job.default_constraints => {
                eprintln!("note: the default constraints are left out on this network: {e}");
                params = ConstraintParams::default();
                Constraints::none(network, budget, &job.keep)
            }
            Err(ConstraintError::Usage(m)) => return Err(usage(m)),
            Err(ConstraintError::Infeasible(m)) => {
                return Err(usage(format!("the constraints cannot be met: {m}")));
            }
        }
    };
    for note in constraints.notes() {
        eprintln!("note: {note}");
    }
    Ok((constraints, params))
}

/// The run folder's writer and the point to resume from: a new folder, or with `resume` the
/// recorded run in `out`. `None` when that run is already complete (its summary printed, its
/// pictures drawn if a stop had left them out).
fn open_writer<'a>(
    out: &Path,
    resume: bool,
    fresh: Option<&FreshStart>,
    network: &'a Network,
    setup: RunSetup,
    mesh: Option<&TriMesh>,
    budget: f64,
) -> anyhow::Result<Option<(OutputWriter<'a>, Option<ResumePoint>)>> {
    if !(resume && out.join("result.json").is_file()) {
        if let Some(fresh) = fresh
            && let Some(note) = fresh.apply().map_err(|e| usage(e.to_string()))?
        {
            eprintln!("note: {note}");
        }
        let writer = OutputWriter::create(out, network, setup, budget).map_err(failure)?;
        return Ok(Some((writer, None)));
    }
    let (writer, point) = OutputWriter::resume(out, network, &setup, mesh).map_err(usage)?;
    print_warnings(writer.warnings());
    match &point {
        None if writer.result().complete => {
            eprintln!("{}: the run is already complete", out.display());
            // A run stopped while its pictures were drawn is complete without them.
            if !out.join("viewer.html").is_file() {
                write_pictures(out);
            }
            print!("{}", summary(writer.result()));
            return Ok(None);
        }
        Some(p) => eprintln!(
            "resuming after iteration {} ({} curves)",
            p.iterations.len() - 1,
            p.iterations.last().map_or(0, |i| i.curves.len())
        ),
        None => {}
    }
    Ok(Some((writer, point)))
}

/// The greedy's progress bar: the share of the length to remove.
fn progress_bar() -> ProgressBar {
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:40} {percent}% of the length to remove, ETA {eta} {msg}")
            .expect("valid template"),
    );
    bar
}

/// Moves `bar` to iteration `r`: the share of `total - budget` removed, the curves left, λ
/// and (in the physical mode) the first frequency.
fn show_progress(bar: &ProgressBar, r: &IterationRecord, total: f64, budget: f64) {
    let done = ((total - r.length) / (total - budget).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    bar.set_position((done * 1000.0) as u64);
    let f1 = match r.physical.as_ref().map(|p| p.first_frequency_hz) {
        Some(Some(f)) => format!(", f₁ {f:.3} Hz"),
        Some(None) => ", unstable".to_string(),
        None => String::new(),
    };
    bar.set_message(format!("{} curves, λ {:.4e}{f1}", r.curves.len(), r.lambda));
}

/// The exit of a greedy that failed: 130 when cancelled (its `done` iterations kept in `out`
/// for `--resume`), the error otherwise.
fn greedy_error(e: SimplifyError, done: usize, out: &Path) -> anyhow::Error {
    match e {
        SimplifyError::Cancelled => ExitError {
            code: signals::CANCELLED,
            message: format!(
                "cancelled: {done} iteration(s) kept in {}; rerun with --resume to continue",
                out.display()
            ),
        }
        .into(),
        e => e.into(),
    }
}

/// A failure to write the run folder: exit 1 with its message.
fn failure(message: String) -> ExitError {
    ExitError { code: 1, message }
}

/// What runs after the greedy, each optional.
struct AfterGreedy {
    /// The local search from the greedy's final network.
    local_search: bool,
    /// Alternatives to record beside the answer (0: none).
    alternatives: usize,
    /// The fixed-geometry certificate of the answer.
    certificate: bool,
    /// Branch and bound nodes spent tightening the certificate (None: by network size).
    certificate_nodes: Option<usize>,
}

/// The seconds the steps after the greedy took (0 for a step that did not run).
#[derive(Clone, Copy)]
struct AfterSeconds {
    local_search: f64,
    alternatives: f64,
    certificate: f64,
}

impl AfterGreedy {
    /// The local search, the answer and the alternatives, and the certificate, recorded in
    /// `writer`; exit 130 when a signal came during a step.
    fn run(
        &self,
        analyzer: &Analyzer,
        params: &GreedyParams,
        constraints: &Constraints,
        outcome: &GreedyOutcome,
        writer: &mut OutputWriter<'_>,
        out: &Path,
    ) -> anyhow::Result<AfterSeconds> {
        let cancel = signals::token();
        let (local, local_seconds) = optional_step(self.local_search, "local search", || {
            let _stage = Stage::start();
            local_search_of(analyzer, params, constraints, outcome, &cancel)
        });
        stop_if_cancelled(&cancel, "the local search", out)?;
        let (local, visited) = local.map_or((None, Vec::new()), |(r, v)| (Some(r), v));
        let local_eval = local
            .as_ref()
            .and_then(|l| evaluate_curves(analyzer, &l.curves, "local search's network"));
        writer.set_local_search(local);
        let alternatives_start = Instant::now();
        let chosen = {
            let _stage = Stage::start();
            let found = Found {
                local: local_eval,
                visited: &visited,
                alternatives: self.alternatives,
            };
            answer_of(analyzer, constraints, outcome, found, &cancel, out)
        };
        let alternatives_seconds = alternatives_start.elapsed().as_secs_f64();
        stop_if_cancelled(&cancel, "the search for alternatives", out)?;
        if self.alternatives > chosen.alternatives.len() {
            eprintln!(
                "note: {} alternative(s) asked for, {} found: the searches met no other stable \
                 network within the budget and the constraints that is distinct from these and \
                 not one of them with curves added",
                self.alternatives,
                chosen.alternatives.len()
            );
        }
        // The certificate is of the answer (the greedy's final network when there is none).
        let certified = match &chosen.answer {
            Ok(a) => Some(a.found.curves.clone()),
            Err(_) => outcome.iterations.last().map(|it| it.curves.clone()),
        };
        writer.set_answer(chosen.answer, chosen.state);
        writer.set_alternatives(chosen.alternatives);
        let (certificate, certificate_seconds) =
            optional_step(self.certificate, "certificate", || {
                let _stage = Stage::start();
                certificate_of(
                    analyzer,
                    out,
                    params,
                    constraints,
                    outcome,
                    certified.as_deref().unwrap_or_default(),
                    self.certificate_nodes,
                    &cancel,
                )
            });
        stop_if_cancelled(&cancel, "the certificate", out)?;
        writer.set_certificate(certificate);
        Ok(AfterSeconds {
            local_search: local_seconds,
            alternatives: alternatives_seconds,
            certificate: certificate_seconds,
        })
    }
}

/// The finished run's summary on stdout: the result, the last network's physical numbers,
/// the times of the steps that ran and where the output is.
fn print_run_summary(result: &ResultFile, seconds: AfterSeconds, start: Instant, out: &Path) {
    print!("{}", summary(result));
    if let Some(line) = physical_line(result.iterations.last()) {
        println!("{line}");
    }
    if result.local_search.is_some() {
        println!("local search time: {:.2} s", seconds.local_search);
    }
    if result.certificate.is_some() {
        println!("certificate time: {:.2} s", seconds.certificate);
    }
    println!(
        "wall time: {:.2} s; output in {}",
        start.elapsed().as_secs_f64(),
        out.display()
    );
}

/// The last network's physical numbers in one line (the physical mode only).
fn physical_line(last: Option<&IterationRecord>) -> Option<String> {
    let p = last?.physical.as_ref()?;
    let opt = |v: Option<f64>, unit: &str| {
        v.map_or("none (unstable)".into(), |v| format!("{v:.4} {unit}"))
    };
    let mut line = format!(
        "physical (last network): first frequency {}, self-weight deflection {}, worst-load \
         deflection {}, assembly bending stress {:.1} MPa, mass {:.2} kg",
        opt(p.first_frequency_hz, "Hz"),
        opt(p.self_weight_max_deflection, "(scene units)"),
        opt(p.load_max_deflection, "(scene units)"),
        p.assembly_max_bending_stress_mpa,
        p.mass_kg
    );
    if let Some(u) = p.max_utilisation {
        line.push_str(&format!(", utilisation {u:.3}"));
    }
    if !p.overstressed_curves.is_empty() {
        line.push_str(&format!(
            ", curves that would break when bent: {}",
            list(&p.overstressed_curves)
        ));
    }
    Some(line)
}

/// Writes the pictures, viewer page (last) and fabrication table of the finished run in `out`.
/// A failure leaves the run's results intact, so it is a warning.
fn write_pictures(out: &Path) {
    match curvenet::report::viewer::write_run_outputs(out) {
        Ok(o) => print_warnings(&o.warnings),
        Err(e) => print_warnings(&[format!("pictures and viewer not written: {e}")]),
    }
}

/// Makes sure `out` is (or can be made) a folder and locks it for this run (a resumed run's
/// stale temporary files removed), before any work:
/// a file there, a folder that cannot be created, one another run holds, or (for a fresh run)
/// a non-empty folder that is no curvenet run's without `force`, is a usage error naming it.
/// A fresh run gets what it removes of an earlier run's files once it starts writing.
fn output_folder(
    out: &std::path::Path,
    resume: bool,
    force: bool,
) -> anyhow::Result<(FolderLock, Option<FreshStart>)> {
    if out.exists() && !out.is_dir() {
        return Err(usage(format!(
            "--out {}: is a file, not a folder; give a folder for the run's outputs",
            out.display()
        )));
    }
    std::fs::create_dir_all(out).map_err(|e| {
        usage(format!(
            "--out {}: cannot create the folder: {e}",
            out.display()
        ))
    })?;
    let folder_error = |e: FolderError| usage(format!("--out {e}"));
    let resuming = resume && out.join("result.json").is_file();
    let held = claim(out, resuming).map_err(folder_error)?;
    let lock = held.lock;
    if let Some(w) = &lock.warning {
        print_warnings(std::slice::from_ref(w));
    }
    if held.stale_temp_files > 0 {
        eprintln!(
            "note: {}: removed {} temporary file(s) a stopped run left",
            out.display(),
            held.stale_temp_files
        );
    }
    if resuming {
        return Ok((lock, None));
    }
    let fresh = fresh_start(out, force).map_err(folder_error)?;
    Ok((lock, Some(fresh)))
}

/// The warning of a run that ended without meeting its budget: what it ended at and why.
fn budget_unmet(outcome: &GreedyOutcome, budget: f64) -> Option<String> {
    let last = outcome.iterations.last()?;
    let why = match outcome.stop {
        StopReason::BudgetMet => return None,
        StopReason::BudgetUnmet if last.curves.len() == 1 => {
            "a single curve is left, and it alone is longer than the budget"
        }
        StopReason::BudgetUnmet => "only curves of the keep list are left",
        StopReason::NoScorableCandidate => "no curve could be scored for removal",
        StopReason::RemovalLimit => "the removal limit was reached",
        StopReason::Blocked => "the design constraints allow no further removal",
    };
    Some(format!(
        "the budget {} was not met: the run ended at {} curve(s) of total length {} ({why}); \
         the final network is over the budget",
        fmt_length(budget),
        last.curves.len(),
        fmt_length(last.length)
    ))
}

/// What the searches after the greedy found, offered beside the greedy's path.
struct Found<'v> {
    /// The local search's network, evaluated in full, when it ran.
    local: Option<curvenet::stability::Evaluation>,
    /// The feasible sets the local search evaluated, best first.
    visited: &'v [SubsetScore],
    /// Alternatives asked for.
    alternatives: usize,
}

/// The answer and the alternatives, each with its equilibrium and mode when it is not one of
/// the greedy's iterations.
struct Chosen {
    answer: Result<Answer, NoAnswer>,
    state: Option<NetworkState>,
    alternatives: Vec<(Answer, Option<NetworkState>)>,
}

/// The run's answer among the greedy's iterations, the local search's network (when it
/// ran, evaluated in full) and, with `--alternatives`, the best distinct networks the local
/// search evaluated (each evaluated in full); and the alternatives. With `--max-deviation`,
/// each greedy iteration's deviation is measured on its state in the run folder `out`.
fn answer_of(
    analyzer: &Analyzer,
    constraints: &Constraints,
    outcome: &GreedyOutcome,
    found: Found<'_>,
    cancel: &Cancel,
    out: &Path,
) -> Chosen {
    let mut offers = greedy_offers(&outcome.iterations);
    if constraints.params().max_deviation.is_some()
        && let Err(e) = measure_greedy_deviations(&mut offers, out, analyzer.network())
    {
        print_warnings(&[format!(
            "the greedy's deviations could not all be measured ({e}); iterations left \
             unmeasured are not offered as the answer"
        )]);
    }
    let mut states: Vec<(Vec<usize>, NetworkState)> = Vec::new();
    if let Some(e) = &found.local {
        offers.push(evaluated_offer("local_search", e, analyzer.network()));
        states.push((e.curves.clone(), NetworkState::of(e)));
    }
    let more = alternative_offers(
        analyzer,
        constraints,
        &offers,
        found.visited,
        "local_search",
        found.alternatives,
        cancel,
    );
    for (o, s) in more {
        states.push((o.curves.clone(), s));
        offers.push(o);
    }
    let choice = choose(constraints, &offers, found.alternatives);
    let state_of = |a: &Answer| {
        a.found
            .iteration
            .is_none()
            .then(|| {
                states
                    .iter()
                    .find(|s| s.0 == a.found.curves)
                    .map(|s| s.1.clone())
            })
            .flatten()
    };
    Chosen {
        state: choice.answer.as_ref().ok().and_then(state_of),
        alternatives: choice
            .alternatives
            .iter()
            .map(|a| (a.clone(), state_of(a)))
            .collect(),
        answer: choice.answer,
    }
}

/// `curves` relaxed and its spectrum computed (a warning and `None` when that fails).
fn evaluate_curves(
    analyzer: &Analyzer,
    curves: &[usize],
    what: &str,
) -> Option<curvenet::stability::Evaluation> {
    let active = ActiveSet::from_curves(analyzer.network().rods.len(), curves);
    analyzer
        .evaluate(&active, Warm::default(), Preset::Analysis, Prepare::Nothing)
        .map_err(|e| print_warnings(&[format!("the {what} could not be evaluated: {e}")]))
        .ok()
}

/// The local search (its default: descent with part steps, then variable-depth chains) from
/// the greedy's final network (when it is within the budget) and from the best single curves,
/// with the run's budget, keep list and constraints.
fn local_search_of(
    analyzer: &Analyzer,
    params: &GreedyParams,
    constraints: &Constraints,
    outcome: &GreedyOutcome,
    cancel: &Cancel,
) -> anyhow::Result<(LocalSearchRecord, Vec<SubsetScore>)> {
    let last = outcome
        .iterations
        .last()
        .ok_or_else(|| anyhow::anyhow!("no iteration"))?;
    let local = LocalParams {
        keep: params.keep.clone(),
        ..LocalParams::new(params.budget)
    };
    let o = local_search(analyzer, &local, Some(constraints), &last.curves, cancel)?;
    let mut record = LocalSearchRecord::new(&local, &o, &last.curves)
        .ok_or_else(|| anyhow::anyhow!("λ_eq could not be evaluated"))?;
    record.objective = objective_name(analyzer.objective()).into();
    Ok((record, o.visited))
}

/// Exit 130 once a signal came during `stage`: the greedy's iterations stay recorded in `out`,
/// and `--resume` goes on from them.
fn stop_if_cancelled(cancel: &Cancel, stage: &str, out: &Path) -> anyhow::Result<()> {
    if !cancel.is_cancelled() {
        return Ok(());
    }
    Err(ExitError {
        code: signals::CANCELLED,
        message: format!(
            "cancelled during {stage}: the greedy's iterations are kept in {}; rerun with \
             --resume to continue",
            out.display()
        ),
    }
    .into())
}

/// Runs an optional step after the greedy when `on`: its result, or `None` with a warning
/// when it fails (the greedy's results stand either way; a cancelled step is no failure), and
/// the seconds it took.
fn optional_step<T>(
    on: bool,
    what: &str,
    run: impl FnOnce() -> anyhow::Result<T>,
) -> (Option<T>, f64) {
    let start = Instant::now();
    let result = if on {
        run()
            .map_err(|e| {
                if !signals::cancelled() {
                    print_warnings(&[format!("no {what}: {e}")]);
                }
            })
            .ok()
    } else {
        None
    };
    (result, start.elapsed().as_secs_f64())
}

/// The fixed-geometry certificate of `curves` (the answer): `λ_fix` at the full network's
/// equilibrium (iteration 0's state) against the relaxation's certified bound on any network
/// within the budget.
#[allow(clippy::too_many_arguments)]
fn certificate_of(
    analyzer: &Analyzer,
    out: &Path,
    params: &GreedyParams,
    constraints: &Constraints,
    outcome: &GreedyOutcome,
    curves: &[usize],
    nodes: Option<usize>,
    cancel: &Cancel,
) -> anyhow::Result<Certificate> {
    let n = analyzer.network().rods.len();
    let full_state = outcome
        .iterations
        .first()
        .filter(|it| it.curves.len() == n)
        .and_then(|_| read_f64_file(&out.join("states/0000.bin")).ok());
    let problem = match full_state {
        Some(u) => FixedProblem::with_displacement(analyzer, u, params.budget, &params.keep)?,
        None => FixedProblem::new(analyzer, params.budget, &params.keep)?,
    };
    if curves.is_empty() || !problem.feasible(curves) {
        anyhow::bail!("the final network does not meet the budget");
    }
    let mut c = certificate(&problem, curves, &CertifyParams::default(), cancel)?;
    // Branch and bound nodes: as given, or about 1e6 unknowns' worth of eigen solves.
    let nodes = nodes.unwrap_or_else(|| (1e6 / analyzer.model().dofs().max(1) as f64) as usize);
    tighten_certificate(
        &problem,
        &mut c,
        Some(constraints),
        nodes.min(100_000),
        cancel,
    )?;
    Ok(c)
}

/// Curve ids as a user reads them: `3, 5, 8`.
fn list(ids: &[usize]) -> String {
    ids.iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

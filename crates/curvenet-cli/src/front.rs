//! The command line's side of the application layer: how it spells options ([`Flags`]),
//! what it shows while a run goes ([`Console`]: warnings and notes on stderr, the progress
//! bar, the signal handler's stages) and how an [`AppError`] becomes an exit code.

use crate::exit::ExitError;
use crate::signals::{self, Stage as SignalStage};
use curvenet::app::{AppError, Observer, Stage};
use curvenet::report::ReportError;
use curvenet::simplify::greedy::IterationRecord;
use curvenet::words::{Message, Opt, Wording};
use indicatif::{ProgressBar, ProgressStyle};
use std::sync::Mutex;

/// Options as the command line spells them: `--max-gap`, `--max-gap 900`.
pub struct Flags;

impl Wording for Flags {
    fn option(&self, opt: Opt) -> String {
        format!("--{}", opt.key().replace('_', "-"))
    }
}

/// A message in the command line's words.
pub fn say(m: &Message) -> String {
    m.render(&Flags)
}

/// An export's or a picture's error as the command line reports it: exit 2 when the run
/// folder read is at fault (missing or damaged files, a network it lacks: bad input), 1
/// otherwise.
pub fn report_exit(e: &ReportError) -> ExitError {
    ExitError {
        code: if e.is_input() { 2 } else { 1 },
        message: e.render(&Flags),
    }
}

/// The error of the application layer as the command line reports it: exit 2 for what the
/// user can fix, 130 when cancelled, 1 otherwise.
pub fn fail(e: AppError) -> anyhow::Error {
    let code = match &e {
        AppError::Cancelled { .. } => signals::CANCELLED,
        e if e.is_input() => 2,
        _ => 1,
    };
    ExitError {
        code,
        message: e.render(&Flags),
    }
    .into()
}

/// Prints warnings on stderr, one per line: `warning: …`, or as they are when they already read
/// `file:line: warning: …` (the findings of the readers).
pub fn print_warnings(warnings: &[String]) {
    for w in warnings {
        if w.contains(": warning: ") {
            eprintln!("{w}");
        } else {
            eprintln!("warning: {w}");
        }
    }
}

/// Prints the library's warnings in the command line's words, as [`print_warnings`] does.
pub fn print_messages(warnings: &[Message]) {
    print_warnings(&warnings.iter().map(say).collect::<Vec<_>>());
}

/// What a run shows on the terminal while it goes.
pub struct Console {
    bar: Mutex<Option<ProgressBar>>,
    stages: Mutex<Vec<SignalStage>>,
}

impl Console {
    /// A console with no progress bar yet (one appears with the first iteration).
    pub fn new() -> Self {
        Console {
            bar: Mutex::new(None),
            stages: Mutex::new(Vec::new()),
        }
    }

    fn clear_bar(&self) {
        if let Some(bar) = self.bar.lock().unwrap_or_else(|e| e.into_inner()).take() {
            bar.finish_and_clear();
        }
    }
}

impl Observer for Console {
    fn warning(&self, warning: &Message) {
        self.clear_bar();
        print_warnings(&[say(warning)]);
    }

    fn note(&self, note: &Message) {
        self.clear_bar();
        eprintln!("note: {}", say(note));
    }

    fn iteration(&self, r: &IterationRecord, total: f64, budget: f64) {
        let mut bar = self.bar.lock().unwrap_or_else(|e| e.into_inner());
        let bar = bar.get_or_insert_with(progress_bar);
        let done = ((total - r.length) / (total - budget).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        bar.set_position((done * 1000.0) as u64);
        let f1 = match r.physical.as_ref().map(|p| p.first_frequency_hz) {
            Some(Some(f)) => format!(", f₁ {f:.3} Hz"),
            Some(None) => ", unstable".to_string(),
            None => String::new(),
        };
        bar.set_message(format!("{} curves, λ {:.4e}{f1}", r.curves.len(), r.lambda));
    }

    fn slide_step(&self, s: &curvenet::slide::Step) {
        eprintln!(
            "sliding: {} networks evaluated, best {:.6e}",
            s.evaluation, s.value
        );
    }

    fn stage(&self, stage: Stage, started: bool) {
        let mut stages = self.stages.lock().unwrap_or_else(|e| e.into_inner());
        if started {
            stages.push(SignalStage::start());
        } else {
            stages.pop();
            if stage == Stage::Greedy {
                drop(stages);
                self.clear_bar();
            }
        }
    }
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

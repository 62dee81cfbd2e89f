//! `curvenet serve --bench`: the latency of edits at the server beside cold analyses of the
//! same structures, measured in one process, one after the other.
//!
//! The sequence is fixed by a seed: starting from the design's structure `A`, curve `c₀` is
//! removed, then for each next `cᵢ` (drawn among the kept curves) `cᵢ` is removed and
//! `cᵢ₋₁` restored — every state `A − cᵢ₋₁ − cᵢ` and `A − cᵢ` new, so each edit is computed
//! (a removal, then a restore) — and `c_last` is restored. Each computed state is then
//! analysed cold (from the drawn state, with the gravity deflection, as
//! `curvenet analyze --remove` does) right after its edit, so both see the same machine.
//! Last, every `cᵢ` is removed and restored again: sets analysed before, answered from the
//! cache.

use crate::design::{Design, DesignError, Source, Status};
use curvenet::profile::{self, Snapshot};
use curvenet::rng::SplitMix64;
use std::fmt::Write as _;
use std::time::Instant;

/// What the benchmark runs.
#[derive(Clone, Copy, Debug)]
pub struct BenchParams {
    /// Curves removed (each later restored).
    pub removals: usize,
    /// Seed of the curves drawn.
    pub seed: u64,
}

impl Default for BenchParams {
    fn default() -> Self {
        BenchParams {
            removals: 12,
            seed: 1,
        }
    }
}

/// Removal or restore.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// A curve removed.
    Remove,
    /// A curve restored.
    Restore,
}

/// One edit of the sequence.
#[derive(Clone, Debug)]
pub struct EditRow {
    /// Removal or restore.
    pub op: Op,
    /// The curve.
    pub curve: usize,
    /// Where the server's answer came from.
    pub source: Source,
    /// Server-side milliseconds.
    pub ms: f64,
    /// `λ` served.
    pub lambda: f64,
    /// The state's status.
    pub status: Status,
    /// The cold analysis of the same set (computed edits only): milliseconds and `λ`.
    pub cold: Option<(f64, f64)>,
    /// Where the edit's time went (the library's phase timers, over the edit alone).
    pub phases: Snapshot,
}

/// The benchmark's edits.
#[derive(Clone, Debug)]
pub struct BenchReport {
    /// Curves in the network.
    pub curves: usize,
    /// Vertices in the network.
    pub vertices: usize,
    /// Every edit, in order.
    pub edits: Vec<EditRow>,
}

/// Runs the sequence of `params` on `design` (left at its starting structure).
///
/// # Errors
///
/// A failed analysis, or a structure too small for the sequence (it needs two curves).
pub fn run(design: &Design, params: BenchParams) -> Result<BenchReport, DesignError> {
    let start = design.current().summary.curves.clone();
    if start.len() < 2 {
        return Err(DesignError::Empty);
    }
    let analyzer = design.analyzer();
    let mut rng = SplitMix64::new(params.seed);
    let mut edits = Vec::new();
    let mut removed = Vec::new();
    let edit = |op: Op, curve: usize, edits: &mut Vec<EditRow>| -> Result<(), DesignError> {
        profile::reset();
        let e = design.toggle(curve)?;
        let phases = profile::snapshot();
        let cold = if e.source == Source::Cache {
            None
        } else {
            let set = analyzer.set(&e.summary.curves);
            let t = Instant::now();
            let a = analyzer
                .analyze(&set, None)
                .map_err(DesignError::Analysis)?;
            Some((t.elapsed().as_secs_f64() * 1e3, a.lambda()))
        };
        edits.push(EditRow {
            op,
            curve,
            source: e.source,
            ms: e.elapsed.as_secs_f64() * 1e3,
            lambda: e.summary.lambda,
            status: e.summary.status,
            cold,
            phases,
        });
        Ok(())
    };
    for i in 0..params.removals {
        let kept = design.current().summary.curves.clone();
        let c = kept[rng.below(kept.len() as u64) as usize];
        edit(Op::Remove, c, &mut edits)?;
        if i > 0 {
            edit(Op::Restore, removed[i - 1], &mut edits)?;
        }
        removed.push(c);
    }
    if let Some(&last) = removed.last() {
        edit(Op::Restore, last, &mut edits)?;
    }
    for &c in &removed {
        edit(Op::Remove, c, &mut edits)?;
        edit(Op::Restore, c, &mut edits)?;
    }
    Ok(BenchReport {
        curves: analyzer.curve_count(),
        vertices: analyzer.network().vertex_count(),
        edits,
    })
}

/// Median and 90th percentile (nearest rank) of `ms`; zeros when empty.
pub fn median_p90(mut ms: Vec<f64>) -> (f64, f64) {
    if ms.is_empty() {
        return (0.0, 0.0);
    }
    ms.sort_by(f64::total_cmp);
    let rank = |q: f64| ms[((q * ms.len() as f64).ceil() as usize).clamp(1, ms.len()) - 1];
    let n = ms.len();
    let median = if n % 2 == 1 {
        ms[n / 2]
    } else {
        0.5 * (ms[n / 2 - 1] + ms[n / 2])
    };
    (median, rank(0.9))
}

impl BenchReport {
    /// Server-side milliseconds of the edits `keep` selects.
    fn ms(&self, keep: impl Fn(&EditRow) -> bool) -> Vec<f64> {
        self.edits
            .iter()
            .filter(|e| keep(e))
            .map(|e| e.ms)
            .collect()
    }

    /// Median and 90th percentile of the computed edits (not from the cache).
    pub fn computed(&self) -> (f64, f64) {
        median_p90(self.ms(|e| e.source != Source::Cache))
    }

    /// Median and 90th percentile of the cold analyses.
    pub fn cold(&self) -> (f64, f64) {
        median_p90(
            self.edits
                .iter()
                .filter_map(|e| e.cold.map(|c| c.0))
                .collect(),
        )
    }

    /// The largest relative difference between a served `λ` and the cold one, over the
    /// stable states.
    pub fn largest_difference(&self) -> f64 {
        self.edits
            .iter()
            .filter(|e| e.status == Status::Stable)
            .filter_map(|e| e.cold.map(|(_, l)| (e.lambda - l).abs() / l.abs()))
            .fold(0.0, f64::max)
    }

    /// The report as text: a line per edit, then the medians and the speed-up.
    pub fn text(&self, name: &str) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "serve bench: {name}, {} curves, {} vertices",
            self.curves, self.vertices
        );
        let _ = writeln!(
            s,
            "{:<8} {:>5} {:<6} {:>9} {:>14} {:<9} {:>9} {:>10}",
            "edit", "curve", "from", "ms", "λ", "status", "cold ms", "Δλ/λ"
        );
        for e in &self.edits {
            let op = match e.op {
                Op::Remove => "remove",
                Op::Restore => "restore",
            };
            let source = match e.source {
                Source::Cache => "cache",
                Source::Warm => "warm",
                Source::Drawn => "drawn",
            };
            let status = e.status.word();
            let (cold_ms, diff) = match e.cold {
                Some((ms, l)) => (
                    format!("{ms:.1}"),
                    format!("{:.1e}", (e.lambda - l).abs() / l.abs()),
                ),
                None => (String::from("-"), String::from("-")),
            };
            let _ = writeln!(
                s,
                "{op:<8} {:>5} {source:<6} {:>9.1} {:>14.6e} {status:<9} {cold_ms:>9} {diff:>10}",
                e.curve, e.ms, e.lambda
            );
        }
        let count = |src: Source| self.edits.iter().filter(|e| e.source == src).count();
        let part = |op: Op| median_p90(self.ms(|e| e.op == op && e.source != Source::Cache));
        let (med, p90) = self.computed();
        let (rm, _) = part(Op::Remove);
        let (rs, _) = part(Op::Restore);
        let (cmed, cp90) = self.cold();
        let (hit, hit90) = median_p90(self.ms(|e| e.source == Source::Cache));
        let _ = writeln!(
            s,
            "computed edits: {} ({} warm, {} from the drawn state): median {med:.1} ms, p90 {p90:.1} ms (removals {rm:.1}, restores {rs:.1})",
            count(Source::Warm) + count(Source::Drawn),
            count(Source::Warm),
            count(Source::Drawn)
        );
        let _ = writeln!(
            s,
            "from the cache: {}: median {hit:.3} ms, p90 {hit90:.3} ms",
            count(Source::Cache)
        );
        let _ = writeln!(
            s,
            "cold analyze --remove of the same sets: median {cmed:.1} ms, p90 {cp90:.1} ms"
        );
        let speedup = if med > 0.0 { cmed / med } else { f64::INFINITY };
        let _ = writeln!(
            s,
            "speed-up (cold median / computed edit median): {speedup:.1}x; largest |Δλ|/λ over stable states: {:.1e}",
            self.largest_difference()
        );
        s.push_str(&self.phases());
        s
    }

    /// Where the warm edits' time goes: medians over them of each phase's milliseconds and
    /// calls (the phases overlap: the relaxation holds its factorizations and solves).
    fn phases(&self) -> String {
        let warm: Vec<&Snapshot> = self
            .edits
            .iter()
            .filter(|e| e.source == Source::Warm)
            .map(|e| &e.phases)
            .collect();
        if warm.is_empty() {
            return String::new();
        }
        let median =
            |f: &dyn Fn(&Snapshot) -> f64| median_p90(warm.iter().map(|p| f(p)).collect()).0;
        let phase = |name: &str, f: &dyn Fn(&Snapshot) -> profile::PhaseTotal| {
            format!(
                "{name} {:.1} ms ({})",
                median(&|p| f(p).seconds * 1e3),
                median(&|p| f(p).calls as f64)
            )
        };
        format!(
            "a warm edit's phases (medians, ms and calls): {}, {}; within them {}, {}, {}\n",
            phase("relaxation", &|p| p.relax),
            phase("spectrum", &|p| p.eigen),
            phase("factorizations", &|p| p.factor),
            phase("solves", &|p| p.solve),
            phase("assembly", &|p| p.assemble),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::median_p90;

    #[test]
    fn medians_and_percentiles() {
        assert_eq!(median_p90(vec![]), (0.0, 0.0));
        assert_eq!(median_p90(vec![3.0, 1.0, 2.0]), (2.0, 3.0));
        let ten: Vec<f64> = (1..=10).map(f64::from).collect();
        assert_eq!(median_p90(ten), (5.5, 9.0));
    }
}

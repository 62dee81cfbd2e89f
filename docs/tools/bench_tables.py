#!/usr/bin/env python3
"""The measured tables of docs/benchmarks.md, regenerated from `curvenet bench --json` and the
user's own commands.

    python3 docs/tools/bench_tables.py [--curvenet PATH] [--examples A,B] [--repeat N]
                                      [--reference FILE] [--reference-command CMD]
                                      [--techniques A,B] [--sections S,T]
                                      [--wait-load L] [--quick] [--stdout] [--check]

Three sections of docs/benchmarks.md are generated, each between the markers
`<!-- bench_tables:NAME begin -->` and `<!-- bench_tables:NAME end -->` (everything outside
them is left as it is):

- `commands`: each example's greedy as `curvenet bench --examples NAME --json` times it
  (wall, CPU and peak memory of the greedy, in a process of its own) beside the user's
  command `curvenet example NAME --out DIR` timed as a whole process (wall, CPU and peak
  memory from `os.wait4`), their ratio, and the bench's counts and phase times.
- `reference`: the same medians beside the reference implementation's times from a file of
  seconds by example (`docs/tools/reference-times.json`, the format `bench --reference`
  reads). With `--reference-command CMD` the reference is timed side by side instead: in
  each round, before each example's bench and user's command, `CMD` (a shell command, `{example}`
  replaced by the example's name) runs as a whole process (wall time and peak memory from
  `os.wait4`); the section shows the medians of those runs, and the script writes them to
  the reference file (the times `bench --reference` then shows), unless it ran one round.
- `techniques`: `bench --off NAME` for each technique `bench --help` names (and
  `--threads 1`): its wall time divided by the wall time with everything on. A
  configuration whose removals differ from the default's is refused (its cells say so and
  the script exits 1 after writing).

The runs go in rounds (each example's bench and example, then every technique, then the
bench with everything on again, once per round), so the machine's drift touches them alike;
each figure is the median over the rounds (the techniques' baseline over both runs with
everything on).
Every section states the command, the date, the repository's commit, the binary, the
machine's load average before and after the runs and the range of the load at each run's start
(`--wait-load L` waits before each run for the 1-minute load to fall below L). `--quick` is tower only, one round: a check
that the tables regenerate, not a measurement to quote. `--check` runs nothing: it verifies
the markers and that the reference file parses, and exits 1 on a problem.

Python 3 standard library only.
"""

import argparse
import datetime
import json
import math
import os
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "benchmarks.md"
REFERENCE = ROOT / "docs" / "tools" / "reference-times.json"
SECTIONS = ("commands", "reference", "techniques")
DEFAULT_EXAMPLES = "tower,arcshell,shell"
TARGET_RATIO = 50.0


def marker(name, edge):
    return f"<!-- bench_tables:{name} {edge} -->"


# ---------------------------------------------------------------------------------------------
# Checks that need no run


def read_references(path):
    """The reference times, seconds by example: a JSON object of positive numbers."""
    data = json.loads(Path(path).read_text())
    if not isinstance(data, dict) or not data:
        raise ValueError(f"{path}: expected a non-empty JSON object of seconds by example")
    for name, s in data.items():
        if isinstance(s, bool) or not isinstance(s, (int, float)) or not (math.isfinite(s) and s > 0):
            raise ValueError(f"{path}: {name}: {s!r} is not a positive number of seconds")
    return {k: float(v) for k, v in data.items()}


def marker_problems(text, names=SECTIONS):
    """What is wrong with the generated sections' markers in `text` (empty: nothing)."""
    problems = []
    for name in names:
        begin, end = marker(name, "begin"), marker(name, "end")
        nb, ne = text.count(begin), text.count(end)
        if nb != 1 or ne != 1:
            problems.append(f"section {name}: {nb} begin and {ne} end markers (want one each)")
        elif text.index(begin) > text.index(end):
            problems.append(f"section {name}: its end marker comes before its begin marker")
    return problems


def check(doc, reference):
    problems = marker_problems(doc.read_text())
    try:
        read_references(reference)
    except (OSError, ValueError) as e:
        problems.append(f"reference file: {e}")
    for p in problems:
        print(f"bench_tables: {p}", file=sys.stderr)
    if not problems:
        print(f"bench_tables: {doc.relative_to(ROOT) if doc.is_relative_to(ROOT) else doc}: "
              f"markers of {', '.join(SECTIONS)} in place; {reference.name} parses")
    return 1 if problems else 0


def replace_sections(text, bodies):
    """`text` with the lines between each section's markers replaced by `bodies[name]`."""
    for name, body in bodies.items():
        begin, end = marker(name, "begin"), marker(name, "end")
        i, j = text.index(begin) + len(begin), text.index(end)
        text = text[:i] + "\n" + body.rstrip("\n") + "\n" + text[j:]
    return text


# ---------------------------------------------------------------------------------------------
# Runs


def fail(message):
    print(f"bench_tables: {message}", file=sys.stderr)
    sys.exit(2)


def techniques_from_help(curvenet):
    """The technique names `bench --off` takes, as its help lists them."""
    out = subprocess.run([curvenet, "bench", "--help"], capture_output=True, text=True,
                         check=True).stdout
    flat = " ".join(out.split())
    m = re.search(r"--off <OFF>.*?\):\s*([a-z][a-z-]*(?:,\s*[a-z][a-z-]*)+)", flat)
    if not m:
        fail("could not read the technique names from `curvenet bench --help`; "
             "give them with --techniques")
    return [t.strip() for t in m.group(1).split(",")]


# The 1-minute load average at each run's start, and how long to wait for a quieter one.
START_LOADS = []
SETTLE = {"below": None, "patience": 0.0}


def settle():
    """Waits (at most `SETTLE["patience"]` seconds) for the 1-minute load average to fall
    below `SETTLE["below"]`, if given, and records the load the run starts at."""
    waited = 0.0
    while (SETTLE["below"] is not None and os.getloadavg()[0] >= SETTLE["below"]
           and waited < SETTLE["patience"]):
        time.sleep(5)
        waited += 5
    START_LOADS.append(os.getloadavg()[0])


def bench(curvenet, examples, off=None, threads=None, reference=None):
    """`curvenet bench --json` on `examples` (one run each): the JSON rows by example."""
    cmd = [curvenet, "bench", "--examples", ",".join(examples), "--json"]
    if off:
        cmd += ["--off", off]
    if threads:
        cmd += ["--threads", str(threads)]
    if reference:
        cmd += ["--reference", str(reference)]
    settle()
    done = subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    if done.returncode != 0:
        fail(f"`{shlex.join(cmd)}` failed ({done.returncode}): {done.stderr.strip()}")
    rows = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    return {r["example"]: r for r in rows}


def timed(cmd, stderr=subprocess.DEVNULL):
    """Runs `cmd` (an argument list) as a whole process once the load has settled: its exit
    code, wall s and resource usage (the kernel's accounting of it and the children it waited
    for, `os.wait4`)."""
    settle()
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                            stderr=stderr)
    _, status, usage = os.wait4(proc.pid, 0)
    return os.waitstatus_to_exitcode(status), time.monotonic() - t0, usage


def example(curvenet, name, out):
    """`curvenet example NAME --out DIR` as a whole process, into an empty folder: wall s, CPU
    s, peak MiB (from the kernel's accounting of the process), the greedy's own seconds from
    the run's timings.json, and the removals from its result.json."""
    if out.exists():
        shutil.rmtree(out)
    cmd = [curvenet, "example", name, "--out", str(out)]
    with tempfile.TemporaryFile("w+") as err:
        code, wall, usage = timed(cmd, stderr=err)
        if code != 0:
            err.seek(0)
            fail(f"`{shlex.join(cmd)}` failed ({code}): {err.read().strip()}")
    timings = json.loads((out / "timings.json").read_text()) if (out / "timings.json").exists() else {}
    result = json.loads((out / "result.json").read_text())
    return {
        "wall_s": wall,
        "cpu_s": usage.ru_utime + usage.ru_stime,
        "peak_mib": usage.ru_maxrss / 1024.0,  # KiB on Linux
        "greedy_s": (timings.get("greedy") or {}).get("total_seconds"),
        "removed": [it.get("removed") for it in result.get("iterations", [])],
    }


def reference_run(template, name):
    """The reference implementation's run of example `name` (`template`, a shell command with
    `{example}` in it) as a whole process: wall s and peak MiB; its output is discarded."""
    cmd = template.replace("{example}", shlex.quote(name))
    code, wall, usage = timed(["/bin/sh", "-c", cmd])
    if code != 0:
        fail(f"the reference's `{cmd}` failed ({code})")
    # ru_maxrss covers the shell's children: the largest process it waited for.
    return {"wall_s": wall, "peak_mib": usage.ru_maxrss / 1024.0}


def median_row(rows):
    """The run with the median wall time (the slower middle one for an even count), with the
    range of every run's wall time."""
    ordered = sorted(rows, key=lambda r: r["wall_s"])
    row = dict(ordered[len(ordered) // 2])
    row["wall_lo"], row["wall_hi"] = ordered[0]["wall_s"], ordered[-1]["wall_s"]
    return row


def med(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


# ---------------------------------------------------------------------------------------------
# Provenance


def git(*args):
    try:
        return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None


def machine():
    model = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = ""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal"):
                mem = f", {int(line.split()[1]) / 2**20:.0f} GiB RAM"
    except OSError:
        pass
    return f"{os.cpu_count()} × {model}{mem}"


def load():
    return " / ".join(f"{x:.2f}" for x in os.getloadavg())


def provenance(args, curvenet, load_before, load_after, rounds):
    commit = git("rev-parse", "--short", "HEAD") or "unknown"
    dirty = git("status", "--porcelain", "--untracked-files=no")
    version = subprocess.run([curvenet, "--version"], capture_output=True, text=True).stdout.strip()
    built = datetime.datetime.fromtimestamp(os.path.getmtime(curvenet), datetime.timezone.utc)
    now = datetime.datetime.now(datetime.timezone.utc)
    script = Path(sys.argv[0]).resolve()
    shown = script.relative_to(ROOT) if script.is_relative_to(ROOT) else script
    command = shlex.join(["python3", str(shown), *sys.argv[1:]])
    quick = (" **A quick run (one round): it shows that the tables regenerate; its numbers are "
             "not a measurement to quote.**" if rounds == 1 else "")
    return (
        f"*Generated by `{command}` on {now:%Y-%m-%d %H:%M} UTC; the repository at `{commit}`"
        f"{' (with uncommitted changes)' if dirty else ''}; binary `{curvenet}` ({version}, "
        f"built {built:%Y-%m-%d %H:%M} UTC); {machine()}; load average (1 / 5 / 15 min) "
        f"{load_before} before the runs, {load_after} after; the 1-minute load at the "
        f"{len(START_LOADS)} runs' starts {min(START_LOADS):.2f}–{max(START_LOADS):.2f} "
        f"(median {statistics.median(START_LOADS):.2f}); medians of {rounds} "
        f"round{'s' if rounds != 1 else ''}.*{quick}"
    )


# ---------------------------------------------------------------------------------------------
# Tables


def s2(x):
    return "–" if x is None else f"{x:.2f}"


def wall_cell(row):
    if row["wall_lo"] == row["wall_hi"]:
        return f"{row['wall_s']:.2f}"
    return f"{row['wall_s']:.2f} ({row['wall_lo']:.2f}–{row['wall_hi']:.2f})"


def commands_table(names, benches, examples):
    lines = [
        "| example | curves | dofs | `bench` greedy wall s | greedy CPU s | greedy peak MiB "
        "| `example NAME` wall s | CPU s | peak MiB | greedy inside the run s "
        "| `example` ÷ `bench` wall | same removals |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name in names:
        b, e = median_row(benches[name]), median_row(examples[name])
        same = all(x["removed"] == benches[name][0]["removed"] for x in examples[name])
        lines.append(
            f"| {name} | {b['curves']}→{b['kept']} | {b['dofs']} | {wall_cell(b)} "
            f"| {s2(med([r.get('cpu_s') for r in benches[name]]))} "
            f"| {med([r.get('peak_mib') for r in benches[name]]) or 0:.0f} "
            f"| {wall_cell(e)} | {s2(med([r['cpu_s'] for r in examples[name]]))} "
            f"| {med([r['peak_mib'] for r in examples[name]]):.0f} "
            f"| {s2(med([r['greedy_s'] for r in examples[name]]))} "
            f"| {e['wall_s'] / b['wall_s']:.2f} | {'yes' if same else '**no**'} |")
    lines += [
        "",
        "The greedy's work in the `bench` run with the median wall time (counts; seconds summed "
        "over threads):",
        "",
        "| example | iterations | candidates scored | pruned | factorizations | solves "
        "| relax s | assemble s | factor s | solve s | eigen s | bound s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name in names:
        b = median_row(benches[name])
        lines.append(
            f"| {name} | {b['iterations']} | {b['evaluated']} | {b['pruned']} "
            f"| {b['factorizations']} | {b['solves']} | {b['relax_s']:.2f} "
            f"| {b['assemble_s']:.2f} | {b['factor_s']:.2f} | {b['solve_s']:.2f} "
            f"| {b['eigen_s']:.2f} | {b['bound_s']:.2f} |")
    return "\n".join(lines)


def reference_table(names, benches, examples, refs, ref_path, measured=None, command=None):
    """The ratios to the reference's times: `refs` read from `ref_path`, or, with `measured`
    (its runs by example, timed side by side by `command`), those runs' medians."""
    shown = ref_path.relative_to(ROOT) if ref_path.is_relative_to(ROOT) else ref_path
    if measured:
        lines = [
            f"The reference timed side by side with curvenet in the same rounds (`{command}` "
            "before each example's `bench` and `example` runs); the medians are written to "
            f"`{shown}` when there are several rounds.",
            "",
            "| example | reference s | reference peak MiB | `example NAME` wall s | `example` peak MiB "
            f"| reference ÷ `example` | `bench` greedy wall s | reference ÷ `bench` "
            f"| {TARGET_RATIO:.0f}× met by `example` |",
            "|---|---|---|---|---|---|---|---|---|",
        ]
    else:
        lines = [
            f"Reference times from `{shown}`.",
            "",
            "| example | reference s | `example NAME` wall s | reference ÷ `example` "
            f"| `bench` greedy wall s | reference ÷ `bench` | {TARGET_RATIO:.0f}× met by `example` |",
            "|---|---|---|---|---|---|---|",
        ]
    header = len(lines)
    for name in names:
        if measured:
            ref = median_row(measured[name])
            r, peak = ref["wall_s"], med([x["peak_mib"] for x in measured[name]])
        elif name in refs:
            r = refs[name]
        else:
            continue
        e, b = median_row(examples[name]), median_row(benches[name])["wall_s"]
        met = "yes" if r / e["wall_s"] >= TARGET_RATIO else "no"
        if measured:
            lines.append(
                f"| {name} | {wall_cell(ref)} | {peak:.0f} | {wall_cell(e)} "
                f"| {med([x['peak_mib'] for x in examples[name]]):.0f} "
                f"| {r / e['wall_s']:.0f}× | {b:.2f} | {r / b:.0f}× | {met} |")
        else:
            lines.append(
                f"| {name} | {r:.1f} | {e['wall_s']:.2f} | {r / e['wall_s']:.0f}× | {b:.2f} "
                f"| {r / b:.0f}× | {met} |")
    if len(lines) == header:
        lines.append("| (no example of this run has a reference time) |||||||")
    return "\n".join(lines)


def techniques_table(names, benches, configs, refused):
    # The baseline: the median of every run with everything on (an even count: the mean of
    # the middle two).
    base = {n: statistics.median(r["wall_s"] for r in benches[n]) for n in names}
    lines = [
        "| switched off | " + " | ".join(f"{n}: s (× all on)" for n in names) + " |",
        "|---|" + "---|" * len(names),
        "| nothing (everything on, at each round's start and end) | "
        + " | ".join(f"{base[n]:.2f} (1.00×)" for n in names) + " |",
    ]
    for label, runs in configs.items():
        cells = []
        for n in names:
            if (label, n) in refused:
                cells.append("refused: other removals")
                continue
            w = median_row(runs[n])["wall_s"]
            cells.append(f"{w:.2f} ({w / base[n]:.2f}×)")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------


def main():
    p = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    p.add_argument("--curvenet", default=str(ROOT / "target" / "release" / "curvenet"),
                   help="the release binary (default: target/release/curvenet)")
    p.add_argument("--examples", default=DEFAULT_EXAMPLES,
                   help=f"comma-separated (default {DEFAULT_EXAMPLES}); never the bunny "
                        "unless you mean it (minutes per run)")
    p.add_argument("--repeat", type=int, default=3, help="rounds (default 3)")
    p.add_argument("--reference", type=Path, default=REFERENCE,
                   help="the reference's seconds by example (default docs/tools/reference-times.json)")
    p.add_argument("--reference-command", metavar="CMD",
                   help="time the reference side by side: a shell command running one example "
                        "of the reference implementation, `{example}` standing for its name "
                        "(e.g. 'cd /opt/ref && ./build/bin/curvenet {example}'); the medians of "
                        "two or more rounds are written to the reference file")
    p.add_argument("--techniques", help="comma-separated (default: every one `bench --off` takes)")
    p.add_argument("--no-threads-row", action="store_true", help="leave out `--threads 1`")
    p.add_argument("--sections", default=",".join(SECTIONS),
                   help=f"which to regenerate (default {','.join(SECTIONS)})")
    p.add_argument("--quick", action="store_true", help="tower only, one round")
    p.add_argument("--wait-load", type=float, metavar="L",
                   help="before each run, wait for the 1-minute load average to fall below L "
                        "(each run raises it: expect about a minute per run for L = 1)")
    p.add_argument("--wait-max", type=float, default=300.0, metavar="S",
                   help="with --wait-load, wait at most S seconds per run (default 300)")
    p.add_argument("--doc", type=Path, default=DOC, help="the file whose sections are "
                   "rewritten (default docs/benchmarks.md)")
    p.add_argument("--out", type=Path, help="where `example` writes its runs (default: a "
                   "temporary folder, removed)")
    p.add_argument("--stdout", action="store_true", help="print the sections, write nothing")
    p.add_argument("--check", action="store_true",
                   help="only check the markers and the reference file; run nothing")
    a = p.parse_args()

    if a.check:
        sys.exit(check(a.doc, a.reference))
    sections = [s.strip() for s in a.sections.split(",") if s.strip()]
    if unknown := [s for s in sections if s not in SECTIONS]:
        fail(f"unknown section(s) {', '.join(unknown)}; one of {', '.join(SECTIONS)}")
    if a.quick:
        a.examples, a.repeat = "tower", 1
    SETTLE.update(below=a.wait_load, patience=a.wait_max)
    if a.repeat < 1:
        fail("--repeat must be at least 1")
    names = [n.strip() for n in a.examples.split(",") if n.strip()]
    curvenet = shutil.which(a.curvenet) or a.curvenet
    if not os.access(curvenet, os.X_OK):
        fail(f"{a.curvenet}: no such executable (build it: cargo build --release)")
    if problems := marker_problems(a.doc.read_text(), sections):
        fail("; ".join(problems))
    side_by_side = a.reference_command is not None
    if side_by_side and "{example}" not in a.reference_command:
        fail("--reference-command must contain {example}")
    if side_by_side and "reference" not in sections:
        fail("--reference-command times the reference for the reference section: "
             "add `reference` to --sections")
    refs = read_references(a.reference) if "reference" in sections and not side_by_side else {}

    configs = {}
    if "techniques" in sections:
        techniques = (a.techniques.split(",") if a.techniques else techniques_from_help(curvenet))
        configs = {f"`{t}`": {"off": t} for t in techniques}
        if not a.no_threads_row:
            configs["one thread (`--threads 1`)"] = {"threads": 1}

    # The user's command is timed for the tables that show it; the techniques' table needs
    # only the bench's runs with everything on.
    timed_commands = "commands" in sections or "reference" in sections
    load_before = load()
    benches = {n: [] for n in names}
    examples = {n: [] for n in names}
    config_runs = {label: {n: [] for n in names} for label in configs}
    closing = {n: [] for n in names}
    reference_runs = {n: [] for n in names}
    out = a.out or Path(tempfile.mkdtemp(prefix="bench-tables-"))
    try:
        for r in range(a.repeat):
            for n in names:
                print(f"round {r + 1}/{a.repeat}: {n}", file=sys.stderr)
                if side_by_side:
                    reference_runs[n].append(reference_run(a.reference_command, n))
                benches[n].append(bench(curvenet, [n])[n])
                if timed_commands:
                    examples[n].append(example(curvenet, n, out / n))
            for label, c in configs.items():
                print(f"round {r + 1}/{a.repeat}: {label}", file=sys.stderr)
                for n, row in bench(curvenet, names, **c).items():
                    config_runs[label][n].append(row)
            if configs:
                # Everything on again at the round's end: the techniques' baseline brackets
                # their runs, so the machine's drift over the round touches both.
                print(f"round {r + 1}/{a.repeat}: everything on again", file=sys.stderr)
                for n, row in bench(curvenet, names).items():
                    closing[n].append(row)
    finally:
        if a.out is None:
            shutil.rmtree(out, ignore_errors=True)
    load_after = load()

    # The greedy is deterministic: every run of an example makes the same removals with the
    # same λ_eq, bit for bit (JSON round-trips them).
    for n in names:
        first = benches[n][0]
        if any((x["removed"], x["lambdas"]) != (first["removed"], first["lambdas"])
               for x in benches[n] + closing[n]):
            fail(f"{n}: two bench runs made different removals or λ_eq")
    refused = {(label, n) for label, runs in config_runs.items() for n in names
               if any(x["removed"] != benches[n][0]["removed"] for x in runs[n])}

    stamp = provenance(a, curvenet, load_before, load_after, a.repeat)
    bodies = {}
    if "commands" in sections:
        bodies["commands"] = stamp + "\n\n" + commands_table(names, benches, examples)
    if "reference" in sections:
        bodies["reference"] = stamp + "\n\n" + reference_table(
            names, benches, examples, refs, a.reference.resolve(),
            reference_runs if side_by_side else None, a.reference_command)
    if "techniques" in sections:
        baseline = {n: benches[n] + closing[n] for n in names}
        bodies["techniques"] = stamp + "\n\n" + techniques_table(names, baseline, config_runs,
                                                                 refused)
    if side_by_side and not a.stdout and a.repeat > 1:
        # The reference file keeps every example it had; the measured ones take their medians
        # (never from one round: a quick run is no measurement to quote).
        try:
            kept = read_references(a.reference)
        except (OSError, ValueError):
            kept = {}
        kept.update({n: round(median_row(reference_runs[n])["wall_s"], 1) for n in names})
        tmp = a.reference.with_suffix(".json.tmp")
        tmp.write_text(json.dumps(kept, indent=2) + "\n")
        os.replace(tmp, a.reference)
        print(f"bench_tables: wrote the reference's medians to {a.reference}", file=sys.stderr)
    if a.stdout:
        for name, body in bodies.items():
            print(f"{marker(name, 'begin')}\n{body}\n{marker(name, 'end')}\n")
    else:
        text = replace_sections(a.doc.read_text(), bodies)
        tmp = a.doc.with_suffix(".md.tmp")
        tmp.write_text(text)
        os.replace(tmp, a.doc)
        print(f"bench_tables: wrote {', '.join(bodies)} in {a.doc}", file=sys.stderr)
    for label, n in sorted(refused):
        print(f"bench_tables: {label} made other removals than the default on {n}: refused",
              file=sys.stderr)
    sys.exit(1 if refused else 0)


if __name__ == "__main__":
    main()

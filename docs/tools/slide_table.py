#!/usr/bin/env python3
"""The table of docs/benchmarks.md, "Sliding": each paper example's answer at its own budget
slid at the default largest move (5% of the surface's bounding-box diagonal).

    python3 docs/tools/slide_table.py [--curvenet PATH] [--out DIR] [EXAMPLE ...]

For each example it runs `curvenet example NAME --out DIR/NAME` and then
`curvenet slide DIR/NAME --out DIR/NAME-slid`, and prints one markdown row from the slid run's
result.json (the objective before and after, the largest move, the joints changed, the
networks evaluated) and the slide's wall time. Then the median gain over the examples with a
stable start.
"""

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--curvenet", default="curvenet")
    p.add_argument("--out", default="slide-table")
    p.add_argument("--max-move", default="5%")
    p.add_argument("examples", nargs="*", default=["tower", "roof", "shell", "hill", "tent"])
    a = p.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    print("| example | curves | λ_eq before | λ_eq after | gain | largest move (of D) "
          "| joints +/− | length / budget | networks | slide s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    gains = []
    for name in a.examples:
        run, slid = out / name, out / f"{name}-slid"
        subprocess.run([a.curvenet, "example", name, "--out", str(run), "--force"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        start = time.monotonic()
        done = subprocess.run([a.curvenet, "slide", str(run), "--out", str(slid), "--force",
                               "--max-move", a.max_move],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        seconds = time.monotonic() - start
        if done.returncode != 0:
            print(f"| {name} | {done.stderr.strip().splitlines()[-1]} |||||||||")
            continue
        s = json.loads((slid / "result.json").read_text())["slide"]
        before, after = s["lambda_before"], s["lambda_after"]
        gain = after / before if before > 0 else float("nan")
        if before > 0:
            gains.append(gain)
        print(f"| {name} | {len(s['curves'])} | {before:.4e} | {after:.4e} | {gain:.3f}× "
              f"| {s['largest_move']:.4g} ({s['largest_move'] / s['max_move']:.0%}) "
              f"| +{s['joints_added']}/−{s['joints_removed']} "
              f"| {s['length_after'] / s['budget']:.1%} | {s['evaluations']} | {seconds:.1f} |")
        sys.stdout.flush()
    if gains:
        print(f"\nmedian gain {statistics.median(gains):.3f}× over {len(gains)} examples")


if __name__ == "__main__":
    main()

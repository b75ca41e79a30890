#!/usr/bin/env python3
"""Issue #39's scorecard: hompm's step against the lean bit-identical steps,
interleaved in one run on one machine, as CPU time per particle-step.

Each measurement is the processor time (user + system, from os.wait4) of
an example binary run for LONG steps minus the same for SHORT steps (which
removes the set-up), divided by (LONG - SHORT) x the particles. One round
runs every variant once, in order; ROUNDS rounds are interleaved, so that
a change in the machine's load touches every variant alike. For each case
the script prints the best and the median over the rounds, the ratio of
the bests and the median of the per-round ratios, and the issue's target:

  1D P1 bar x 4 PPC, hompm with the stability monitor (`watched`) against
  the lean step: <= 1.4 at 1024 and 16384 cells;
  2D aligned vibration x 9 PPC, BSMPM p = 2 and bilinear against their
  lean steps: <= 1.15 at 16 and 64 cells;
  MLS <= 300 ns and TLS <= 120 ns per particle-step at 16 and 64 cells.

A ratio is compared with its target as the ratio of the bests; the median
ratio is printed beside it, because on a noisy host the two can fall on
either side of a target (then the verdict says which one is within it:
"met by best only" or "met by median only"). The absolute targets
were set on one host; the lean steps' own times are printed as that host's
yardstick (docs/conventions.md, "Session 13"). The MLS and TLS cases also
run the lean BSMPM step at the same size and print hompm's time in its
units, a figure that moves less from host to host than nanoseconds do
(about 10 % between session 11's host, MLS 3.95 and 4.53 and TLS 1.70 and
1.76 at 16 and 64 cells, and session 15's, where the nanoseconds doubled;
docs/conventions.md, "Session 15"); the verdict is the absolute one.

Build the examples first, then run it on a quiet machine (no build, no
helper session):
  cargo build --release --example p1_step_cost --example mpm2d_step_cost
  python3 scripts/step_cost.py [--rounds N] [--only TEXT] [--examples DIR]
Only the standard library.
"""
import argparse
import os
import statistics
import subprocess
import sys

# (label, example, cells per side, particles per cell, short and long step
# counts, the variants (name, example argument), the target (kind, value)).
CASES = [
    ("1D P1, 1024 cells", "p1_step_cost", 1024, 4, 1000, 5000,
     [("hompm", "watched"), ("lean", "lean")], ("ratio", 1.4)),
    ("1D P1, 16384 cells", "p1_step_cost", 16384, 4, 100, 500,
     [("hompm", "watched"), ("lean", "lean")], ("ratio", 1.4)),
    ("2D BSMPM p = 2, 16 cells", "mpm2d_step_cost", 16, 9, 200, 1000,
     [("hompm", "hompm-bsmpm"), ("lean", "lean-bsmpm")], ("ratio", 1.15)),
    ("2D BSMPM p = 2, 64 cells", "mpm2d_step_cost", 64, 9, 50, 250,
     [("hompm", "hompm-bsmpm"), ("lean", "lean-bsmpm")], ("ratio", 1.15)),
    ("2D bilinear, 16 cells", "mpm2d_step_cost", 16, 9, 200, 1000,
     [("hompm", "hompm-bilinear"), ("lean", "lean-bilinear")], ("ratio", 1.15)),
    ("2D bilinear, 64 cells", "mpm2d_step_cost", 64, 9, 50, 250,
     [("hompm", "hompm-bilinear"), ("lean", "lean-bilinear")], ("ratio", 1.15)),
    ("2D MLS, 16 cells", "mpm2d_step_cost", 16, 9, 50, 250,
     [("hompm", "hompm-mls"), ("lean", "lean-bsmpm")], ("ns", 300.0)),
    ("2D MLS, 64 cells", "mpm2d_step_cost", 64, 9, 20, 80,
     [("hompm", "hompm-mls"), ("lean", "lean-bsmpm")], ("ns", 300.0)),
    ("2D TLS, 16 cells", "mpm2d_step_cost", 16, 9, 100, 500,
     [("hompm", "hompm-tls"), ("lean", "lean-bsmpm")], ("ns", 120.0)),
    ("2D TLS, 64 cells", "mpm2d_step_cost", 64, 9, 30, 130,
     [("hompm", "hompm-tls"), ("lean", "lean-bsmpm")], ("ns", 120.0)),
]


def cpu_seconds(binary, variant, cells, steps):
    """User + system seconds of one run of `binary variant cells steps`."""
    p = subprocess.Popen([binary, variant, str(cells), str(steps)],
                         stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(p.pid, 0)
    if status != 0:
        sys.exit(f"step_cost: {binary} {variant} {cells} {steps} failed ({status})")
    return usage.ru_utime + usage.ru_stime


def verdict(value, target, median):
    """"met" when the ratio of the bests and the median of the rounds'
    ratios are both within the target; otherwise which one is, or neither."""
    if value <= target and median <= target:
        return "met"
    if value <= target:
        return "met by best only"
    if median <= target:
        return "met by median only"
    return "not met"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--only", default="", help="cases whose label contains this")
    ap.add_argument("--examples", default=os.path.join(
        os.environ.get("CARGO_TARGET_DIR", "target"), "release", "examples"))
    a = ap.parse_args()
    if a.rounds < 1:
        sys.exit("step_cost: --rounds must be at least 1")
    cases = [c for c in CASES if a.only in c[0]]
    if not cases:
        sys.exit(f"step_cost: no case contains {a.only!r}")
    for c in cases:
        path = os.path.join(a.examples, c[1])
        if not os.access(path, os.X_OK):
            sys.exit(f"step_cost: {path} is missing (cargo build --release --example {c[1]})")
    # times[case][variant] = [ns per particle-step, one per round]
    times = {c[0]: {v: [] for v, _ in c[6]} for c in cases}
    for _ in range(a.rounds):
        for label, binary, cells, ppc, short, long, variants, _ in cases:
            path = os.path.join(a.examples, binary)
            particles = ppc * cells * (cells if binary == "mpm2d_step_cost" else 1)
            for name, arg in variants:
                extra = cpu_seconds(path, arg, cells, long) - cpu_seconds(path, arg, cells, short)
                times[label][name].append(1e9 * extra / ((long - short) * particles))
    print(f"CPU ns per particle-step, {a.rounds} interleaved rounds (best / median)\n")
    print("| case | hompm | lean | hompm / lean (best; median of rounds) | target | verdict |")
    # For MLS and TLS the lean column is the lean BSMPM step: information,
    # not the target.
    print("|---|---:|---:|---:|---:|---|")
    for label, _, _, _, _, _, variants, (kind, target) in cases:
        h = times[label]["hompm"]
        hompm = f"{min(h):.1f} / {statistics.median(h):.1f}"
        if kind == "ratio":
            le = times[label]["lean"]
            lean = f"{min(le):.1f} / {statistics.median(le):.1f}"
            best = min(h) / min(le)
            median = statistics.median([x / y for x, y in zip(h, le)])
            shown = f"{best:.3f}; {median:.3f}"
            print(f"| {label} | {hompm} | {lean} | {shown} | {target} | "
                  f"{verdict(best, target, median)} |")
        else:
            le = times[label]["lean"]
            lean = f"{min(le):.1f} / {statistics.median(le):.1f} (BSMPM)"
            median = statistics.median([x / y for x, y in zip(h, le)])
            shown = f"{min(h) / min(le):.3f}; {median:.3f} (information)"
            print(f"| {label} | {hompm} | {lean} | {shown} | {target:.0f} ns | "
                  f"{verdict(min(h), target, statistics.median(h))} |")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Where the error of an aligned-vibration run sits (issue #38).

Reads the documents of `hompm run aligned-vibration ... --json` (MLS paper
Eqs. 38-39, either --solution) and splits each run's error in u and v
against the exact solution three ways:
  - by the particles' distance X from the nearest wall, in cells
    (< 1 h, 1-2 h, 2-4 h, >= 4 h): RMS and share of the squared error;
  - the part along the manufactured mode itself, the exact velocity's
    pattern sin(n pi X_k / L) cos(c pi t / L [+ pi]) per component (a phase
    error of u or an amplitude error of v has it), and the rest;
  - the part that is the mean over the particles of one initial cell
    (grid-resolved) and the part within a cell (particle-scale noise).
Run by hand:
  hompm run aligned-vibration --method bsmpm --degree 2 --cells 64 --ppc 9 \\
        --steps 2000 [flags] --json > run.json
  python3 scripts/aligned_error_anatomy.py run.json [more.json ...]
Only the standard library."""
import json, math, sys
from collections import defaultdict


def exact(doc, x0):
    """u and v of MLS paper Eqs. (38)-(39) (n = 2) or the axis-aligned
    form (n = 1), at X = x0 and the run's time."""
    p = doc["params"]
    c = math.sqrt(p["young"] / p["density"])
    L, A, t = p["length"], p["amplitude"], doc["time"]
    n = 1.0 if p.get("solution") == "axis-aligned" else 2.0
    phase = c * math.pi * t / L
    s = (math.sin(phase), math.sin(phase + math.pi))
    cs = (math.cos(phase), math.cos(phase + math.pi))
    a = A * c * math.pi / L
    shape = [math.sin(n * math.pi * x0[k] / L) for k in range(2)]
    u = [A * shape[k] * s[k] for k in range(2)]
    v = [a * shape[k] * cs[k] for k in range(2)]
    # The exact velocity's pattern: a phase error of u and an amplitude
    # error of v both have it (the y component runs half a period behind).
    mode = [shape[k] * cs[k] for k in range(2)]
    # The same shape with one sign in x and y (orthogonal to the above).
    same = [shape[k] * cs[0] for k in range(2)]
    return u, v, mode, same


def anatomy(path):
    doc = json.load(open(path))
    parts, cells = doc["particles"], doc["cells"]
    L = doc["params"]["length"]
    h = L / cells
    bands = {"< 1 h": [0, 0.0, 0.0], "1-2 h": [0, 0.0, 0.0],
             "2-4 h": [0, 0.0, 0.0], ">= 4 h": [0, 0.0, 0.0]}
    # <e, mode>, <mode, mode>, <e, same>, <same, same>
    along = {"u": [0.0] * 4, "v": [0.0] * 4}
    groups = defaultdict(list)
    total = {"u": 0.0, "v": 0.0}
    for x0, u, v in zip(parts["x0"], parts["u"], parts["v"]):
        ue, ve, mode, same = exact(doc, x0)
        eu = [u[k] - ue[k] for k in range(2)]
        ev = [v[k] - ve[k] for k in range(2)]
        d = min(x0[0], L - x0[0], x0[1], L - x0[1]) / h
        band = "< 1 h" if d < 1 else "1-2 h" if d < 2 else "2-4 h" if d < 4 else ">= 4 h"
        su, sv = eu[0] ** 2 + eu[1] ** 2, ev[0] ** 2 + ev[1] ** 2
        bands[band][0] += 1
        bands[band][1] += su
        bands[band][2] += sv
        total["u"] += su
        total["v"] += sv
        for k in range(2):
            for q, e in (("u", eu), ("v", ev)):
                along[q][0] += e[k] * mode[k]
                along[q][1] += mode[k] ** 2
                along[q][2] += e[k] * same[k]
                along[q][3] += same[k] ** 2
        cell = (min(int(x0[0] / h), cells - 1), min(int(x0[1] / h), cells - 1))
        groups[cell].append(eu + ev)
    n = len(parts["x0"])
    within = [0.0] * 4
    for g in groups.values():
        mean = [sum(e[k] for e in g) / len(g) for k in range(4)]
        for e in g:
            for k in range(4):
                within[k] += (e[k] - mean[k]) ** 2
    rms = lambda s, m: math.sqrt(s / m) if m else float("nan")
    print(f"{path}: {cells} cells, t = {doc['time']} s, RMS u {rms(total['u'], n):.3e} m, "
          f"v {rms(total['v'], n):.3e} m/s")
    for name, (m, su, sv) in bands.items():
        print(f"  {name:7s} {m:6d} particles: u RMS {rms(su, m):.3e} ({su / total['u']:.2f} of the "
              f"squared error), v RMS {rms(sv, m):.3e} ({sv / total['v']:.2f})")
    for q in ("u", "v"):
        dot, norm, dot_same, norm_same = along[q]
        share = dot * dot / norm / total[q]
        share_same = dot_same * dot_same / norm_same / total[q]
        rest = max(total[q] * (1 - share - share_same), 0.0)
        print(f"  {q}: along the exact velocity's pattern {share:.3f} of the squared error, "
              f"along the same shape with one sign in x and y {share_same:.3f}, "
              f"the rest RMS {rms(rest, n):.3e}")
    wu, wv = within[0] + within[1], within[2] + within[3]
    print(f"  within the initial cells: u {wu / total['u']:.3f}, v {wv / total['v']:.3f} of the "
          f"squared error (the rest is the cells' mean error)")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for f in sys.argv[1:]:
        anatomy(f)

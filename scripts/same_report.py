#!/usr/bin/env python3
"""Compares two `hompm reproduce --out DIR` reports (DIR/report.json) with
their wall-clock fields removed: every key naming seconds, a speed or a rate
per second, the "N ns per particle-step" and "0.3 s," of the notes, t_TLS,
and tls-8's t_subpoints/t_TLS column (a ratio of wall times). Everything else,
the summary counts and every computed number, status and note, must be equal.
Use it for a change meant to make `hompm reproduce` faster and otherwise
identical (issue #39):

    python3 scripts/same_report.py BEFORE/report.json AFTER/report.json

Prints the first differences and their count; exit status 1 if any."""
import json, re, sys

TIMING_KEYS = ("seconds", "ns_per", "speed", "per_second")


def note(s):
    s = re.sub(r"\d+ ns per particle-step", "N ns per particle-step", s)
    s = re.sub(r"t_TLS = [0-9.]+ s", "t_TLS = T s", s)
    return re.sub(r"[0-9.]+ s, N ns", "S s, N ns", s)


def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not any(t in k for t in TIMING_KEYS)}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return note(x) if isinstance(x, str) else x


def tables(report):
    out = {}
    for t in report["tables"]:
        t = dict(t)
        if t["id"] == "tls-8":  # the third column is t_subpoints/t_TLS
            for k in ("computed", "deviation", "status", "to_digits", "tolerance"):
                if isinstance(t.get(k), list):
                    t[k] = [row[:2] for row in t[k]]
        out[t["id"]] = strip(t)
    return out


def main():
    a, b = (json.load(open(p)) for p in sys.argv[1:3])
    found = []

    def walk(x, y, path):
        if type(x) is not type(y):
            found.append(f"{path}: {type(x).__name__} vs {type(y).__name__}")
        elif isinstance(x, dict):
            for k in sorted(set(x) | set(y)):
                if k not in x or k not in y:
                    found.append(f"{path}/{k}: only in {'after' if k not in x else 'before'}")
                else:
                    walk(x[k], y[k], f"{path}/{k}")
        elif isinstance(x, list):
            if len(x) != len(y):
                found.append(f"{path}: {len(x)} vs {len(y)} entries")
            for i, (u, v) in enumerate(zip(x, y)):
                walk(u, v, f"{path}[{i}]")
        elif x != y:
            found.append(f"{path}: {str(x)[:100]!r} vs {str(y)[:100]!r}")

    for k in ("reproduced", "to_digits", "digits_apply", "published_in_computed_tables",
              "published_total", "unimplemented"):
        walk(a.get(k), b.get(k), k)
    walk(tables(a), tables(b), "tables")
    walk(strip(a.get("studies")), strip(b.get("studies")), "studies")
    for line in found[:40]:
        print(line)
    print(f"{len(found)} differences")
    sys.exit(1 if found else 0)


if __name__ == "__main__":
    main()

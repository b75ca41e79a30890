#!/usr/bin/env python3
"""Runs generated `hompm check` inputs through the binary (issue #35).

Every input is hompm's OWN valid output, obtained by running the binary
(`run … --json`, `trace … --json`, `trace … --csv` of a 1D and a 2D setup,
each with two methods), mutated in one of issue #35's families and written
as JSON or CSV; a control family is the same output unmutated.

| family | what is mutated | exit expected |
|---|---|---|
| control | nothing (run JSON, object of columns, array of rows, CSV, trace JSON/CSV) | 0 |
| wrong_types | null/string/number/object/bool/nested array for a column or entry, a 2D entry of another width, bad CSV cells | 2 |
| duplicate_keys | a key twice in particles, rows, the trace header, a step, its equations; a CSV column or `# key:` line twice | 2 |
| step_lengths | a trace quantity shorter, longer or empty, at the last step or another | 2 |
| step_numbering | a step 0, beyond steps, 2^64, negative, fractional, twice, the last missing | 2 |
| x0_id | x0 moved or all 0, ids permuted against x0, 1-based ids in another order, ids twice or out of range | 1 or 2 |
| column_mapping | `--columns` mapping two fields to one column, physical columns renamed (ux, vx, s11), unknown or malformed names | 2 (1 for a mapping to a wrong column) |
| huge | u/v/stress values of ±1e155..1.7976931348623157e308 | 1 |
| tiny | one u, v or stress value changed by 1e-6 relative | 1 |
| column_counts | CSV headers of 10k, 100k and 2,000,000 columns (ragged, a name twice, no physical column, a tiny change) | 2 (1 for the tiny change) |
| streams | --input /dev/zero, /dev/urandom, a FIFO or stdin (/dev/stdin, -) fed endlessly | 2 |

Each input runs under a memory cap (prlimit --as, default 4 GiB) and a
time limit (default 20 s). Each outcome is one class: panic (exit 101, a
signal, or "panicked" on stderr), false agrees (exit 0 on a mutated input),
silent NaN/inf (NaN/inf/infinity in stdout, or a non-finite number or null
in a --json report), unbounded read (timeout, memory kill, or "out of memory"
on stderr: the read went on up to the memory cap), multi-line
error (exit 2 with more than one stderr line), wrong exit code (any other
exit outside the family's), ok. A table of counts per family x class is
printed, and written as JSON with --out. Inputs whose class is not ok are
kept under WORKDIR/kept; with --repro-dir, panics, false agrees, silent
NaN/inf and unbounded reads are copied there with their command line.

    scripts/fuzz_check.py [--binary target/release/hompm] [--count 3200] [--seed 1] [--jobs 2] [--out counts.json]

Every case is generated from its own seeded generator (seed, case number),
so `--cases 17,204` reruns exactly those cases.
"""
import argparse, collections, concurrent.futures, copy, errno, hashlib, json, math, os, random, re, shutil
import subprocess, sys, tempfile, threading, time

SETUPS = {
    "1d": ["vibrating-bar", "--cells", "4", "--ppc", "2", "--dt", "1e-3", "--steps", "5"],
    "1d-bsmpm": ["vibrating-bar", "--method", "bsmpm", "--mapping", "cubic-spline", "--mass", "richardson",
                 "--cells", "4", "--ppc", "2", "--dt", "1e-3", "--steps", "5"],
    "2d": ["aligned-vibration", "--cells", "4", "--ppc", "4", "--steps", "3"],
    "2d-mls": ["aligned-vibration", "--method", "bsmpm-mls", "--cells", "4", "--ppc", "4", "--steps", "3"],
}
FAMILIES = ["wrong_types", "duplicate_keys", "step_lengths", "step_numbering", "x0_id", "column_mapping",
            "huge", "tiny", "column_counts", "streams"]
CLASSES = ["panic", "false agrees", "silent NaN/inf", "unbounded read", "multi-line error", "wrong exit code", "ok"]
SERIOUS = {"panic", "false agrees", "silent NaN/inf", "unbounded read"}
# JSON names of 2D particle columns -> CSV component names ([x, y] pairs,
# [xx, xy, yx, yy] rows).
COMPONENTS = {"x0": ["x0_x", "x0_y"], "x": ["x_x", "x_y"], "u": ["u_x", "u_y"], "v": ["v_x", "v_y"],
              "stress": ["stress_xx", "stress_xy", "stress_yx", "stress_yy"],
              "deformation_gradient": ["F_xx", "F_xy", "F_yx", "F_yy"]}
PHYSICAL = {"u", "v", "stress", "deformation_gradient"}
SYMMETRIC = {"stress_xy", "stress_yx"}  # equal in hompm's output: a mapping of one to the other may agree
META = ["scene", "cells", "ppc", "steps", "dt", "time"]
WIDE = [10_000, 100_000, 2_000_000]


# --- JSON text with repeated keys and raw numbers -------------------------

class Obj(list):
    """A JSON object as (key, value) pairs: keys may repeat."""


class Raw(str):
    """Text put into the JSON as it is (1e400, -0, …)."""


def dumps(v):
    if isinstance(v, Raw):
        return str(v)
    if isinstance(v, Obj):
        return "{" + ", ".join(json.dumps(k) + ": " + dumps(x) for k, x in v) + "}"
    if isinstance(v, dict):
        return "{" + ", ".join(json.dumps(k) + ": " + dumps(x) for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(dumps(x) for x in v) + "]"
    if isinstance(v, float):
        assert math.isfinite(v), v
        return repr(v)
    return json.dumps(v)


def with_dup(d, key, value, rng):
    """`d` (a dict) as an Obj with `key: value` added at a random place."""
    pairs = list(d.items())
    pairs.insert(rng.randrange(len(pairs) + 1), (key, value))
    return Obj(pairs)


def fmt(x):
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        return str(x)
    return str(x) if isinstance(x, int) else repr(x)


# --- hompm's own output ----------------------------------------------------

class Base:
    """One setup's run (JSON), trace (JSON) and trace (CSV text)."""

    def __init__(self, name, binary):
        self.name, self.setup = name, SETUPS[name]
        self.two_d = self.setup[0] == "aligned-vibration"

        def out(*extra):
            p = subprocess.run([binary, *extra], capture_output=True, text=True)
            if p.returncode != 0:
                sys.exit(f"{binary} {' '.join(extra)}: exit {p.returncode}: {p.stderr.strip()}")
            return p.stdout

        self.run_text = out("run", *self.setup, "--json")
        self.trace_text = out("trace", *self.setup, "--json")
        self.trace_csv_text = out("trace", *self.setup, "--csv")
        self.run = json.loads(self.run_text)
        self.trace = json.loads(self.trace_text)
        self.particles = self.run["particles"]
        self.n = len(self.particles["x0"])
        self.steps = int(self.run["steps"])
        lines = self.trace_csv_text.splitlines()
        self.trace_comments = [l for l in lines if l.startswith("#")]
        body = [l for l in lines if l.strip() and not l.startswith("#")]
        self.trace_header, self.trace_rows = body[0], [l.split(",") for l in body[1:]]
        x0 = self.particles["x0"]
        xs = sorted({e[0] if self.two_d else e for e in x0})
        self.spacing = min(b - a for a, b in zip(xs, xs[1:]))
        keys = self.trace["steps"][-1]["equations"]
        if self.two_d:
            self.trace_phys = {"u": "mls-30-u", "v": "mls-29", "stress": "mls-41"}
        else:
            self.trace_phys = {"u": "book-4.12", "v": "book-4.9",
                               "stress": "book-4.16" if "book-4.16" in keys else "book-4.15"}

    def digest(self):
        return hashlib.sha256((self.run_text + self.trace_text + self.trace_csv_text).encode()).hexdigest()[:16]

    # Forms of the particles.
    def p(self):
        return copy.deepcopy(self.particles)

    def run_doc(self, p):
        d = copy.deepcopy(self.run)
        d["particles"] = p
        return d

    def csv_parts(self, p, meta):
        """Particles (JSON names) as CSV: comment lines, header, rows of text."""
        header, cols = [], []
        for name, column in p.items():
            if self.two_d and name in COMPONENTS:
                for c, cname in enumerate(COMPONENTS[name]):
                    header.append(cname)
                    cols.append([fmt(e[c]) for e in column])
            else:
                header.append(name)
                cols.append([fmt(e) for e in column])
        rows = [list(r) for r in zip(*cols)]
        comments = [f"# {k}: {self.run[k]}" for k in META if k in self.run] if meta else []
        return comments, header, rows

    def trace_csv(self):
        return list(self.trace_comments), self.trace_header, [list(r) for r in self.trace_rows]


def csv_text(comments, header, rows):
    return "".join(l + "\n" for l in comments) + ",".join(header) + "\n" + "".join(",".join(r) + "\n" for r in rows)


def trace_csv_text(comments, header, rows):
    return "".join(l + "\n" for l in comments) + header + "\n" + "".join(",".join(r) + "\n" for r in rows)


def particles_text(b, p, form, rng):
    """`p` (JSON names) written in `form`: run, columns, rows or csv."""
    if form == "run":
        return dumps(b.run_doc(p)), "json"
    if form == "columns":
        return dumps(p), "json"
    if form == "rows":
        return dumps([{k: p[k][i] for k in p} for i in range(len(next(iter(p.values()))))]), "json"
    return csv_text(*b.csv_parts(p, meta=rng.random() < 0.5)), "csv"


class Case:
    def __init__(self, family, variant, base, text=None, ext="json", extra=(), expect=(2,), stream=None,
                 input_path=None, json_report=False):
        self.family, self.variant, self.base = family, variant, base
        self.text, self.ext, self.extra = text, ext, list(extra)
        self.expect, self.stream, self.input_path = set(expect), stream, input_path
        self.json_report = json_report


def big_entry(rng, values, at_least=1e-3):
    """An index (and component) of a value of at least `at_least` times
    the largest magnitude of `values` (scalars or lists)."""
    flat = [(i, c, x) for i, e in enumerate(values) for c, x in (enumerate(e) if isinstance(e, list) else [(None, e)])]
    top = max(abs(x) for _, _, x in flat)
    pool = [(i, c) for i, c, x in flat if top > 0 and abs(x) >= at_least * top]
    return rng.choice(pool) if pool else None


def set_entry(column, i, c, value):
    if c is None:
        column[i] = value
    else:
        column[i][c] = value


def get_entry(column, i, c):
    return column[i] if c is None else column[i][c]


# --- the families ----------------------------------------------------------

BAD_CELLS = ["abc", "null", "true", "NaN", "nan", "inf", "-inf", "Infinity", "", " ", "1e400", "-1e400", "0x10",
             "1.0.0", "1e", "--1", "[1;2]", "{}", "x1", "1_000", "\u0661"]


def fam_control(rng, b):
    kind = rng.choice(["run", "columns", "rows", "csv", "trace-json", "trace-csv", "trace-csv-noheader"])
    if kind == "trace-json":
        text, ext = b.trace_text, "json"
    elif kind.startswith("trace-csv"):
        comments, header, rows = b.trace_csv()
        text, ext = trace_csv_text([] if kind.endswith("noheader") else comments, header, rows), "csv"
    else:
        text, ext = particles_text(b, b.p(), kind, rng)
    return Case("control", kind, b, text, ext, expect=(0,), json_report=rng.random() < 0.4)


def fam_wrong_types(rng, b):
    kind = rng.choice(["column", "entry", "entry", "row", "trace", "trace", "csv", "csv-trace"])
    p = b.p()
    if kind == "column":
        col = rng.choice(list(p))
        column = p[col]
        bads = [None, "x", 1.5, {}, True, False, [column], {"0": column[0]}]
        if isinstance(column[0], list):
            bads += [[e[0] for e in column], [e + [0.0] for e in column], [[e] for e in column]]
        else:
            bads += [[[e, e] for e in column], [str(e) for e in column]]
        p[col] = rng.choice(bads)
        text, ext = particles_text(b, p, rng.choice(["run", "columns"]), rng)
        return Case("wrong_types", "column", b, text, ext)
    if kind == "entry":
        col = rng.choice(list(p))
        i = rng.randrange(b.n)
        e = p[col][i]
        bads = [None, "0.1", "x", {}, True, []]
        if isinstance(e, list):
            bads += [e + [0.0], e[:1], e[0], [e], [e[0], None] + e[2:], [e[0], "1"] + e[2:], e + e]
        else:
            bads += [[e, e], [[e]]]
        p[col][i] = rng.choice(bads)
        text, ext = particles_text(b, p, rng.choice(["run", "columns", "rows"]), rng)
        return Case("wrong_types", "entry", b, text, ext)
    if kind == "row":
        rows = [{k: p[k][i] for k in p} for i in range(b.n)]
        i = rng.randrange(1, b.n)
        choice = rng.randrange(3)
        if choice == 0:
            rows[i] = rng.choice([None, [1.0, 2.0], 1.5, "x", True])
        elif choice == 1:
            rows[i]["w"] = 1.0
        else:
            rows = [list(r.values()) for r in rows]
        return Case("wrong_types", "row", b, dumps(rows), "json")
    if kind == "trace":
        t = copy.deepcopy(b.trace)
        s = rng.randrange(len(t["steps"]))
        step = t["steps"][s]
        key = rng.choice(list(step["equations"]))
        target = rng.choice(["quantity", "value", "step", "time", "equations", "steps", "header", "header-value"])
        if target == "quantity":
            q = step["equations"][key]
            step["equations"][key] = rng.choice([None, "x", 1.5, {}, True, [q], [[x] for x in q], [str(x) for x in q]])
        elif target == "value":
            step["equations"][key][rng.randrange(len(step["equations"][key]))] = rng.choice(
                [None, "x", "0.1", {}, True, [1.0, 2.0], []])
        elif target == "step":
            step["step"] = rng.choice([str(step["step"]), None, True, {}, [step["step"]]])
        elif target == "time":
            step["time"] = rng.choice(["x", {}, True, [step["time"]]])
        elif target == "equations":
            step["equations"] = rng.choice([None, [], "x", 1, [step["equations"]]])
        elif target == "steps":
            t["steps"] = rng.choice([{"1": t["steps"][0]}, None, "x", 1, True])
        elif target == "header":
            t["header"] = rng.choice(["x", 1.5, [], True, [t["header"]]])
        else:
            k = rng.choice([k for k in t["header"] if k not in ("every", "hompm")])
            t["header"][k] = rng.choice(["x", True, [], [t["header"][k]], None if isinstance(t["header"][k], dict) else {}])
        return Case("wrong_types", "trace-" + target, b, dumps(t), "json")
    if kind == "csv":
        comments, header, rows = b.csv_parts(p, meta=rng.random() < 0.5)
        c = rng.randrange(len(header))
        if rng.random() < 0.2:
            bad = rng.choice(["null", "abc", "nan", ""])
            for r in rows:
                r[c] = bad
        else:
            rows[rng.randrange(len(rows))][c] = rng.choice(BAD_CELLS)
        return Case("wrong_types", "csv-cell", b, csv_text(comments, header, rows), "csv")
    comments, header, rows = b.trace_csv()
    col = rng.choice([0, 1, 3, 4, 4, 4])  # step, time, index, value
    rows[rng.randrange(len(rows))][col] = rng.choice(BAD_CELLS)
    return Case("wrong_types", "csv-trace-" + ["step", "time", "", "index", "value"][col], b,
                trace_csv_text(comments if rng.random() < 0.7 else [], header, rows), "csv")


def fam_duplicate_keys(rng, b):
    kind = rng.choice(["particles", "particles", "rows", "header", "step", "equations", "top", "nested-header",
                       "csv-column", "csv-column", "csv-comment", "csv-trace-comment"])
    p = b.p()
    same = rng.random() < 0.5
    if kind == "particles":
        col = rng.choice(list(p))
        value = copy.deepcopy(p[col]) if same else [copy.deepcopy(p[col][0])] * b.n
        obj = with_dup(p, col, value, rng)
        form = rng.choice(["run", "columns"])
        if form == "run":
            d = b.run_doc(None)
            d["particles"] = obj
            return Case("duplicate_keys", "particles", b, dumps(d))
        return Case("duplicate_keys", "columns", b, dumps(obj))
    if kind == "rows":
        rows = [{k: p[k][i] for k in p} for i in range(b.n)]
        i = rng.randrange(b.n)
        k = rng.choice(list(rows[i]))
        rows[i] = with_dup(rows[i], k, rows[i][k] if same else 0.0, rng)
        return Case("duplicate_keys", "row", b, dumps(rows))
    t = copy.deepcopy(b.trace)
    if kind == "header":
        k = rng.choice(list(t["header"]))
        t["header"] = with_dup(t["header"], k, copy.deepcopy(t["header"][k]) if same else 1.0, rng)
        return Case("duplicate_keys", "trace-header", b, dumps(t))
    if kind == "nested-header":
        nested = [k for k, v in t["header"].items() if isinstance(v, dict)]
        k = rng.choice(nested)
        kk = rng.choice(list(t["header"][k]))
        t["header"][k] = with_dup(t["header"][k], kk, t["header"][k][kk] if same else 7.0, rng)
        return Case("duplicate_keys", "trace-header-nested", b, dumps(t))
    s = rng.randrange(len(t["steps"]))
    if kind == "step":
        k = rng.choice(["step", "time", "equations"])
        t["steps"][s] = with_dup(t["steps"][s], k, copy.deepcopy(t["steps"][s][k]) if same else (
            {} if k == "equations" else 1), rng)
        return Case("duplicate_keys", "trace-step", b, dumps(t))
    if kind == "equations":
        eq = t["steps"][s]["equations"]
        k = rng.choice(list(eq))
        t["steps"][s]["equations"] = with_dup(eq, k, copy.deepcopy(eq[k]) if same else [0.0] * len(eq[k]), rng)
        return Case("duplicate_keys", "trace-equations", b, dumps(t))
    if kind == "top":
        if rng.random() < 0.5:
            d = b.run_doc(p)
            k = rng.choice(["particles", "cells", "dt", "steps", "scene", "time", "method"])
            return Case("duplicate_keys", "run-top", b, dumps(with_dup(d, k, copy.deepcopy(d[k]), rng)))
        k = rng.choice(["steps", "header", "schema", "version"])
        return Case("duplicate_keys", "trace-top", b, dumps(with_dup(t, k, copy.deepcopy(t[k]), rng)))
    if kind == "csv-column":
        comments, header, rows = b.csv_parts(p, meta=rng.random() < 0.5)
        c = rng.randrange(len(header))
        if rng.random() < 0.5:  # another column renamed to this one
            o = rng.choice([k for k in range(len(header)) if k != c])
            header[o] = header[c]
        else:  # a copy of the column
            at = rng.randrange(len(header) + 1)
            header.insert(at, header[c])
            for r in rows:
                r.insert(at, r[c] if same else "0")
        return Case("duplicate_keys", "csv-column", b, csv_text(comments, header, rows), "csv")
    if kind == "csv-comment":
        comments, header, rows = b.csv_parts(p, meta=True)
        k = rng.choice(META + ["note"])
        value = b.run.get(k, "x") if same else rng.choice(["8", "1e-4", "x"])
        comments.insert(rng.randrange(len(comments) + 1), f"# {k}: {b.run.get(k, 'x')}")
        comments.insert(rng.randrange(len(comments) + 1), f"# {k}: {value}")
        return Case("duplicate_keys", "csv-comment", b, csv_text(comments, header, rows), "csv")
    comments, header, rows = b.trace_csv()
    line = rng.choice(comments)
    comments.insert(rng.randrange(len(comments) + 1), line if same else line.split(":")[0] + ": 1")
    return Case("duplicate_keys", "csv-trace-comment", b, trace_csv_text(comments, header, rows), "csv")


def fam_step_lengths(rng, b):
    last = rng.random() < 0.5
    s = len(b.trace["steps"]) - 1 if last else rng.randrange(len(b.trace["steps"]) - 1)
    where = "last" if last else "other"
    if rng.random() < 0.6:
        t = copy.deepcopy(b.trace)
        eq = t["steps"][s]["equations"]
        k = rng.choice(list(eq))
        q = eq[k]
        op = rng.choice(["shorter", "shorter", "drop-middle", "longer", "longer", "empty", "much-longer"])
        if op == "shorter":
            del q[len(q) - rng.randint(1, len(q)):]
        elif op == "drop-middle":
            del q[rng.randrange(len(q))]
        elif op == "longer":
            q += [rng.choice([0.0, q[-1]])] * rng.randint(1, 5)
        elif op == "empty":
            q.clear()
        else:
            q *= 10
        return Case("step_lengths", f"json-{op}-{where}", b, dumps(t))
    comments, header, rows = b.trace_csv()
    step = b.trace["steps"][s]["step"]
    k = rng.choice(sorted({r[2] for r in rows}))
    mine = [i for i, r in enumerate(rows) if r[0] == str(step) and r[2] == k]
    op = rng.choice(["shorter", "drop-middle", "longer", "index-twice"])
    if op == "shorter":
        drop = set(mine[len(mine) - rng.randint(1, max(1, len(mine) - 1)):])
        rows = [r for i, r in enumerate(rows) if i not in drop]
    elif op == "drop-middle":
        d = rng.choice(mine)
        rows = rows[:d] + rows[d + 1:]
    elif op == "longer":
        tail = rows[mine[-1]]
        extra = [[tail[0], tail[1], k, str(len(mine) + j), "0e0"] for j in range(rng.randint(1, 5))]
        rows = rows[:mine[-1] + 1] + extra + rows[mine[-1] + 1:]
    else:
        d = rng.choice(mine)
        rows.insert(d + 1, list(rows[d]) if rng.random() < 0.5 else rows[d][:4] + ["0e0"])
    return Case("step_lengths", f"csv-{op}-{where}", b,
                trace_csv_text(comments if rng.random() < 0.7 else [], header, rows), "csv")


def fam_step_numbering(rng, b):
    n = b.steps
    numbers = [0, n + 1, n + 2, 1000, 2 ** 32, 2 ** 63 - 1, 2 ** 63, 2 ** 64 - 1, 2 ** 64, 2 ** 64 + 1, 10 ** 30,
               -1, -(2 ** 63), -(2 ** 64), 1.5, "frac", Raw("1e400"), Raw("-0"), Raw("1e3"), Raw("1E1")]
    count = len(b.trace["steps"])
    if rng.random() < 0.6:
        t = copy.deepcopy(b.trace)
        op = rng.choice(["renumber", "renumber", "renumber", "twice", "copy", "missing-last", "shift"])
        s = rng.choice([0, count - 1, rng.randrange(count)])
        if op == "renumber":
            v = rng.choice(numbers)
            t["steps"][s]["step"] = (t["steps"][s]["step"] + 0.5) if v == "frac" else v
        elif op == "twice":
            o = rng.choice([k for k in range(count) if k != s])
            t["steps"][s]["step"] = t["steps"][o]["step"]
        elif op == "copy":
            t["steps"].insert(rng.randrange(count + 1), copy.deepcopy(t["steps"][s]))
        elif op == "missing-last":
            t["steps"].pop()
        else:  # every step moved by one: 0..n-1 or 2..n+1
            d = rng.choice([1, -1])
            for st in t["steps"]:
                st["step"] += d
        return Case("step_numbering", "json-" + op, b, dumps(t))
    comments, header, rows = b.trace_csv()
    op = rng.choice(["renumber", "renumber", "row", "twice", "missing-last"])
    s = str(rng.choice([1, n, rng.randint(1, n)]))
    if op in ("renumber", "row"):
        v = rng.choice([str(x) for x in numbers if x != "frac"] + [s + ".5", "", "0x1", "+1", "1.0e0"])
        if v in ("+1", "1.0e0") and s == "1":
            v = "-1"  # would be the same number
        idx = [i for i, r in enumerate(rows) if r[0] == s]
        for i in (idx if op == "renumber" else [rng.choice(idx)]):
            rows[i][0] = v
    elif op == "twice":
        o = rng.choice([str(k) for k in range(1, n + 1) if str(k) != s])
        for r in rows:
            if r[0] == s:
                r[0] = o
    else:
        rows = [r for r in rows if r[0] != str(n)]
    return Case("step_numbering", "csv-" + op, b,
                trace_csv_text(comments if rng.random() < 0.7 else [], header, rows), "csv")


def permute_changes_data(b, p, perm):
    keys = [k for k in p if k not in ("x0", "id")]
    return any(p[k][perm[i]] != p[k][i] for k in keys for i in range(b.n))


def fam_x0_id(rng, b):
    p0 = b.p()
    keep = ["x0"] + [k for k in p0 if k not in ("x0",) and (k in ("u", "x") or rng.random() < 0.6)]
    p = {k: p0[k] for k in keep}
    n = b.n
    ident = list(range(n))
    extra, expect = [], (2,)

    def perm_nontrivial():
        while True:
            q = ident[:]
            if rng.random() < 0.5:
                i, j = rng.sample(ident, 2)
                q[i], q[j] = q[j], q[i]
            else:
                rng.shuffle(q)
            if q != ident and permute_changes_data(b, p, q):
                return q

    def reorder(q):
        return {k: [v[q[i]] for i in range(n)] for k, v in p.items()}

    variant = rng.choice(["x0-moved", "x0-moved", "x0-all-zero", "x0-all-same", "id-permuted", "id-permuted-data",
                          "id1-reversed", "id1-permuted", "id1-rotated", "id-twice", "id-out-of-range",
                          "order-shuffled", "match-x0-moved", "match-id-contradiction", "id-only-permuted"])
    ids = None
    if variant in ("x0-moved", "match-x0-moved"):
        i = rng.randrange(n)
        f = rng.choice([1e-6, 0.01, 0.1, 0.2, 0.24, 0.26, 0.3, 0.5, 0.75, 1.0, 2.0, 100.0]) * rng.choice([1, -1])
        if b.two_d:
            p["x0"][i][rng.randrange(2)] += f * b.spacing
        else:
            p["x0"][i] += f * b.spacing
        expect = (1, 2)
        if variant == "match-x0-moved":
            extra = ["--match", "x0"]
        elif rng.random() < 0.5:
            ids = ident
    elif variant in ("x0-all-zero", "x0-all-same"):
        v = p["x0"][rng.randrange(n)] if variant == "x0-all-same" else ([0.0, 0.0] if b.two_d else 0.0)
        p["x0"] = [copy.deepcopy(v) for _ in range(n)]
        ids = ident if rng.random() < 0.5 else None
    elif variant in ("id-permuted", "match-id-contradiction"):
        ids = perm_nontrivial()
        if variant == "match-id-contradiction":
            extra = ["--match", "id"]
    elif variant == "id-permuted-data":
        q = perm_nontrivial()
        x0 = p["x0"]
        p = reorder(q)
        p["x0"] = x0
        ids = q
    elif variant == "id1-reversed":
        p = reorder(ident[::-1])
        ids = [i + 1 for i in ident]
    elif variant == "id1-permuted":
        p = reorder(perm_nontrivial())
        ids = [i + 1 for i in ident]
    elif variant == "id1-rotated":
        k = rng.randint(1, n - 1)
        p = reorder([(i + k) % n for i in ident])
        ids = [i + 1 for i in ident]
    elif variant == "id-twice":
        ids = ident[:]
        i, j = rng.sample(ident, 2)
        ids[i] = ids[j]
    elif variant == "id-out-of-range":
        ids = ident[:]
        ids[rng.randrange(n)] = rng.choice([n, n + 3, -1, 2 ** 64, 10 ** 6, 1.5])
    elif variant == "order-shuffled":
        p = reorder(perm_nontrivial())
        if rng.random() < 0.5:
            del p["x0"]
        # With x0, an x0 that contradicts the order is refused (2).
        extra, expect = ["--match", "order"], (1,) if "x0" not in p else (1, 2)
    else:  # id-only-permuted: no x0, ids name other particles than the rows' values
        del p["x0"]
        ids = perm_nontrivial()
        expect = (1, 2)
    if ids is not None:
        p = {"id": ids, **p}
        if rng.random() < 0.3:  # id last
            p = {**{k: v for k, v in p.items() if k != "id"}, "id": ids}
    form = rng.choice(["run", "columns", "rows", "csv"])
    text, ext = particles_text(b, p, form, rng)
    return Case("x0_id", variant, b, text, ext, extra, expect, json_report=rng.random() < 0.3)


def fam_column_mapping(rng, b):
    p = b.p()
    variants = ["two-to-one", "one-from-two", "renamed-no-physical", "renamed-no-physical", "unknown-ours",
                "mapped-column-absent", "malformed", "wrong-column", "swapped"]
    variant = rng.choice(variants)
    if b.two_d and variant not in ("renamed-no-physical", "unknown-ours", "malformed"):
        form = "csv"
    else:
        form = rng.choice(["csv", "csv", "columns", "run"])
    meta = rng.random() < 0.5
    if form == "csv":
        comments, header, rows = b.csv_parts(p, meta)
    else:
        comments, header, rows = None, list(p), None
    names = list(header)
    phys = [h for h in names if h in PHYSICAL or h in ("stress", "u", "v") or
            any(h in COMPONENTS[k] for k in PHYSICAL if k in COMPONENTS)]
    others = [h for h in names if h not in phys]
    rename = {}
    expect = (2,)
    if variant == "two-to-one":
        a, c = rng.sample(phys, 2) if rng.random() < 0.6 else (rng.choice(phys), rng.choice(others))
        rename[a] = "U"
        cols = f"{a}=U,{c}=U"
    elif variant == "one-from-two":
        a = rng.choice(phys)
        rename[a] = "U"
        cols = f"{a}=U,{a}={rng.choice([h for h in names if h != a])}"
    elif variant == "renamed-no-physical":
        pool = ["ux", "vx", "s11", "s12", "s21", "s22", "disp", "vel", "sig", "F11", "F12", "F21", "F22", "uy",
                "vy", "sxx", "syy", "sxy", "u-x", "sigma", "dx", "vel_x", "vel_y", "tau"]
        chosen = rng.sample(pool, len(phys))
        rename = dict(zip(phys, chosen))
        cols = None
    elif variant == "unknown-ours":
        a = rng.choice(phys)
        cols = f"{rng.choice(['nope', 'velocity', 'displacement', 'sigma', 'U', 'ux', 'id2', 'x0_z'])}={a}"
    elif variant == "mapped-column-absent":
        a = rng.choice(phys)
        cols = f"{a}={rng.choice(['U', 'missing', a + '2', a.upper()])}"
    elif variant == "malformed":
        a = rng.choice(phys)
        cols = rng.choice([a, f"={a}", f"{a}=", f"{a}=U=V", "=", f"{a}={a},=", f"{a}={a},{a}"])
        if cols == f"{a}={a},{a}":
            cols = f"{a}:{a}"
    elif variant == "wrong-column":
        a = rng.choice(phys)
        cols = f"{a}={rng.choice([h for h in names if h != a and {a, h} != SYMMETRIC])}"
        expect = (1, 2)
    else:  # swapped: two physical columns exchanged by the mapping
        a, c = rng.sample(phys, 2)
        while {a, c} == SYMMETRIC:
            a, c = rng.sample(phys, 2)
        rename = {a: "A", c: "C"}
        cols = f"{a}=C,{c}=A"
        expect = (1, 2)
    if form == "csv":
        header = [rename.get(h, h) for h in header]
        text, ext = csv_text(comments, header, rows), "csv"
    else:
        q = {rename.get(k, k): v for k, v in p.items()}
        text, ext = (dumps(q), "json") if form == "columns" else (dumps(b.run_doc(q)), "json")
    extra = ["--columns", cols] if cols is not None else []
    return Case("column_mapping", variant, b, text, ext, extra, expect, json_report=rng.random() < 0.3)


HUGE = [1e155, 1e200, 1e250, 1e300, 1e307, 1.7e308, 1.7976931348623157e308]


def huge_value(rng):
    v = rng.choice(HUGE) if rng.random() < 0.7 else 10 ** rng.uniform(155, 308)
    return v * rng.choice([1, -1])


def change_particles(rng, b, family, change):
    """One (or more) u/v/stress values of the particles changed by `change`."""
    p = b.p()
    col = rng.choice(["u", "v", "stress"])
    where = rng.choice(["one", "one", "several", "column"]) if family == "huge" else "one"
    if where == "one":
        i, c = big_entry(rng, p[col]) if family == "tiny" else (rng.randrange(b.n), rng.randrange(len(p[col][0])) if b.two_d else None)
        set_entry(p[col], i, c, change(get_entry(p[col], i, c)))
    else:
        rows = range(b.n) if where == "column" else rng.sample(range(b.n), rng.randint(2, b.n))
        changed = False
        for i in rows:
            for c in (range(len(p[col][i])) if b.two_d else [None]):
                if not b.two_d or rng.random() < 0.7:
                    set_entry(p[col], i, c, change(get_entry(p[col], i, c)))
                    changed = True
        if not changed:
            set_entry(p[col], rows[0], 0, change(get_entry(p[col], rows[0], 0)))
    form = rng.choice(["run", "columns", "rows", "csv", "csv"])
    text, ext = particles_text(b, p, form, rng)
    return text, ext, f"{form}-{col}-{where}", (1,)


def change_trace(rng, b, family, change):
    col = rng.choice(["u", "v", "stress"])
    key = b.trace_phys[col]
    t = copy.deepcopy(b.trace)
    while True:
        s = rng.randrange(len(t["steps"]))
        q = t["steps"][s]["equations"][key]
        i = big_entry(rng, q) if family == "tiny" else (rng.randrange(len(q)), None)
        if i is not None:
            break
        col = rng.choice(["u", "v", "stress"])
        key = b.trace_phys[col]
    i = i[0]
    where = "last" if s == len(t["steps"]) - 1 else "other"
    # A huge u_p at the last step puts the final x0 = x_p - u_p far from
    # hompm's particle: refused (2) as well as "differs" (1) is right.
    expect = (1, 2) if family == "huge" and where == "last" and col == "u" else (1,)
    if rng.random() < 0.5:
        q[i] = change(q[i])
        return dumps(t), "json", f"trace-json-{key}-{where}", expect
    comments, header, rows = b.trace_csv()
    step = str(t["steps"][s]["step"])
    for r in rows:
        if r[0] == step and r[2] == key and r[3] == str(i):
            r[4] = repr(change(float(r[4])))
            break
    else:
        raise AssertionError("row not found")
    return trace_csv_text(comments, header, rows), "csv", f"trace-csv-{key}-{where}", expect


def fam_huge(rng, b):
    change = lambda x: huge_value(rng)
    text, ext, variant, expect = (change_trace if rng.random() < 0.3 else change_particles)(rng, b, "huge", change)
    return Case("huge", variant, b, text, ext, expect=expect, json_report=rng.random() < 0.5)


def fam_tiny(rng, b):
    sign = rng.choice([1, -1])
    change = lambda x: x * (1 + sign * 1e-6)
    text, ext, variant, expect = (change_trace if rng.random() < 0.3 else change_particles)(rng, b, "tiny", change)
    return Case("tiny", variant, b, text, ext, expect=expect, json_report=rng.random() < 0.3)


_wide_lock = threading.Lock()


def fam_column_counts(rng, b, workdir):
    n = rng.choices(WIDE, weights=[45, 35, 20])[0]
    variants = ["padded-tiny", "ragged", "name-twice", "no-physical", "header-only", "rows-longer", "mapped-to-zeros"]
    if b.two_d and n == 2_000_000:
        variants = ["ragged", "header-only"]  # 64 rows of 2M values would be 256 MB
    variant = rng.choice(variants)
    # Few parameters for the big files, so that they are written once.
    param = rng.randrange(3 if n == 2_000_000 else 1000)
    key = f"{b.name}-{n}-{variant}-{param}"
    path = os.path.join(workdir, "wide", key + ".csv")
    prng = random.Random(key)
    extra, expect = [], (2,)
    if variant == "padded-tiny":
        expect = (1,)
    if variant == "mapped-to-zeros":
        col = prng.choice(["u", "v", "stress"])
        col = COMPONENTS[col][0] if b.two_d else col
        extra, expect = ["--columns", f"{col}=c{prng.randrange(n)}"], (1, 2)
    with _wide_lock:
        if not os.path.exists(path):
            os.makedirs(os.path.dirname(path), exist_ok=True)
            p = b.p()
            if variant == "padded-tiny":
                col = prng.choice(["u", "v", "stress"])
                i, c = big_entry(prng, p[col])
                set_entry(p[col], i, c, get_entry(p[col], i, c) * (1 + 1e-6))
            comments, header, rows = b.csv_parts(p, meta=prng.random() < 0.5)
            names = [f"c{k}" for k in range(n)]
            if variant == "name-twice":
                names[prng.randrange(n)] = prng.choice([h for h in header if h not in ("volume", "density")])
            if variant == "no-physical":
                header = [h if not (h in ("u", "v", "stress") or h.startswith(("u_", "v_", "stress_", "F_")))
                          else "q" + h for h in header]
            pad = "," + ",".join(["0"] * n)
            with open(path + ".tmp", "w") as f:
                f.write("".join(l + "\n" for l in comments))
                f.write(",".join(header) + ("" if variant == "rows-longer" else "," + ",".join(names)) + "\n")
                if variant != "header-only":
                    for r in rows:
                        f.write(",".join(r) + ("" if variant == "ragged" else pad) + "\n")
            os.rename(path + ".tmp", path)
    return Case("column_counts", f"{n}-{variant}", b, None, "csv", extra, expect, input_path=path,
                json_report=rng.random() < 0.2)


STREAM_CONTENT = ["zeros", "ones", "csv-rows", "brackets", "spaces", "random", "newlines", "comments",
                  "json-array", "valid-then-spaces"]


def fam_streams(rng, b):
    source = rng.choice(["/dev/zero", "/dev/urandom", "fifo", "fifo", "fifo", "stdin-pipe", "stdin-zero", "dash-pipe"])
    content = rng.choice(STREAM_CONTENT) if source in ("fifo", "stdin-pipe", "dash-pipe") else None
    limit = rng.choice([None, None, "256KiB", "1MiB", "16MiB", "64MiB", "512MiB"])
    if b.two_d and limit in ("256KiB", "1MiB"):
        limit = "16MiB"
    variant = source + (f"-{content}" if content else "") + f"-{limit or 'default'}"
    c = Case("streams", variant, b, None, "", expect=(2,), stream={"source": source, "content": content})
    c.pre = ["--max-memory", limit] if limit else []
    return c


# --- running ---------------------------------------------------------------

def stream_chunks(kind, b, rng):
    """An endless stream: (prefix bytes, chunk repeated for ever)."""
    if kind == "zeros":
        return b"", b"\0" * (1 << 20)
    if kind == "ones":
        return b"", b"1" * (1 << 20)
    if kind == "csv-rows":
        comments, header, rows = b.csv_parts(b.p(), meta=False)
        body = "".join(",".join(r) + "\n" for r in rows).encode()
        return (",".join(header) + "\n").encode(), body * max(1, (1 << 20) // len(body))
    if kind == "brackets":
        return b"", b"[" * (1 << 20)
    if kind == "spaces":
        return b"", b" " * (1 << 20)
    if kind == "random":
        return b"", rng.randbytes(1 << 20)
    if kind == "newlines":
        return b"", b"\n" * (1 << 20)
    if kind == "comments":
        return b"", b"# c: x\n" * (1 << 17)
    if kind == "json-array":
        return b'{"particles": {"u": [', b"0.5," * (1 << 18)
    return b.run_text.encode(), b" " * (1 << 20)


def writer(fd_or_file, prefix, chunk, stop):
    try:
        if prefix:
            os.write(fd_or_file, prefix)
        view = memoryview(chunk)
        while not stop.is_set():
            os.write(fd_or_file, view)
    except OSError:
        pass
    finally:
        try:
            os.close(fd_or_file)
        except OSError:
            pass


def fifo_writer(path, prefix, chunk, stop):
    while not stop.is_set():
        try:
            fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
        except OSError as e:
            if e.errno in (errno.ENXIO, errno.EINTR):
                time.sleep(0.005)
                continue
            return
        os.set_blocking(fd, True)
        writer(fd, prefix, chunk, stop)
        return


def command(binary, case, input_path, memory, seconds):
    args = list(getattr(case, "pre", [])) + ["check", *case.base.setup, "--input", input_path, *case.extra]
    if case.json_report:
        args.append("--json")
    return ["prlimit", f"--as={memory}", "timeout", "-k", "5", str(seconds), binary] + args


def run_case(binary, index, case, workdir, memory, seconds, seed):
    stem = os.path.join(workdir, "cases", f"case-{index:05d}")
    stdin, stop, threads, cleanup, own = subprocess.DEVNULL, threading.Event(), [], [], False
    if case.stream:
        src = case.stream["source"]
        rng = random.Random(f"{seed}-{index}-stream")
        if src in ("/dev/zero", "/dev/urandom"):
            input_path = src
        elif src == "fifo":
            input_path = stem + ".fifo"
            os.mkfifo(input_path)
            cleanup.append(input_path)
            prefix, chunk = stream_chunks(case.stream["content"], case.base, rng)
            threads.append(threading.Thread(target=fifo_writer, args=(input_path, prefix, chunk, stop), daemon=True))
        elif src == "stdin-zero":
            input_path, stdin = "/dev/stdin", open("/dev/zero", "rb")
        else:
            input_path = "-" if src == "dash-pipe" else "/dev/stdin"
            stdin = subprocess.PIPE
    elif case.input_path:
        input_path = case.input_path
    else:
        input_path, own = f"{stem}.{case.ext}", True
        with open(input_path, "w") as f:
            f.write(case.text)
    cmd = command(binary, case, input_path, memory, seconds)
    with open(stem + ".out", "wb") as out, open(stem + ".err", "wb") as err:
        p = subprocess.Popen(cmd, stdin=stdin, stdout=out, stderr=err, start_new_session=True)
        if stdin is subprocess.PIPE:
            prefix, chunk = stream_chunks(case.stream["content"], case.base, rng)
            threads.append(threading.Thread(target=writer, args=(os.dup(p.stdin.fileno()), prefix, chunk, stop),
                                             daemon=True))
            p.stdin.close()
        for t in threads:
            t.start()
        try:
            code = p.wait(timeout=seconds + 30)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, 9)
            code = p.wait()
        stop.set()
    for t in threads:
        t.join(timeout=10)
    if hasattr(stdin, "close"):
        stdin.close()
    for path in cleanup:
        os.remove(path)
    with open(stem + ".out", "rb") as f:
        stdout = f.read().decode("utf-8", "replace")
    with open(stem + ".err", "rb") as f:
        stderr = f.read().decode("utf-8", "replace")
    os.remove(stem + ".out")
    os.remove(stem + ".err")
    return cmd, input_path, own, code, stdout, stderr


NONFINITE = re.compile(r"(?<![A-Za-z_])[-+]?(nan|inf|infinity)(?![A-Za-z_])", re.I)


def bad_numbers(v, path="$"):
    """Paths of the non-finite numbers and nulls in a JSON value."""
    if v is None:
        return [path]
    if isinstance(v, float) and not math.isfinite(v):
        return [path]
    if isinstance(v, dict):
        return [q for k, x in v.items() for q in bad_numbers(x, f"{path}.{k}")]
    if isinstance(v, list):
        return [q for k, x in enumerate(v) for q in bad_numbers(x, f"{path}[{k}]")]
    return []


def classify(case, code, out, err):
    lines = [l for l in err.splitlines() if l.strip()]
    if code in (124, 137, -9) or "memory allocation" in err:
        return "unbounded read", "timeout" if code == 124 else "memory"
    if "out of memory" in err:  # read until the address-space cap, then failed gracefully
        return "unbounded read", "read up to the memory cap"
    if code == 101 or "panicked" in err or code < 0 or code >= 128:
        return "panic", f"exit {code}"
    if code == 0 and case.family != "control":
        return "false agrees", ""
    m = NONFINITE.search(out)
    if m:
        return "silent NaN/inf", f"'{m.group(0)}' in stdout"
    if case.json_report and code in (0, 1):
        try:
            doc = json.loads(out)
        except ValueError as e:
            return "wrong exit code", ("no JSON report on stdout" if not out.strip() else f"invalid JSON report: {e}")
        bad = bad_numbers(doc)
        if bad:
            return "silent NaN/inf", "null/non-finite at " + ", ".join(bad[:5])
    if code == 2 and len(lines) > 1:
        return "multi-line error", f"{len(lines)} lines"
    if code not in case.expect:
        return "wrong exit code", f"exit {code}, expected {sorted(case.expect)}"
    return "ok", ""


def generate(index, family, seed, bases, workdir):
    rng = random.Random(f"{seed}-{index}")
    pool = list(bases.values())
    b = rng.choice(pool)
    if family == "column_counts":
        return fam_column_counts(rng, b if rng.random() < 0.3 else rng.choice([x for x in pool if not x.two_d]),
                                 workdir)
    if family == "streams":
        return fam_streams(rng, b if rng.random() < 0.2 else rng.choice([x for x in pool if not x.two_d]))
    return globals()["fam_" + family](rng, b)


def shell(cmd):
    return " ".join(a if re.fullmatch(r"[A-Za-z0-9_./=:,+-]+", a) else "'" + a.replace("'", "'\\''") + "'"
                    for a in cmd)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--binary", default="target/release/hompm")
    ap.add_argument("--base-binary", help="the binary whose output is mutated (default: --binary)")
    ap.add_argument("--count", type=int, default=3200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--memory", default=str(4 << 30))
    ap.add_argument("--seconds", type=int, default=20)
    ap.add_argument("--out", help="write the counts (and an example per family x class) as JSON here")
    ap.add_argument("--workdir", help="where inputs are written (default: a new directory under /tmp)")
    ap.add_argument("--repro-dir", help="copy inputs of panics, false agrees, silent NaN/inf, unbounded reads here")
    ap.add_argument("--cases", help="run only these case numbers (comma-separated)")
    ap.add_argument("--families", help="run only these families (comma-separated)")
    ap.add_argument("--keep", action="store_true", help="keep every input, not only those not ok")
    ap.add_argument("--log", help="write one JSON line per case (family, variant, class, exit, stderr) here")
    a = ap.parse_args()
    binary = os.path.abspath(a.binary)
    started = time.monotonic()
    workdir = os.path.abspath(a.workdir or tempfile.mkdtemp(prefix="fuzz-check-", dir="/tmp"))
    os.makedirs(os.path.join(workdir, "cases"), exist_ok=True)
    os.makedirs(os.path.join(workdir, "kept"), exist_ok=True)
    bases = {name: Base(name, os.path.abspath(a.base_binary or a.binary)) for name in SETUPS}
    # Families: the control gets 1/16 of the count, the ten others share the rest.
    control = max(1, a.count // 16)
    plan = ["control"] * control + [FAMILIES[k % len(FAMILIES)] for k in range(a.count - control)]
    random.Random(a.seed).shuffle(plan)
    chosen = range(a.count)
    if a.cases:
        chosen = [int(x) for x in a.cases.split(",")]
    if a.families:
        keep = set(a.families.split(","))
        chosen = [i for i in chosen if plan[i] in keep]
    cases = [(i, generate(i, plan[i], a.seed, bases, workdir)) for i in chosen]

    counts = collections.defaultdict(collections.Counter)
    examples, variants = {}, collections.defaultdict(collections.Counter)
    kept = []
    log = open(a.log, "w") if a.log else None

    def one(item):
        i, case = item
        cmd, input_path, own, code, out, err = run_case(binary, i, case, workdir, a.memory, a.seconds, a.seed)
        cls, why = classify(case, code, out, err)
        return i, case, cmd, input_path, own, code, out, err, cls, why

    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        for i, case, cmd, input_path, own, code, out, err, cls, why in pool.map(one, cases):
            counts[case.family][cls] += 1
            written = input_path
            if log:
                log.write(json.dumps({"case": i, "family": case.family, "variant": case.variant, "class": cls,
                                      "why": why, "exit": code, "extra": case.extra, "json": case.json_report,
                                      "stderr": err.strip().splitlines()[:3]}) + "\n")
            if cls != "ok":
                variants[(case.family, cls)][case.variant] += 1
                if not case.stream:
                    dest = os.path.join(workdir, "kept", f"case-{i:05d}.{case.ext}")
                    shutil.copy(input_path, dest)
                    cmd, input_path = [dest if x == input_path else x for x in cmd], dest
            if own and not a.keep:
                os.remove(written)
            if cls in SERIOUS and a.repro_dir:
                os.makedirs(a.repro_dir, exist_ok=True)
                name = f"{case.family}-{i:05d}"
                if not case.stream:
                    dest = os.path.join(a.repro_dir, name + os.path.splitext(input_path)[1])
                    shutil.copy(input_path, dest)
                    cmd = [dest if x == input_path else x for x in cmd]
                with open(os.path.join(a.repro_dir, name + ".cmd"), "w") as f:
                    f.write(shell(cmd) + "\n")
                    if case.stream:
                        f.write(f"# stream: {json.dumps(case.stream)}\n")
                    f.write(f"# exit {code}; {why}\n# stderr: {err.strip()[:2000]}\n")
            if cls != "ok":
                kept.append({"case": i, "family": case.family, "variant": case.variant, "class": cls, "why": why,
                             "exit": code, "command": shell(cmd), "stream": case.stream,
                             "stderr": err.strip().splitlines()[:3]})
            examples.setdefault((case.family, cls), {
                "case": i, "variant": case.variant, "exit": code, "why": why, "command": shell(cmd),
                "stderr": (err.strip().splitlines() or [""])[0][:300]})

    shutil.rmtree(os.path.join(workdir, "wide"), ignore_errors=True)
    elapsed = time.monotonic() - started
    families = ["control"] + FAMILIES
    total = collections.Counter()
    for f in families:
        total.update(counts[f])
    print(f"{len(cases)} check inputs, seed {a.seed}, binary {binary}, memory cap {a.memory} bytes, "
          f"{a.seconds} s each, {a.jobs} jobs, bases "
          + ", ".join(f"{n} {b.digest()}" for n, b in bases.items()) + f"; {elapsed:.0f} s wall\n")
    print("| family | inputs | " + " | ".join(CLASSES) + " |")
    print("|---|---:|" + "---:|" * len(CLASSES))
    for f in families + ["total"]:
        c = total if f == "total" else counts[f]
        print(f"| {f} | {sum(c.values())} | " + " | ".join(str(c[k]) for k in CLASSES) + " |")
    notok = [(f, k) for f in families for k in CLASSES if k != "ok" and counts[f][k]]
    if notok:
        print("\nnot ok, by variant, with an example:")
        for f, k in notok:
            e = examples[(f, k)]
            print(f"- {f} / {k}: {dict(variants[(f, k)])}\n  case {e['case']} ({e['variant']}): exit {e['exit']} "
                  f"{e['why']}; {e['command']}\n  stderr: {e['stderr']}")
    print(f"\ninputs not ok kept under {os.path.join(workdir, 'kept')}")
    if a.out:
        with open(a.out, "w") as f:
            json.dump({"binary": binary, "seed": a.seed, "count": len(cases), "memory": int(a.memory),
                       "seconds": a.seconds, "jobs": a.jobs, "wall_seconds": round(elapsed, 1),
                       "bases": {n: b.digest() for n, b in bases.items()},
                       "classes": CLASSES,
                       "counts": {f: {k: counts[f][k] for k in CLASSES} for f in families},
                       "total": {k: total[k] for k in CLASSES},
                       "variants_not_ok": {f"{f} / {k}": dict(variants[(f, k)]) for f, k in notok},
                       "examples": {f"{f} / {k}": v for (f, k), v in examples.items()},
                       "not_ok": kept}, f, indent=1)


if __name__ == "__main__":
    main()

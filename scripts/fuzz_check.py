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

`--kind dump` (issue #36; `--kind all` mixes both) writes hompm's own runs
(`run vibrating-bar --cells 4 --steps 20`, `run aligned-vibration --method
mpm --cells 2 --ppc 4 --steps 3`, and the same with bsmpm of degree 2 on 4
cells for Taichi's flags) as LAMMPS-style dump files the way Karamelo
writes them (ids from 1; `id type x0 x vx s11` in 1D, `id type x0 y0 x y vx
vy s11 s22 s12` in 2D; checked with `--columns v=vx,stress=s11` or the 2D
mapping) and mutates them. Where a mutated file is still well-formed, the
expected exit is the tolerance rule of docs/oracle.md applied here to the
values the file holds (`judge`): 1 beyond 4× the tolerance, 0 below a
quarter of it, either in between.

| family | what is mutated | exit expected |
|---|---|---|
| dump_control | nothing, or what must not matter: no type/x/x0/id column, u written, rows or columns shuffled, an earlier block, TIME/UNITS, a triclinic box, CRLF, tabs, blank lines, --format lammps-dump, --match x0, Karamelo's y-fastest order, zero z columns | 0 |
| dump_structure | a row or an ITEM/value line dropped or doubled, a section twice, adjacent lines swapped, sections moved, the file cut at a byte, blank, comment or garbage lines | 2 (0 or 1 where the file stays well-formed) |
| dump_counts | NUMBER OF ATOMS or TIMESTEP of another, huge, negative, fractional or non-numeric value; rows and count both changed | 2 (0 for another spelling of the same count) |
| dump_numbers | nan, inf, 1e400, hex, empty, Unicode digits or separators, control characters in a cell; or another valid spelling (-0, 1e-400, %.6g) | 2 (0/1 for valid spellings) |
| dump_blocks | a timestep twice, a later or earlier block, --dump-step of each or of none, empty blocks, blocks of other columns, many blocks, ATOMS without columns or with a name twice | 2, or the chosen block's verdict |
| dump_items | unknown ITEM lines, TIME/UNITS, ITEM: without a space or lower-case, BOX BOUNDS variants | 2 (0 for what LAMMPS writes) |
| dump_whitespace | CRLF, CR only, tabs, VT/FF/NBSP/U+3000 separators, BOM, NUL, invalid UTF-8, no final newline | 0 or 2 |
| dump_ids | 0-based, zero, negative, fractional, twice, out of range, shifted by one, permuted with or against the rows and x0, none with --match order/id | 2 (0/1 where the match is right) |
| dump_perturb | one value changed by 1e-3..1e-15 relative, a position by a fraction of max\|u\|, a column scaled, written to 6..16 digits, two columns swapped by --columns, a row copied, positions translated, a column under hompm's own name next to the mapped one | the judged verdict (2 for the name twice) |
| dump_format | --format csv/json on a dump, --format lammps-dump or --dump-step on CSV/JSON, --dump-step spellings, leading blank lines, --convergence of three dumps | 2, 0 or 1 |
| dump_flags | a dump of a run with convention flags A checked with flags B | the judged verdict against hompm's run with B; 2 when B is not a valid combination |
| dump_json_flags | hompm's run JSON or trace JSON with flags A checked with flags B | 2 when the conventions differ (an exit 0 there is a wrong exit code, not a false agrees, if the values do agree), else 0 |
| dump_huge | 1k..400k blocks before the last, a huge count, a 10^7-digit number, 100k columns, 300k rows, endless dumps on a FIFO or stdin | 0 or 2 |

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
        # Since #36 hompm derives u = x − x0 from its x and x0: rename x too,
        # so that nothing physical is left.
        for k, h in enumerate(h for h in names if h == "x" or h in ("x_x", "x_y")):
            rename[h] = f"pos{k}"
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
                # x goes too: since #36 hompm derives u = x − x0 from it.
                header = [h if not (h in ("u", "v", "stress", "x") or
                                    h.startswith(("u_", "v_", "stress_", "F_", "x_")))
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


# --- LAMMPS-style dump files (issue #36; --kind dump) ----------------------
#
# Inputs are hompm's own runs written as Karamelo writes its particles
# (ids from 1; 1D `id type x0 x vx s11`, 2D `id type x0 y0 x y vx vy s11 s22
# s12`), checked with `--columns v=vx,stress=s11` (1D) or the 2D mapping,
# then mutated. Where a mutated file is still well-formed, the expected exit
# comes from the tolerance rule of docs/oracle.md re-done here (`judge`:
# scale per field, the floor 4√n·ε·max|x| of a derived u, the 2D stress's
# (λ + 2μ)·atol·max|F|): more than 4× the tolerance is 1, below a quarter
# 0, in between either.

DUMP_SETUPS = {
    "dump-1d": ["vibrating-bar", "--cells", "4", "--steps", "20"],
    "dump-2d": ["aligned-vibration", "--method", "mpm", "--cells", "2", "--ppc", "4", "--steps", "3"],
    # 4 cells: on 2 cells the padded quadratic grid has one free node, which the
    # symmetric motion leaves at rest (u = 0 with --knots padded).
    "dump-2d-bsmpm": ["aligned-vibration", "--method", "bsmpm", "--degree", "2", "--cells", "4", "--ppc", "4",
                      "--steps", "3"],
}
DUMP_FAMILIES = ["dump_structure", "dump_counts", "dump_numbers", "dump_blocks", "dump_items", "dump_whitespace",
                 "dump_ids", "dump_perturb", "dump_format", "dump_flags", "dump_json_flags", "dump_huge"]
DUMP_HEADER = {False: ["id", "type", "x0", "x", "vx", "s11"],
               True: ["id", "type", "x0", "y0", "x", "y", "vx", "vy", "s11", "s22", "s12"]}
# A dump column -> hompm's column (what --columns maps, ours=theirs).
DUMP_MAP = {False: {"vx": "v", "s11": "stress", "ux": "u"},
            True: {"x0": "x0_x", "y0": "x0_y", "x": "x_x", "y": "x_y", "vx": "v_x", "vy": "v_y",
                   "s11": "stress_xx", "s22": "stress_yy", "s12": "stress_xy", "ux": "u_x", "uy": "u_y"}}
DUMP_FIELDS = {
    False: {"u": ["u"], "v": ["v"], "stress": ["stress"], "x0": ["x0"], "x": ["x"], "volume": ["volume"],
            "density": ["density"]},
    True: {"u": ["u_x", "u_y"], "v": ["v_x", "v_y"], "stress": ["stress_xx", "stress_xy", "stress_yx", "stress_yy"],
           "F": ["F_xx", "F_xy", "F_yx", "F_yy"], "x0": ["x0_x", "x0_y"], "x": ["x_x", "x_y"],
           "volume": ["volume"], "density": ["density"]}}
DUMP_PHYSICAL = {"u", "v", "stress", "F"}
RTOL, ATOL, EPS = 1e-9, 1e-12, 2.220446049250313e-16
FLOAT_RE = re.compile(r"[+-]?(inf|infinity|nan|([0-9]+|[0-9]+\.[0-9]*|[0-9]*\.[0-9]+)([eE][+-]?[0-9]+)?)", re.I)
U64_RE = re.compile(r"\+?[0-9]+")
# Rust's char::is_whitespace (what split_whitespace splits on).
RUST_WS = set("\t\n\x0b\x0c\r \x85\xa0\u1680\u2000\u2001\u2002\u2003\u2004\u2005\u2006\u2007\u2008\u2009\u200a"
              "\u2028\u2029\u202f\u205f\u3000")
CONVENTION_FLAGS = {
    "--scheme": ["musl", "usl", "usf"],
    "--transfer": ["flip", "pic", "flip:0.5", "flip:0.99", "flip:1", "flip:0", "apic"],
    "--positions": ["projected", "grid"],
    "--body-force": ["particles", "nodes"],
    "--knots": ["open", "padded"],
    "--gradient": ["basis", "affine"],
    "--solution": ["mls-paper", "axis-aligned"],
}
TAICHI = ["--transfer", "apic", "--gradient", "affine", "--knots", "padded"]


def rust_float(tok):
    """The number Rust's `str::parse::<f64>` reads from `tok`, or None."""
    return float(tok) if FLOAT_RE.fullmatch(tok) else None


def rust_split(line):
    """`str::split_whitespace` as Rust does it."""
    out, cur = [], ""
    for ch in line:
        if ch in RUST_WS:
            if cur:
                out.append(cur)
            cur = ""
        else:
            cur += ch
    return out + ([cur] if cur else [])


def rust_u64(tok):
    t = tok.strip("".join(RUST_WS))
    return int(t) if U64_RE.fullmatch(t) and int(t) < 2 ** 64 else None


def dfmt(v, style="repr"):
    if isinstance(v, int):
        return str(v)
    if style == "repr":
        return repr(float(v))
    return style % v


def with_steps(setup, k):
    s = list(setup)
    s[s.index("--steps") + 1] = str(k)
    return s


class DumpBase:
    """One setup's run (JSON) as the base of dump files, and a cache of runs
    and traces of the same setup under other flags."""

    def __init__(self, name, binary):
        self.name, self.setup, self.binary = name, DUMP_SETUPS[name], binary
        self.two_d = self.setup[0] == "aligned-vibration"
        self.cache = {}
        code, self.run_text, err = self.output("run", [])
        if code != 0:
            sys.exit(f"{binary} run {' '.join(self.setup)}: exit {code}: {err}")
        self.run = json.loads(self.run_text)
        self.n = len(self.run["particles"]["x0"])
        self.steps = int(self.run["steps"])
        x0 = self.run["particles"]["x0"]
        xs = sorted({e[0] if self.two_d else e for e in x0})
        self.spacing = min(b - a for a, b in zip(xs, xs[1:]))
        self.header = DUMP_HEADER[self.two_d]
        self.map = DUMP_MAP[self.two_d]
        self.length = float(self.run["params"]["length"])
        self.stress_k = 0.0
        if self.two_d:
            e, nu = self.run["params"]["young"], self.run["params"]["poisson"]
            mu, lam = e / (2 * (1 + nu)), e * nu / ((1 + nu) * (1 - 2 * nu))
            self.stress_k = lam + 2 * mu

    def output(self, command, flags, setup=None):
        key = (command, tuple(setup or self.setup), tuple(flags))
        if key not in self.cache:
            p = subprocess.run([self.binary, command, *(setup or self.setup), *flags, "--json"], capture_output=True,
                               text=True)
            self.cache[key] = (p.returncode, p.stdout, p.stderr.strip())
        return self.cache[key]

    def run_json(self, flags=(), setup=None):
        code, out, _ = self.output("run", list(flags), setup)
        return json.loads(out) if code == 0 else None

    def digest(self):
        return hashlib.sha256(self.run_text.encode()).hexdigest()[:16]

    def conventions(self, run):
        """The conventions a run ran with (its JSON names them unless they are the book's)."""
        c = dict(run.get("conventions") or {"scheme": "musl", "transfer": "flip",
                                            "positions": "grid" if self.two_d else "projected",
                                            "body-force": "particles", "knots": "open", "gradient": "basis"})
        if self.two_d:
            c["solution"] = run["params"].get("solution", "mls-paper")
        return c


def dump_values(b, run):
    """Per particle (hompm's order), the dump's columns as numbers."""
    p, rows = run["particles"], []
    for i in range(len(p["x0"])):
        if b.two_d:
            s = p["stress"][i]
            r = {"x0": p["x0"][i][0], "y0": p["x0"][i][1], "x": p["x"][i][0], "y": p["x"][i][1],
                 "vx": p["v"][i][0], "vy": p["v"][i][1], "s11": s[0], "s22": s[3], "s12": s[1]}
            r["ux"], r["uy"] = r["x"] - r["x0"], r["y"] - r["y0"]
        else:
            r = {"x0": p["x0"][i], "x": p["x"][i], "vx": p["v"][i], "s11": p["stress"][i]}
            r["ux"] = r["x"] - r["x0"]
        r["id"], r["type"] = i + 1, 1
        rows.append(r)
    return rows


class DBlock:
    """One block of a dump file, as text tokens."""

    def __init__(self, timestep, header, rows, box):
        self.timestep, self.natoms = str(timestep), None
        self.header, self.rows, self.box = list(header), rows, list(box)
        self.pre = []  # lines between the atom count and the box

    def lines(self):
        head = ["ITEM: TIMESTEP", self.timestep, "ITEM: NUMBER OF ATOMS",
                str(len(self.rows)) if self.natoms is None else self.natoms]
        return head + self.pre + self.box + ["ITEM: ATOMS " + " ".join(self.header)] + [" ".join(r) for r in self.rows]


def box_lines(b):
    return (["ITEM: BOX BOUNDS sm sm sm", f"0 {b.length!r}", f"0 {b.length!r}" if b.two_d else "0 0", "0 0"])


def make_block(b, run=None, header=None, timestep=None, style="repr", order=None, ids=None):
    """A block of `run`'s particles (default: the base run) in `order`; `ids`
    (default: each particle's own, from 1) by row."""
    values = dump_values(b, run or b.run)
    header = list(header or b.header)
    order = list(range(len(values))) if order is None else order
    rows = []
    for r, k in enumerate(order):
        v = dict(values[k])
        if ids is not None:
            v["id"] = ids[r]
        rows.append([dfmt(v[h], style) for h in header])
    ts = int((run or b.run)["steps"]) if timestep is None else timestep
    return DBlock(ts, header, rows, box_lines(b))


def dump_text(blocks, newline="\n"):
    return newline.join(l for blk in blocks for l in blk.lines()) + newline


def dump_columns(b, header, colmap=None):
    """--columns for the dump columns in `header`."""
    m = b.map if colmap is None else colmap
    cols = ",".join(f"{m[h]}={h}" for h in dict.fromkeys(header) if h in m and m[h] != h)
    return ["--columns", cols] if cols else []


def theirs_of(b, header, rows, colmap=None, match="auto", lenient=False):
    """hompm-named columns in hompm's particle order from a well-formed block
    (every token a finite number), or None where the file must be refused
    (rows that match no particle, twice, or an id that contradicts x0).
    `lenient` matches ids as hompm does (a column 1..n after the dump's −1 is
    taken as 1-based once more); otherwise dump ids must be 1..n."""
    m = b.map if colmap is None else colmap
    cols = {}
    for c, h in enumerate(header):
        cols[m.get(h, h)] = [float(r[c]) for r in rows]
    n = len(rows)
    if n != b.n:
        return None
    x0names = ["x0_x", "x0_y"] if b.two_d else ["x0"]
    ref_x0 = b.run["particles"]["x0"]
    ref_x0 = [[e[0] for e in ref_x0], [e[1] for e in ref_x0]] if b.two_d else [ref_x0]
    their_x0 = [cols[c] for c in x0names] if all(c in cols for c in x0names) else None
    ids = cols.pop("id", None)
    if match == "order":
        perm = list(range(n))
    elif ids is not None and match in ("auto", "id"):
        k = [i - 1 for i in ids]
        if lenient and all(x >= 1 for x in k) and float(n) in k:
            k = [x - 1 for x in k]
        if sorted(k) != [float(i) for i in range(n)]:
            return None
        perm = [int(x) for x in k]
        if their_x0 is not None:
            for r in range(n):
                if any(abs(their_x0[a][r] - ref_x0[a][perm[r]]) > b.spacing / 4 for a in range(len(x0names))):
                    return None
    else:
        if their_x0 is None:
            return None
        perm = []
        for r in range(n):
            best = min(range(n), key=lambda k: sum((their_x0[a][r] - ref_x0[a][k]) ** 2 for a in range(len(x0names))))
            if any(abs(their_x0[a][r] - ref_x0[a][best]) > b.spacing / 4 for a in range(len(x0names))):
                return None
            perm.append(best)
        if len(set(perm)) != n:
            return None
    known = {c for cs in DUMP_FIELDS[b.two_d].values() for c in cs}
    out = {}
    for name, vals in cols.items():
        if name in known:
            col = [0.0] * n
            for r in range(n):
                col[perm[r]] = vals[r]
            out[name] = col
    return out


def ours_of(b, run):
    p = run["particles"]
    if not b.two_d:
        return {k: list(p[k]) for k in ("x0", "x", "u", "v", "stress", "volume", "density") if k in p}
    out = {}
    for name, comps in COMPONENTS.items():
        if name in p:
            for c, cname in enumerate(comps):
                out[cname] = [e[c] for e in p[name]]
    for k in ("volume", "density"):
        if k in p:
            out[k] = list(p[k])
    return out


def judge(b, ref, theirs):
    """The largest |yours − hompm| over its tolerance (docs/oracle.md), or
    None when no physical field is compared."""
    ours, theirs = ours_of(b, ref), dict(theirs)
    steps = int(ref["steps"])
    axes = [("u_x", "x_x", "x0_x"), ("u_y", "x_y", "x0_y")] if b.two_d else [("u", "x", "x0")]
    derived = set()
    for u, x, x0 in axes:
        if x in theirs and x0 in theirs:
            vals = [a - c for a, c in zip(theirs[x], theirs[x0])]
            if u not in theirs:
                theirs[u] = vals
                derived.add(u)
            elif theirs[u] == vals:
                derived.add(u)
    largest_x = max([max(abs(v) for v in theirs[x]) for _, x, _ in axes if x in theirs] or [0.0])
    floor = 4 * math.sqrt(max(steps, 1)) * EPS * largest_x if derived else 0.0
    stress_floor = 0.0
    if b.two_d:
        stress_floor = b.stress_k * ATOL * max(abs(v) for c in ("F_xx", "F_xy", "F_yx", "F_yy") for v in ours[c])
    worst, physical = 0.0, False
    for field, cols in DUMP_FIELDS[b.two_d].items():
        present = [c for c in cols if c in theirs and c in ours]
        if not present:
            continue
        physical |= field in DUMP_PHYSICAL
        scale = max(abs(v) for c in present for v in ours[c])
        for c in present:
            least = floor if c in derived else (stress_floor if c.startswith("stress") else 0.0)
            atol_abs = max(ATOL * scale, least)
            for a, h in zip(theirs[c], ours[c]):
                d = abs(a - h)
                thr = max(atol_abs, RTOL * abs(h))
                r = d / thr if thr > 0 else (math.inf if d > 0 else 0.0)
                worst = max(worst, r)
    return worst if physical else None


def expect_of(worst):
    if worst is None:
        return (2,)
    if worst > 4:
        return (1,)
    if worst < 0.25:
        return (0,)
    return (0, 1)


def oracle(b, ref, header, rows, colmap=None, match="auto"):
    """(expected exits, whether an exit 0 would be physically right) for a
    well-formed block checked against the run `ref`."""
    strict = theirs_of(b, header, rows, colmap, match)
    expect = expect_of(judge(b, ref, strict)) if strict is not None else (2,)
    lenient = theirs_of(b, header, rows, colmap, match, lenient=True)
    ok0 = lenient is not None and 0 in expect_of(judge(b, ref, lenient))
    return expect, ok0


def dcase(family, variant, b, text, header, expect, rng, extra=(), agree_ok=False, colmap=None, columns=True):
    ex = (dump_columns(b, header, colmap) if columns else []) + list(extra)
    c = Case(family, variant, b, text, "dump", ex, expect, json_report=rng.random() < 0.25)
    c.agree_ok = agree_ok
    return c


def judged_case(family, variant, b, blocks, rng, chosen=None, extra=(), ref=None, colmap=None, match="auto",
                text=None, header_for_columns=None):
    """A well-formed file: expected exit from the oracle on the chosen block."""
    blk = chosen or blocks[-1]
    expect, ok0 = oracle(b, ref or b.run, blk.header, blk.rows, colmap, match)
    extra = list(extra) + (["--match", match] if match != "auto" else [])
    hdr = header_for_columns or sorted({h for bl in blocks for h in bl.header})
    return dcase(family, variant, b, text if text is not None else dump_text(blocks), hdr, expect, rng, extra,
                 agree_ok=ok0, colmap=colmap)


def karamelo_order(b):
    """Row order y-fastest (Karamelo's 2D numbering); hompm's is x-fastest."""
    if not b.two_d:
        return list(range(b.n))
    x0 = b.run["particles"]["x0"]
    return sorted(range(b.n), key=lambda k: (x0[k][0], x0[k][1]))


def earlier_run(b, rng):
    k = rng.randint(1, b.steps - 1)
    return k, b.run_json([], with_steps(b.setup, k))


def fam_dump_control(rng, b):
    kinds = ["plain", "no-type", "with-u", "no-x", "no-x0", "no-id", "rows-shuffled", "columns-shuffled", "karamelo-3d",
             "earlier-block", "earlier-block-step", "final-first-step", "time-units", "triclinic", "crlf", "tabs",
             "blank-lines", "trailing-space", "leading-blank", "format-flag", "match-x0", "karamelo-order-x0",
             "17g", "json-report"]
    kind = rng.choice(kinds)
    header = list(b.header)
    order, ids, extra, match = None, None, [], "auto"
    style = "%.17g" if kind == "17g" else "repr"
    if kind == "no-type":
        header.remove("type")
    elif kind == "with-u":
        header += ["ux", "uy"] if b.two_d else ["ux"]
    elif kind == "no-x":
        header = [h for h in header if h not in ("x", "y")]
    elif kind == "no-x0":
        header = [h for h in header if h not in ("x0", "y0")]
    elif kind == "no-id":
        header.remove("id")
    elif kind == "rows-shuffled":
        order = list(range(b.n))
        rng.shuffle(order)
    elif kind == "columns-shuffled":
        rng.shuffle(header)
    elif kind == "match-x0":
        match = "x0"
    elif kind == "karamelo-order-x0":
        order, match = karamelo_order(b), "x0"
        ids = list(range(1, b.n + 1))
    final = make_block(b, header=header, order=order, ids=ids, style=style)
    if kind == "karamelo-3d":  # the columns a 3D-capable code writes besides, all zero: not compared
        more = ["z0", "z", "vz", "s33", "s13", "s23"] + ([] if b.two_d else ["y0", "y", "vy", "s22", "s12"])
        final.header += more
        for r in final.rows:
            r.extend(["0"] * len(more))
    blocks = [final]
    if kind in ("earlier-block", "earlier-block-step", "final-first-step"):
        k, run = earlier_run(b, rng)
        early = make_block(b, run=run, header=header, timestep=k)
        blocks = [final, early] if kind == "final-first-step" else [early, final]
        if kind != "earlier-block":
            extra += ["--dump-step", str(b.steps)]
    if kind == "time-units":
        final.pre = ["ITEM: TIME", repr(float(b.run["time"])), "ITEM: UNITS", "si"]
    if kind == "triclinic":
        final.box = ["ITEM: BOX BOUNDS xy xz yz pp pp pp", f"0 {b.length!r} 0", "0 1 0", "0 0 0"]
    if kind == "format-flag":
        extra += ["--format", "lammps-dump"]
    text = dump_text(blocks)
    if kind == "crlf":
        text = text.replace("\n", "\r\n")
    elif kind == "tabs":
        text = "\n".join(l if l.startswith("ITEM") else l.replace(" ", "\t") for l in text.split("\n"))
    elif kind == "blank-lines":
        lines = text.split("\n")
        for _ in range(rng.randint(1, 5)):
            lines.insert(rng.randrange(1, len(lines)), rng.choice(["", "   ", "\t"]))
        text = "\n".join(lines)
    elif kind == "trailing-space":
        text = text.replace("\n", "  \n")
    elif kind == "leading-blank":
        text = "\n\n  \n" + text
    c = judged_case("dump_control", kind, b, blocks, rng, chosen=final, extra=extra, match=match, text=text)
    if kind == "json-report":
        c.json_report = True
    return c


def fam_dump_structure(rng, b):
    blocks = [make_block(b)]
    if rng.random() < 0.3:
        k, run = earlier_run(b, rng)
        blocks.insert(0, make_block(b, run=run, timestep=k))
    final = blocks[-1]
    op = rng.choice(["drop-row", "drop-row-fix-count", "dup-row", "dup-row-fix-count", "drop-line", "dup-line",
                     "dup-section-timestep", "dup-section-count", "count-twice-other", "dup-section-box",
                     "swap-adjacent", "swap-adjacent", "move-count-first", "move-box-first", "truncate", "truncate",
                     "truncate-end", "blank-lines", "comment-line", "garbage-line"])
    if op in ("drop-row", "drop-row-fix-count"):
        del final.rows[rng.randrange(b.n)]
        final.natoms = str(b.n) if op == "drop-row" else None
        return dcase("dump_structure", op, b, dump_text(blocks), final.header, (2,), rng)
    if op in ("dup-row", "dup-row-fix-count"):
        i = rng.randrange(b.n)
        final.rows.insert(rng.randrange(b.n + 1), list(final.rows[i]))
        final.natoms = str(b.n) if op == "dup-row" else None
        return dcase("dump_structure", op, b, dump_text(blocks), final.header, (2,), rng)
    if op in ("drop-line", "dup-line"):
        lines = final.lines()
        heads = len(lines) - len(final.rows)
        i = rng.randrange(heads)
        before = [l for blk in blocks[:-1] for l in blk.lines()]
        if op == "drop-line":
            del lines[i]
        else:
            lines.insert(i, lines[i])
        text = "\n".join(before + lines) + "\n"
        return dcase("dump_structure", f"{op}-{i}", b, text, final.header, (2,), rng)
    if op == "dup-section-timestep":
        final.pre = ["ITEM: TIMESTEP", final.timestep]
        return dcase("dump_structure", op, b, dump_text(blocks), final.header, (2,), rng)
    if op == "dup-section-count":
        final.pre = ["ITEM: NUMBER OF ATOMS", str(b.n)]
        c = judged_case("dump_structure", op, b, blocks, rng)  # accepted or refused: both (0 or 2) are fine
        c.expect |= {2}
        return c
    if op == "count-twice-other":
        other = str(rng.choice([b.n + 1, 2 * b.n, 0, 10 ** 9]))
        if rng.random() < 0.5:  # the right count second: the reader keeps the last one
            final.natoms, final.pre = other, ["ITEM: NUMBER OF ATOMS", str(b.n)]
            c = judged_case("dump_structure", op + "-right-last", b, blocks, rng)
            c.agree_ok, c.expect = 0 in c.expect, {2}
            return c
        final.pre = ["ITEM: NUMBER OF ATOMS", other]
        return dcase("dump_structure", op + "-right-first", b, dump_text(blocks), final.header, (2,), rng)
    if op == "dup-section-box":
        final.pre = list(final.box)
        c = judged_case("dump_structure", op, b, blocks, rng)
        c.expect |= {2}
        return c
    if op in ("move-count-first", "move-box-first"):
        lines = final.lines()
        head, rest = lines[:4], lines[4:]
        if op == "move-count-first":
            lines = head[2:4] + head[0:2] + rest
        else:
            lines = rest[:4] + head + rest[4:]
        text = "".join(l + "\n" for blk in blocks[:-1] for l in blk.lines()) + "\n".join(lines) + "\n"
        c = judged_case("dump_structure", op, b, blocks, rng, text=text)
        c.expect |= {2}
        return c
    if op == "swap-adjacent":
        lines = [l for blk in blocks for l in blk.lines()]
        kinds = []
        for bi, blk in enumerate(blocks):
            kinds += [(bi, "item"), (bi, "value"), (bi, "item"), (bi, "value"), (bi, "item"), (bi, "box"),
                      (bi, "box"), (bi, "box"), (bi, "item")] + [(bi, "row")] * len(blk.rows)
        i = rng.randrange(len(lines) - 1)
        (b1, k1), (b2, k2) = kinds[i], kinds[i + 1]
        same_block = b1 == b2
        lines[i], lines[i + 1] = lines[i + 1], lines[i]
        text = "\n".join(lines) + "\n"
        if lines[i] == lines[i + 1] or (same_block and k1 == k2 and k1 in ("row", "box")):
            if k1 == "row" and b1 == len(blocks) - 1:
                r = i - sum(len(blk.lines()) for blk in blocks[:-1]) - 9
                final.rows[r], final.rows[r + 1] = final.rows[r + 1], final.rows[r]
            return judged_case("dump_structure", f"swap-{k1}-{k2}", b, blocks, rng, text=text)
        return dcase("dump_structure", f"swap-{k1}-{k2}", b, text, final.header, (2,), rng)
    if op in ("truncate", "truncate-end"):
        return truncated(rng, b, blocks, op)
    if op == "blank-lines":
        lines = [l for blk in blocks for l in blk.lines()]
        for _ in range(rng.randint(1, 6)):
            lines.insert(rng.randrange(len(lines) + 1), rng.choice(["", " ", "\t", "  \t "]))
        return judged_case("dump_structure", op, b, blocks, rng, text="\n".join(lines) + "\n")
    lines = [l for blk in blocks for l in blk.lines()]
    new = (rng.choice(["# a comment", "#", "# ITEM: TIMESTEP"]) if op == "comment-line"
           else rng.choice(["garbage", "1 2 3", "x", "ITEM", "ITEMS: TIMESTEP", "END"]))
    lines.insert(rng.randrange(len(lines) + 1), new)
    return dcase("dump_structure", op, b, "\n".join(lines) + "\n", final.header, (2,), rng)


def truncated(rng, b, blocks, op):
    """The file cut at a byte: refused unless the cut leaves whole blocks or
    only shortens the last number of a block's last row to a number."""
    spans = []  # (block index, is that block's last row, line)
    for bi, blk in enumerate(blocks):
        ls = blk.lines()
        for li, l in enumerate(ls):
            spans.append((bi, li == len(ls) - 1, l))
    text = "".join(l + "\n" for _, _, l in spans)
    if op == "truncate-end":
        cut = len(text) - rng.randint(0, 30)
    else:
        cut = rng.randrange(len(text) + 1)
    pos = 0
    for idx, (bi, last_row, line) in enumerate(spans):
        end = pos + len(line)
        if cut <= end:
            off = cut - pos
            break
        pos = end + 1
    else:
        idx, off = len(spans) - 1, len(spans[-1][2])
    bi, last_row, line = spans[idx]
    cut_text = text[:cut]
    variant = f"{op}-{'block' + str(bi)}"
    if off == 0 and idx > 0 and spans[idx - 1][1]:  # a cut right after a block's last row
        blk = blocks[spans[idx - 1][0]]
        return judged_case("dump_structure", variant + "-at-block-end", b, blocks[:spans[idx - 1][0] + 1], rng,
                           chosen=blk, text=cut_text)
    if last_row and off > 0:
        t0 = line.rfind(" ") + 1
        blk = blocks[bi]
        if off > t0:
            tok = line[t0:off]
            v = rust_float(tok)
            if v is not None and math.isfinite(v):
                rows = [list(r) for r in blk.rows]
                rows[-1][-1] = tok
                expect, ok0 = oracle(b, b.run, blk.header, rows)
                return dcase("dump_structure", variant + ("-last-number" if off < len(line) else "-newline"), b,
                             cut_text, blk.header, expect, rng, agree_ok=ok0)
    return dcase("dump_structure", variant + "-partial", b, cut_text, blocks[-1].header, (2,), rng)


def fam_dump_counts(rng, b):
    blocks = [make_block(b)]
    if rng.random() < 0.3:
        k, run = earlier_run(b, rng)
        blocks.insert(0, make_block(b, run=run, timestep=k))
    final = blocks[-1]
    n = b.n
    op = rng.choice(["count", "count", "timestep", "timestep", "rows-fewer", "rows-more", "count-huge"])
    if op == "count":
        tok = rng.choice([n - 1, n + 1, 0, 2 * n, 2 ** 32, 2 ** 63, 2 ** 64 - 1, 2 ** 64, 10 ** 12, -n, f"{n}.0",
                          f"{n / 10}e1", hex(n), "", f"+{n}", f"0{n}", f" {n} ", f"{n} {n}", "sixteen",
                          "\u0661\u0666", "-0", f"{n}\u2028"])
        final.natoms = str(tok)
        v = rust_u64(final.natoms) if final.natoms.strip() else None
        if v == n:
            return judged_case("dump_counts", "count-same-value", b, blocks, rng)
        return dcase("dump_counts", f"count-{'other' if v is not None else 'bad'}", b, dump_text(blocks),
                     final.header, (2,), rng)
    if op == "timestep":
        tok = str(rng.choice([0, 1, b.steps, 2 ** 64 - 1, 2 ** 64, -1, "1.5", "abc", "", f"+{b.steps}",
                              f"0{b.steps}", "1e3", "2e1", " 7 ", "\u0662"]))
        final.timestep = tok
        v = rust_u64(tok) if tok.strip() else None
        if v is None:
            return dcase("dump_counts", "timestep-bad", b, dump_text(blocks), final.header, (2,), rng)
        if len(blocks) > 1 and v == int(blocks[0].timestep):
            return dcase("dump_counts", "timestep-twice", b, dump_text(blocks), final.header, (2,), rng)
        return judged_case("dump_counts", "timestep-valid", b, blocks, rng)
    if op == "rows-fewer":
        k = rng.randint(1, n - 1)
        for _ in range(k):
            del final.rows[rng.randrange(len(final.rows))]
        return dcase("dump_counts", op, b, dump_text(blocks), final.header, (2,), rng)
    if op == "rows-more":
        k = rng.randint(1, 5)
        xi = final.header.index("x0")
        for j in range(k):
            row = list(final.rows[rng.randrange(n)])
            row[final.header.index("id")] = str(n + 1 + j)
            row[xi] = repr(float(row[xi]) + b.spacing * (j + 1) * 0.37)
            final.rows.append(row)
        return dcase("dump_counts", op, b, dump_text(blocks), final.header, (2,), rng)
    final.natoms = str(rng.choice([10 ** 9, 2 ** 40, 2 ** 63, 10 ** 18]))
    return dcase("dump_counts", op, b, dump_text(blocks), final.header, (2,), rng)


BAD_DUMP_NUMBERS = ["nan", "NaN", "-nan", "+nan", "inf", "-inf", "Infinity", "-infinity", "INF", "1e400", "-1e400",
                    "1e309", "0x10", "0x1p3", "1,5", "1.0.0", "1e", "e5", "--1", "+-1", "1_000", "\u0661", "1d0",
                    "1.0D+00", "\u00bd", "1e+", ".", "-", "+", "\u221e", "NULL", "true", "1e4OO", "1\u20282",
                    "1\u00a02", "1\x002", "\x1e1", "1\x0b2", "1\u00851", "\ufeff1", "1#", "'1'", '"1"', "(1)"]


def odd_number(rng, text):
    """A valid spelling of another or the same number."""
    v = float(text)
    return rng.choice(["1e-400", "-0", "0", "+" + text, text + "e0", text.upper(), "%.6g" % v, "%.3e" % v,
                       ("%.17e" % v).replace("e", "E"), "%.20f" % v, "-" + text if v >= 0 else text[1:],
                       "1e-320", "4.9e-324", "1.7976931348623157e308", "-1.7976931348623157e308",
                       "00" + text if v >= 0 else text, text + "0" if "." in text and "e" not in text else text])


def fam_dump_numbers(rng, b):
    final = make_block(b)
    col = rng.choice([h for h in final.header if h != "id"])
    c = final.header.index(col)
    rows_hit = range(b.n) if rng.random() < 0.2 else [rng.randrange(b.n)]
    kind = rng.choice(["bad", "bad", "odd", "empty"])
    for r in rows_hit:
        if kind == "bad":
            final.rows[r][c] = rng.choice(BAD_DUMP_NUMBERS)
        elif kind == "odd":
            final.rows[r][c] = odd_number(rng, final.rows[r][c])
        else:
            final.rows[r][c] = ""
    text = dump_text([final])
    tokens = [rust_split(" ".join(r)) for r in final.rows]
    valid = all(len(t) == len(final.header) for t in tokens) and all(
        rust_float(x) is not None and math.isfinite(rust_float(x)) for t in tokens for x in t)
    variant = f"{kind}-{'column' if len(rows_hit) > 1 else 'one'}-{col}"
    if not valid:
        return dcase("dump_numbers", variant, b, text, final.header, (2,), rng)
    rows = [list(t) for t in tokens]
    expect, ok0 = oracle(b, b.run, final.header, rows)
    return dcase("dump_numbers", variant, b, text, final.header, expect, rng, agree_ok=ok0)


def fam_dump_blocks(rng, b):
    final = make_block(b)
    k, run = earlier_run(b, rng)
    early = make_block(b, run=run, timestep=k)
    op = rng.choice(["same-timestep-twice", "same-timestep-other", "later-block", "earlier-dump-step",
                     "final-then-earlier", "final-then-earlier-step", "absent-step", "empty-last", "empty-first",
                     "empty-chosen", "other-columns-earlier", "other-columns-chosen", "many-earlier",
                     "no-atoms-at-end", "atoms-no-columns", "atoms-dup-column", "atoms-more-names",
                     "atoms-fewer-names", "timestep-twice-in-block", "descending-many"])
    fh = final.header
    if op == "same-timestep-twice":
        return dcase("dump_blocks", op, b, dump_text([final, final]), fh, (2,), rng)
    if op == "same-timestep-other":
        early.timestep = final.timestep
        blocks = [early, final] if rng.random() < 0.5 else [final, early]
        return dcase("dump_blocks", op, b, dump_text(blocks), fh, (2,), rng)
    if op == "later-block":
        later_steps = b.steps + rng.randint(1, b.steps)
        later = make_block(b, run=b.run_json([], with_steps(b.setup, later_steps)), timestep=later_steps)
        step = rng.choice([None, b.steps, later_steps])
        extra = ["--dump-step", str(step)] if step is not None else []
        chosen = final if step == b.steps else later
        return judged_case("dump_blocks", f"{op}-{'none' if step is None else 'final' if step == b.steps else 'later'}",
                           b, [final, later], rng, chosen=chosen, extra=extra)
    if op == "earlier-dump-step":
        return judged_case("dump_blocks", op, b, [early, final], rng, chosen=early, extra=["--dump-step", str(k)])
    if op in ("final-then-earlier", "final-then-earlier-step"):
        extra = ["--dump-step", str(b.steps)] if op.endswith("step") else []
        return judged_case("dump_blocks", op, b, [final, early], rng, chosen=final if extra else early, extra=extra)
    if op == "absent-step":
        step = rng.choice([k + b.steps, 0, 2 ** 64 - 1, b.steps + 1, b.steps - 1 if b.steps - 1 != k else 0])
        blocks = [early, final] if rng.random() < 0.5 else [final]
        if any(int(bl.timestep) == step for bl in blocks):
            step = 10 ** 9
        return dcase("dump_blocks", op, b, dump_text(blocks), fh, (2,), rng, extra=["--dump-step", str(step)])
    if op in ("empty-last", "empty-first", "empty-chosen"):
        empty = DBlock(b.steps + 5 if op == "empty-last" else 0, fh, [], box_lines(b))
        if op == "empty-first":
            return judged_case("dump_blocks", op, b, [empty, final], rng, chosen=final)
        blocks = [final, empty]
        extra = ["--dump-step", str(b.steps + 5)] if op == "empty-chosen" else []
        return dcase("dump_blocks", op, b, dump_text(blocks), fh, (2,), rng, extra=extra)
    if op in ("other-columns-earlier", "other-columns-chosen"):
        hdr = rng.choice([["id", "x"], ["id", "type"], ["id", "x0"], ["id", "x", "x0"], ["id", "vx"],
                          ["id", "s11", "type"]])
        if b.two_d:
            hdr = rng.choice([["id", "x", "y"], ["id", "type"], ["id", "x0", "y0"], ["id", "x", "y", "x0", "y0"],
                              ["id", "vx", "vy"], ["id", "s12"]])
        other = make_block(b, run=run, header=hdr, timestep=k)
        if op == "other-columns-earlier":
            return judged_case("dump_blocks", op, b, [other, final], rng, chosen=final)
        return judged_case("dump_blocks", op + "-" + "+".join(hdr), b, [final, other], rng, chosen=other,
                           extra=["--dump-step", str(k)], header_for_columns=sorted(set(hdr)))
    if op == "many-earlier":
        blocks = []
        for t in range(rng.randint(50, 500)):
            blk = DBlock(t, ["id", "x"], [], box_lines(b)) if rng.random() < 0.5 else make_block(b, run=run,
                                                                                               timestep=t + 10 ** 6)
            blocks.append(blk)
        ts = {bl.timestep for bl in blocks}
        if len(ts) != len(blocks) or final.timestep in ts:
            return dcase("dump_blocks", op + "-dup", b, dump_text(blocks + [final]), fh, (2,), rng)
        return judged_case("dump_blocks", op, b, blocks + [final], rng, chosen=final)
    if op == "descending-many":
        blocks = [make_block(b, run=run, timestep=10 ** 6 - t) for t in range(rng.randint(2, 20))]
        return judged_case("dump_blocks", op, b, [final] + blocks, rng, chosen=final,
                           extra=["--dump-step", str(b.steps)])
    if op == "no-atoms-at-end":
        text = dump_text([final]) + f"ITEM: TIMESTEP\n{b.steps + 1}\n" + (
            f"ITEM: NUMBER OF ATOMS\n{b.n}\n" if rng.random() < 0.5 else "")
        return dcase("dump_blocks", op, b, text, fh, (2,), rng)
    if op == "atoms-no-columns":
        final.header = []
        return dcase("dump_blocks", op, b, dump_text([final]), fh, (2,), rng)
    if op == "atoms-dup-column":
        h = rng.choice(fh)
        c = fh.index(h)
        final.header = fh + [h]
        for r in final.rows:
            r.append(r[c])
        return dcase("dump_blocks", op + "-" + h, b, dump_text([final]), fh, (2,), rng)
    if op == "atoms-more-names":
        final.header = fh + [rng.choice(["extra", "vz", "s33"])]
        return dcase("dump_blocks", op, b, dump_text([final]), fh, (2,), rng)
    if op == "atoms-fewer-names":
        final.header = fh[:-1]
        return dcase("dump_blocks", op, b, dump_text([final]), fh, (2,), rng)
    final.pre = ["ITEM: TIMESTEP", str(b.steps + 1)]
    return dcase("dump_blocks", op, b, dump_text([final]), fh, (2,), rng)


UNKNOWN_ITEMS = ["ITEM: FOO", "ITEM:", "ITEM: atoms id x", "ITEM: TIMESTEPS", "ITEM: TIMESTEP extra",
                 "ITEM: NUMBER OF ATOM", "ITEM: ENTRIES c_1[1]", "ITEM: DIMENSION", "ITEM: BOX", "ITEM: time",
                 "ITEM: NUMBER  OF ATOMS", "ITEM: TIME\u2028X", "ITEM: \x1b[31mRED", "ITEM: A\x0bB"]


def fam_dump_items(rng, b):
    final = make_block(b)
    fh = final.header
    op = rng.choice(["unknown", "unknown", "unknown-in-rows", "time", "units", "time-before-timestep",
                     "time-no-value-at-end", "time-bad-value", "no-space", "leading-space", "lowercase-prefix",
                     "box-no-flags", "box-triclinic", "box-nan", "box-one-number", "box-text", "box-two-lines",
                     "box-missing", "box-suffix", "atoms-tabs"])
    lines = final.lines()
    if op in ("unknown", "unknown-in-rows"):
        item = rng.choice(UNKNOWN_ITEMS)
        at = rng.choice([0, 2, 4, 8]) if op == "unknown" else rng.randrange(10, len(lines) + 1)
        new = [item] + ([rng.choice(["1", "x"])] if rng.random() < 0.5 else [])
        lines[at:at] = new
        return dcase("dump_items", op, b, "\n".join(lines) + "\n", fh, (2,), rng)
    if op in ("time", "units"):
        final.pre = ["ITEM: TIME", repr(float(b.run["time"]))] if op == "time" else ["ITEM: UNITS", "lj"]
        return judged_case("dump_items", op, b, [final], rng)
    if op == "time-before-timestep":
        text = f"ITEM: TIME\n{float(b.run['time'])!r}\n" + dump_text([final])
        return judged_case("dump_items", op, b, [final], rng, text=text)
    if op == "time-no-value-at-end":
        return dcase("dump_items", op, b, dump_text([final]) + "ITEM: TIME\n", fh, (2,), rng)
    if op == "time-bad-value":
        final.pre = ["ITEM: TIME", rng.choice(["abc", "nan", "inf", "1e400", "-1"])]
        c = judged_case("dump_items", op, b, [final], rng)
        c.expect |= {2}
        return c
    if op in ("no-space", "leading-space"):
        i = rng.choice([0, 2, 4, 8])
        lines[i] = lines[i].replace("ITEM: ", "ITEM:") if op == "no-space" else "   " + lines[i]
        c = judged_case("dump_items", f"{op}-{i}", b, [final], rng, text="\n".join(lines) + "\n")
        c.expect |= {2} if op == "no-space" else set()
        return c
    if op == "lowercase-prefix":
        i = rng.choice([0, 2, 4, 8])
        lines[i] = lines[i].replace("ITEM:", rng.choice(["item:", "Item:", "ITEM ", "ITEMS:"]))
        return dcase("dump_items", f"{op}-{i}", b, "\n".join(lines) + "\n", fh, (2,), rng)
    if op.startswith("box"):
        ok = True
        if op == "box-no-flags":
            final.box[0] = "ITEM: BOX BOUNDS"
        elif op == "box-triclinic":
            final.box = ["ITEM: BOX BOUNDS xy xz yz pp pp pp", f"0 {b.length!r} 0.5", "0 1 0", "0 0 0"]
        elif op == "box-nan":
            final.box[rng.randint(1, 3)] = rng.choice(["nan nan", "inf -inf", "1e400 0"])
        elif op == "box-suffix":
            final.box[0] = "ITEM: BOX BOUNDSxyz"
        elif op == "box-missing":
            final.box = []
        else:
            ok = False
            if op == "box-one-number":
                final.box[rng.randint(1, 3)] = "0"
            elif op == "box-text":
                final.box[rng.randint(1, 3)] = "0 abc"
            else:
                del final.box[rng.randint(1, 3)]
        if not ok:
            return dcase("dump_items", op, b, dump_text([final]), fh, (2,), rng)
        c = judged_case("dump_items", op, b, [final], rng)
        if op not in ("box-no-flags", "box-triclinic"):
            c.expect |= {2}
        return c
    text = dump_text([final]).replace("ITEM: ATOMS " + " ".join(fh), "ITEM: ATOMS\t" + "\t".join(fh))
    return judged_case("dump_items", op, b, [final], rng, text=text)


def fam_dump_whitespace(rng, b):
    final = make_block(b)
    fh = final.header
    text = dump_text([final])
    op = rng.choice(["crlf", "mixed-crlf", "tabs", "multi-space", "trailing-space", "leading-space", "vt-ff",
                     "nbsp", "ideographic", "cr-only", "bom", "nul-in-row", "invalid-utf8", "no-final-newline",
                     "cr-cr-lf", "ff-line", "u2028-line", "nel-line"])
    maybe = False
    if op == "crlf":
        text = text.replace("\n", "\r\n")
    elif op == "mixed-crlf":
        text = "".join(l + rng.choice(["\n", "\r\n"]) for l in text.split("\n")[:-1])
    elif op == "tabs":
        text = text.replace(" ", "\t").replace("ITEM:\t", "ITEM: ").replace("NUMBER\tOF\tATOMS", "NUMBER OF ATOMS") \
            .replace("BOX\tBOUNDS", "BOX BOUNDS")
    elif op == "multi-space":
        text = "\n".join(l if l.startswith("ITEM") else l.replace(" ", "   ") for l in text.split("\n"))
    elif op == "trailing-space":
        text = text.replace("\n", " \t \n")
    elif op == "leading-space":
        text = "\n".join("  " + l if l and not l.startswith("ITEM") else l for l in text.split("\n"))
    elif op in ("vt-ff", "nbsp", "ideographic"):
        sep = {"vt-ff": rng.choice(["\x0b", "\x0c"]), "nbsp": "\u00a0", "ideographic": "\u3000"}[op]
        text = "\n".join(l if l.startswith("ITEM") else l.replace(" ", sep) for l in text.split("\n"))
        maybe = True
    elif op == "cr-only":
        text = text.replace("\n", "\r")
        return dcase("dump_whitespace", op, b, text, fh, (2,), rng)
    elif op == "bom":
        c = judged_case("dump_whitespace", op, b, [final], rng, text="\ufeff" + text)
        c.expect |= {2}
        return c
    elif op == "nul-in-row":
        lines = text.split("\n")
        i = rng.randrange(9, 9 + b.n)
        lines[i] = lines[i].replace(" ", "\x00", 1) if rng.random() < 0.5 else lines[i] + "\x00"
        return dcase("dump_whitespace", op, b, "\n".join(lines), fh, (2,), rng)
    elif op == "invalid-utf8":
        raw = text.encode()
        at = rng.randrange(len(raw))
        raw = raw[:at] + rng.choice([b"\xff", b"\xc3\x28", b"\xe2\x82", b"\x80"]) + raw[at:]
        return dcase("dump_whitespace", op, b, raw, fh, (2,), rng)
    elif op == "no-final-newline":
        text = text.rstrip("\n")
    elif op == "cr-cr-lf":
        text = text.replace("\n", "\r\r\n")
    elif op in ("ff-line", "u2028-line", "nel-line"):
        lines = text.split("\n")
        lines.insert(rng.randrange(1, len(lines)), {"ff-line": "\x0c", "u2028-line": "\u2028",
                                                    "nel-line": "\x85"}[op])
        text = "\n".join(lines)
        maybe = op != "ff-line"
    c = judged_case("dump_whitespace", op, b, [final], rng, text=text)
    if maybe:
        c.expect |= {2}
    return c


def fam_dump_ids(rng, b):
    n = b.n
    op = rng.choice(["zero-based", "one-zero", "one-negative", "one-fractional", "float-format", "dup",
                     "out-of-range", "shifted", "permuted-consistent", "permuted-inconsistent",
                     "permuted-inconsistent-no-x0", "permuted-inconsistent-match-x0", "no-id-no-x0",
                     "no-id-no-x0-order", "match-id-without-id", "karamelo-order", "karamelo-order-x0",
                     "scaled", "id-last"])
    header, order, ids, match, extra = list(b.header), None, None, "auto", []
    base_ids = list(range(1, n + 1))
    if op == "zero-based":
        ids = [i - 1 for i in base_ids]
    elif op in ("one-zero", "one-negative", "one-fractional", "out-of-range", "dup"):
        ids = list(base_ids)
        j = rng.randrange(n)
        ids[j] = {"one-zero": 0, "one-negative": rng.choice([-1, -5, -(2 ** 31)]),
                  "one-fractional": ids[j] + rng.choice([0.5, 1e-9, -0.25]),
                  "out-of-range": rng.choice([n + 1, n + 5, 10 ** 6, 1e300, 2 ** 53 + 1, 2 ** 64]),
                  "dup": ids[(j + rng.randrange(1, n)) % n]}[op]
    elif op == "float-format":
        ids = [rng.choice([f"{i}.0", f"{i}e0", f"{i}.", f"+{i}", f"{i}.000", f"0{i}"]) for i in base_ids]
    elif op == "shifted":
        ids = [i + 1 for i in base_ids]
    elif op == "permuted-consistent":
        order = list(range(n))
        rng.shuffle(order)
    elif op.startswith("permuted-inconsistent"):
        ids = list(base_ids)
        while ids == base_ids:
            rng.shuffle(ids)
        if op.endswith("no-x0"):
            header = [h for h in header if h not in ("x0", "y0")]
        if op.endswith("match-x0"):
            match = "x0"
    elif op.startswith("no-id-no-x0"):
        header = [h for h in header if h not in ("id", "x0", "y0")]
        if op.endswith("order"):
            match = "order"
            if rng.random() < 0.5:
                order = list(range(n))
                rng.shuffle(order)
    elif op == "match-id-without-id":
        header.remove("id")
        match = "id"
    elif op.startswith("karamelo-order"):
        order, ids = karamelo_order(b), list(base_ids)
        if op.endswith("x0"):
            match = "x0"
    elif op == "scaled":
        ids = [i * rng.choice([2, 10, 1000]) for i in base_ids]
    else:
        header = [h for h in header if h != "id"] + ["id"]
    blk = make_block(b, header=header, order=order, ids=ids)
    if op == "float-format":
        for r, t in zip(blk.rows, ids):
            r[header.index("id")] = t
    if op == "match-id-without-id":
        return dcase("dump_ids", op, b, dump_text([blk]), header, (2,), rng, extra=["--match", "id"])
    valid = all(rust_float(r[header.index("id")]) is not None for r in blk.rows) if "id" in header else True
    return judged_case("dump_ids", op, b, [blk], rng, match=match) if valid else \
        dcase("dump_ids", op, b, dump_text([blk]), header, (2,), rng)


def fam_dump_perturb(rng, b):
    blk = make_block(b)
    header = blk.header
    op = rng.choice(["value", "value", "value", "position", "position", "column-scaled", "precision",
                     "swap-mapping", "row-copied", "translate", "shadowed"])
    colmap, variant = None, op
    phys = ["vx", "s11"] + (["vy", "s22", "s12"] if b.two_d else [])
    pos = ["x", "x0"] + (["y", "y0"] if b.two_d else [])
    values = dump_values(b, b.run)
    if op == "value":
        col = rng.choice(phys)
        c = header.index(col)
        column = [v[col] for v in values]
        i, _ = big_entry(rng, column) or (rng.randrange(b.n), None)
        d = rng.choice([1e-3, 1e-6, 1e-8, 3e-9, 1e-10, 1e-13, 1e-15]) * rng.choice([1, -1])
        blk.rows[i][c] = repr(column[i] * (1 + d))
        variant = f"value-{col}-{abs(d):g}"
    elif op == "position":
        col = rng.choice(pos)
        c = header.index(col)
        axis = "x" if col in ("x", "x0") else "y"
        umax = max(abs(v[axis] - v[axis + "0"]) for v in values)
        i = rng.randrange(b.n)
        d = rng.choice([1e-3, 1e-6, 1e-8, 1e-10, 1e-12, 1e-15]) * rng.choice([1, -1])
        blk.rows[i][c] = repr(values[i][col] + d * umax)
        variant = f"position-{col}-{abs(d):g}·max|u|"
    elif op == "column-scaled":
        col = rng.choice(phys + pos)
        c = header.index(col)
        f = rng.choice([1e-3, 1e3, -1.0, 1 + 1e-7, 1 + 1e-12, 1 - 1e-11])
        for r, v in zip(blk.rows, values):
            r[c] = repr(v[col] * f)
        variant = f"column-scaled-{col}-{f:g}"
    elif op == "precision":
        style = rng.choice(["%.6g", "%.9g", "%.12g", "%.15g", "%.16g"])
        blk = make_block(b, style=style)
        variant = f"precision-{style}"
    elif op == "swap-mapping":
        a, c2 = rng.sample(phys, 2)
        colmap = dict(b.map)
        colmap[a], colmap[c2] = b.map[c2], b.map[a]
        variant = f"swap-mapping-{a}-{c2}"
    elif op == "row-copied":
        i, j = rng.sample(range(b.n), 2)
        for col in phys + (["x", "y"] if b.two_d else ["x"]):
            blk.rows[i][header.index(col)] = blk.rows[j][header.index(col)]
    elif op == "shadowed":
        # A column under hompm's own name next to the one --columns maps to it.
        col = rng.choice(phys)
        name = b.map[col]
        same = rng.random() < 0.5
        blk.header.append(name)
        c = header.index(col)
        for r in blk.rows:
            r.append(r[c] if same else "123.5")
        return dcase("dump_perturb", f"shadowed-{name}-{'same' if same else 'other'}", b, dump_text([blk]),
                     header, (2,), rng)
    else:
        d = rng.choice([1e-15, 1e-12, 1e-9, 1e-6, 1e-3]) * b.length
        for col in pos:
            c = header.index(col)
            for r, v in zip(blk.rows, values):
                r[c] = repr(v[col] + d)
        variant = f"translate-{d / b.length:g}L"
    return judged_case("dump_perturb", variant, b, [blk], rng, colmap=colmap)


def fam_dump_format(rng, b):
    blk = make_block(b)
    fh = blk.header
    text = dump_text([blk])
    op = rng.choice(["format-csv", "format-json", "dump-on-csv", "dump-on-json", "dump-step-on-csv",
                     "dump-step-on-json", "dump-step-value", "dump-step-value", "auto-leading-blank",
                     "csv-header-item", "convergence"])
    csv = ",".join(b.map.get(h, h) for h in fh if h != "type") + "\n" + "".join(
        ",".join(r[k] for k, h in enumerate(fh) if h != "type") + "\n" for r in blk.rows)
    if op in ("format-csv", "format-json"):
        return dcase("dump_format", op, b, text, fh, (2,), rng, extra=["--format", op.split("-")[1]])
    if op == "dump-on-csv":
        return dcase("dump_format", op, b, csv, fh, (2,), rng, extra=["--format", "lammps-dump"], columns=False)
    if op == "dump-on-json":
        return dcase("dump_format", op, b, b.run_text, fh, (2,), rng, extra=["--format", "lammps-dump"],
                     columns=False)
    if op in ("dump-step-on-csv", "dump-step-on-json"):
        t = csv if op.endswith("csv") else b.run_text
        return dcase("dump_format", op, b, t, fh, (2,), rng, extra=["--dump-step", str(b.steps)], columns=False)
    if op == "dump-step-value":
        tok = rng.choice(["-1", "1.5", "", "0x14", "18446744073709551616", "abc", f"+{b.steps}", f"0{b.steps}",
                          f"{b.steps}.0", f"{b.steps}e0", f" {b.steps}", str(b.steps), "-0"])
        extra = [f"--dump-step={tok}"] if rng.random() < 0.5 else ["--dump-step", tok]
        if tok.startswith("-") and len(extra) == 2:
            extra = [f"--dump-step={tok}"]
        v = rust_u64(tok) if U64_RE.fullmatch(tok) else None
        if v == b.steps:
            c = judged_case("dump_format", "dump-step-" + ("plus" if tok.startswith("+") else "same"), b, [blk],
                            rng, extra=extra)
            if tok != str(b.steps):  # "+20", "020": a refusal is fine as well
                c.expect |= {2}
            return c
        return dcase("dump_format", "dump-step-bad", b, text, fh, (2,), rng, extra=extra)
    if op == "convergence":
        # Three resolutions as dump files, --cells naming them: a verdict (0 or 1), never a panic.
        i = b.setup.index("--cells")
        files, cells = [], [2, 4, 8] if b.two_d else [4, 8, 16]
        for k in cells:
            s = list(b.setup)
            s[i + 1] = str(k)
            run = b.run_json([], s)
            files.append(dump_text([make_block(b, run=run)]))
        step = ["--dump-step", str(b.steps)] if rng.random() < 0.5 else []
        c = dcase("dump_format", op, b, files[0], fh, (0, 1), rng, extra=step)
        c.convergence = (files, cells)
        return c
    if op == "auto-leading-blank":
        return judged_case("dump_format", op, b, [blk], rng, text=rng.choice(["\n\n", "   \n", " \t\n\n  "]) + text)
    return dcase("dump_format", op, b, "ITEM: " + csv, fh, (2,), rng, columns=False)


def random_flags(rng, b, p=0.35):
    if not b.two_d:
        pool = {k: v for k, v in CONVENTION_FLAGS.items() if k not in ("--knots", "--gradient", "--solution")}
        if rng.random() < 0.1:  # 2D-only values, refused in 1D
            pool = CONVENTION_FLAGS
    else:
        pool = CONVENTION_FLAGS
    flags = []
    if b.name == "dump-2d-bsmpm" and rng.random() < 0.3:
        flags = list(TAICHI)
    for k, vals in pool.items():
        if k not in flags and rng.random() < p:
            flags += [k, rng.choice(vals)]
    return flags


def valid_flags(rng, b):
    for _ in range(40):
        f = random_flags(rng, b)
        if b.run_json(f) is not None:
            return f
    return []


def neighbour_flags(rng, b, a):
    """`a` with one flag changed, added or removed."""
    pairs = [a[i:i + 2] for i in range(0, len(a), 2)]
    keys = [p[0] for p in pairs]
    choice = rng.random()
    if pairs and choice < 0.3:
        del pairs[rng.randrange(len(pairs))]
    elif pairs and choice < 0.7:
        i = rng.randrange(len(pairs))
        pairs[i] = [pairs[i][0], rng.choice([v for v in CONVENTION_FLAGS[pairs[i][0]] if v != pairs[i][1]])]
    else:
        k = rng.choice([k for k in CONVENTION_FLAGS if k not in keys] or list(CONVENTION_FLAGS))
        pairs.append([k, rng.choice(CONVENTION_FLAGS[k])])
    return [x for p in pairs for x in p]


def same_flags(rng, b, a):
    """`a` reordered, with a default spelled out."""
    pairs = [a[i:i + 2] for i in range(0, len(a), 2)]
    rng.shuffle(pairs)
    keys = {p[0] for p in pairs}
    if rng.random() < 0.5:
        if "--body-force" not in keys:
            pairs.append(["--body-force", "particles"])
        elif "--transfer" not in keys:
            pairs.append(["--transfer", "flip"])
    return [x for p in pairs for x in p]


def pick_flags(rng, b):
    a = valid_flags(rng, b)
    r = rng.random()
    if r < 0.25:
        return a, same_flags(rng, b, a), "same"
    if r < 0.65:
        return a, neighbour_flags(rng, b, a), "one-changed"
    return a, random_flags(rng, b), "random"


def fam_dump_flags(rng, b):
    """A dump of a run with flags A, checked with flags B."""
    a, bf, how = pick_flags(rng, b)
    run_a, run_b = b.run_json(a), b.run_json(bf)
    header = list(b.header) if rng.random() < 0.7 else [h for h in b.header if h != "type"]
    blk = make_block(b, run=run_a, header=header)
    if run_b is None:
        c = dcase("dump_flags", f"{how}-B-invalid", b, dump_text([blk]), header, (2,), rng, extra=bf)
    else:
        differ = sorted(k for k, v in b.conventions(run_a).items() if b.conventions(run_b).get(k) != v)
        variant = f"{how}-conv-{'same' if not differ else 'differ'}"
        c = judged_case("dump_flags", variant, b, [blk], rng, extra=bf, ref=run_b)
    c.flags_a = a
    return c


def fam_dump_json_flags(rng, b):
    """hompm's run JSON (or trace JSON) with flags A, checked with flags B:
    refused when their conventions differ."""
    a, bf, how = pick_flags(rng, b)
    run_a, run_b = b.run_json(a), b.run_json(bf)
    kind = "trace" if rng.random() < 0.3 else "run"
    code, text, _ = b.output(kind, a)
    if run_b is None:
        c = Case("dump_json_flags", f"{kind}-{how}-B-invalid", b, text, "json", bf, (2,),
                 json_report=rng.random() < 0.25)
        c.flags_a = a
        return c
    conv_a, conv_b = b.conventions(run_a), b.conventions(run_b)
    differ = sorted(k for k, v in conv_a.items() if conv_b.get(k) != v)
    physically_same = judge(b, run_b, ours_of(b, run_a)) < 0.25
    if not differ:
        expect = (0,) if physically_same or kind == "trace" else (0, 1)
        c = Case("dump_json_flags", f"{kind}-{how}-conv-same", b, text, "json", bf, expect,
                 json_report=rng.random() < 0.25)
    else:
        doc = json.loads(text)
        if kind == "run":
            named = doc.get("conventions")
            solution = doc.get("params", {}).get("solution")
        else:
            h = doc.get("header", {})
            named = h.get("conventions") or h.get("discretisation", {}).get("conventions")
            solution = h.get("scene", {}).get("solution") if isinstance(h.get("scene"), dict) else None
        named_keys = set(named or {}) | ({"solution"} if solution else set())
        where = "named" if set(differ) & named_keys else "unnamed"
        # A file that names no other convention (a default run's) is
        # compared, not refused (docs/oracle.md, "Recipes by code"): its
        # verdict is the values' — differs, or agrees within the tolerance.
        expect = (2,) if where == "named" else ((0, 1) if physically_same else (1,))
        if where == "unnamed" and kind == "trace" and "knots" in differ:
            # Padded knots have other nodes: the traces' node arrays differ
            # in length, which is refused.
            expect = (2,)
        c = Case("dump_json_flags", f"{kind}-differ-{'+'.join(differ)}-{where}", b, text, "json", bf, expect,
                 json_report=rng.random() < 0.25)
        c.agree_ok = physically_same
    c.flags_a = a
    return c


_dump_wide_lock = threading.Lock()


def fam_dump_huge(rng, b, workdir):
    op = rng.choice(["many-blocks", "many-blocks", "many-blocks-dup", "count-huge", "long-token", "many-columns",
                     "many-rows", "stream", "stream"])
    if op == "stream":
        source = rng.choice(["fifo", "fifo", "stdin-pipe", "dash-pipe"])
        content = rng.choice(["dump-rows", "dump-blocks"])
        limit = rng.choice([None, "16MiB", "64MiB", "256MiB"])
        c = Case("dump_huge", f"stream-{source}-{content}-{limit or 'default'}", b, None, "", expect=(2,),
                 stream={"source": source, "content": content})
        c.pre = ["--max-memory", limit] if limit else []
        return c
    if op in ("many-blocks", "many-blocks-dup"):
        k = rng.choice([1000, 10_000, 50_000, 100_000, 200_000, 400_000])
        key = f"{b.name}-{op}-{k}"
        path = os.path.join(workdir, "wide", key + ".dump")
        final = make_block(b)
        with _dump_wide_lock:
            if not os.path.exists(path):
                os.makedirs(os.path.dirname(path), exist_ok=True)
                with open(path + ".tmp", "w") as f:
                    for t in range(k):
                        f.write(f"ITEM: TIMESTEP\n{10 ** 6 + t}\nITEM: NUMBER OF ATOMS\n0\nITEM: ATOMS id x\n")
                    if op == "many-blocks-dup":
                        final.timestep = str(10 ** 6)
                    f.write(dump_text([final]))
                os.rename(path + ".tmp", path)
        expect, ok0 = ((2,), False) if op == "many-blocks-dup" else oracle(b, b.run, final.header, final.rows)
        c = Case("dump_huge", f"{op}-{k}", b, None, "dump", dump_columns(b, final.header), expect, input_path=path)
        c.agree_ok = ok0
        return c
    final = make_block(b)
    fh = final.header
    if op == "count-huge":
        final.natoms = str(rng.choice([10 ** 18, 2 ** 64 - 1, 10 ** 12]))
        return dcase("dump_huge", op, b, dump_text([final]), fh, (2,), rng)
    if op == "long-token":
        n = rng.choice([10 ** 5, 10 ** 6, 10 ** 7])
        c = fh.index(rng.choice(["vx", "s11"]))
        i = rng.randrange(b.n)
        form = rng.choice(["ones", "zeros-then-one", "trailing-zeros"])
        tok = {"ones": "1" * n, "zeros-then-one": "0." + "0" * n + "1",
               "trailing-zeros": (final.rows[i][c] if "e" not in final.rows[i][c] else "0.5") + "0" * n}[form]
        final.rows[i][c] = tok
        v = float(tok) if form != "ones" else math.inf
        if not math.isfinite(v):
            return dcase("dump_huge", f"{op}-{form}-{n}", b, dump_text([final]), fh, (2,), rng)
        rows = [list(r) for r in final.rows]
        rows[i][c] = repr(v)
        expect, ok0 = oracle(b, b.run, fh, rows)
        return dcase("dump_huge", f"{op}-{form}-{n}", b, dump_text([final]), fh, expect, rng, agree_ok=ok0)
    if op == "many-columns":
        k = rng.choice([1000, 100_000])
        names = [f"c{j}" for j in range(k)]
        final.header = fh + names
        pad = ["0"] * k
        for r in final.rows:
            r.extend(pad)
        ragged = rng.random() < 0.3
        if ragged:
            final.rows[rng.randrange(b.n)].pop()
            return dcase("dump_huge", f"{op}-{k}-ragged", b, dump_text([final]), fh, (2,), rng)
        return judged_case("dump_huge", f"{op}-{k}", b, [final], rng, header_for_columns=fh)
    k = rng.choice([10 ** 4, 10 ** 5, 3 * 10 ** 5])
    row = " ".join(final.rows[0])
    text = (f"ITEM: TIMESTEP\n{b.steps}\nITEM: NUMBER OF ATOMS\n{k}\n" + "\n".join(box_lines(b)) +
            "\nITEM: ATOMS " + " ".join(fh) + "\n" + (row + "\n") * k)
    return dcase("dump_huge", f"{op}-{k}", b, text, fh, (2,), rng)


def dump_stream_chunks(kind):
    if kind == "dump-rows":
        return (b"ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1000000000000\nITEM: ATOMS id x vx s11\n",
                b"1 0.5 0.25 0.125\n" * (1 << 16))
    block = b"ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id x\n1 0.5\n"
    return b"", block * max(1, (1 << 20) // len(block))



# --- running ---------------------------------------------------------------

def stream_chunks(kind, b, rng):
    """An endless stream: (prefix bytes, chunk repeated for ever)."""
    if kind.startswith("dump-"):
        return dump_stream_chunks(kind)
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
        binary_text = isinstance(case.text, bytes)
        with open(input_path, "wb" if binary_text else "w", **({} if binary_text else {"encoding": "utf-8"})) as f:
            f.write(case.text)
    if getattr(case, "convergence", None):
        files, cells = case.convergence
        paths = [input_path]
        for k, text in enumerate(files[1:], 1):
            paths.append(f"{stem}-c{cells[k]}.{case.ext}")
            with open(paths[-1], "w", encoding="utf-8") as f:
                f.write(text)
        cleanup.extend(paths[1:])
        setup = list(case.base.setup)
        setup[setup.index("--cells") + 1] = ",".join(map(str, cells))
        cmd = ["prlimit", f"--as={memory}", "timeout", "-k", "5", str(seconds), binary, "check", *setup,
               "--convergence", *paths, *case.extra] + (["--json"] if case.json_report else [])
        input_path = paths[0]
    else:
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
    if code == 0 and case.family != "control" and 0 not in case.expect:
        if getattr(case, "agree_ok", False):  # the values do agree; the file should have been refused
            return "wrong exit code", f"exit 0 (the values agree within the tolerance), expected {sorted(case.expect)}"
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
        newlines = len([l for l in err.split("\n") if l.strip()])
        return "multi-line error", f"{len(lines)} lines" + (
            "" if newlines > 1 else " (one by \\n: split at U+2028/U+2029/U+0085 or another Unicode line break)")
    if code not in case.expect:
        return "wrong exit code", f"exit {code}, expected {sorted(case.expect)}"
    return "ok", ""


def generate(index, family, seed, bases, workdir, dbases=None):
    rng = random.Random(f"{seed}-{index}")
    if family.startswith("dump_"):
        b = rng.choice(list(dbases.values()))
        if family == "dump_huge":
            return fam_dump_huge(rng, b, workdir)
        if family in ("dump_flags", "dump_json_flags") and rng.random() < 0.4:
            b = dbases["dump-2d-bsmpm"]
        return globals()["fam_" + family](rng, b)
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
    ap.add_argument("--kind", choices=["classic", "dump", "all"], default="classic",
                    help="classic: issue #35's families (CSV/JSON/trace); dump: LAMMPS-style dump files and the "
                         "convention flags (issue #36); all: both")
    ap.add_argument("--repro-all", action="store_true",
                    help="with --repro-dir, copy every input that is not ok (wrong exit codes and multi-line errors too)")
    a = ap.parse_args()
    binary = os.path.abspath(a.binary)
    started = time.monotonic()
    workdir = os.path.abspath(a.workdir or tempfile.mkdtemp(prefix="fuzz-check-", dir="/tmp"))
    os.makedirs(os.path.join(workdir, "cases"), exist_ok=True)
    os.makedirs(os.path.join(workdir, "kept"), exist_ok=True)
    base_binary = os.path.abspath(a.base_binary or a.binary)
    bases = {name: Base(name, base_binary) for name in SETUPS} if a.kind != "dump" else {}
    dbases = {name: DumpBase(name, base_binary) for name in DUMP_SETUPS} if a.kind != "classic" else {}
    if a.kind == "classic":
        # Families: the control gets 1/16 of the count, the ten others share the rest.
        control = max(1, a.count // 16)
        plan = ["control"] * control + [FAMILIES[k % len(FAMILIES)] for k in range(a.count - control)]
        families = ["control"] + FAMILIES
    elif a.kind == "dump":
        control = max(1, a.count // 10)
        plan = ["dump_control"] * control + [DUMP_FAMILIES[k % len(DUMP_FAMILIES)] for k in range(a.count - control)]
        families = ["dump_control"] + DUMP_FAMILIES
    else:
        control = max(1, a.count // 16)
        both = FAMILIES + DUMP_FAMILIES
        plan = (["control"] * control + ["dump_control"] * control
                + [both[k % len(both)] for k in range(a.count - 2 * control)])
        families = ["control"] + FAMILIES + ["dump_control"] + DUMP_FAMILIES
    random.Random(a.seed).shuffle(plan)
    chosen = range(a.count)
    if a.cases:
        chosen = [int(x) for x in a.cases.split(",")]
    if a.families:
        keep = set(a.families.split(","))
        chosen = [i for i in chosen if plan[i] in keep]
    cases = [(i, generate(i, plan[i], a.seed, bases, workdir, dbases)) for i in chosen]

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
                                      "expect": sorted(case.expect), "flags_a": getattr(case, "flags_a", None),
                                      "stderr": err.strip().splitlines()[:3]}) + "\n")
            if cls != "ok":
                variants[(case.family, cls)][case.variant] += 1
                if not case.stream:
                    dest = os.path.join(workdir, "kept", f"case-{i:05d}.{case.ext}")
                    shutil.copy(input_path, dest)
                    cmd, input_path = [dest if x == input_path else x for x in cmd], dest
            if own and not a.keep:
                os.remove(written)
            if a.repro_dir and (cls in SERIOUS or (a.repro_all and cls != "ok")):
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
                    if getattr(case, "flags_a", None) is not None:
                        f.write(f"# the input is hompm's own output with flags A: hompm run|trace "
                                f"{' '.join(case.base.setup)} {' '.join(case.flags_a)} --json "
                                f"(variant run-/trace-: that document; dump_flags: a dump of the run)\n")
                    f.write(f"# family {case.family}, variant {case.variant}, expected exit {sorted(case.expect)}\n")
                    f.write(f"# exit {code}; {why}\n# stderr: {err.strip()[:2000]}\n")
            if cls != "ok":
                kept.append({"case": i, "family": case.family, "variant": case.variant, "class": cls, "why": why,
                             "exit": code, "expect": sorted(case.expect), "flags_a": getattr(case, "flags_a", None),
                             "command": shell(cmd), "stream": case.stream,
                             "stderr": err.strip().splitlines()[:3]})
            examples.setdefault((case.family, cls), {
                "case": i, "variant": case.variant, "exit": code, "why": why, "command": shell(cmd),
                "stderr": (err.strip().splitlines() or [""])[0][:300]})

    shutil.rmtree(os.path.join(workdir, "wide"), ignore_errors=True)
    elapsed = time.monotonic() - started
    bases = {**bases, **dbases}
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

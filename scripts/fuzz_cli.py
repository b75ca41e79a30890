#!/usr/bin/env python3
"""Runs generated `hompm` command lines through the binary (issue #13).

Each line runs under a memory cap (prlimit --as, default 4 GiB) and a time
limit (default 20 s); the outcomes are tabulated as in issue #13. The
generator draws from the same pools as tests/spec/cli/cli_fuzz.rs (boundary values,
huge sizes, NaN, unknown names, mismatched lists), seeded.

    scripts/fuzz_cli.py [--binary target/release/hompm] [--count 3400] [--seed 1]
"""
import argparse, concurrent.futures, random, subprocess, collections, json

COUNTS = ["0", "1", "2", "3", "7", "16", "-1", "1.5", "abc", "", "9223372036854775807",
          "18446744073709551615", "18446744073709551616", "1000000000", "100000", "5000", "100"]
FLOATS = ["0", "-1", "1e-5", "0.01", "0.5", "1", "31.25", "nan", "inf", "-inf", "1e308", "5e-324", "-0"]
LISTS = ["0,0,1,1", "0,0,0,0.5,1,1,1", "0,1", "0,0.25,0.5,0.75,1", "0.1,0.4,0.6,0.9", "1,nan",
         "0,0,5e-324,5e-324", "-1e308,-1e308,1e308,1e308", "1,0.5,0", "", "0,1e308", "1,2,3",
         "0.2,0.5,0.7", "x", "0,1\n2", "0,1e-300,2e-300"]
SPEC = {
    "basis": [("--degree", COUNTS), ("--knots", LISTS), ("--at", LISTS), ("--derivatives", None), ("--json", None)],
    "mass": [("--degree", COUNTS), ("--spans", COUNTS), ("--dim", ["1", "2", "3", "0", "-2"]), ("--dirichlet", None),
             ("--condition", None), ("--solve", ["cg", "pmg", "richardson", "direct", "bogus"]), ("--tol", FLOATS),
             ("--json", None)],
    "reconstruct": [("--method", ["tls", "tls-conservative", "cubic-spline", "cubic-spline-natural", "mls", "spline"]),
                    ("--cells", LISTS), ("--points", LISTS), ("--values", LISTS), ("--integrals", LISTS),
                    ("--order", COUNTS), ("--at", LISTS), ("--json", None)],
    "run": [("--method", ["mpm", "mpm-p2", "ddmpm", "bsmpm", "bogus"]), ("--degree", COUNTS),
            ("--mapping", ["direct", "tls", "cubic-spline", "nope"]), ("--mass", ["lumped", "consistent", "richardson", "heavy"]),
            ("--cells", COUNTS), ("--ppc", COUNTS), ("--dt", FLOATS), ("--steps", COUNTS),
            ("--params", ["thesis-table-4.1", "tls-table-2", "nope"]), ("--json", None)],
    "table": [("--list", None), ("--json", None)],
}
SCENES = ["vibrating-bar", "column-self-weight", "column-top-load", "column-compaction"]


def generate(rng):
    cmd = rng.choices(list(SPEC), weights=[3, 3, 3, 4, 1])[0]
    args = [cmd] + ([rng.choice(SCENES)] if cmd == "run" else [])
    if cmd == "table" and rng.random() < 0.5:
        args.append(rng.choice(["no-such-table", "", "book-4.2\n", "thesis-a1"]))
    # Required options are present most of the time, so that most lines
    # reach validation and work rather than clap's "required argument".
    required = {"basis": 3, "mass": 2, "reconstruct": 4}.get(cmd, 0)
    opts = [o for i, o in enumerate(SPEC[cmd]) if rng.random() < (0.9 if i < required else 0.4)]
    if cmd == "reconstruct" and rng.random() < 0.9:
        opts.append(("--at", LISTS))
    rng.shuffle(opts)
    for flag, pool in opts:
        args += [flag] if pool is None else [flag, rng.choice(pool)]
    return args


def classify(args, code, out, err):
    lines = [l for l in err.splitlines() if l.strip()]
    errors = [l for l in lines if l.startswith("error:")]
    if code == 101 or "panicked" in err:
        return "panic (exit 101)"
    if code == 124:
        return "timeout after announcing its estimate" if "note:" in err else "timeout, no estimate"
    if code < 0 or code in (134, 137) or "memory allocation" in err:
        return "aborted by the memory cap"
    if code == 0:
        tokens = out.replace(",", " ").replace("[", " ").replace("]", " ").split()
        if any(t.lower() in ("nan", "inf", "-inf") for t in tokens):
            return "success with NaN/inf in the output"
        if "--json" in args and args[0] != "table":
            try:
                doc = json.loads(out)
            except ValueError:
                return "success with invalid JSON"
            if "null" in json.dumps(doc):
                return "success with null in the JSON"
        return "success"
    if len(errors) == 1 and len(lines) - len([l for l in lines if l.startswith(("warning:", "note:"))]) == 1:
        return f"refused in one line (exit {code})"
    return f"error not on one line (exit {code})"


def run_one(binary, args, memory, seconds):
    cmd = ["prlimit", f"--as={memory}", "timeout", str(seconds), binary] + args
    p = subprocess.run(cmd, capture_output=True, text=True, errors="replace")
    return args, p.returncode, p.stdout, p.stderr


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default="target/release/hompm")
    ap.add_argument("--count", type=int, default=3400)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--memory", default=str(4 << 30))
    ap.add_argument("--seconds", type=int, default=20)
    a = ap.parse_args()
    rng = random.Random(a.seed)
    lines = [generate(rng) for _ in range(a.count)]
    outcomes = collections.Counter()
    examples = {}
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        for args, code, out, err in pool.map(lambda l: run_one(a.binary, l, a.memory, a.seconds), lines):
            kind = classify(args, code, out, err)
            outcomes[kind] += 1
            examples.setdefault(kind, (args, err.strip().splitlines()[:1]))
    print(f"{a.count} command lines, seed {a.seed}, memory cap {a.memory} bytes, {a.seconds} s each\n")
    print("| outcome | count | example |\n|---|---|---|")
    for kind, n in outcomes.most_common():
        args, err = examples[kind]
        print(f"| {kind} | {n} | `{' '.join(repr(x) if (' ' in x or not x or chr(10) in x) else x for x in args)}` {err[0][:100] if err else ''} |")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Issue #37's measure of the equation map: 8 done rows of docs/equations.md
picked with a fixed seed, and the files a reader opens for each (the files
that declare the items the row names outside `(reference: …)`, including
its "called by" items, plus the test files it names).

    scripts/map_sample.py [--seed 37] [--rows 8]
"""
import argparse, os, random, re, subprocess


def done_rows(path="docs/equations.md"):
    for line in open(path, encoding="utf-8"):
        if line.startswith("| ") and not line.startswith("| id "):
            cells = [c.strip().replace("\x01", "|")
                     for c in line.replace("\\|", "\x01").strip().strip("|").split("|")]
            if len(cells) == 5 and cells[4] == "done":
                yield cells


def called_part(cell):
    """The cell without its `(reference: …)` parts."""
    out, rest = "", cell
    while "reference:" in rest:
        i = rest.index("reference:")
        out += rest[:i]
        after, depth, end = rest[i:], 0, None
        for k, c in enumerate(after):
            if c == "(":
                depth += 1
            elif c == ")":
                if depth == 0:
                    end = k
                    break
                depth -= 1
        rest = after[end:] if end is not None else ""
    return out + rest


def files_of(path):
    """The source file that declares the item `a::b::Item::member`."""
    segs = path.split("::")
    for k in range(len(segs), 0, -1):
        f = "src/" + "/".join(segs[:k]) + ".rs"
        d = "src/" + "/".join(segs[:k])
        if os.path.isfile(f):
            return {f}
        if os.path.isfile(d + "/mod.rs"):
            if k == len(segs):
                return {d + "/mod.rs"}
            name = segs[k]
            found = subprocess.run(
                ["grep", "-rlE", rf"(fn|struct|enum|trait|const|type) {name}\b", d],
                capture_output=True, text=True).stdout.split()
            return set(sorted(found)[:1]) or {d + "/mod.rs"}
    return set()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=37)
    ap.add_argument("--rows", type=int, default=8)
    a = ap.parse_args()
    rows = list(done_rows())
    total = 0
    for r in random.Random(a.seed).sample(rows, a.rows):
        paths = [w.strip(":") for w in re.split(r"[^A-Za-z0-9_:]", called_part(r[2])) if "::" in w]
        files = set().union(*(files_of(p) for p in paths)) if paths else set()
        tests = {t.split("::")[0] for t in r[3].split(", ")}
        total += len(files) + len(tests)
        print(f"{r[0]}: {sorted(files)} + {sorted(tests)} = {len(files) + len(tests)}")
    print(f"files per equation: {total / a.rows:.3f}")


if __name__ == "__main__":
    main()

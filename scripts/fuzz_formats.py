#!/usr/bin/env python3
"""scripts/fuzz_formats.py FILES_DIR [--seed S] [--count N] [--hompm PATH]

The check-input fuzz of issue #36 for the binary and XML formats: it takes
the files scripts/formats_check.py wrote from hompm's own runs (VTK legacy
and XML, .npy, .npz), damages them in seeded ways, and runs each through
`hompm check`. Standard library plus numpy and vtk (the formats' own
readers, as the oracle of what a damaged file really holds).

Classes of outcome:
  panic          hompm panicked or died of a signal
  multi-line     an error of more than one line
  wrong-exit     an exit other than 0, 1 or 2
  timeout        over 20 s (or killed by the 4 GiB address-space cap)
  false-agrees   exit 0 although the formats' own reader reads values that
                 differ from hompm's by more than the tolerance
  untouched      exit 0 "bit for bit" on a file the formats' own reader
                 refuses: the damage lies outside the data compared (cell
                 connectivity, a z component, an unused array)
  unverified     exit 0, not bit for bit, on a file the formats' own
                 reader refuses (listed for reading)
  ok             anything else
"""
import argparse
import collections
import os
import random
import resource
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from formats_check import RUN_1D, RUN_2D, VTK_COLUMNS_1D, VTK_COLUMNS_2D  # noqa: E402

NUMPY_2D = "x0_x=0,x0_y=1,u_x=2,u_y=3,v_x=4,v_y=5,stress_xx=6,stress_xy=7,stress_yx=8,stress_yy=9"
NUMPY_1D = "x0=0,u=1,v=2,stress=3"


def limit():
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))


def columns_for(name):
    two_d = name.startswith("av-")
    if name.endswith((".vtk", ".vtp", ".vtu")):
        return VTK_COLUMNS_2D if two_d else VTK_COLUMNS_1D
    if name.endswith(("plain.npy", "fortran.npy", "big-endian.npy")):
        return NUMPY_2D if two_d else NUMPY_1D
    return ""


def reference_values(path):
    """The arrays the formats' own readers see, or None if they refuse (or
    crash: VTK's readers can die of bad_alloc on a damaged count, so they
    run in a child process)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "ref.npz")
        r = subprocess.run([sys.executable, __file__, "--reference", path, out],
                           capture_output=True, timeout=60, preexec_fn=limit)
        if r.returncode != 0 or not os.path.exists(out):
            return None
        with np.load(out, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}


def read_reference(path):
    try:
        if path.endswith(".npy"):
            a = np.load(path, allow_pickle=False)
            if a.dtype.names:
                from numpy.lib import recfunctions
                a = recfunctions.structured_to_unstructured(a)
            return {"data": a}
        if path.endswith(".npz"):
            with np.load(path, allow_pickle=False) as z:
                return {k: z[k] for k in z.files}
        import vtk
        errors = []
        if path.endswith(".vtk"):
            r = vtk.vtkPolyDataReader()
        elif path.endswith(".vtp"):
            r = vtk.vtkXMLPolyDataReader()
        else:
            r = vtk.vtkXMLUnstructuredGridReader()
        r.AddObserver("ErrorEvent", lambda *a: errors.append(1))
        r.AddObserver("WarningEvent", lambda *a: errors.append(1))
        r.SetFileName(path)
        r.Update()
        if errors:
            return None
        out = r.GetOutput()
        from vtk.util.numpy_support import vtk_to_numpy
        vals = {"Points": vtk_to_numpy(out.GetPoints().GetData())}
        pd = out.GetPointData()
        for k in range(pd.GetNumberOfArrays()):
            vals[pd.GetArrayName(k)] = vtk_to_numpy(pd.GetArray(k))
        return vals
    except Exception:
        return None


def compared(name, key, x):
    """The part of an array hompm compares: x and y of VTK's 3-vectors,
    xx, xy, yx, yy of its 9-tensors in 2D; x of the points in 1D."""
    x = np.asarray(x)
    if not name.endswith((".vtk", ".vtp", ".vtu")) or x.ndim != 2:
        return x
    two_d = name.startswith("av-")
    if x.shape[1] == 3:
        return x[:, :2] if two_d else x[:, :1]
    if x.shape[1] == 9:
        return x[:, [0, 1, 3, 4]]
    return x


def fields_of(name, key, width):
    """hompm's field of each column of the reference array `key`."""
    if key == "data":  # a plain or structured .npy: x0, u, v, stress
        two_d = name.startswith("av-")
        layout = ["x0", "x0", "u", "u", "v", "v"] + ["stress"] * 4 if two_d else ["x0", "u", "v", "stress"]
        return layout[:width]
    field = "x" if key == "Points" else key
    return [field] * width


def same(name, a, b, atol):
    """Whether a (what the formats' own reader sees in the damaged file)
    and b (the original) agree within the tolerance hompm itself used for
    each field: relative 1e-9, or the field's absolute tolerance (atol,
    from `hompm check --json`: 1e-12 of its largest value, or a floor)."""
    if a is None or b is None or a.keys() != b.keys():
        return False
    for k in a:
        x, y = compared(name, k, a[k]), compared(name, k, b[k])
        if x.shape != y.shape:
            return False
        x, y = x.astype(float), y.astype(float)
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            return False
        x2, y2 = x.reshape(len(x), -1), y.reshape(len(y), -1)
        for j, field in enumerate(fields_of(name, k, x2.shape[1])):
            if field not in atol:
                continue
            d = np.abs(x2[:, j] - y2[:, j])
            if np.any(d > np.maximum(1e-9 * np.abs(y2[:, j]), atol[field])):
                return False
    return True


def mutate(rng, data, name):
    data = bytearray(data)
    kind = rng.choice(["bit", "bit-data", "truncate", "insert", "duplicate", "zero", "digit", "attr"])
    n = len(data)
    if kind == "bit":
        k = rng.randrange(n)
        data[k] ^= 1 << rng.randrange(8)
    elif kind == "bit-data":
        k = rng.randrange(n // 5, n)
        data[k] ^= 1 << rng.randrange(8)
    elif kind == "truncate":
        data = data[: rng.randrange(n)]
    elif kind == "insert":
        k = rng.randrange(n)
        data[k:k] = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 9)))
    elif kind == "duplicate":
        a = rng.randrange(n)
        b = min(n, a + rng.randrange(1, 64))
        data[b:b] = data[a:b]
    elif kind == "zero":
        a = rng.randrange(n)
        b = min(n, a + rng.randrange(1, 32))
        data[a:b] = bytes(b - a)
    elif kind == "digit":
        digits = [k for k in range(n) if 48 <= data[k] <= 57]
        if digits:
            k = rng.choice(digits)
            data[k] = 48 + (data[k] - 48 + rng.randrange(1, 10)) % 10
    else:
        text = bytes(data)
        for a, b in [(b"Float64", b"Float32"), (b"UInt32", b"UInt64"), (b"LittleEndian", b"BigEndian"),
                     (b'format="binary"', b'format="ascii"'), (b"double", b"float"),
                     (b"'<f8'", b"'>f8'"), (b"False", b"True"), (b"NumberOfComponents=\"3\"", b"NumberOfComponents=\"2\"")]:
            if a in text:
                idx = [i for i in range(len(text)) if text.startswith(a, i)]
                i = rng.choice(idx)
                data[i:i + len(a)] = b
                break
    return kind, bytes(data)


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--reference":
        vals = read_reference(sys.argv[2])
        if vals is None:
            sys.exit(1)
        np.savez(sys.argv[3], **{k.replace("/", "_"): v for k, v in vals.items()})
        return
    ap = argparse.ArgumentParser()
    ap.add_argument("files")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=1000)
    ap.add_argument("--hompm", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "hompm"))
    args = ap.parse_args()
    rng = random.Random(args.seed)
    names = sorted(f for f in os.listdir(args.files)
                   if f.endswith((".vtk", ".vtp", ".vtu", ".npy", ".npz")) and "float32" not in f)
    originals = {f: reference_values(os.path.join(args.files, f)) for f in names}
    counts = collections.Counter()
    examples = collections.defaultdict(list)
    with tempfile.TemporaryDirectory() as tmp:
        for case in range(args.count):
            name = rng.choice(names)
            with open(os.path.join(args.files, name), "rb") as fh:
                kind, data = mutate(rng, fh.read(), name)
            path = os.path.join(tmp, f"{case}-{name}")
            with open(path, "wb") as fh:
                fh.write(data)
            run = RUN_2D if name.startswith("av-") else RUN_1D
            cmd = [args.hompm, "check", *run, "--input", path]
            cols = columns_for(name)
            if cols:
                cmd += ["--columns", cols]
            try:
                r = subprocess.run(cmd, capture_output=True, text=True, timeout=20, preexec_fn=limit)
                code, err = r.returncode, r.stderr
            except subprocess.TimeoutExpired:
                code, err = "timeout", ""
            if code == "timeout":
                cls = "timeout"
            elif code < 0 or "panicked" in err:
                cls = "panic"
            elif code not in (0, 1, 2):
                cls = "wrong-exit"
            elif code == 2 and len([l for l in err.splitlines() if l.strip()]) > 1:
                cls = "multi-line"
            elif code == 0:
                seen = reference_values(path)
                doc = subprocess.run(cmd + ["--json"], capture_output=True, text=True, timeout=20)
                import json
                atol = {f: v["atol_abs"] for f, v in json.loads(doc.stdout)["fields"].items()}
                if seen is None:
                    cls = "untouched" if "bit for bit" in r.stdout else "unverified"
                elif same(name, seen, originals[name], atol):
                    cls = "ok"
                else:
                    cls = "false-agrees"
            else:
                cls = "ok"
            counts[cls] += 1
            if cls not in ("ok", "untouched") and len(examples[cls]) < 5:
                keep = os.path.join("/tmp", f"fuzz-formats-{cls}-{case}-{name}")
                with open(keep, "wb") as fh:
                    fh.write(data)
                examples[cls].append(f"{kind} {keep}: {err.strip()[:160]}")
    print(f"seed {args.seed}, {args.count} inputs:", dict(counts))
    for cls, ex in examples.items():
        print(f"  {cls}:")
        for e in ex:
            print("    " + e)
    bad = sum(v for k, v in counts.items() if k not in ("ok", "untouched", "unverified"))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()

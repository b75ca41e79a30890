#!/usr/bin/env python3
"""scripts/formats_check.py OUTDIR [--hompm PATH] [--fixtures DIR]

Writes hompm's own final particles through the reference writers of the
binary formats `hompm check` reads (issue #36): VTK's own writers (the
`vtk` package from PyPI: vtkPolyDataWriter for legacy .vtk, versions 4.2
and 5.1, ASCII and binary; vtkXMLPolyDataWriter / vtkXMLUnstructuredGridWriter
for .vtp/.vtu, every data mode, raw and base64 appended data, zlib or no
compression, UInt32 and UInt64 headers) and NumPy's (np.save of a plain,
a Fortran-ordered, a big-endian and a structured array; np.savez and
np.savez_compressed). Each file is then checked with one `hompm check`
line, which must agree (exit 0) for float64 and differ (exit 1) for the
float32 copy, at the magnitude of float32 rounding.

Outside CI: it needs `pip install vtk numpy`. With --fixtures DIR it also
copies a small set of the files into DIR (tests/fixtures/formats is made
this way; the CI tests read those files with the command lines printed
here).
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

import numpy as np

RUN_2D = ["aligned-vibration", "--method", "bsmpm", "--cells", "4", "--ppc", "4",
          "--steps", "20", "--amplitude", "0.05", "--young", "2e7"]
RUN_1D = ["vibrating-bar", "--method", "bsmpm", "--cells", "4", "--ppc", "2",
          "--dt", "1e-3", "--steps", "50"]

# hompm's 2D columns from VTK's: vectors have 3 components, tensors 9
# (row-major, xx = 0, xy = 1, yx = 3, yy = 4).
VTK_COLUMNS_2D = ",".join([
    "x_x=Points:0", "x_y=Points:1", "x0_x=x0:0", "x0_y=x0:1", "u_x=u:0", "u_y=u:1",
    "v_x=v:0", "v_y=v:1", "stress_xx=stress:0", "stress_xy=stress:1",
    "stress_yx=stress:3", "stress_yy=stress:4", "F_xx=F:0", "F_xy=F:1", "F_yx=F:3",
    "F_yy=F:4"])
VTK_COLUMNS_1D = "x=Points:0,x0=x0,u=u,v=v,stress=stress"


def run_json(hompm, run):
    out = subprocess.run([hompm, "run", *run, "--json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def arrays(doc, two_d):
    p = doc["particles"]
    a = {k: np.asarray(p[k], dtype=np.float64) for k in ("x0", "x", "u", "v", "stress")}
    if "deformation_gradient" in p:
        a["F"] = np.asarray(p["deformation_gradient"], dtype=np.float64)
    if two_d:
        a["stress"] = a["stress"].reshape(-1, 2, 2)
        a["F"] = a["F"].reshape(-1, 2, 2)
    return a


def polydata(a, two_d, vtk):
    from vtk.util.numpy_support import numpy_to_vtk
    n = len(a["x"])
    pts = np.zeros((n, 3))
    if two_d:
        pts[:, :2] = a["x"]
    else:
        pts[:, 0] = a["x"]
    poly = vtk.vtkPolyData()
    points = vtk.vtkPoints()
    points.SetData(numpy_to_vtk(pts, deep=True))
    poly.SetPoints(points)
    verts = vtk.vtkCellArray()
    for k in range(n):
        verts.InsertNextCell(1)
        verts.InsertCellPoint(k)
    poly.SetVerts(verts)

    def add(name, values):
        arr = numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        arr.SetName(name)
        poly.GetPointData().AddArray(arr)

    if two_d:
        for name in ("x0", "u", "v"):
            v3 = np.zeros((n, 3))
            v3[:, :2] = a[name]
            add(name, v3)
        for name in ("stress", "F"):
            t9 = np.zeros((n, 3, 3))
            t9[:, :2, :2] = a[name]
            add(name, t9.reshape(n, 9))
    else:
        for name in ("x0", "u", "v", "stress"):
            add(name, a[name])
    cell_ids = numpy_to_vtk(np.arange(n, dtype=np.int64), deep=True)
    cell_ids.SetName("cell_id")
    poly.GetCellData().AddArray(cell_ids)
    return poly


def write_vtk(poly, out, stem):
    import vtk
    files = []
    for version in (42, 51):
        for binary in (False, True):
            w = vtk.vtkPolyDataWriter()
            w.SetFileVersion(version)
            w.SetInputData(poly)
            name = f"{stem}-legacy{version}-{'binary' if binary else 'ascii'}.vtk"
            w.SetFileName(os.path.join(out, name))
            w.SetFileTypeToBinary() if binary else w.SetFileTypeToASCII()
            w.Write()
            files.append(name)
    ug_filter = vtk.vtkAppendFilter()
    ug_filter.AddInputData(poly)
    ug_filter.Update()
    grid = ug_filter.GetOutput()
    for kind, writer, data, ext in (("vtp", vtk.vtkXMLPolyDataWriter, poly, "vtp"),
                                    ("vtu", vtk.vtkXMLUnstructuredGridWriter, grid, "vtu")):
        for mode in ("ascii", "binary", "appended-raw", "appended-base64"):
            for zlib in (False, True):
                for header in ("UInt32", "UInt64"):
                    if mode == "ascii" and (zlib or header == "UInt64"):
                        continue
                    w = writer()
                    w.SetInputData(data)
                    if mode == "ascii":
                        w.SetDataModeToAscii()
                    elif mode == "binary":
                        w.SetDataModeToBinary()
                    else:
                        w.SetDataModeToAppended()
                        w.SetEncodeAppendedData(mode == "appended-base64")
                    if zlib:
                        w.SetCompressorTypeToZLib()
                        w.SetBlockSize(256)  # several blocks even for small files
                    else:
                        w.SetCompressorTypeToNone()
                    w.SetHeaderTypeToUInt64() if header == "UInt64" else w.SetHeaderTypeToUInt32()
                    name = f"{stem}-{mode}-{'zlib' if zlib else 'raw'}-{header}.{ext}"
                    w.SetFileName(os.path.join(out, name))
                    w.Write()
                    files.append(name)
    return files


def write_numpy(a, two_d, out, stem):
    """Returns (file, --columns, expected exit)."""
    n = len(a["x"])
    cases = []
    flat = [a["x0"], a["u"], a["v"]]
    if two_d:
        table = np.column_stack([a["x0"], a["u"], a["v"], a["stress"].reshape(n, 4)])
        cols = "x0_x=0,x0_y=1,u_x=2,u_y=3,v_x=4,v_y=5,stress_xx=6,stress_xy=7,stress_yx=8,stress_yy=9"
    else:
        table = np.column_stack(flat + [a["stress"]])
        cols = "x0=0,u=1,v=2,stress=3"
    np.save(os.path.join(out, f"{stem}-plain.npy"), table)
    cases.append((f"{stem}-plain.npy", cols, 0))
    np.save(os.path.join(out, f"{stem}-fortran.npy"), np.asfortranarray(table))
    cases.append((f"{stem}-fortran.npy", cols, 0))
    np.save(os.path.join(out, f"{stem}-big-endian.npy"), table.astype(">f8"))
    cases.append((f"{stem}-big-endian.npy", cols, 0))
    shape = (2,) if two_d else ()
    tensor = (2, 2) if two_d else ()
    dt = np.dtype([("x0", "<f8", shape), ("u", "<f8", shape), ("v", "<f8", shape),
                   ("stress", "<f8", tensor)])
    rec = np.zeros(n, dtype=dt)
    for k in ("x0", "u", "v", "stress"):
        rec[k] = a[k]
    np.save(os.path.join(out, f"{stem}-structured.npy"), rec)
    cases.append((f"{stem}-structured.npy", "", 0))
    named = {k: a[k] for k in ("x0", "x", "u", "v", "stress", "F") if k in a}
    np.savez(os.path.join(out, f"{stem}-named.npz"), **named)
    cases.append((f"{stem}-named.npz", "", 0))
    np.savez_compressed(os.path.join(out, f"{stem}-compressed.npz"), **named)
    cases.append((f"{stem}-compressed.npz", "", 0))
    np.savez(os.path.join(out, f"{stem}-float32.npz"),
             **{k: v.astype(np.float32) for k, v in named.items()})
    cases.append((f"{stem}-float32.npz", "", 1))
    return cases


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("--hompm", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "hompm"))
    ap.add_argument("--fixtures")
    args = ap.parse_args()
    import vtk  # noqa: F401  (fails early with a clear message if missing)
    os.makedirs(args.outdir, exist_ok=True)
    failures = 0
    for two_d, run, vtk_cols, stem in ((True, RUN_2D, VTK_COLUMNS_2D, "av"),
                                       (False, RUN_1D, VTK_COLUMNS_1D, "bar")):
        doc = run_json(args.hompm, run)
        a = arrays(doc, two_d)
        cases = [(f, vtk_cols, 0) for f in write_vtk(polydata(a, two_d, vtk), args.outdir, stem)]
        cases += write_numpy(a, two_d, args.outdir, stem)
        for name, cols, expect in cases:
            cmd = [args.hompm, "check", *run, "--input", os.path.join(args.outdir, name)]
            if cols:
                cmd += ["--columns", cols]
            r = subprocess.run(cmd, capture_output=True, text=True)
            verdict = (r.stdout.strip().splitlines() or r.stderr.strip().splitlines() or ["?"])
            first = next((l for l in verdict if "agree" in l or "differ" in l), verdict[0])
            ok = r.returncode == expect
            failures += not ok
            print(f"{'ok ' if ok else 'BAD'} exit {r.returncode} (want {expect})  {name}: {first.strip()[:110]}")
            if not ok:
                print("    " + " ".join(cmd))
                print("    " + (r.stderr.strip() or r.stdout.strip())[:400])
    if args.fixtures:
        os.makedirs(args.fixtures, exist_ok=True)
        keep = ["av-legacy42-binary.vtk", "av-legacy51-ascii.vtk", "av-binary-zlib-UInt32.vtp",
                "av-appended-raw-raw-UInt64.vtu", "av-appended-base64-zlib-UInt32.vtp",
                "av-binary-raw-UInt32.vtp",
                "bar-legacy42-ascii.vtk", "bar-named.npz", "bar-compressed.npz",
                "av-structured.npy", "av-fortran.npy", "av-float32.npz"]
        for k in keep:
            shutil.copy(os.path.join(args.outdir, k), os.path.join(args.fixtures, k))
        print(f"copied {len(keep)} fixtures to {args.fixtures}")
    print(f"{failures} unexpected verdicts")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""CPU nanoseconds per particle-step of the aligned vibration's step under
each combination of mls-convergence-study (issue #38).

The table's own wall times are taken while its runs share two cores (and
whatever else the machine runs); this measures the processor time (user +
sys, from os.wait4) of `hompm run aligned-vibration --cells C --ppc 9`
with LONG steps minus the same with 50 (which removes the setup), best of
three, divided by (LONG - 50) steps x the particles; LONG is 550 unless
given (conservative TLS stops near step 260 on 64 cells: use 250 there).
Run by hand (ONLY: run only the combinations whose label contains it):
  python3 scripts/aligned_step_cost.py [path/to/hompm] [cells] [long] [ONLY]
Only the standard library."""
import os, subprocess, sys

HOMPM = sys.argv[1] if len(sys.argv) > 1 else "target/release/hompm"
CELLS = int(sys.argv[2]) if len(sys.argv) > 2 else 32
LONG = int(sys.argv[3]) if len(sys.argv) > 3 else 550
ONLY = sys.argv[4] if len(sys.argv) > 4 else ""

# The flags of src/studies/mls_convergence.rs, `combinations()`.
FLAGS = {
    "BSMPM": "--method bsmpm --degree 2",
    "BSMPM + usl": "--method bsmpm --degree 2 --scheme usl",
    "BSMPM + pic": "--method bsmpm --degree 2 --transfer pic",
    "BSMPM + flip:0.99": "--method bsmpm --degree 2 --transfer flip:0.99",
    "BSMPM + apic (usl)": "--method bsmpm --degree 2 --transfer apic",
    "BSMPM + padded knots": "--method bsmpm --degree 2 --knots padded",
    "BSMPM + projected positions": "--method bsmpm --degree 2 --positions projected",
    "BSMPM + body force at nodes": "--method bsmpm --degree 2 --body-force nodes",
    "BSMPM + axis-aligned solution": "--method bsmpm --degree 2 --solution axis-aligned",
    "Taichi-style (apic, affine, padded)":
        "--method bsmpm --degree 2 --transfer apic --gradient affine --knots padded",
    "Taichi-style - affine": "--method bsmpm --degree 2 --transfer apic --knots padded",
    "Taichi-style - padded knots": "--method bsmpm --degree 2 --transfer apic --gradient affine",
    "Taichi-style, pic for apic":
        "--method bsmpm --degree 2 --transfer pic --scheme usl --knots padded",
    "Taichi-style, flip for apic": "--method bsmpm --degree 2 --scheme usl --knots padded",
    "BSMPM + MLS": "--method bsmpm-mls",
    "BSMPM + MLS + usl": "--method bsmpm-mls --scheme usl",
    "BSMPM + MLS + flip:0.99": "--method bsmpm-mls --transfer flip:0.99",
    "BSMPM + TLS": "--method bsmpm-tls",
    "BSMPM + TLS + usl": "--method bsmpm-tls --scheme usl",
    "BSMPM + TLS + flip:0.99": "--method bsmpm-tls --transfer flip:0.99",
    "BSMPM + PU-TLS": "--method bsmpm-pu-tls",
    "BSMPM + PU-TLS + usl": "--method bsmpm-pu-tls --scheme usl",
    "BSMPM + PU-TLS + flip:0.99": "--method bsmpm-pu-tls --transfer flip:0.99",
    "TL-FE reference (no grid crossing)": "--method tl-fe --degree 2",
}


def cpu_seconds(flags, steps):
    best = float("inf")
    for _ in range(3):
        args = [HOMPM, "run", "aligned-vibration", "--cells", str(CELLS), "--ppc", "9",
                "--steps", str(steps)] + flags.split()
        p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(p.pid, 0)
        if status != 0:
            sys.exit(f"{' '.join(args)} failed")
        best = min(best, usage.ru_utime + usage.ru_stime)
    return best


if __name__ == "__main__":
    particles = CELLS * CELLS * 9
    for label, flags in FLAGS.items():
        if ONLY not in label:
            continue
        ns = 1e9 * (cpu_seconds(flags, LONG) - cpu_seconds(flags, 50)) / ((LONG - 50) * particles)
        print(f"{label}: {ns:.0f} ns per particle-step ({CELLS} cells, {particles} particles)",
              flush=True)

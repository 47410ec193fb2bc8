#!/usr/bin/python3
"""The lane loop (kernels/lanes.cl, 8 particles per work-item) against the
plain loop (one): the same case run with numerics.neighbour_loop lanes and
plain must give the same history to float rounding.

usage: check_lanes.py SPH CASE OUT_FOLDER RTOL [sph --set arguments ...]

Compares every column of history.csv row by row, each relative to the
column's largest magnitude (a quantity that passes through zero is judged
against its scale, not its value near zero), and fails above RTOL; the
Swegle fraction, a count by the sign of a stress that can sit at zero, is
left out. Both loops run the same pair terms and sum over the neighbours
in the same order, so on PoCL they agree to the bit with the polynomial
smoothing kernels; vector and scalar cos and exp (the double-cosine and
Gaussian kernels) round differently, and another device's compiler may
contract vector and scalar arithmetic differently, so RTOL is a few float
ulps grown over the steps.
"""
import csv
import json
import math
import os
import subprocess
import sys


def run(sph, case, out, loop, sets):
    """The run's history rows; fails unless summary.json says it ran the
    loop asked for (1 particle per work-item for plain, 8 for lanes), so the
    two runs cannot be one loop twice."""
    cmd = [sph, "run", case, "--out", out, "--quiet", "--set", f"numerics.neighbour_loop={loop}"]
    for s in sets:
        cmd += ["--set", s]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    sys.stdout.write(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        sys.exit(f"check_lanes: the {loop} run exited {proc.returncode}")
    with open(os.path.join(out, "summary.json")) as f:
        lanes = json.load(f).get("neighbour_lanes")
    if lanes != {"plain": 1, "lanes": 8}[loop]:
        sys.exit(f"FAIL: the {loop} run ran {lanes} particles per work-item")
    with open(os.path.join(out, "history.csv")) as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    sph, case, out, rtol = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
    sets = [a for a in sys.argv[5:] if a != "--set"]
    plain = run(sph, case, os.path.join(out, "plain"), "plain", sets)
    lanes = run(sph, case, os.path.join(out, "lanes"), "lanes", sets)
    if len(plain) != len(lanes):
        sys.exit(f"FAIL: {len(plain)} history rows plain, {len(lanes)} lanes")
    # swegle_fraction counts particles by the sign of W'' sigma along their
    # nearest pair: a particle whose stress along it is at round-off from
    # zero flips between the two runs, so it is not a continuous quantity
    skip = {"step", "time_s", "swegle_fraction"}
    worst = (0.0, "", 0)
    for column in plain[0]:
        if column in skip:
            continue
        a = [float(r[column]) for r in plain]
        b = [float(r[column]) for r in lanes]
        scale = max(max(abs(x) for x in a), 1e-300)
        for k, (x, y) in enumerate(zip(a, b)):
            if not (math.isfinite(x) and math.isfinite(y)):
                sys.exit(f"FAIL: {column} row {k} not finite: plain {x}, lanes {y}")
            err = abs(x - y) / scale
            if err > worst[0]:
                worst = (err, column, k)
    print(f"check_lanes: largest difference {worst[0]:.3g} of the column's scale "
          f"({worst[1]}, row {worst[2]}); tolerance {rtol:g}")
    sys.exit(1 if worst[0] > rtol else 0)


if __name__ == "__main__":
    main()

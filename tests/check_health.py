#!/usr/bin/python3
"""The health indicators (kernels/health.cl: the lane loop's neighbour
search, the per-particle records and their reduction) against a brute-force
search over a snapshot: runs a case, then takes its last snapshot and the
history.csv row written at the same step and recomputes, over every pair of
particles (the symmetry planes' mirror images included, each mirrored across
its plane's position), what the row reports:
  neighbours_min / _mean / _max: j != i within the pair's support, 2 h_ij
    with h_ij the mean of the two smoothing lengths (common.cl PAIR_H);
  min_pair_distance_over_dx: the nearest neighbour's distance over the
    particle's own spacing scale h_i / (h_over_dx dx), over dx;
  clumped_fraction: intact particles with that distance below dx / 2
    (updated Lagrangian form only: the total Lagrangian form compares a
    pair with the separation F_ij X_ij its deformation gives it, and F is
    not in the snapshots; ctest total_lagrangian_clumping_against_deformation
    tests that rule).
Ghosts are not in the snapshot; fixed particles count as neighbours, not as
particles. The snapshot stores positions as the device's reals, so the
counts agree exactly except for pairs within float rounding of the support
(a regular lattice at h = 1.5 dx has pairs at exactly 2 h), and the
distance to float rounding; the test asserts them to history.csv's
printed digits.

usage: check_health.py SPH CASE OUT_FOLDER [sph --set arguments ...]
"""
import glob
import os
import subprocess
import sys

import h5py
import numpy as np
import yaml
from scipy.spatial import cKDTree

FLAG_FIXED, FLAG_DAMAGED = 1, 8  # include/sph_shared.h
SUPPORT_OVER_H = {"wendland_c2": 2.0, "cubic_spline": 2.0}  # kernels/smoothing.cl


def history_row(folder, time):
    rows = np.genfromtxt(os.path.join(folder, "history.csv"), delimiter=",", names=True)
    at = np.flatnonzero(np.abs(rows["time_s"] - time) <= 1e-9 * max(time, 1e-30))
    if len(at) == 0:
        sys.exit(f"FAIL: no history.csv row at the last snapshot's time {time:g} s")
    return rows[at[-1]]


def with_mirrors(x, h, planes):
    """x and h with every combination of the planes' mirror images."""
    xs, hs = [x], [h]
    for p in planes:
        axis = "xyz".index(p["axis"])
        mirrored = []
        for y in xs:
            m = y.copy()
            m[:, axis] = 2 * float(p.get("position", 0.0)) - m[:, axis]
            mirrored.append(m)
        xs += mirrored
        hs += [h] * len(mirrored)
    return np.vstack(xs), np.concatenate(hs)


def brute_force(folder):
    case = yaml.safe_load(open(os.path.join(folder, "case.resolved.yaml")))
    numerics = case["numerics"]
    kernel = numerics.get("kernel", "wendland_c2")
    if kernel not in SUPPORT_OVER_H:
        sys.exit(f"check_health.py knows the support of {sorted(SUPPORT_OVER_H)}, not {kernel}")
    dx, h_over_dx = float(numerics["dx"]), float(numerics.get("h_over_dx", 1.2))
    last = sorted(glob.glob(os.path.join(folder, "snap_*.h5")))[-1]
    with h5py.File(last, "r") as f:
        x = f["position"][...].astype(np.float64)
        h = f["smoothing_length"][...].astype(np.float64)
        flags = f["flags"][...]
        time = float(f.attrs["time_s"][0])
    dim = int(case.get("dimension", 3))
    x = x[:, :dim]
    all_x, all_h = with_mirrors(x, h, case.get("symmetry", []) or [])
    tree = cKDTree(all_x)
    q = SUPPORT_OVER_H[kernel]
    counted = (flags & FLAG_FIXED) == 0
    counts, nearest = [], []
    for i in np.flatnonzero(counted):
        js = np.array(tree.query_ball_point(x[i], q * (h[i] + all_h.max()) / 2 * 1.001))
        js = js[js != i]
        r = np.linalg.norm(all_x[js] - x[i], axis=1)
        within = r < q * 0.5 * (h[i] + all_h[js])
        counts.append(int(within.sum()))
        scale = h[i] / (h_over_dx * dx)
        nearest.append(r[within].min() / scale if within.any() else np.inf)
    counts, nearest = np.array(counts), np.array(nearest)
    intact = (flags[counted] & FLAG_DAMAGED) == 0
    indicators = {
        "neighbours_min": counts.min(),
        "neighbours_mean": counts.mean(),
        "neighbours_max": counts.max(),
        "min_pair_distance_over_dx": nearest.min() / dx,
    }
    if numerics.get("formulation", "updated_lagrangian") != "total_lagrangian":
        indicators["clumped_fraction"] = np.mean((nearest < 0.5 * dx) & intact)
    else:
        print("clumped_fraction: not compared (total Lagrangian: against F_ij X_ij)")
    return time, indicators, len(counts)


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    sph, case, out = sys.argv[1], sys.argv[2], sys.argv[3]
    run = subprocess.run([sph, "run", case, "--out", out, "--quiet"] + sys.argv[4:])
    if run.returncode != 0:
        sys.exit(f"FAIL: sph run exited with {run.returncode}")
    time, brute, particles = brute_force(out)
    row = history_row(out, time)
    # as history.csv prints them: the mean to 3 decimals, the distance and
    # the fraction to 7 significant digits (one particle more or fewer
    # clumped is 1 / particles, far above that); the counts exactly
    tolerance = {
        "neighbours_min": 0,
        "neighbours_mean": 5e-4 + 1e-12,
        "neighbours_max": 0,
        "min_pair_distance_over_dx": 1e-6 * brute["min_pair_distance_over_dx"],
        "clumped_fraction": 1e-6 * brute.get("clumped_fraction", 0) + 1e-12,
    }
    failed = False
    for key, value in brute.items():
        ok = abs(row[key] - value) <= tolerance[key]
        failed |= not ok
        print(f"{key}: history.csv {row[key]:.7g}, brute force {value:.7g}"
              f"{'' if ok else '  <- differs'}")
    print(f"({particles} particles at t = {time:g} s)")
    if failed:
        sys.exit("FAIL: the health indicators differ from the brute-force search")
    print("PASS")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""A graded lattice tiles its body: no gap, no overlap.

    check_graded_lattice.py SPH CASE OUT [--set K=V ...]

Runs one tiny step of CASE (3-D or plane, one graded body whose extents are
whole cells of the coarsest level), then checks on the first snapshot that
the particles' masses add up to density x the body's volume (each particle
carries rho (2^k dx)^dim, so a gap or an overlap of the levels shows as
missing or extra mass of at least one fine cell's, (dx^dim / V) of the
total, which for the tested bodies is far above the 1e-6 that float masses
sum to) and that every level holds particles.
"""
import os
import subprocess
import sys

import h5py
import numpy as np
import yaml


def main():
    sph, case, out, sets = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    run = subprocess.run([sph, "run", case, "--out", out, "--quiet", "--set",
                          "numerics.end_time=1e-12", "--set", "output.snapshot_interval=1e-12",
                          *sets])
    if run.returncode != 0:
        sys.exit(f"FAIL: sph run exited {run.returncode}")
    resolved = yaml.safe_load(open(os.path.join(out, "case.resolved.yaml")))
    body = resolved["bodies"][0]
    density = next(m["density"] for m in resolved["materials"] if m["name"] == body["material"])
    dim = resolved["dimension"]
    volume = float(np.prod(np.subtract(body["max"], body["min"])[:dim]))
    snap = h5py.File(os.path.join(out, "snap_00000.h5"), "r")
    mass = snap["mass"][:].sum(dtype=np.float64)
    h = snap["smoothing_length"][:]
    levels = np.round(np.log2(h / h.min())).astype(int)
    counts = np.bincount(levels)
    error = mass / (density * volume) - 1
    print(f"{len(h)} particles, per level {counts.tolist()}, mass / (rho V) - 1 = {error:.3g}")
    if abs(error) > 1e-6:
        sys.exit("FAIL: the levels do not tile the body")
    if len(counts) != body["grading"]["levels"] + 1 or (counts == 0).any():
        sys.exit(f"FAIL: expected particles on levels 0..{body['grading']['levels']}")
    print("ok")


if __name__ == "__main__":
    main()

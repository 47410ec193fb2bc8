#!/usr/bin/python3
"""Graded lattices: the reach pass (kernels/grid.cl) skips work that cannot
change its answer: particles with no coarser cell in their window (the
marks of grid_coarser_seed / _spread) do not search, and the others skip
the cells of their window wholly beyond the search radius. So every
particle's search reach must be the one the full search gives. Runs a case
twice, as built and with -DSPH_REACH_FULL_SCAN (every particle searches
every cell of its window), and compares the reach bits
of the flags (README: flags) of every snapshot, particle by particle (by
id); fails on any difference, or when the reaches do not differ between
particles (a case that would not test anything).

usage: check_reach.py SPH CASE OUT_FOLDER [sph --set arguments ...]
"""
import glob
import os
import sys

import h5py
import numpy as np

from build_options_run import run_with_options

REACH_SHIFT, REACH_MASK = 12, 255  # include/sph_shared.h


def run(sph, case, out, sets, options):
    run_with_options(sph, case, out, sets, options, "check_reach")
    reaches = []
    for path in sorted(glob.glob(os.path.join(out, "snap_*.h5"))):
        with h5py.File(path, "r") as h:
            order = np.argsort(h["id"][:])
            reaches.append((h["flags"][:][order] >> REACH_SHIFT) & REACH_MASK)
    if not reaches:
        sys.exit(f"check_reach: no snapshot in {out}")
    return reaches


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    sph, case, out = sys.argv[1:4]
    sets = sys.argv[4:]
    marked = run(sph, case, os.path.join(out, "marked"), sets, "")
    full = run(sph, case, os.path.join(out, "full"), sets, "-DSPH_REACH_FULL_SCAN")
    if len(marked) != len(full):
        sys.exit(f"FAIL: {len(marked)} snapshots against {len(full)}")
    for k, (a, b) in enumerate(zip(marked, full)):
        if a.shape != b.shape or np.any(a != b):
            bad = int(np.count_nonzero(a != b)) if a.shape == b.shape else -1
            sys.exit(f"FAIL: snapshot {k}: {bad} particles' reach differs from the full search")
        values = np.unique(b)
        if len(values) < 2:
            sys.exit(f"FAIL: snapshot {k}: every particle has reach {values}: nothing tested")
        print(f"snapshot {k}: {len(a)} particles, reaches {list(values)} as the full search")
    print("check_reach: every particle's reach equals the full search's")


if __name__ == "__main__":
    main()

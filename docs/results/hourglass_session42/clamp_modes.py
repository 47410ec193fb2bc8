#!/usr/bin/env python3
"""How irregular a beam run's displacement is near the clamp (session 42):
the discrete Laplacian of the final displacement over the initial lattice
(the four lattice neighbours' mean minus the particle's own, m), its
largest value within 20 mm of the clamp and its median there and beyond
50 mm. A smooth field gives O(dx^2 u''); an hourglass (zig-zag) mode shows
as a few particles far above the median.

    /usr/bin/python3 docs/results/hourglass_session42/clamp_modes.py RUN...
(run folder names ending in _DX, as run.sh writes them)"""
import glob
import os
import sys

import h5py
import numpy as np

STENCIL = [(1, 0), (-1, 0), (0, 1), (0, -1)]


def laplacians(run):
    dx = float(os.path.basename(run).rsplit("_", 1)[1])
    with h5py.File(sorted(glob.glob(os.path.join(run, "snap_*.h5")))[-1], "r") as f:
        u = np.array(f["displacement"])[:, :2]
        x0 = np.array(f["position"])[:, :2] - u
    ij = np.round((x0 - x0.min(axis=0)) / dx).astype(int)
    grid = {tuple(k): v for k, v in zip(ij, u)}
    out = []
    for (a, b), v in grid.items():
        if all((a + da, b + db) in grid for da, db in STENCIL):
            mean = sum(grid[(a + da, b + db)] for da, db in STENCIL) / 4
            out.append((a * dx, np.abs(mean - v).max()))
    return np.array(out)


def main():
    print("| run | largest, x < 20 mm (m) | median, x < 20 mm | median, x > 50 mm |")
    print("| --- | --- | --- | --- |")
    for run in sys.argv[1:]:
        lap = laplacians(run)
        near, far = lap[lap[:, 0] < 0.02, 1], lap[lap[:, 0] > 0.05, 1]
        print("| %s | %.2e | %.2e | %.2e |" % (os.path.basename(run), near.max(),
                                              np.median(near), np.median(far)))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The rubber rings' pieces and rebound, from run folders of
`sph run cases/rubber_rings_2d.yaml [--set ...] --out RUN`:

    /usr/bin/python3 docs/results/taylor_session39/rings_pieces.py RUN...

Per run: the pieces of each ring (connected components of at least 10
particles, two particles linked when closer than LINK spacings, 1.2 and
1.5) at every fourth snapshot from the sixth, each ring being the particles
that started at x < 0 or x > 0; then at the last snapshot each ring's
centre-of-mass velocity along x, the kinetic energy of those two motions,
the whole kinetic and internal energy and the viscosity's work, over the
initial kinetic energy (history.csv)."""
import csv
import glob
import os
import re
import sys

import h5py
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree



def spacing(run):
    """numerics.dx of the run (m), from the case.resolved.yaml it wrote"""
    with open(os.path.join(run, "case.resolved.yaml")) as f:
        numerics = f.read().split("\nnumerics:", 1)[1]
    return float(re.search(r"^  dx: (\S+)$", numerics, re.M).group(1))


def components(x, link):
    """the connected components of points x linked within `link`: their
    count and each point's label"""
    pairs = cKDTree(x).query_pairs(link, output_type="ndarray")
    n = len(x)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)


def pieces(x, link):
    """the components of at least 10 points"""
    _, label = components(x, link)
    return int(np.sum(np.bincount(label) >= 10))


def positions(path):
    with h5py.File(path, "r") as f:
        return np.array(f["position"])[:, :2]


def report(run):
    dx = spacing(run)
    snaps = sorted(glob.glob(os.path.join(run, "snap_*.h5")))
    left = positions(snaps[0])[:, 0] < 0
    for link in (1.2, 1.5):
        cells = []
        for path in snaps[6::4] + [snaps[-1]]:
            x = positions(path)
            cells.append("%s:%d+%d" % (path[-8:-3], pieces(x[left], link * dx),
                                       pieces(x[~left], link * dx)))
        print("%s  link %.1f dx  pieces (left+right) by snapshot: %s" % (run, link, " ".join(cells)))
    with h5py.File(snaps[-1], "r") as f:
        v = np.array(f["velocity"])[:, :2]
        m = np.array(f["mass"])
    rows = list(csv.DictReader(open(os.path.join(run, "history.csv"))))
    ke0 = float(rows[0]["kinetic_energy_J"])
    vl = np.sum(m[left, None] * v[left], 0) / m[left].sum()
    vr = np.sum(m[~left, None] * v[~left], 0) / m[~left].sum()
    ke_cm = 0.5 * m[left].sum() * vl @ vl + 0.5 * m[~left].sum() * vr @ vr
    print("%s  v_x left %.2f right %.2f m/s; over KE0: rings' own motion %.3f, kinetic %.3f, "
          "internal %.3f, viscosity's work %.2f" % (
              run, vl[0], vr[0], ke_cm / ke0, float(rows[-1]["kinetic_energy_J"]) / ke0,
              float(rows[-1]["internal_energy_J"]) / ke0,
              float(rows[-1]["artificial_viscosity_work_J"]) / ke0))


if __name__ == "__main__":
    for run in sys.argv[1:]:
        report(run)

#!/usr/bin/env python3
"""The face layer's motion in a Taylor run (docs/validation_taylor.md,
"Held face", 3-D copper): for the particles within 3 dx of the wall at
snapshot INDEX (default 12: 60 us in the copper cases), the mean speed and
the rms of each particle's velocity less the mean over its neighbours
within 1.5 dx (the particle-scale scatter).
Usage: noise.py [--index INDEX] RUN..."""
import argparse
import glob

import h5py
import numpy as np
import yaml
from scipy.spatial import cKDTree

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--index", type=int, default=12)
parser.add_argument("runs", nargs="+")
args = parser.parse_args()
for run in args.runs:
    case = yaml.safe_load(open(run + "/case.resolved.yaml"))
    dx, dim = float(case["numerics"]["dx"]), case["dimension"]
    snap = sorted(glob.glob(run + "/snap_*.h5"))[args.index]
    with h5py.File(snap, "r") as h:
        pos, vel = h["position"][...][:, :dim], h["velocity"][...][:, :dim]
    face = np.where(pos[:, dim - 1] < 3 * dx)[0]
    tree = cKDTree(pos)
    scatter = [np.linalg.norm(vel[i] - vel[tree.query_ball_point(pos[i], 1.5 * dx)].mean(axis=0))
               for i in face]
    print(f"{run} {snap[-8:-3]}: {len(face)} face particles, mean |v| "
          f"{np.linalg.norm(vel[face], axis=1).mean():.3g} m/s, scatter rms "
          f"{np.sqrt(np.mean(np.square(scatter))):.3g} m/s")

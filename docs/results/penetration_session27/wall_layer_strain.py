#!/usr/bin/python3
"""How much of its hoop stretch the gel round a sphere stores as strain.

usage: wall_layer_strain.py RUN [SNAPSHOT]

For an elastic gel (a yield stress never reached) whose particles move in
meridional planes about the shot axis (y), the hoop axis does not rotate,
so a particle's hoop deviatoric stress over 2G is the hoop strain its
stress update integrated, and ln(r / r0) the hoop strain it underwent (r
its distance from the axis, r0 at t = 0). The script bins the gel 20-120
degrees from the nose by distance from the sphere's centre (in radii a)
and prints, per band: the mean stretch, the mean integrated hoop strain,
their ratio, von Mises over 3G, and the fraction of each particle's
initial neighbours (within the kernel's support, 2h) that are neighbours
still. 3-D quarter models are mirrored across x = 0 and z = 0 and the
axisymmetric form across the axis for the neighbour counts.
docs/validation_penetration.md, session 27.
"""
import glob
import os
import sys

import h5py
import numpy as np
import yaml
from scipy.spatial import cKDTree

BANDS = [(0.8, 1.1), (1.1, 1.4), (1.4, 1.8), (1.8, 2.4)]
PAIRS = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)]


def sorted_by_id(snap, name):
    return snap[name][:][np.argsort(snap["id"][:])]


def hoop_deviator(stress, x, dim):
    """The hoop component of the deviatoric stress about the y axis."""
    trace = stress[:, 0] + stress[:, 1] + stress[:, 2]
    if dim == 2:
        return stress[:, 2] - trace / 3
    tensor = np.zeros((len(x), 3, 3))
    for k, (i, j) in enumerate(PAIRS):
        tensor[:, i, j] = tensor[:, j, i] = stress[:, k]
    r = np.hypot(x[:, 0], x[:, 2])
    hoop = np.stack([-x[:, 2], np.zeros(len(x)), x[:, 0]], 1) / r[:, None]
    return np.einsum("ni,nij,nj->n", hoop, tensor, hoop) - trace / 3


def mirrored(x, dim):
    if dim == 2:
        return np.concatenate([x, x * [-1, 1, 1]])
    return np.concatenate([x, x * [-1, 1, 1], x * [1, 1, -1], x * [-1, 1, -1]])


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    run = sys.argv[1]
    snaps = sorted(glob.glob(os.path.join(run, "snap_*.h5")))
    pick = snaps[int(sys.argv[2])] if len(sys.argv) == 3 else snaps[-1]
    with open(os.path.join(run, "case.resolved.yaml")) as f:
        case = yaml.safe_load(f)
    material = case["materials"][0]
    shear_modulus = material["youngs_modulus"] / (2 * (1 + material["poisson_ratio"]))
    radius = case["projectile"]["diameter"] / 2
    support = 2 * case["numerics"]["h_over_dx"] * case["numerics"]["dx"]
    with h5py.File(snaps[0]) as first, h5py.File(pick) as snap:
        dim = int(snap.attrs["dimension"][0])
        centre = snap.attrs["projectile_centre_m"]
        x0, x = sorted_by_id(first, "position"), sorted_by_id(snap, "position")
        stress, von_mises = sorted_by_id(snap, "stress"), sorted_by_id(snap, "von_mises_stress")
        time = float(snap.attrs["time_s"][0])
    axis_distance = (lambda y: y[:, 0]) if dim == 2 else (lambda y: np.hypot(y[:, 0], y[:, 2]))
    r, r0 = axis_distance(x), axis_distance(x0)
    along = x[:, 1] - centre[1]
    distance = np.hypot(r, along) / radius
    polar = np.degrees(np.arctan2(r, -along))
    strain = hoop_deviator(stress, x, dim) / (2 * shear_modulus)
    count = len(x)
    before, now = cKDTree(mirrored(x0, dim)), cKDTree(mirrored(x, dim))
    print(f"{pick}: t = {time:.4g} s, a = {radius:.4g} m, G = {shear_modulus:.4g} Pa")
    print("band (a)  particles  stretch  integrated  ratio  von_mises/3G  neighbours_kept")
    for low, high in BANDS:
        band = np.where((distance >= low) & (distance < high) & (polar >= 20) & (polar < 120) &
                        (r0 > 0))[0]
        if len(band) == 0:
            continue
        stretch = np.log(r[band] / r0[band])
        kept = []
        for i in band:
            old = {j % count for j in before.query_ball_point(x0[i], support)} - {i}
            new = {j % count for j in now.query_ball_point(x[i], support)} - {i}
            kept.append(len(old & new) / max(len(old), 1))
        print(f"{low:.1f}-{high:.1f}  {len(band):9d}  {stretch.mean():7.3f}  "
              f"{strain[band].mean():10.3f}  {strain[band].mean() / stretch.mean():5.2f}  "
              f"{von_mises[band].mean() / (3 * shear_modulus):12.2f}  {np.mean(kept):15.2f}")


if __name__ == "__main__":
    main()

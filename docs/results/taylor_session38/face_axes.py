#!/usr/bin/env python3
"""The copper face layer's kernel ellipsoids in a numerics.smoothing: tensor
run (session 38): for the particles that started in the lowest layer, the
semi-axes over h0 (1 / sqrt of the eigenvalues of the snapshot's
smoothing_metric, G = h0^2 M), the share at the bounds 1/2.5 and 2.5
(include/sph_shared.h SPH_TENSOR_AXIS_MAX), and the direction of the
shortest axis against the z axis (the face's normal).

Usage: face_axes.py RUN SNAPSHOT_INDEX [SNAPSHOT_INDEX ...]
"""
import sys

import h5py
import numpy as np

AXIS_MAX = 2.5


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    run = sys.argv[1]
    for k in map(int, sys.argv[2:]):
        with h5py.File(f"{run}/snap_{k:05d}.h5", "r") as f:
            z0 = (f["position"][:] - f["displacement"][:])[:, 2]
            g = f["smoothing_metric"][:]
            t = float(f.attrs["time_s"][0])
        face = np.abs(z0 - z0.min()) < 1e-9
        axes, tilt = [], []
        for xx, yy, zz, xy, yz, xz in g[face]:
            values, vectors = np.linalg.eigh(np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))
            axes.append(1 / np.sqrt(values[::-1]))  # shortest first
            tilt.append(np.degrees(np.arccos(abs(vectors[2, -1]))))
        axes = np.array(axes)
        at_max = np.mean(axes[:, 2] > AXIS_MAX * 0.999)
        at_min = np.mean(axes[:, 0] < 1 / AXIS_MAX * 1.001)
        print(f"t = {t * 1e6:5.1f} us: {face.sum()} face particles; semi-axes / h0 median "
              f"{np.median(axes[:, 0]):.3f} / {np.median(axes[:, 1]):.3f} / "
              f"{np.median(axes[:, 2]):.3f}; at the upper bound {at_max:.0%}, at the lower "
              f"{at_min:.0%}; shortest axis {np.median(tilt):.1f} deg from z (median)")


if __name__ == "__main__":
    main()

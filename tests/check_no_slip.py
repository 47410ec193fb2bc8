#!/usr/bin/python3
"""The no-slip contact (projectile.contact: no_slip, kernels/projectile.cl)
on a run folder: in every snapshot after the first, the particles in the contact layer
(centres closer than R - dx_i/2 to the sphere's) move tangentially with the
sphere.

usage: check_no_slip.py RUN --max-slip F [--min-slip F]

Prints the layer's mean and largest tangential speed relative to the
sphere (the snapshot's projectile_velocity_m_per_s) over its initial
speed, and exits 1 if the mean is above
--max-slip or below --min-slip (a free-slip run gives the second bound a
meaning: the same check fails on it). The snapshot's velocities are at the
full step and the stick acts on the half step's, so a stuck particle may
show the half kick of its other tangential forces (measured 0.0000 on the
ctest's run). Only the layer is checked: the face just outside it is free
to slide, and in an open cavity does (docs/validation_penetration.md,
session 29).
"""
import argparse
import glob
import os
import sys

import h5py
import numpy as np
import yaml

CONTACT_INSET = 0.5  # spacings inside the sphere the layer rides at (kernels/projectile.cl)
LEVEL_SHIFT, LEVEL_MASK = 8, 15  # include/sph_shared.h: SPH_LEVEL_OF


def layer_slip(path, dim, radius, dx):
    """The contact layer's tangential speeds relative to the sphere in one
    snapshot (its centre and velocity are the snapshot's attributes)."""
    with h5py.File(path) as s:
        x = s["position"][:][:, :dim]
        v = s["velocity"][:][:, :dim]
        level = (s["flags"][:] >> LEVEL_SHIFT) & LEVEL_MASK
        centre = s.attrs["projectile_centre_m"][:dim]
        velocity = s.attrs["projectile_velocity_m_per_s"][:dim]
    d = x - centre
    distance = np.linalg.norm(d, axis=1)
    layer = distance < radius - CONTACT_INSET * dx * 2.0 ** level
    normal = d[layer] / distance[layer, None]
    relative = v[layer] - velocity
    tangential = relative - np.sum(relative * normal, axis=1)[:, None] * normal
    return np.linalg.norm(tangential, axis=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run")
    ap.add_argument("--max-slip", type=float, required=True)
    ap.add_argument("--min-slip", type=float, default=0.0)
    args = ap.parse_args()
    with open(os.path.join(args.run, "case.resolved.yaml")) as f:
        case = yaml.safe_load(f)
    dim = case["dimension"]
    radius = 0.5 * case["projectile"]["diameter"]
    speed = float(np.linalg.norm(case["projectile"]["velocity"]))  # the scale: the impact speed
    snaps = sorted(glob.glob(os.path.join(args.run, "snap_*.h5")))[1:]
    slips = [layer_slip(p, dim, radius, case["numerics"]["dx"]) for p in snaps]
    slip = np.concatenate(slips) / speed if slips else np.zeros(0)
    if slip.size == 0:
        sys.exit(f"check_no_slip: no particle in the contact layer in {args.run}'s snapshots "
                 "after the first")
    print(f"{args.run}: {slip.size} contact-layer particles over {len(snaps)} snapshots; "
          f"tangential speed relative to the sphere over its initial speed: mean "
          f"{slip.mean():.4f}, largest {slip.max():.4f}")
    if not args.min_slip <= slip.mean() <= args.max_slip:
        sys.exit(f"check_no_slip: mean slip {slip.mean():.4f} outside [{args.min_slip}, "
                 f"{args.max_slip}]")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Final shape and face-centre state of axisymmetric Taylor runs
(docs/validation_taylor.md, "Held face").

For each run folder (`sph run cases/taylor_axi_42crmo4.yaml --set
numerics.dx=DX ...`), from its last snapshot:
- length: the bar's extent along z plus dx (host/impact.c's measure, taken
  again here because the runs with the wall replaced by a symmetry plane
  have no wall and so no impact summary);
- face: twice the largest radius in the lowest layer (within dx/2 of the
  lowest particle) plus dx, the footprint diameter host/impact.c reports;
- r_max: the largest radius anywhere (the mushroom's widest point: the
  copper benchmark's "mushroom radius");
- first-layer face: twice the largest radius, plus dx, of the particles
  that started in the impact face's layer (z0 < dx): the material face,
  a mesh code's corner node followed to the end;
- the reference's "centre element": DynELA and Abaqus report the plastic
  strain and temperature of the element at the centre of the impact face
  on a 5 x 50 mesh of the 3.2 x 32.4 mm section, i.e. the material that
  started at r0 < 0.64 mm, z0 < 0.648 mm. The SPH figure is the
  mass-weighted mean over the particles that started there (initial
  position = position - displacement), with their largest value.

Usage: face_measures.py RUN... (dx is read from case.resolved.yaml).
Prints one markdown row per run."""
import glob
import os
import sys

import h5py
import numpy as np
import yaml

ELEMENT_R0, ELEMENT_Z0 = 0.64e-3, 0.648e-3  # m: 3.2 / 5 and 32.4 / 50


def measure(run):
    with open(os.path.join(run, "case.resolved.yaml")) as f:
        dx = float(yaml.safe_load(f)["numerics"]["dx"])
    snap = sorted(glob.glob(os.path.join(run, "snap_*.h5")))[-1]
    with h5py.File(snap, "r") as h:
        pos = h["position"][...]
        start = pos - h["displacement"][...]
        strain, temperature, mass = (h[k][...] for k in ("plastic_strain", "temperature", "mass"))
    r, z = pos[:, 0], pos[:, 1]
    lowest = z < z.min() + 0.5 * dx
    first_layer = start[:, 1] < dx
    element = (start[:, 0] < ELEMENT_R0) & (start[:, 1] < ELEMENT_Z0)
    w = mass[element] / mass[element].sum()
    return {
        "run": os.path.basename(os.path.normpath(run)),
        "dx_mm": 1e3 * dx,
        "length_mm": 1e3 * (z.max() - z.min() + dx),
        "face_mm": 2e3 * (r[lowest].max() + 0.5 * dx),
        "r_max_mm": 1e3 * r.max(),
        "first_layer_face_mm": 2e3 * (r[first_layer].max() + 0.5 * dx),
        "centre_strain": float((w * strain[element]).sum()),
        "centre_strain_max": float(strain[element].max()),
        "centre_temperature_K": float((w * temperature[element]).sum()),
        "max_strain": float(strain.max()),
    }


def main():
    keys = ["run", "dx_mm", "length_mm", "face_mm", "first_layer_face_mm", "r_max_mm",
            "centre_strain",
            "centre_strain_max", "centre_temperature_K", "max_strain"]
    print("| " + " | ".join(keys) + " |")
    print("|" + " --- |" * len(keys))
    for run in sys.argv[1:]:
        m = measure(run)
        print("| " + " | ".join(m[k] if k == "run" else f"{m[k]:.3f}" if k != "centre_temperature_K"
                                else f"{m[k]:.0f}" for k in keys) + " |")


if __name__ == "__main__":
    main()

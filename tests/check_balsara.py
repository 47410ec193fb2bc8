#!/usr/bin/python3
"""Balsara's factor on the switch's floor (numerics.artificial_viscosity.
balsara, kernels/material.cl switch_floor), on homogeneous flows of an
elastic block (plane strain, 40 x 40 spacings, started with a linear
velocity field): the interior particles' alpha after 1 ms.

usage: check_balsara.py SPH WORK

- simple shear (div v = 0, |curl v| = the shear rate): the plain switch
  holds alpha at its floor alpha_min = 0.1 (interior mean within 1%);
  with balsara the floor is alpha_min |div v| / (|div v| + |curl v| +
  1e-4 c/h), zero here, and the interior mean must stay under a fifth of
  the plain one (measured 0.0119 against 0.1002: the lattice's own
  compressions lift some particles);
- compression (started uniform, curl v = 0; the free faces' release
  reaches the interior by about 0.35 ms): the factor starts at 200 /
  (200 + 2.4) = 0.988, and the interior mean alpha, raised above the
  floor by the compression (Morris & Monaghan's source -div v), must be
  within 6% of the plain switch's (measured 0.0971 against 0.1011).
Exits 1 naming the flow and the number otherwise.
"""
import os
import subprocess
import sys

import h5py
import numpy as np

CASE = """name: {name}
dimension: 2
plane: strain
materials:
  - {{name: block, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.3}}
bodies:
  - {{name: block, material: block, min: [0, 0], max: [0.04, 0.04], velocity: [0, 0],
     velocity_gradient: {gradient}}}
numerics:
  dx: 1.0e-3
  artificial_viscosity: {{balsara: {balsara}}}
  end_time: 1.0e-3
output: {{snapshot_interval: 1.0e-3, history_interval: 1.0e-3}}
"""
# rates of 100 /s: far above the factor's 1e-4 c/h (about 2.4 /s here), so
# that the curl (shear) or the divergence (compression) decides it
FLOWS = {"shear": [0, 100, 0, 0, 0, 0, 0, 0, 0],
         "compression": [-100, 0, 0, 0, -100, 0, 0, 0, 0]}


def interior_alpha(sph, work, flow, balsara):
    name = f"{flow}_{'balsara' if balsara else 'plain'}"
    folder = os.path.join(work, name)
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "case.yaml")
    with open(path, "w") as f:
        f.write(CASE.format(name=name, gradient=FLOWS[flow], balsara=str(balsara).lower()))
    out = os.path.join(folder, "run")
    proc = subprocess.run([sph, "run", path, "--out", out, "--quiet"], capture_output=True,
                          text=True)
    if proc.returncode != 0:
        sys.exit(f"{name}: sph exited {proc.returncode}: {proc.stderr.strip()}")
    with h5py.File(os.path.join(out, "snap_00001.h5")) as snap:
        x0 = snap["position"][:, :2] - snap["displacement"][:, :2]
        alpha = snap["artificial_viscosity_alpha"][:]
    inner = np.all((x0 > 0.01) & (x0 < 0.03), axis=1)
    print(f"{name}: interior alpha {alpha[inner].min():.6g} to {alpha[inner].max():.6g}, "
          f"mean {alpha[inner].mean():.6g}")
    return float(alpha[inner].mean())


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sph, work = sys.argv[1], sys.argv[2]
    failures = []
    plain, balsara = (interior_alpha(sph, work, "shear", b) for b in (False, True))
    if abs(plain - 0.1) > 1e-3:
        failures.append(f"shear, plain switch: mean alpha {plain:.6g}, expected the floor 0.1")
    if balsara > 0.2 * plain:
        failures.append(f"shear: mean alpha {balsara:.6g} with balsara, {plain:.6g} without; "
                        "expected under a fifth of it")
    plain, balsara = (interior_alpha(sph, work, "compression", b) for b in (False, True))
    if plain <= 0.1 or abs(balsara - plain) > 0.06 * plain:
        failures.append(f"compression: mean alpha {balsara:.6g} with balsara, {plain:.6g} "
                        "without; expected within 6%, above the floor 0.1")
    for failure in failures:
        print("FAIL:", failure)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

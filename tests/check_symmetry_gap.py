#!/usr/bin/python3
"""A particle driven onto a symmetry plane stays a quarter of its spacing
off it (kernels/integrate.cl, integrate_drift): a column of soft material
(plane strain, E = 1 MPa, one spacing wide: 3 particles, half a spacing
from the plane x = 0) thrown at the plane at 200 m/s, so fast against its
sound speed that it moves about 0.3 spacing a step (3 steps): a check of
the drift's bound, not of the collapse it prevents (the 3-D SEBS quarter
of docs/validation_penetration.md, session 33, too costly for a test).
Without the gap it reached x = 0.0057 dx (build bfd9dcd fails this test).
With it every snapshot has x >= dx / 4 (measured 0.268 dx); XSPH is off,
so the bound is exact up to the float position's rounding.

usage: check_symmetry_gap.py SPH WORK
Exits 1 naming the smallest x otherwise.
"""
import glob
import os
import subprocess
import sys

import h5py

DX = 1.0e-3
CASE = """name: symmetry_gap
dimension: 2
plane: strain
materials:
  - {name: soft, density: 1000, youngs_modulus: 1.0e6, poisson_ratio: 0.45}
bodies:
  - {name: column, material: soft, min: [0, 0], max: [1.0e-3, 3.0e-3], velocity: [-200, 0]}
symmetry:
  - {axis: x, position: 0}
numerics:
  dx: 1.0e-3
  xsph: 0
  end_time: 5.0e-6
output:
  snapshot_interval: 1.0e-7
"""


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sph, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    case = os.path.join(work, "symmetry_gap.yaml")
    with open(case, "w") as f:
        f.write(CASE)
    out = os.path.join(work, "run")
    proc = subprocess.run([sph, "run", case, "--out", out, "--quiet"], capture_output=True,
                          text=True)
    if proc.returncode != 0:
        sys.exit(f"sph run exited {proc.returncode}: {proc.stderr}")
    snaps = sorted(glob.glob(os.path.join(out, "snap_*.h5")))
    if len(snaps) < 3:
        sys.exit(f"{len(snaps)} snapshots, expected several")
    smallest = min(float(h5py.File(s)["position"][:, 0].min()) for s in snaps)
    print(f"smallest x over {len(snaps)} snapshots: {smallest / DX:.4f} dx")
    if smallest < 0.25 * DX * (1 - 1e-5):
        print(f"a particle came within {smallest / DX:.4f} dx of the plane (bound 0.25 dx)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

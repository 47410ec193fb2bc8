#!/usr/bin/python3
"""The total Lagrangian form keeps angular momentum on a spinning body
(cases/rubber_rings_2d.yaml, the right ring 2 cm higher).

usage: check_angular_momentum.py SPH WORKDIR

The rings meet off centre and turn. Every pair force of the form is equal
and opposite. The hourglass spring pulls on the whole mismatch p_ij - x_ij
(kernels/total_lagrangian.cl tl_hourglass, since session 44), not along
the pair, so it exerts a couple of the order of the mismatch where the
motion is not linear. The angular momentum about the origin, sum m (x v_y
- y v_x) over each snapshot, must stay within 1e-3 of its initial value
through contact, rebound and separation. Measured at dx = 2 mm: 1.8e-4
(8.7e-5 at 1 mm; 1.3e-3 at 2 mm with the coefficient 1; 1.7e-6 with
session 43's central spring, so the rest of the form keeps it to about
that), so the bound is five times the default's change and fails for a
spring ten times stiffer.
"""
import glob
import os
import subprocess
import sys

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BOUND = 1e-3


def angular_momentum(snapshot):
    """(time, L_z about the origin) of one snapshot, per metre of depth."""
    with h5py.File(snapshot, "r") as f:
        x = np.array(f["position"], dtype=float)[:, :2]
        v = np.array(f["velocity"], dtype=float)[:, :2]
        m = np.array(f["mass"], dtype=float)
        return float(f.attrs["time_s"][0]), float(np.sum(m * (x[:, 0] * v[:, 1] - x[:, 1] * v[:, 0])))


def main():
    sph, workdir = sys.argv[1], sys.argv[2]
    out = os.path.join(workdir, "rings_off_centre")
    subprocess.run([sph, "run", os.path.join(ROOT, "cases", "rubber_rings_2d.yaml"), "--quiet",
                    "--out", out, "--set", "numerics.dx=2e-3",
                    "--set", "bodies.right.min=[0.01,-0.02]",
                    "--set", "bodies.right.max=[0.09,0.06]"], check=True)
    series = [angular_momentum(s) for s in sorted(glob.glob(os.path.join(out, "snap_*.h5")))]
    initial = series[0][1]
    worst_time, worst = max(((t, abs(l - initial) / abs(initial)) for t, l in series),
                            key=lambda tl: tl[1])
    print("angular momentum %.6g kg m^2/s per m at t = 0; largest relative change %.3g at %.4g s "
          "over %d snapshots" % (initial, worst, worst_time, len(series)))
    if len(series) < 20 or abs(initial) < 1.0:
        print("FAIL: %d snapshots, initial angular momentum %.3g: not the spinning rings"
              % (len(series), initial))
        return 1
    if worst > BOUND:
        print("FAIL: angular momentum changed by %.3g of its initial value, expected within %g"
              % (worst, BOUND))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

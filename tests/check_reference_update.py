#!/usr/bin/env python3
"""numerics.reference_update (kernels/total_lagrangian.cl, tl_reference_reset):
after an update the form's reference is the configuration of then and its
displacement is measured from it; the snapshots must still report the
displacement from the initial position (host/fields.c adds the reference's
offset back), so position - displacement is every particle's initial
position in every snapshot, before and after the updates.

usage: check_reference_update.py SPH WORK_DIR

The 3-D 42CrMo4 quarter at 0.6 mm to 6 us with the update at |E| = 0.3
takes three updates (0.95, 2.74, 4.91 us); without the offset the
difference is the displacement at the last update, up to 0.6 mm.
"""
import json
import os
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.join(HERE, "..", "cases", "taylor_3d_42crmo4.yaml")
TOLERANCE_M = 1e-7  # float rounding of cm coordinates summed over the updates


def fail(message):
    print("FAIL:", message)
    sys.exit(1)


def main():
    if len(sys.argv) != 3:
        fail(__doc__)
    sph, work = sys.argv[1], sys.argv[2]
    args = [sph, "run", CASE, "--out", work, "--quiet", "--set", "numerics.dx=0.6e-3",
            "--set", "numerics.end_time=6e-6", "--set", "numerics.reference_update=0.3",
            "--set", "output.snapshot_interval=1.5e-6"]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        fail(f"exit {p.returncode}\n{p.stderr[-2000:]}")
    with open(os.path.join(work, "summary.json")) as f:
        summary = json.load(f)
    updates = summary.get("reference_updates", 0)
    if updates < 2:
        fail(f"expected at least two reference updates, summary.json says {updates}")
    snaps = sorted(n for n in os.listdir(work) if n.startswith("snap_") and n.endswith(".h5"))
    with h5py.File(os.path.join(work, snaps[0])) as h:
        initial = h["position"][:]
    worst = 0.0
    for name in snaps:
        with h5py.File(os.path.join(work, name)) as h:
            start = h["position"][:] - h["displacement"][:]
        worst = max(worst, float(np.abs(start - initial).max()))
        if worst > TOLERANCE_M:
            fail(f"{name}: position - displacement is {worst:.3g} m from the initial position")
    print(f"{updates} reference updates; position - displacement is the initial position to "
          f"{worst:.2g} m in {len(snaps)} snapshots")


if __name__ == "__main__":
    main()

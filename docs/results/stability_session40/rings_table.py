#!/usr/bin/env python3
"""The table of run_rings.sh's runs (docs/stability.md, "The rubber rings as
two parts"):

    /usr/bin/python3 docs/results/stability_session40/rings_table.py OUT > rings_parts.md

Per run: the pieces of each ring at 1.5 ms (linked within 1.5 spacings, as
docs/results/taylor_session39/rings_pieces.py counts them), the first
snapshot at which either ring is in more than one piece, the speed at which
the rings' centres of mass move apart at 1.5 ms (each ring's, out of the
50.27 m/s each came in with), the energy balance and the viscosity's work
over the initial kinetic energy (summary.json)."""
import glob
import json
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                "taylor_session39"))
from rings_pieces import pieces, positions, spacing  # noqa: E402

LINK = 1.5  # spacings


def row(run):
    dx = spacing(run)
    snaps = sorted(glob.glob(os.path.join(run, "snap_*.h5")))
    left = positions(snaps[0])[:, 0] < 0
    first_torn, counts = None, None
    for path in snaps:
        x = positions(path)
        counts = (pieces(x[left], LINK * dx), pieces(x[~left], LINK * dx))
        if first_torn is None and max(counts) > 1:
            with h5py.File(path, "r") as f:
                first_torn = float(f.attrs["time_s"][0])
    with h5py.File(snaps[-1], "r") as f:
        v, m = np.array(f["velocity"])[:, 0], np.array(f["mass"])
    apart = (np.sum(m[~left] * v[~left]) / m[~left].sum() -
             np.sum(m[left] * v[left]) / m[left].sum()) / 2
    with open(os.path.join(run, "summary.json")) as f:
        summary = json.load(f)
    return "| %s | %g | %d + %d | %s | %.1f | %.2f%% | %.2f |" % (
        os.path.basename(run).rsplit("_", 1)[0], dx * 1e3, counts[0], counts[1],
        "whole" if first_torn is None else "%.2f" % (first_torn * 1e3), apart,
        100 * summary["energy_drift"], summary["artificial_viscosity_work_fraction"])


def main():
    print("| numerics | dx (mm) | pieces at 1.5 ms | first torn (ms) | moving apart (m/s) |"
          " energy balance | viscosity's work / KE0 |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    runs = sorted(glob.glob(os.path.join(sys.argv[1], "*")),
                  key=lambda r: (os.path.basename(r)[0], -spacing(r), r))
    for run in runs:
        if os.path.exists(os.path.join(run, "summary.json")):
            print(row(run))


if __name__ == "__main__":
    main()

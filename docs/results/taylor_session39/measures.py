#!/usr/bin/env python3
"""The session-39 figures that are not in a run's summary.json, read from
run folders (`sph run CASE --set ... --out RUN`; the folders are not kept
here, the commands are in docs/validation_taylor.md, "The copper rods and
the iron bar in the one numerics block"):

  measures.py profile RUN...   axisymmetric rod at its last snapshot: the
                               outer surface (largest r) in height bands
                               above the wall, in mm
  measures.py closest RUN...   where the closest pair sits at the last
                               snapshot (r, z in mm; distance over dx)
  measures.py energy RUN...    history.csv's energy error at a dozen times
  measures.py order            the observed order and Richardson limit of
                               the copper face and length over the last
                               three spacings (summaries/, studylib's
                               richardson)

    /usr/bin/python3 docs/results/taylor_session39/measures.py profile RUN..."""
import csv
import glob
import json
import os
import sys

import h5py
import numpy as np
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "..", "tools"))
import studylib  # noqa: E402

BANDS_MM = (0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.8, 1.2)


def last_snapshot(run):
    with h5py.File(sorted(glob.glob(os.path.join(run, "snap_*.h5")))[-1], "r") as f:
        return np.array(f["position"])[:, :2] * 1e3


def spacing_mm(run):
    with open(os.path.join(run, "case.resolved.yaml")) as f:
        for line in f:
            if line.strip().startswith("dx:"):
                return float(line.split(":")[1]) * 1e3
    raise SystemExit("measures: no dx in %s/case.resolved.yaml" % run)


def profile(runs):
    for run in runs:
        x, width = last_snapshot(run), max(spacing_mm(run), 0.05)
        cells = []
        for z0 in BANDS_MM:
            band = (x[:, 1] >= z0) & (x[:, 1] < z0 + width)
            cells.append("z %.2f: %.3f" % (z0, x[band, 0].max()))
        print("%s  lowest z %.4f mm; largest r by band: %s" % (run, x[:, 1].min(), ", ".join(cells)))


def closest(runs):
    for run in runs:
        x, dx = last_snapshot(run), spacing_mm(run)
        d, _ = cKDTree(x).query(x, k=2)
        i = int(np.argmin(d[:, 1]))
        print("%s  closest pair %.2g dx at r %.3f z %.4f mm" % (run, d[i, 1] / dx, x[i, 0], x[i, 1]))


def energy(runs):
    for run in runs:
        rows = list(csv.DictReader(open(os.path.join(run, "history.csv"))))
        step = max(1, len(rows) // 12)
        print(run + "  " + ", ".join("%.1f us: %.2e" % (1e6 * float(r["time_s"]), float(r["energy_error"]))
                                     for r in rows[::step]))


def order():
    for h in ("1.5", "1.2"):
        runs = []
        for dx in ("0.1e-3", "0.05e-3", "0.025e-3"):
            with open(os.path.join(HERE, "summaries", "axi_%s_h%s.json" % (dx, h))) as f:
                runs.append(json.load(f))
        for key in ("footprint_radius_m", "final_length_m"):
            values = [1e3 * s[key] for s in runs]
            found = studylib.richardson([0.1, 0.05, 0.025], values)
            print("h = %s dx, %s over 0.1 / 0.05 / 0.025 mm: %s -> %s" % (
                h, key, " / ".join("%.3f" % v for v in values),
                "limit %.3f mm, order %.2f" % found if found else "no order (steps change sign)"))


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] not in ("profile", "closest", "energy", "order"):
        raise SystemExit(__doc__)
    if sys.argv[1] == "order":
        order()
    else:
        {"profile": profile, "closest": closest, "energy": energy}[sys.argv[1]](sys.argv[2:])

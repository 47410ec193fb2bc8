#!/usr/bin/env python3
"""history.csv of run_set.sh's runs, old build against new, column by
column: which differ and by how much (docs/performance.md, "The health
indicators through the lanes"). Usage: compare.py OLD_DIR NEW_DIR"""
import sys

import numpy as np

old, new = sys.argv[1], sys.argv[2]
for c in ["gel3d", "gelaxi", "t4340", "beam", "beamtl", "sebsobl", "rings", "cu3d"]:
    a = np.genfromtxt(f"{old}/{c}/history.csv", delimiter=",", names=True)
    b = np.genfromtxt(f"{new}/{c}/history.csv", delimiter=",", names=True)
    out = []
    for n in a.dtype.names:
        d = np.abs(a[n] - b[n])
        if d.max() > 0:
            rel = np.max(d / np.maximum(np.abs(a[n]), 1e-300))
            out.append(f"{n}: max|diff| {d.max():.3g} (rel {rel:.2g}) in {int((d > 0).sum())} of {len(d)} rows")
    print(c, "identical" if not out else "; ".join(out))

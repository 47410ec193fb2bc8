#!/usr/bin/python3
"""Re-plots taylor_4340_convergence.csv (session 25): the 4340 bar's final
length against wall time, the one numerics block beside the thesis'
numerics, with the peers' band (LS-DYNA 34.5 mm, MSPH 34.7 mm).
  /usr/bin/python3 docs/results/numerics_block_s25/plot.py"""
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
with open(os.path.join(HERE, "taylor_4340_convergence.csv")) as f:
    rows = list(csv.DictReader(f))
fig, ax = plt.subplots(figsize=(7, 4.5))
ax.axhspan(34.5, 34.7, color="0.9", label="LS-DYNA 34.5 to MSPH 34.7 mm")
for variant, colour in (("block", "C0"), ("thesis", "C3")):
    for geometry, marker in (("axi", "o"), ("3d", "s")):
        pts = sorted((float(r["wall_time_s"]), 1e3 * float(r["final_length_m"]),
                      1e3 * float(r["dx_m"]), r["healthy"] == "True")
                     for r in rows if r["variant"] == variant and r["geometry"] == geometry)
        if not pts:
            continue
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=marker, color=colour,
                mfc="white" if geometry == "3d" else colour,
                label=f"{variant}, {'axisymmetric' if geometry == 'axi' else '3-D quarter'}")
        for t, length, dx, healthy in pts:
            ax.annotate(f"{dx:g}" + ("" if healthy else " (clumped)"), (t, length),
                        textcoords="offset points", xytext=(4, 4), fontsize=7)
ax.set_xscale("log")
ax.set_xlabel("wall time on two cores (s)")
ax.set_ylabel("final length (mm)")
ax.set_title("4340 Taylor bar, block vs thesis numerics (labels: dx in mm)")
ax.grid(alpha=0.3, which="both")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(HERE, "taylor_4340_block_vs_thesis.png"), dpi=120)

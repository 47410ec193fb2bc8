#!/usr/bin/env python3
"""Redraws faces.png (docs/validation_taylor.md, "Held face") from
axisymmetric_runs.md beside it: the face diameter against the spacing, the
penalty wall's (lowest layer and first layer) and the held wall's, with the
references. Usage: plot_faces.py"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

here = os.path.dirname(os.path.abspath(__file__))
rows = {}
for line in open(os.path.join(here, "axisymmetric_runs.md")):
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    if len(cells) == 10 and cells[0] not in ("run", "---"):
        rows[cells[0]] = [float(c) for c in cells[1:]]


def series(prefix, column):
    runs = sorted((v for k, v in rows.items() if k.startswith(prefix + "_")), key=lambda v: -v[0])
    return [v[0] for v in runs], [v[column] for v in runs]


fig, axes = plt.subplots(1, 2, figsize=(10, 4))
for ax, (name, held, penalty, refs) in zip(axes, [
        ("copper, 227 m/s", "tcusym", "tcu", [(14.44, "Foulk et al. 2021 (converged)"),
                                             (14.24, "Simo 1992"), (14.22, "Zienkiewicz 1998")]),
        ("42CrMo4, 287 m/s", "t42sym", "t42", [(11.155, "DynELA / Abaqus (5 x 50 mesh)")])]):
    x, y = series(held, 2)
    if held == "tcusym":  # the 0.4 mm held run is tcuhold
        x, y = [0.4] + x, [rows["tcuhold_0.4e-3"][2]] + y
    ax.plot(x, y, "o-", label="held face")
    x, y = series(penalty, 2)
    ax.plot(x, y, "s--", label="penalty wall: lowest layer")
    x, y = series(penalty, 3)
    ax.plot(x, y, "^:", label="penalty wall: first layer's material")
    for value, label in refs:
        ax.axhline(value, color="grey", lw=0.8)
    for k, (value, label) in enumerate(refs):
        ax.text(0.39 if k < 2 else 0.25, value, label, fontsize=7, ha="left", color="grey",
                va="top" if k == 2 else "bottom")
    ax.set_xscale("log")
    ax.set_xticks([0.4, 0.2, 0.1, 0.05])
    ax.set_xticklabels(["0.4", "0.2", "0.1", "0.05"])
    ax.minorticks_off()
    ax.set_xlim(0.42, 0.045)
    ax.set_xlabel("particle spacing dx (mm)")
    ax.set_ylabel("final impact-face diameter (mm)")
    ax.set_title(name)
    ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(here, "faces.png"), dpi=110)
print(os.path.join(here, "faces.png"))

#!/usr/bin/env python3
"""Prints the table of docs/performance.md, "Two experiments, not kept
(session 36)": each bench JSON's step, passes and lists' build (ms per
step). Usage: report.py [FOLDER ...] (default: both experiments here)."""
import glob
import json
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
folders = sys.argv[1:] or [os.path.join(here, d) for d in ("j_side_csph", "grid_split2")]
names = ("pass1_velocity_gradient", "pass2_momentum_energy", "lane_list_build")
print("| run | step | pass 1 | pass 2 | build | M particle-steps/s | steal |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for folder in folders:
    for path in sorted(glob.glob(os.path.join(folder, "*.json"))):
        scene = json.load(open(path))["scenes"][0]
        ms = {k["kernel"]: 1e3 * k["s_per_step"] for k in scene["kernels"]}
        row = [os.path.relpath(path, here), "%.1f" % (1e3 * scene["median_seconds_per_step"])]
        row += ["%.1f" % ms.get(n, 0.0) for n in names]
        row += ["%.3f" % (scene["particle_steps_per_s"] / 1e6),
                "%.1f%%" % (100 * scene["cpu_steal_fraction"])]
        print("| " + " | ".join(row) + " |")

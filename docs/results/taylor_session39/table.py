#!/usr/bin/env python3
"""Prints the session-39 runs' table (summaries/*.json, each a run's
summary.json) as markdown: the copper rods at h = 1.5 dx and 1.2 dx, the
iron bar and the rubber rings shipped and with the one numerics block.

    /usr/bin/python3 docs/results/taylor_session39/table.py"""
import glob
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    print("| run | particles | steps | length (mm) | face radius (mm) | energy | clumped max |"
          " closest pair (dx) | AV work / KE0 | wall (s) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for path in sorted(glob.glob(os.path.join(HERE, "summaries", "*.json"))):
        with open(path) as f:
            s = json.load(f)
        length = s.get("final_length_m")
        radius = s.get("footprint_radius_m")
        print("| %s | %d | %d | %s | %s | %.2f%% | %.1f%% | %.2g | %.2f | %.0f |" % (
            os.path.basename(path)[:-5], s["particles"], s["steps"],
            "%.3f" % (1e3 * length) if length else "-",
            "%.3f" % (1e3 * radius) if radius else "-",
            100 * s["energy_drift"], 100 * s["max_clumped_fraction"],
            s["min_pair_distance_over_dx"], s["artificial_viscosity_work_fraction"],
            s["wall_time_s"]))


if __name__ == "__main__":
    main()

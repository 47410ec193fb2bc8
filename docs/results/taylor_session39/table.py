#!/usr/bin/env python3
"""Prints the session-39 runs' table (summaries/*.json, each a run's
summary.json) as markdown: the copper rods at h = 1.5 dx and 1.2 dx, the
iron bar and the rubber rings shipped and with the one numerics block.
The columns are tools/taylor_study.py's (`row`), then the two health
figures this session compared: the largest clumped fraction and the
closest pair.

    /usr/bin/python3 docs/results/taylor_session39/table.py"""
import glob
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "..", "tools"))
from taylor_study import HEADER, row  # noqa: E402


def main():
    header = list(HEADER) + ["clumped max (%)", "closest pair (dx)"]
    header[1] = "run"
    print("| " + " | ".join(header) + " |")
    print("|" + " --- |" * len(header))
    for path in sorted(glob.glob(os.path.join(HERE, "summaries", "*.json"))):
        with open(path) as f:
            s = json.load(f)
        cells = row(s["case"], os.path.basename(path)[:-5], s) + [
            round(100 * s["max_clumped_fraction"], 1), "%.2g" % s["min_pair_distance_over_dx"]]
        print("| " + " | ".join(str(c) for c in cells) + " |")


if __name__ == "__main__":
    main()

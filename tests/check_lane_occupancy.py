#!/usr/bin/env python3
"""tools/lane_occupancy.py on a small bar: with one lane a candidate is
evaluated exactly when it is a neighbour, so evaluated == neighbours; with
eight, every neighbour is evaluated and some masked lanes come with them
(neighbours < evaluated <= 8 x tested)."""
import json
import os
import subprocess
import sys
import tempfile

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools",
                    "lane_occupancy.py")


def run(lanes, out):
    subprocess.run([sys.executable, TOOL, "--radius", "4", "--length", "8", "--lanes", str(lanes),
                    "--json", out], check=True)
    with open(out) as f:
        return json.load(f)["orders"]


def main():
    with tempfile.TemporaryDirectory() as tmp:
        one = run(1, os.path.join(tmp, "one.json"))
        eight = run(8, os.path.join(tmp, "eight.json"))
    for name, r in one.items():
        assert abs(r["evaluated"] - r["neighbours"]) < 1e-9, (name, r)
    for name, r in eight.items():
        assert r["neighbours"] < r["evaluated"] <= 8 * r["tested"], (name, r)
    print("lane_occupancy: counts consistent")
    return 0


if __name__ == "__main__":
    sys.exit(main())

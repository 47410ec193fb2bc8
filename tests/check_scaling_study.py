#!/usr/bin/env python3
"""tools/scaling_study.py on a 1k-particle 3-D bar over 1 and 2 ranks: the
strong-scaling table has both rows with positive times, the 2-rank run has
a halo, and the weak-scaling model's efficiencies lie in (0, 1] and fall
as the ranks grow at fixed particles per rank.

usage: check_scaling_study.py TOOL OUT"""
import csv
import json
import os
import subprocess
import sys

tool, out = sys.argv[1], sys.argv[2]
cmd = [sys.executable, tool, "--out", out, "--ranks", "1", "2", "--no-bind",
       "--per-rank", "1e5", "--model-ranks", "8", "64",
       "--set", "numerics.dx=0.75e-3", "--set", "numerics.h_over_dx=1.2",
       "--set", "numerics.end_time=3e-6"]
proc = subprocess.run(cmd, capture_output=True, text=True)
sys.stdout.write(proc.stdout)
if proc.returncode != 0:
    sys.exit("FAIL: scaling_study exited %d: %s" % (proc.returncode, proc.stderr[-2000:]))
rows = list(csv.DictReader(open(os.path.join(out, "strong_scaling.csv"))))
if [int(r["ranks"]) for r in rows] != [1, 2] or not all(float(r["ms/step"]) > 0 for r in rows):
    sys.exit("FAIL: strong_scaling.csv: %s" % rows)
if not float(rows[1]["halo particles/rank"]) > 0:
    sys.exit("FAIL: the 2-rank run reports no halo")
model = list(csv.DictReader(open(os.path.join(out, "weak_scaling_model.csv"))))
eff = [float(r["efficiency"]) for r in model]
if len(eff) != 2 or not all(0 < e <= 1 for e in eff) or not eff[1] <= eff[0]:
    sys.exit("FAIL: weak_scaling_model.csv efficiencies %s" % eff)
scaling = json.load(open(os.path.join(out, "scaling.json")))
if not scaling["largest_per_gpu"] > 1e6:
    sys.exit("FAIL: largest case per GPU %s" % scaling["largest_per_gpu"])
print("PASS")

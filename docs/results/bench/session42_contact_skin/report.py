#!/usr/bin/env python3
"""The contact search's share with and without its skin (session 42):
    /usr/bin/python3 docs/results/bench/session42_contact_skin/report.py
reads the four profile.json files beside it (`sph run
cases/rubber_rings_2d.yaml --set numerics.dx=0.5e-3 --set
numerics.end_time=6e-4 --profile`, base = 1fbf0c4 (before the skin), new =
the skin, alternated)."""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
SEARCH = {"contact_cell_keys", "contact_cell_ranges", "contact_cell_parts", "bucket_count",
          "bucket_block_total", "bucket_block_offsets", "bucket_block_scan", "bucket_scatter",
          "fill_int"}

print("| run | steps | device (s) | search (s) | search share | searches | contact pass (s) |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for run in ("base_1", "new_1", "base_2", "new_2"):
    with open(os.path.join(HERE, run + ".profile.json")) as f:
        p = json.load(f)
    k = {row["kernel"]: row for row in p["kernels"]}
    search = sum(row["device_s"] for name, row in k.items() if name in SEARCH)
    print("| %s | %d | %.2f | %.3f | %.1f%% | %d | %.3f |" % (
        run, p["steps"], p["device_s"], search, 100 * search / p["device_s"],
        k["contact_cell_keys"]["calls"], k["tl_part_contact"]["device_s"]))

#!/usr/bin/env python3
"""Prints one row per summary.json in summaries/ (session 43, numerics.
reference_update and the total Lagrangian form without the plane gap):
length, face diameter (twice footprint_radius_m), peak plastic strain,
energy balance, updates, neighbour loss, hourglass and viscosity work.
Beam rows print the tip deflection instead. usage: table.py [FOLDER]"""
import glob
import json
import os
import sys

folder = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "summaries")
print("| run | status | length (mm) | face diameter (mm) / tip (mm) | peak eps_p | energy balance | updates | lost neighbours | hourglass work | viscosity work |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for path in sorted(glob.glob(os.path.join(folder, "*.json"))):
    with open(path) as f:
        s = json.load(f)

    def num(key, scale=1.0, fmt="%.3f"):
        v = s.get(key)
        return fmt % (v * scale) if isinstance(v, (int, float)) else "-"

    shape = (num("footprint_radius_m", 2e3) if "footprint_radius_m" in s
             else num("tip_deflection_final_m", 1e3))
    print(f"| {os.path.basename(path)[:-5]} | {s.get('status')} | {num('final_length_m', 1e3)} | "
          f"{shape} | {num('max_plastic_strain', 1, '%.2f')} | {num('energy_drift', 100, '%.2f%%')} | "
          f"{s.get('reference_updates', '-')} | {num('max_neighbour_loss_fraction', 100, '%.2f%%')} | "
          f"{num('hourglass_work_fraction', 100, '%.2f%%')} | "
          f"{num('artificial_viscosity_work_fraction', 100, '%.1f%%')} |")

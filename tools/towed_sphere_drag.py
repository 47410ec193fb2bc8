#!/usr/bin/python3
"""A rigid sphere towed at constant speed through a Newtonian liquid at
rest: its drag coefficient against the standard curve (issue 16, item 3).

usage: towed_sphere_drag.py [--case CASE] [--re RE ...] [--n N ...]
                            [--contact no_slip free_slip] [--results DIR]
                            [--set KEY=VALUE ...] [--check LOW HIGH]
                            [--min-stick-ratio R]

For each Reynolds number Re = rho U d / eta (eta set from it), each
spacing d / dx = N and each contact, runs `sph run CASE` and takes
Cd = 2 F / (rho U^2 pi d^2 / 4) as the mean of the holding force F
(ballistics.csv, decelerating_force_N) over the second half of the run, the
first half being the start-up (the sphere starts impulsively). The
reference is the standard drag curve of a solid (no-slip) sphere in an
unbounded liquid, Clift & Gauvin's fit (tools/penetration_models.py); the
case's tube raises the drag by its blockage (cases/towed_sphere_3d.yaml
says by how much). Writes DIR/towed_sphere_drag.csv and .md (default
results/towed_sphere/). --check LOW HIGH exits 1 unless every Cd / Cd_ref
lies in [LOW, HIGH]; --min-stick-ratio R exits 1 unless, at each Re and
spacing run with both contacts, the no-slip Cd is at least R times the
free-slip one (the ctest's short form: a stick that does nothing fails).
"""
import argparse
import csv
import math
import os
import sys

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import studylib  # noqa: E402
from penetration_models import clift_gauvin_cd  # noqa: E402


def case_parameters(path):
    """rho (kg/m^3), U (m/s), d (m) and the liquid's name from the case."""
    with open(path) as f:
        case = yaml.safe_load(f)
    material = case["materials"][0]
    velocity = case["projectile"]["velocity"]
    speed = math.sqrt(sum(v * v for v in velocity))
    return float(material["density"]), speed, float(case["projectile"]["diameter"]), material["name"]


def drag_coefficient(run, rho, speed, diameter):
    """Mean Cd over the second half of the run, and its standard deviation."""
    with open(os.path.join(run, "ballistics.csv")) as f:
        rows = list(csv.DictReader(f))
    end = float(rows[-1]["time_s"])
    mean, spread = studylib.resistance_in_window(rows, diameter, 0.5 * end, end)
    dynamic = 0.5 * rho * speed * speed
    return mean / dynamic, spread / dynamic


def main():
    root = studylib.ROOT
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", default=os.path.join(root, "cases", "towed_sphere_3d.yaml"))
    ap.add_argument("--re", type=float, nargs="+", default=[10.0])
    ap.add_argument("--n", type=float, nargs="+", default=[8.0], help="d / dx")
    ap.add_argument("--contact", nargs="+", default=["no_slip"], choices=["no_slip", "free_slip"])
    ap.add_argument("--results", default=os.path.join(root, "results", "towed_sphere"))
    ap.add_argument("--set", action="append", default=[], help="extra case override")
    ap.add_argument("--check", type=float, nargs=2, metavar=("LOW", "HIGH"))
    ap.add_argument("--min-stick-ratio", type=float, metavar="R")
    args = ap.parse_args()
    rho, speed, diameter, liquid = case_parameters(args.case)
    os.makedirs(args.results, exist_ok=True)
    rows, ratios, by_contact = [], [], {}
    for re in args.re:
        eta = rho * speed * diameter / re
        for n in args.n:
            for contact in args.contact:
                out = os.path.join(args.results, f"re{re:g}_n{n:g}_{contact}")
                sets = [f"materials.{liquid}.viscosity={eta:.9g}",
                        f"numerics.dx={diameter / n:.9g}",
                        f"projectile.contact={contact}"] + args.set
                summary = studylib.run(args.case, out, sets, "towed_sphere_drag")
                cd, spread = drag_coefficient(out, rho, speed, diameter)
                reference = float(clift_gauvin_cd(re))
                ratios.append(cd / reference)
                by_contact[(re, n, contact)] = cd
                rows.append([f"{re:g}", f"{n:g}", contact, f"{eta:.4g}", f"{cd:.4f}", f"{spread:.4f}",
                             f"{reference:.4f}", f"{cd / reference:.3f}", summary.get("status"),
                             summary.get("particles"), summary.get("steps"),
                             f"{summary.get('wall_time_s', 0):.0f}"])
    studylib.write_table(args.results, "towed_sphere_drag",
                         ["Re", "d/dx", "contact", "eta (Pa s)", "Cd", "Cd spread (std)",
                          "Cd standard curve", "ratio", "status", "particles", "steps", "wall (s)"],
                         rows)
    if args.check and not all(args.check[0] <= r <= args.check[1] for r in ratios):
        sys.exit(f"towed_sphere_drag: Cd / Cd_ref {ratios} outside [{args.check[0]}, "
                 f"{args.check[1]}]")
    if args.min_stick_ratio:
        pairs = [(key, cd) for key, cd in by_contact.items()
                 if key[2] == "no_slip" and (key[0], key[1], "free_slip") in by_contact]
        if not pairs:
            sys.exit("towed_sphere_drag: --min-stick-ratio needs runs with both contacts "
                     "(--contact no_slip free_slip)")
        for (re, n, _), cd in pairs:
            free = by_contact[(re, n, "free_slip")]
            print(f"Re {re:g}, d/dx {n:g}: no-slip Cd / free-slip Cd = {cd / free:.3f}")
            if cd / free < args.min_stick_ratio:
                sys.exit(f"towed_sphere_drag: no-slip Cd {cd:.4f} is less than "
                         f"{args.min_stick_ratio} times the free-slip {free:.4f}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Cantilever beam studies (issue: elastic solver validation).

  tools/beam_study.py static  [--dx 2e-3 1e-3 5e-4] [--loads 1750 17500]
      quasi-static beam (cases/beam_2d_static.yaml) at each spacing and load:
      final tip deflection against Reissner's beam (tools/reissner_beam.py)
      and the elastica, observed order.
  tools/beam_study.py dynamic [--dx 1e-3]
      the thesis' dynamic beam (cases/beam_2d.yaml) with all six kernels:
      e_av against 33.59 mm (thesis, linear) and 30.4 mm (elastica + shear),
      and the mean tip deflection over 1.5-3.0 ms.

Runs go to results/beam_<study>/<run>/; the table is written as CSV and
Markdown next to them, with a PNG. Every figure comes from the runs' own
summary.json and history.csv.
"""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import reissner_beam  # noqa: E402
import studylib  # noqa: E402
from studylib import write_table  # noqa: E402
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KERNELS = ["cubic_spline", "gaussian", "quintic_spline", "wendland_c2", "double_cosine",
           "hyperbolic"]
# The thesis beam (REFERENCES.md 1): L 100 mm, height 10 mm, thickness 1 mm,
# E 210 GPa, nu 0.3.
BEAM = dict(length=0.1, ea=210e9 * 1e-5, gas=5 / 6 * 210e9 / 2.6 * 1e-5,
            ei=210e9 * 1e-3 * 1e-6 / 12)


def reissner(load):
    """Tip deflection from Reissner's beam (extension and shear included)."""
    return -reissner_beam.solve(load, BEAM["length"], BEAM["ea"], BEAM["gas"], BEAM["ei"])[1]


def elastica(load):
    """Tip deflection of the inextensible, unshearable elastica."""
    return -reissner_beam.solve(load, BEAM["length"], 1e30, 1e30, BEAM["ei"])[1]


ELASTICA = {1750.0: 30.4e-3}  # the dynamic study's second reference (Reissner 30.40 mm)
LINEAR_1750 = 33.59e-3


def history(out):
    with open(os.path.join(out, "history.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    return [float(r["time_s"]) for r in rows], [float(r["tip_deflection_m"]) for r in rows]


def e_av(times, values, reference, window=(1.5e-3, 3.0e-3)):
    errors = [abs(abs(v) - reference) / reference for t, v in zip(times, values)
              if window[0] <= t <= window[1] * (1 + 1e-9)]
    return sum(errors) / len(errors) if errors else float("nan")


def static(args):
    folder = os.path.join(args.results, "beam_static")
    os.makedirs(folder, exist_ok=True)
    rows, series = [], {}
    for load in args.loads:
        for dx in args.dx:
            out = os.path.join(folder, f"F{int(load)}_dx{dx:g}")
            ref, ref_elastica = reissner(load), elastica(load)
            s = studylib.run(os.path.join(ROOT, "cases", "beam_2d_static.yaml"), out,
                             [f"numerics.dx={dx}", f"groups.tip.load.force=[0, {-load}]",
                              f"reference.value={-ref}"] + args.set, "beam_study")
            w = abs(s.get("tip_deflection_final_m") or float("nan"))
            rows.append([int(load), dx * 1e3, s["particles"], s["steps"], round(s["wall_time_s"], 1),
                         s["status"], round(w * 1e3, 3), round(ref * 1e3, 3),
                         round(100 * (w - ref) / ref, 2),
                         round(100 * (w - ref_elastica) / ref_elastica, 2),
                         s.get("max_neighbour_loss_fraction")])
            series.setdefault(load, []).append((dx, w))
    orders = []
    for load, pts in series.items():
        pts.sort(reverse=True)
        for (h1, w1), (h2, w2), (h3, w3) in zip(pts, pts[1:], pts[2:]):
            fit = studylib.richardson((h1, h2, h3), (w1, w2, w3))
            if fit:
                orders.append((load, h3, fit[1]))
    write_table(folder, "static" + args.tag, ["F (N)", "dx (mm)", "particles", "steps", "wall (s)", "status",
                                   "tip deflection (mm)", "Reissner (mm)", "error vs Reissner (%)",
                                   "error vs elastica (%)", "neighbour-loss fraction"], rows)
    for load, h, p in orders:
        print(f"observed order at F = {load:g} N down to dx = {h * 1e3:g} mm: {p:.2f}")
    fig, ax = plt.subplots(figsize=(6, 4))
    for load, pts in series.items():
        ax.loglog([p[0] * 1e3 for p in pts],
                  [abs(p[1] - reissner(load)) / reissner(load) for p in pts], "o-",
                  label=f"F = {load / 1e3:g} kN")
    ax.set_xlabel("dx (mm)")
    ax.set_ylabel("|W - W_Reissner| / W_Reissner")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(folder, f"static_convergence{args.tag}.png"), dpi=110)


def dynamic(args):
    folder = os.path.join(args.results, "beam_dynamic")
    os.makedirs(folder, exist_ok=True)
    rows = []
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for kernel in args.kernels:
        out = os.path.join(folder, kernel)
        s = studylib.run(os.path.join(ROOT, "cases", "beam_2d.yaml"), out,
                         [f"numerics.kernel={kernel}", f"numerics.dx={args.dx[0]}"] + args.set,
                         "beam_study")
        t, w = history(out)
        window = [abs(v) for tt, v in zip(t, w) if 1.5e-3 <= tt <= 3.0e-3 * (1 + 1e-9)]
        mean = sum(window) / len(window) if window else float("nan")
        rows.append([kernel, s["status"], s["steps"], round(s["wall_time_s"], 1),
                     round(mean * 1e3, 3), round(100 * e_av(t, w, LINEAR_1750), 2),
                     round(100 * e_av(t, w, ELASTICA[1750.0]), 2),
                     round(100 * (s.get("energy_drift") or float("nan")), 3)])
        ax.plot([1e3 * x for x in t], [-1e3 * x for x in w], label=kernel)
    write_table(folder, "dynamic", ["kernel", "status", "steps", "wall (s)",
                                    "mean deflection 1.5-3 ms (mm)", "e_av vs 33.59 mm (%)",
                                    "e_av vs 30.4 mm (%)", "energy drift (%)"], rows)
    ax.axhline(33.59, color="k", ls=":", label="linear 33.59 mm")
    ax.axhline(30.4, color="k", ls="--", label="elastica 30.4 mm")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("tip deflection (mm)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "dynamic_kernels.png"), dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study", choices=["static", "dynamic"])
    ap.add_argument("--dx", type=float, nargs="+")
    ap.add_argument("--loads", type=float, nargs="+", default=[1750.0, 17500.0])
    ap.add_argument("--kernels", nargs="+", default=KERNELS)
    ap.add_argument("--set", action="append", default=[], help="extra --set for every run")
    ap.add_argument("--tag", default="", help="suffix of the table and plot names")
    ap.add_argument("--results", default=os.path.join(ROOT, "results"),
                    help="folder for the runs and tables (default results/)")
    args = ap.parse_args()
    if not os.path.exists(studylib.SPH):
        sys.exit(f"beam_study: {studylib.SPH} not found; build first (tools/setup.sh build)")
    if args.study == "static":
        args.dx = args.dx or [2e-3, 1e-3, 5e-4]
        static(args)
    else:
        args.dx = args.dx or [1e-3]
        dynamic(args)


if __name__ == "__main__":
    main()

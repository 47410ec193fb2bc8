#!/usr/bin/python3
"""Accuracy against cost (issue: stability where SPH fails, accuracy
against speed).

  tools/pareto_study.py [--cases beam1750 beam17500 taylor] [--kernels ... | all]
                        [--precision float double] [--beam-dx 2e-3 1e-3]
                        [--taylor-dx 1e-3 5e-4 2.5e-4] [--set key=value ...]
                        [--results DIR] [--reuse]

Runs each case over spacing x kernel x precision and plots the error
against the wall time on log axes, with the Pareto front (the runs no other
run beats on both) marked; writes results/pareto/<case>.csv, .md and .png
and the observed order of convergence per kernel and precision
(<case>_orders.csv, .md).

Errors: the quasi-static beam (cases/beam_2d_static.yaml) against Reissner's
beam (tools/reissner_beam.py: 30.397 mm at 1.75 kN, 82.251 mm at 17.5 kN);
the axisymmetric Taylor bar (cases/taylor_axi_4340.yaml) against the finest
run of the same kernel and precision (REFERENCES.md holds peers' results,
not an exact value, for its final length), so its finest run is left out
of the plot.
"""
import argparse
import itertools
import json
import math
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import reissner_beam  # noqa: E402
import studylib  # noqa: E402
from studylib import write_table  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ALL_KERNELS = ["cubic_spline", "gaussian", "quintic_spline", "wendland_c2", "double_cosine",
               "hyperbolic"]
REUSE = False
EI, EA, GAS = 210e9 * 1e-3 * 1e-6 / 12, 210e9 * 1e-5, 5 / 6 * 210e9 / 2.6 * 1e-5


def run(case, out, sets, tool):
    """studylib.run, or with --reuse the summary.json already in `out`.

    Each timed run follows a one-step run of the same configuration: PoCL
    finishes compiling a kernel at its first launch, inside the time loop,
    and that once-per-configuration cost is not what a run costs."""
    if REUSE and os.path.exists(os.path.join(out, "summary.json")):
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)
    warm = out + "_warmup"
    studylib.run(case, warm, sets + ["numerics.end_time=1e-9"], tool)
    shutil.rmtree(warm, ignore_errors=True)
    return studylib.run(case, out, sets, tool)


def reissner(load):
    return -reissner_beam.solve(load, 0.1, EA, GAS, EI)[1]


def beam_runs(args, load, folder):
    """(kernel, precision, dx, wall, value, reference) for the static beam."""
    reference = reissner(load)
    out = []
    for kernel, precision, dx in itertools.product(args.kernels, args.precision, args.beam_dx):
        s = run(os.path.join(ROOT, "cases", "beam_2d_static.yaml"),
                         os.path.join(folder, f"{kernel}_{precision}_dx{dx:g}"),
                         [f"numerics.kernel={kernel}", f"numerics.precision={precision}",
                          f"numerics.dx={dx}", f"groups.tip.load.force=[0,{-load}]",
                          f"reference.value={-reference}"] + args.set, "pareto_study")
        out.append((kernel, precision, dx, s["wall_time_s"],
                    abs(s.get("tip_deflection_final_m") or float("nan")), reference))
    return out


def taylor_runs(args, folder):
    """The same for the axisymmetric Taylor bar, against the finest run."""
    out = []
    finest = min(args.taylor_dx)
    for kernel, precision in itertools.product(args.kernels, args.precision):
        runs = []
        for dx in sorted(args.taylor_dx, reverse=True):
            s = run(os.path.join(ROOT, "cases", "taylor_axi_4340.yaml"),
                             os.path.join(folder, f"{kernel}_{precision}_dx{dx:g}"),
                             [f"numerics.kernel={kernel}", f"numerics.precision={precision}",
                              f"numerics.dx={dx}"] + args.set, "pareto_study")
            runs.append((dx, s["wall_time_s"], s.get("final_length_m", float("nan"))))
        reference = [r[2] for r in runs if r[0] == finest][0]
        out += [(kernel, precision, dx, wall, value, reference) for dx, wall, value in runs]
    return out


def pareto_front(points):
    """Indices of the points no other point beats in both coordinates."""
    front = []
    for i, (x, y) in enumerate(points):
        if not any((x2 <= x and y2 <= y) and (x2 < x or y2 < y) for x2, y2 in points):
            front.append(i)
    return front


def report(folder, name, runs, exclude_reference_runs):
    rows, pts, labels = [], [], []
    for kernel, precision, dx, wall, value, reference in runs:
        error = abs(value - reference) / reference
        rows.append([kernel, precision, dx * 1e3, round(wall, 1), round(value * 1e3, 4),
                     round(reference * 1e3, 4), f"{error:.3e}"])
        if exclude_reference_runs and error == 0:
            continue
        pts.append((wall, error))
        labels.append((kernel, precision, dx))
    write_table(folder, name, ["kernel", "precision", "dx (mm)", "wall (s)", "value (mm)",
                               "reference (mm)", "relative error"], rows)
    orders = []
    for kernel, precision in sorted({(r[0], r[1]) for r in runs}):
        series = sorted((r[2], abs(r[4] - r[5]) / r[5]) for r in runs
                        if r[0] == kernel and r[1] == precision)
        series = [p for p in series if p[1] > 0]
        for (h1, e1), (h2, e2) in zip(series, series[1:]):
            order = math.log(e2 / e1) / math.log(h2 / h1)
            print(f"{name}: {kernel} {precision}: order {order:.2f}"
                  f" between dx = {h1 * 1e3:g} and {h2 * 1e3:g} mm")
            orders.append([kernel, precision, f"{h1 * 1e3:g}", f"{h2 * 1e3:g}", f"{e1:.3e}",
                           f"{e2:.3e}", f"{order:.2f}"])  # h1 < h2: fine, coarse
    write_table(folder, name + "_orders", ["kernel", "precision", "dx fine (mm)",
                                           "dx coarse (mm)", "error fine", "error coarse",
                                           "observed order"], orders)
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    kernels = sorted({l[0] for l in labels})
    colour = {k: f"C{i}" for i, k in enumerate(kernels)}
    for kernel, precision in sorted({(l[0], l[1]) for l in labels}):
        sel = [p for p, l in zip(pts, labels) if l[0] == kernel and l[1] == precision]
        ax.loglog([p[0] for p in sel], [p[1] for p in sel], "o" if precision == "float" else "s",
                  color=colour[kernel], mfc="none" if precision == "double" else colour[kernel],
                  label=f"{kernel}, {precision}", alpha=0.8)
    front = sorted(pareto_front(pts), key=lambda i: pts[i][0])
    ax.loglog([pts[i][0] for i in front], [pts[i][1] for i in front], "k--", lw=1,
              label="Pareto front")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("relative error")
    ax.set_title(name)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=6, ncol=2 if len(kernels) > 2 else 1)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, f"{name}.png"), dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="+", choices=["beam1750", "beam17500", "taylor"],
                    default=["beam1750", "beam17500", "taylor"])
    ap.add_argument("--kernels", nargs="+", default=["wendland_c2", "cubic_spline"],
                    help="kernels to run, or 'all' for the six (default: wendland_c2 "
                    "cubic_spline, which keeps the default under 30 minutes on two cores)")
    ap.add_argument("--precision", nargs="+", choices=["float", "double"],
                    default=["float", "double"])
    ap.add_argument("--beam-dx", type=float, nargs="+", default=[2e-3, 1e-3])
    ap.add_argument("--taylor-dx", type=float, nargs="+", default=[1e-3, 5e-4, 2.5e-4])
    ap.add_argument("--set", action="append", default=[], help="extra --set for every run")
    ap.add_argument("--results", default=os.path.join(ROOT, "results"),
                    help="folder for the runs and tables (default results/)")
    ap.add_argument("--reuse", action="store_true",
                    help="take a run whose folder already holds a summary.json from there "
                    "instead of running it again (to resume, or to redraw the tables)")
    args = ap.parse_args()
    global REUSE
    REUSE = args.reuse
    if args.kernels == ["all"]:
        args.kernels = ALL_KERNELS
    folder = os.path.join(args.results, "pareto")
    for name in args.cases:
        sub = os.path.join(folder, name)
        os.makedirs(sub, exist_ok=True)
        if name == "taylor":
            report(folder, name, taylor_runs(args, sub), True)
        else:
            report(folder, name, beam_runs(args, 1750.0 if name == "beam1750" else 17500.0, sub),
                   False)


if __name__ == "__main__":
    main()

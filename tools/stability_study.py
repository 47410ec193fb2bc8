#!/usr/bin/python3
"""Stability map (issue: stability where SPH fails).

  tools/stability_study.py [--cases tension rings beam] [--kernels ...]
                           [--stress off on] [--csph off on] [--h 1.2 2.0]
                           [--epsilon 0.3] [--set key=value ...] [--results DIR]
                           [--max-wall SECONDS] [--reuse]

Runs every combination of smoothing kernel x artificial stress (off, or on
with epsilon 0.3, --epsilon to change it) x CSPH (off, on) x h/dx on each
stability case and records the health indicators of each run (summary.json):
whether it stayed whole, the time it first went unhealthy (clumping) and
the reason, the largest clumped and Swegle fractions, the smallest pair
distance, the fraction of particles that lost a third of their neighbours,
the probe's final value and e_av. Writes
results/stability/<case>.csv and .md and a map per case (PNG): one panel
per h/dx, kernels down, (artificial stress, CSPH) across, green for healthy,
orange for clumped or torn but completed, red for a run that blew up, grey
for a run stopped at --max-wall.

Default size: 3 cases x 6 kernels x 2 x 2 x h/dx (1.2, 2.0) = 144 runs, 25.8
minutes of wall time on two cores as measured in docs/stability.md (the full
map with h/dx 1.5 as well: about 39 by the same per-run cost). --max-wall
stops a run that crawls on after a blow-up.

Cases (each at dx = 2 mm by default): tension = cases/tension_bar_2d.yaml
(2 GPa tension, 0.5 ms), rings = cases/rubber_rings_2d.yaml (Gray, Monaghan
& Swift 2001) in the updated Lagrangian form with its published constant
viscosity and XSPH 0.5, beam = cases/beam_2d.yaml at 17.5 kN (the thesis' large
bending, 2 ms).
"""
import argparse
import csv
import itertools
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import studylib  # noqa: E402
from studylib import write_table  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KERNELS = ["cubic_spline", "gaussian", "quintic_spline", "wendland_c2", "double_cosine",
           "hyperbolic"]
# Each case at a coarse default size, so that the whole map stays short on a
# CPU (override with --set, e.g. --set numerics.dx=1e-3).
CASES = {
    "tension": ("tension_bar_2d.yaml", ["numerics.dx=2e-3", "numerics.end_time=5e-4"]),
    # the rings in the updated form, with the published constant viscosity
    # the map was measured with (the case ships the total Lagrangian form,
    # which has no tensile instability to map: docs/stability.md)
    "rings": ("rubber_rings_2d.yaml", ["numerics.dx=2e-3",
                                       "numerics.formulation=updated_lagrangian",
                                       "numerics.artificial_viscosity.scheme=monaghan",
                                       "numerics.artificial_viscosity.alpha=1.0",
                                       "numerics.artificial_viscosity.beta=1.0",
                                       "numerics.xsph=0.5"]),
    "beam": ("beam_2d.yaml", ["groups.tip.load.force=[0,-17500]", "reference.value=-82.25e-3",
                              "numerics.dx=2e-3", "numerics.end_time=2e-3"]),
}
EPSILON = 0.3


def verdict(s):
    """0 healthy, 1 completed but unhealthy (clumped or torn), 2 blew up, 3 stopped at the
    wall-time limit (--max-wall) before its end time."""
    if s["status"] == "stopped":
        return 3
    if s["status"] != "completed":
        return 2
    return 0 if s.get("healthy") else 1


def reason_letter(reason):
    """The map's one-letter tag of why a run went unhealthy (host/run.c's reasons)."""
    for start, letter in (("torn", "T"), ("smallest pair", "P"), ("energy", "E")):
        if reason.startswith(start):
            return letter
    return "C"  # clumped


def run_one(case, out, sets, max_wall):
    """studylib.run, or with max_wall > 0 the same run stopped after max_wall seconds (a
    beam torn apart can crawl on at a hundredth of its time step); a stopped run's row
    comes from its history.csv and is kept in out/stopped.json for --reuse."""
    if max_wall <= 0:
        return studylib.run(case, out, sets, "stability_study")
    cmd = [studylib.SPH, "run", case, "--out", out, "--quiet"]
    for x in sets:
        cmd += ["--set", x]
    print("$ " + " ".join(cmd), flush=True)
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=max_wall)
    except subprocess.TimeoutExpired:
        s = from_history(out, max_wall)
        with open(os.path.join(out, "stopped.json"), "w") as f:
            json.dump(s, f, indent=2)
        print(f"stopped after {max_wall:g} s wall at t = {s['end_time_s']:.4g} s: {out}",
              flush=True)
        return s
    sys.stdout.write(proc.stdout)
    if proc.returncode not in (0, 3):
        sys.stderr.write(proc.stderr)
        sys.exit(f"stability_study: sph exited with {proc.returncode}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def from_history(out, wall, clumped_limit=0.01):
    """The summary keys the map needs, from history.csv of a run that was stopped: the
    health extremes and the first row above the clumped limit (the case default)."""
    with open(os.path.join(out, "history.csv")) as f:
        rows = [r for r in csv.DictReader(f) if None not in r.values()]  # whole rows only
    last = rows[-1]
    s = {"status": "stopped", "healthy": False, "end_time_s": float(last["time_s"]),
         "wall_time_s": wall,
         "min_pair_distance_over_dx": min(float(r["min_pair_distance_over_dx"]) for r in rows),
         "max_clumped_fraction": max(float(r["clumped_fraction"]) for r in rows),
         "max_swegle_fraction": max(float(r["swegle_fraction"]) for r in rows),
         "max_neighbour_loss_fraction": float("nan")}
    probe = list(last)[3]  # time_s, step, dt_s, then the probe
    if probe.endswith("_m"):
        s[probe[:-2] + "_final_m"] = float(last[probe])
    for r in rows:
        if float(r["clumped_fraction"]) > clumped_limit:
            s["first_unhealthy_time_s"] = float(r["time_s"])
            s["unhealthy_reason"] = (f"{100 * float(r['clumped_fraction']):.1f}% of particles "
                                     f"clumped (from history.csv; run stopped at the wall limit)")
            break
    return s


def run_case(args, name):
    case, base_sets = CASES[name]
    folder = os.path.join(args.results, "stability", name)
    os.makedirs(folder, exist_ok=True)
    rows, grid = [], {}
    for kernel, stress, csph, h in itertools.product(args.kernels, args.stress, args.csph, args.h):
        label = f"{kernel}_as-{stress}_csph-{csph}_h{h:g}"
        epsilon = args.epsilon if stress == "on" else 0
        sets = base_sets + [f"numerics.kernel={kernel}", f"numerics.csph={csph == 'on'}".lower(),
                            f"numerics.artificial_stress.epsilon={epsilon}",
                            f"numerics.h_over_dx={h}"] + args.set
        out = os.path.join(folder, label)
        done = [os.path.join(out, x) for x in ("summary.json", "stopped.json")
                if os.path.exists(os.path.join(out, x))]
        if args.reuse and done:
            with open(done[0]) as f:
                s = json.load(f)
        else:
            s = run_one(os.path.join(ROOT, "cases", case), out, sets, args.max_wall)
        onset = s.get("first_unhealthy_time_s")
        reason = s.get("unhealthy_reason") or ""
        grid[(kernel, stress, csph, h)] = (verdict(s), onset, reason_letter(reason))
        rows.append([kernel, stress, csph, h, s["status"], s.get("healthy"),
                     s.get("first_unhealthy_time_s", ""), s.get("unhealthy_reason", ""),
                     round(s.get("max_clumped_fraction", float("nan")), 4),
                     round(s.get("max_swegle_fraction", float("nan")), 3),
                     round(s.get("min_pair_distance_over_dx", float("nan")), 3),
                     round(s.get("max_neighbour_loss_fraction", float("nan")), 4),
                     f"{s['end_time_s']:.4g}", probe_final_mm(s),
                     f"{s['e_av']:.4f}" if s.get("e_av") is not None else "",
                     round(s["wall_time_s"], 1)])
    write_table(folder, name,
                ["kernel", "artificial stress", "CSPH", "h/dx", "status", "healthy",
                 "first unhealthy (s)", "reason", "max clumped", "max Swegle",
                 "min pair distance / dx", "neighbour loss", "reached (s)", "probe final (mm)",
                 "e_av", "wall (s)"], rows)
    plot_map(folder, name, args, grid)


def probe_final_mm(s):
    """The probe's final value in mm (summary key <probe>_final_m), or ''."""
    keys = [k for k in s if k.endswith("_final_m") and k != "final_length_m"]
    return f"{1e3 * s[keys[0]]:.2f}" if keys and s[keys[0]] is not None else ""


def plot_map(folder, name, args, grid):
    columns = list(itertools.product(args.stress, args.csph))
    colours = ["#4caf50", "#ff9800", "#e53935", "#9e9e9e"]
    fig, axes = plt.subplots(1, len(args.h), figsize=(3.2 * len(args.h) + 1, 3.6), squeeze=False)
    for ax, h in zip(axes[0], args.h):
        for r, kernel in enumerate(args.kernels):
            for c, (stress, csph) in enumerate(columns):
                cell = grid.get((kernel, stress, csph, h))
                if cell is None:
                    continue
                v, onset, kind = cell
                ax.add_patch(plt.Rectangle((c, r), 1, 1, color=colours[v]))
                if onset is not None and v != 0:  # when it first went unhealthy, and how
                    ax.text(c + 0.5, r + 0.5, f"{kind} {1e6 * onset:.0f} us", ha="center",
                            va="center", fontsize=6)
        ax.set_xlim(0, len(columns))
        ax.set_ylim(len(args.kernels), 0)
        ax.set_xticks([c + 0.5 for c in range(len(columns))])
        ax.set_xticklabels([f"AS {s}\nCSPH {c}" for s, c in columns], fontsize=7)
        ax.set_yticks([r + 0.5 for r in range(len(args.kernels))])
        ax.set_yticklabels(args.kernels if ax is axes[0][0] else [], fontsize=7)
        ax.set_title(f"{name}, h = {h:g} dx", fontsize=9)
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in colours]
    fig.legend(handles, ["healthy", "unhealthy from the time shown (C clumped, T torn, "
                         "P pair distance, E energy)", "blew up", "stopped (wall limit)"],
               loc="lower center", ncol=2, fontsize=7)
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    fig.savefig(os.path.join(folder, f"{name}_map.png"), dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="+", choices=list(CASES), default=list(CASES))
    ap.add_argument("--kernels", nargs="+", default=KERNELS)
    ap.add_argument("--stress", nargs="+", choices=["off", "on"], default=["off", "on"])
    ap.add_argument("--csph", nargs="+", choices=["off", "on"], default=["off", "on"])
    ap.add_argument("--h", type=float, nargs="+", default=[1.2, 2.0],
                    help="h/dx values (default 1.2 2.0, which keeps the default map within 30 "
                    "minutes on two cores; --h 1.2 1.5 2.0 for the issue's full map)")
    ap.add_argument("--epsilon", type=float, default=EPSILON,
                    help=f"artificial-stress epsilon of the 'on' runs (default {EPSILON})")
    ap.add_argument("--set", action="append", default=[], help="extra --set for every run")
    ap.add_argument("--results", default=os.path.join(ROOT, "results"),
                    help="folder for the runs and tables (default results/)")
    ap.add_argument("--max-wall", type=float, default=0,
                    help="stop a run after this many seconds of wall time and take its row "
                    "from history.csv (default 0: no limit)")
    ap.add_argument("--reuse", action="store_true",
                    help="take a run whose folder already holds a summary.json from there "
                    "instead of running it again (to resume, or to redraw the tables)")
    args = ap.parse_args()
    for name in args.cases:
        run_case(args, name)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Where the artificial viscosity's work goes in a penetration run: split by
distance from the projectile's surface and by time.

The totals are the solver's own (history.csv's cumulative
artificial_viscosity_work_J, the same ledger as summary.json's
artificial_viscosity_work_fraction). Each interval between two history rows
is split in space by the shares the nearest snapshots give (their
artificial_viscosity_heating field, W/kg, times the particles' masses, in
bands of distance from the sphere's surface in diameters d), so the split is
as fine in time as the snapshots are: take snapshot_interval a few per cent
of the run or less. Writes RUN/av_work_split.csv (cumulative work per band
against time, J) and a PNG of the work per band against time.

It also integrates the snapshots' heating in time and prints it over the
ledger's work for the same span (1 where the field is the power the ledger
integrates and the snapshots follow it); --check TOL makes that an exit
status.

usage: tools/av_work_split.py RUN_FOLDER [--bands 0.25 1 4] [--windows T1 T2 ...]
                              [--out FILE.png] [--check TOL]
"""
import argparse
import bisect
import csv
import glob
import json
import os
import sys

import numpy as np
import yaml

try:
    import h5py
except ImportError:
    sys.exit("av_work_split: needs h5py (Debian: apt install python3-h5py)")


def read_history(folder):
    path = os.path.join(folder, "history.csv")
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"av_work_split: cannot read {path}: {e.strerror}")
    if not rows or "artificial_viscosity_work_J" not in rows[0]:
        sys.exit(f"av_work_split: {path} has no artificial_viscosity_work_J column")
    t = np.array([float(r["time_s"]) for r in rows])
    w = np.array([float(r["artificial_viscosity_work_J"]) for r in rows])
    return t, w


def snapshot_shares(path, edges, diameter):
    """(time, shares per band, total) of one snapshot's artificial-viscosity
    power (the total in W per radian or per metre in 2-D, as the masses)."""
    with h5py.File(path, "r") as f:
        if "artificial_viscosity_heating" not in f:
            sys.exit(f"av_work_split: {path} has no artificial_viscosity_heating "
                     "(runs from before it was written lack it; rerun the case)")
        if "projectile_centre_m" not in f.attrs:
            sys.exit(f"av_work_split: {path} has no projectile: this tool splits by distance "
                     "from a projectile's surface")
        t = float(f.attrs["time_s"][0])
        centre = np.asarray(f.attrs["projectile_centre_m"], dtype=float)
        pos = f["position"][:]  # a snapshot holds the real particles only
        power = f["mass"][:] * f["artificial_viscosity_heating"][:]
    dim = pos.shape[1]
    gap = np.linalg.norm(pos - centre[:dim], axis=1) - diameter / 2
    band = np.searchsorted(edges, np.maximum(gap, 0) / diameter, side="right") - 1
    shares = np.bincount(band, weights=power, minlength=len(edges))[: len(edges)]
    total = shares.sum()
    return t, (shares / total if total > 0 else None), total


def read_case_keys(folder):
    """The projectile's diameter (m) and the factor from the snapshots' masses
    to the ledger's (2 pi axisymmetric, the thickness in plane 2-D, else 1:
    host/step.c, thickness_scale)."""
    with open(os.path.join(folder, "case.resolved.yaml")) as f:
        case = yaml.safe_load(f)
    diameter = float(case["projectile"]["diameter"])
    if case["dimension"] != 2:
        return diameter, 1.0
    return diameter, 2 * np.pi if case.get("plane") == "axisymmetric" \
        else float(case.get("thickness", 1))


def snapshot_integral(snaps, scale, t_hist, w_hist):
    """The snapshots' heating integrated in time (trapezoids) over the
    ledger's work over the same span: 1 where the field is the power the
    ledger integrates and the snapshots are dense enough to follow it."""
    times = np.array([s[0] for s in snaps])
    power = scale * np.array([s[2] for s in snaps])
    integral = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(times)))
    ledger = float(np.interp(times[-1], t_hist, w_hist) - np.interp(times[0], t_hist, w_hist))
    return integral / ledger if ledger > 0 else float("nan")


def split(t_hist, w_hist, snaps, bands):
    """Cumulative work per band at each history row: each interval's work
    goes by the shares of the snapshot nearest its midpoint (with shares)."""
    times = [s[0] for s in snaps]
    cumulative = np.zeros((len(t_hist), bands))
    for i in range(1, len(t_hist)):
        mid = 0.5 * (t_hist[i - 1] + t_hist[i])
        k = bisect.bisect_left(times, mid)
        near = sorted((k - 1, k), key=lambda j: abs(times[j] - mid) if 0 <= j < len(times) else 1e30)
        share = snaps[near[0]][1]
        cumulative[i] = cumulative[i - 1] + (w_hist[i] - w_hist[i - 1]) * share
    return cumulative


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", help="run folder of a penetration run (sph run)")
    ap.add_argument("--bands", type=float, nargs="+", default=[0.25, 1, 4],
                    help="band edges: distance from the sphere's surface in diameters (default "
                         "0.25 1 4: the contact zone, the rest of the first diameter, out to 4 d, "
                         "beyond)")
    ap.add_argument("--windows", type=float, nargs="*", default=None,
                    help="times (s) that split the run into windows for the table (default: "
                         "t(P_max) and the end)")
    ap.add_argument("--out", help="PNG path (default RUN/av_work_split.png)")
    ap.add_argument("--check", type=float, metavar="TOL",
                    help="exit 1 unless the snapshots' heating integrated in time is within TOL "
                         "(relative) of the ledger's work over the same span")
    args = ap.parse_args()
    if sorted(args.bands) != args.bands or args.bands[0] <= 0:
        sys.exit("av_work_split: --bands must be positive and increasing")
    try:
        with open(os.path.join(args.run, "summary.json")) as f:
            summary = json.load(f)
        diameter, scale = read_case_keys(args.run)
    except (OSError, ValueError, KeyError, TypeError, yaml.YAMLError) as e:
        sys.exit(f"av_work_split: {args.run}: no summary.json or no projectile diameter in "
                 f"case.resolved.yaml ({e})")
    edges = np.array([0.0] + args.bands)
    t_hist, w_hist = read_history(args.run)
    snaps = [snapshot_shares(p, edges, diameter)
             for p in sorted(glob.glob(os.path.join(args.run, "snap_*.h5")))]
    ratio = snapshot_integral(snaps, scale, t_hist, w_hist)
    snaps = [s for s in snaps if s[1] is not None]
    if len(snaps) < 2:
        sys.exit(f"av_work_split: {args.run} has fewer than two snapshots with heating")
    spacing = max(b[0] - a[0] for a, b in zip(snaps[:-1], snaps[1:]))
    if spacing > 0.05 * t_hist[-1]:
        print(f"av_work_split: note: snapshots up to {spacing:.3g} s apart, "
              f"{100 * spacing / t_hist[-1]:.0f}% of the run: the split in space is coarse in time")
    cumulative = split(t_hist, w_hist, snaps, len(edges))
    total = w_hist[-1]
    fraction = summary.get("artificial_viscosity_work_fraction")
    ke_ref = total / fraction if fraction else None
    names = [f"{a:g}-{b:g}d" for a, b in zip(edges[:-1], edges[1:])] + [f">{edges[-1]:g}d"]

    with open(os.path.join(args.run, "av_work_split.csv"), "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["time_s"] + [f"work_J_{n}" for n in names])
        for i in range(len(t_hist)):
            out.writerow([f"{t_hist[i]:.6e}"] + [f"{v:.6e}" for v in cumulative[i]])

    windows = args.windows
    if windows is None:
        windows = [summary["time_of_max_penetration_s"]] if "time_of_max_penetration_s" in summary \
            else []
    edges_t = [0.0] + sorted(w for w in windows if 0 < w < t_hist[-1]) + [t_hist[-1]]
    norm = ke_ref or total
    label = "of the ledger's reference energy" if ke_ref else "of the total"
    print(f"{args.run}: artificial viscosity work {total:.4g} J ({norm and total / norm:.3f} {label}); "
          f"{len(snaps)} snapshots with heating; the table's fractions are {label}")
    print("window (s)            " + " ".join(f"{n:>9}" for n in names) + "     total")
    for a, b in zip(edges_t[:-1], edges_t[1:]):
        ia, ib = np.searchsorted(t_hist, a), np.searchsorted(t_hist, b)
        ib = min(ib, len(t_hist) - 1)
        part = (cumulative[ib] - cumulative[ia]) / norm
        print(f"{a:9.3e}-{b:9.3e}  " + " ".join(f"{v:9.4f}" for v in part) + f" {part.sum():9.4f}")
    part = cumulative[-1] / norm
    print("whole run              " + " ".join(f"{v:9.4f}" for v in part) + f" {part.sum():9.4f}")

    print(f"the snapshots' heating integrated in time: {ratio:.4f} of the ledger's work over "
          "the same span")
    plot(args, summary, t_hist, cumulative / norm, names, bool(ke_ref))
    if args.check is not None and not abs(ratio - 1) <= args.check:
        sys.exit(f"av_work_split: the snapshots' heating gives {ratio:.4f} of the ledger's work, "
                 f"not within {args.check} of 1")


def plot(args, summary, t_hist, fractions, names, of_energy):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from plot_run import plt, save_figure, unit_for  # the run plots' units and style

    fig, ax = plt.subplots(figsize=(8, 4))
    scale, unit = unit_for(t_hist[-1] or 1, "s")
    ax.stackplot(t_hist * scale, fractions.T, labels=names)
    ax.set_xlabel(f"time ({unit})")
    ax.set_ylabel("artificial viscosity work / KE0" if of_energy else "share of the work")
    ax.set_title(f"{summary.get('case', '')}: where the artificial viscosity's work goes "
                 "(distance from the sphere's surface)", fontsize=9)
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    save_figure(fig, args.out or os.path.join(args.run, "av_work_split.png"))


if __name__ == "__main__":
    main()

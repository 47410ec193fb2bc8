#!/usr/bin/python3
"""Compares the penetration histories of several runs: the sphere's depth
at common times and its maximum depth P_max, each against the first run
(the reference), as a table and as a plot of depth and velocity against
time. For the checks this project makes by hand every time: a 3-D quarter
against the axisymmetric case at the same spacing, one contact against
another, one spacing against the next, or this solver against another
code's curve.

usage: tools/compare_runs.py REFERENCE OTHER [OTHER ...] [--label NAME ...]
                             [--times T ...] [--out FILE.png]

Each argument is a run folder (its ballistics.csv is read) or a CSV file
with the columns time_s and penetration_m (SI units; velocity_m_per_s is
plotted when present), such as another code's history exported by hand.
--times (s) are the times of the table's columns (default: eight evenly
spaced up to the shortest history's end); a time past a history's end
is left blank for it. A P_max at a history's last row is marked as not
yet a maximum unless the sphere was already moving back there
(velocity_m_per_s <= 0). Prints a markdown table (depth in um, time in
ns, the difference from the reference in %) and writes the plot (default
compare_runs.png in the working folder), its path as the last line.
Exits 1 with the file, line and what was expected on input it cannot read.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import studylib  # noqa: E402

REQUIRED = ("time_s", "penetration_m")


def history_path(source):
    if os.path.isdir(source):
        return os.path.join(source, "ballistics.csv")
    return source


def read_history(source):
    """{column: array} of a run's ballistics (time_s, penetration_m, and
    velocity_m_per_s when present); exits naming the file and line."""
    path = history_path(source)
    if not os.path.exists(path):
        sys.exit(f"compare_runs: cannot read {path}: expected a run folder or a ballistics CSV file")
    columns = studylib.read_columns(path, "compare_runs", REQUIRED, ("velocity_m_per_s",))
    if len(columns["time_s"]) < 2:
        sys.exit(f"compare_runs: {path}: expected at least two rows of history")
    history = {c: np.array(v) for c, v in columns.items()}
    if np.any(np.diff(history["time_s"]) < 0):
        sys.exit(f"compare_runs: {path}: expected time_s in increasing order")
    return history


def maximum_depth(history):
    """(P_max in m, its time in s)."""
    i = int(np.argmax(history["penetration_m"]))
    return history["penetration_m"][i], history["time_s"][i]


def still_going(history):
    """Whether the deepest row is the last and the sphere was not yet
    turning back there (velocity_m_per_s > 0, or unknown)."""
    if int(np.argmax(history["penetration_m"])) != len(history["time_s"]) - 1:
        return False
    return "velocity_m_per_s" not in history or history["velocity_m_per_s"][-1] > 0


def depth_at(history, t):
    """The depth at time t (m), linear between rows; None past the end."""
    if t > history["time_s"][-1] or t < history["time_s"][0]:
        return None
    return float(np.interp(t, history["time_s"], history["penetration_m"]))


def percent(value, reference):
    """The difference from the reference as ' (+1.23%)'; empty where either has no value."""
    if value is None or reference is None or reference == 0:
        return ""
    return f" ({100 * (value / reference - 1):+.2f}%)"


def table(labels, histories, times):
    """Markdown lines: depth (um) at each time and P_max, each run against
    the first."""
    head = ["run"] + [f"{1e9 * t:.0f} ns" for t in times] + ["P_max (um)", "t(P_max) (ns)"]
    lines = ["| " + " | ".join(head) + " |", "|" + " --- |" * len(head)]
    ref = histories[0]
    ref_max, _ = maximum_depth(ref)
    for label, h in zip(labels, histories):
        cells = [label]
        for t in times:
            d = depth_at(h, t)
            cells.append("" if d is None else f"{1e6 * d:.2f}" +
                         ("" if h is ref else percent(d, depth_at(ref, t))))
        p_max, t_max = maximum_depth(h)
        if still_going(h):
            cells.append(f"{1e6 * p_max:.2f} (at the end: not yet a maximum)")
        else:
            cells.append(f"{1e6 * p_max:.2f}" + ("" if h is ref else percent(p_max, ref_max)))
        cells.append(f"{1e9 * t_max:.0f}")
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def plot(labels, histories, out):
    has_velocity = any("velocity_m_per_s" in h for h in histories)
    fig, axes = plt.subplots(1, 2 if has_velocity else 1, figsize=(11 if has_velocity else 6, 4))
    axes = np.atleast_1d(axes)
    for label, h in zip(labels, histories):
        axes[0].plot(1e9 * h["time_s"], 1e6 * h["penetration_m"], label=label)
        if has_velocity and "velocity_m_per_s" in h:
            axes[1].plot(1e9 * h["time_s"], h["velocity_m_per_s"], label=label)
    axes[0].set_ylabel("depth (um)")
    if has_velocity:
        axes[1].set_ylabel("sphere velocity (m/s)")
    for ax in axes:
        ax.set_xlabel("time (ns)")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", help="run folders or ballistics CSV files, reference first")
    ap.add_argument("--label", nargs="+", help="a name per run (default: the folder's name)")
    ap.add_argument("--times", nargs="+", type=float, help="table times (s)")
    ap.add_argument("--out", default="compare_runs.png", help="the plot (PNG)")
    args = ap.parse_args()
    if len(args.runs) < 2:
        ap.error("give a reference and at least one run to compare with it")
    labels = args.label or [os.path.basename(os.path.normpath(r)) for r in args.runs]
    if len(labels) != len(args.runs):
        ap.error(f"{len(labels)} labels for {len(args.runs)} runs")
    histories = [read_history(r) for r in args.runs]
    times = args.times
    if not times:
        end = min(h["time_s"][-1] for h in histories)
        times = [end * k / 8 for k in range(1, 9)]
    print("\n".join(table(labels, histories, times)))
    plot(labels, histories, args.out)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())

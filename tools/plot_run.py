#!/usr/bin/python3
"""Plots a run folder's history: the probe against time (with the case's
reference and window when it has one) and the energy balance.

usage: tools/plot_run.py RUN_FOLDER [--out FILE.png]
"""
import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_history(folder):
    path = os.path.join(folder, "history.csv")
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"plot_run: cannot read {path}: {e.strerror}")
    if not rows:
        sys.exit(f"plot_run: {path} has no rows")
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def read_summary(folder):
    try:
        with open(os.path.join(folder, "summary.json")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", help="run folder written by sph run")
    ap.add_argument("--out", help="PNG path (default RUN/history.png)")
    args = ap.parse_args()
    h = read_history(args.run)
    summary = read_summary(args.run)
    t_ms = [1e3 * t for t in h["time_s"]]
    probe = next(k for k in h if k.endswith("_m") and k != "time_s")
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    ax1.plot(t_ms, [1e3 * v for v in h[probe]], label=probe[:-2])
    if summary.get("reference_m") is not None:
        ax1.axhline(1e3 * summary["reference_m"], color="k", ls="--", label="reference")
    ax1.set_ylabel(f"{probe[:-2]} (mm)")
    ax1.legend()
    ax1.grid(alpha=0.3)
    for key, label in [("kinetic_energy_J", "kinetic"), ("internal_energy_J", "internal"),
                       ("external_work_J", "external work"), ("total_energy_J", "total (K + U - W)")]:
        ax2.plot(t_ms, h[key], label=label)
    ax2.set_xlabel("time (ms)")
    ax2.set_ylabel("energy (J)")
    ax2.legend()
    ax2.grid(alpha=0.3)
    fig.suptitle(f"{summary.get('case', '')}: {summary.get('status', '')}")
    out = args.out or os.path.join(args.run, "history.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plots a run folder: the probe against time (with the case's reference
when it has one), the energy balance, and for a penetration run the
sphere's depth, velocity, decelerating force and the cavity diameters
(ballistics.csv). Time and length units are chosen to fit the run.

usage: tools/plot_run.py RUN_FOLDER [--out FILE.png]
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import studylib  # noqa: E402


def read_csv(path, required=True):
    """Every column of a run's CSV (studylib.read_columns); None for a
    missing file that is not `required` (a run without a projectile has no
    ballistics.csv)."""
    if not required and not os.path.exists(path):
        return None
    return studylib.read_columns(path, "plot_run")


def read_summary(folder):
    try:
        with open(os.path.join(folder, "summary.json")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def unit_for(largest, base):
    """(scale, label) putting `largest` (in SI `base` units) between 1 and 1000."""
    for scale, prefix in [(1, ""), (1e3, "m"), (1e6, "u")]:
        if largest * scale >= 1:
            return scale, prefix + base
    return 1e9, "n" + base


def save_figure(fig, out):
    """Writes the figure as a PNG and prints its path as the last line."""
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(out)


def plot_probe(ax, h, summary, t, probe):
    values = h[probe]
    scale, unit = unit_for(max(abs(v) for v in values) or 1, "m")
    ax.plot(t, [scale * v for v in values], label=probe[:-2])
    if summary.get("reference_m") is not None:
        ax.axhline(scale * summary["reference_m"], color="k", ls="--", label="reference")
    ax.set_ylabel(f"{probe[:-2]} ({unit})")
    ax.legend()


def plot_energy(ax, h, t):
    for key, label in [("kinetic_energy_J", "kinetic (particles)"), ("internal_energy_J", "internal"),
                       ("external_work_J", "external work"),
                       ("artificial_viscosity_work_J", "artificial viscosity heat"),
                       ("total_energy_J", "total (ledger)")]:
        if key in h:
            ax.plot(t, h[key], label=label)
    ax.set_ylabel("energy (J)")
    ax.legend(fontsize=8)


def plot_ballistics(axes, b, summary, t_scale, t_unit):
    t = [t_scale * v for v in b["time_s"]]
    depth = b["penetration_m"]
    scale, unit = unit_for(max(abs(v) for v in depth) or 1, "m")
    ax = axes[0]
    ax.plot(t, [scale * v for v in depth], label="nose depth")
    if summary.get("perforated"):
        ax.set_title(f"perforated at {summary['exit_time_s'] * t_scale:.4g} {t_unit}, residual "
                     f"{summary['residual_velocity_m_per_s']:.4g} m/s", fontsize=9)
    cavity = [k for k in b if k.startswith("cavity_d1")]
    if cavity:
        ax.plot(t, [scale * max(b[k][i] for k in cavity) for i in range(len(t))],
                label="largest empty-cavity diameter")
    ax.set_ylabel(f"({unit})")
    ax.legend(fontsize=8)
    axes[1].plot(t, b["velocity_m_per_s"], label="velocity along the shot")
    axes[1].set_ylabel("velocity (m/s)")
    twin = axes[1].twinx()
    twin.plot(t, b["decelerating_force_N"], color="tab:red", lw=0.8, label="decelerating force")
    twin.set_ylabel("force (N)", color="tab:red")
    axes[1].legend(loc="upper right", fontsize=8)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", help="run folder written by sph run")
    ap.add_argument("--out", help="PNG path (default RUN/history.png)")
    args = ap.parse_args()
    h = read_csv(os.path.join(args.run, "history.csv"))
    b = read_csv(os.path.join(args.run, "ballistics.csv"), required=False)
    summary = read_summary(args.run)
    t_scale, t_unit = unit_for(max(h["time_s"]) or 1, "s")
    t = [t_scale * v for v in h["time_s"]]
    probe = next((k for k in h if k.endswith("_m") and f"{k[:-2]}_final_m" in summary), None)
    panels = (probe is not None) + 1 + (2 if b else 0)
    fig, axes = plt.subplots(panels, 1, figsize=(8, 2.6 * panels + 0.6), sharex=True)
    axes = list(axes) if panels > 1 else [axes]
    row = 0
    if probe:
        plot_probe(axes[row], h, summary, t, probe)
        row += 1
    if b:
        plot_ballistics(axes[row:row + 2], b, summary, t_scale, t_unit)
        row += 2
    plot_energy(axes[row], h, t)
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel(f"time ({t_unit})")
    fig.suptitle(f"{summary.get('case', '')}: {summary.get('status', '')}")
    save_figure(fig, args.out or os.path.join(args.run, "history.png"))


if __name__ == "__main__":
    main()

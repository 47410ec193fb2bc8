#!/usr/bin/python3
"""Plots of `sph bench --json` output (issue: performance you can measure).

  tools/bench_plot.py BENCH.json [MORE.json ...] [--out DIR] [--label TEXT ...]

Writes into DIR (default: the first file's folder):
  bench_throughput.png  particle-steps/s and time per step against particle
                        count (log-log), one line per scene family and file,
                        with a line of slope 1 through the smallest 3-D point
                        (time per step proportional to particle count);
  bench_kernels.png     share of the device time per kernel, one bar per scene;
  bench_summary.md/.csv the figures per scene.
Several files (e.g. before and after an optimisation) are drawn side by side,
labelled by --label or by file name.
"""
import argparse
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from studylib import write_table  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def family(name):
    """'taylor3d-200k' -> 'taylor3d': scenes that differ only in size."""
    return re.sub(r"-\d+[km]?$", "", name)


def plot_throughput(runs, path):
    fig, (ax_rate, ax_time) = plt.subplots(1, 2, figsize=(11, 4.5))
    for label, bench in runs:
        groups = {}
        for s in bench["scenes"]:
            groups.setdefault(family(s["name"]), []).append(s)
        for fam, scenes in sorted(groups.items()):
            scenes.sort(key=lambda s: s["particles"])
            n = [s["particles"] for s in scenes]
            tag = f"{fam} ({label})" if len(runs) > 1 else fam
            ax_rate.plot(n, [s["particle_steps_per_s"] for s in scenes], "o-", label=tag)
            ax_time.plot(n, [s["median_seconds_per_step"] for s in scenes], "o-", label=tag)
            if len(scenes) > 1 and scenes[0]["dimension"] == 3:
                n0, t0 = n[0], scenes[0]["median_seconds_per_step"]
                ax_time.plot([n0, n[-1]], [t0, t0 * n[-1] / n0], "k:", lw=1,
                             label="slope 1 (linear)" if fam == "taylor3d" else None)
    for ax in (ax_rate, ax_time):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("particles")
        ax.grid(True, which="both", alpha=0.3)
    ax_rate.set_ylabel("particle-steps per second")
    ax_time.set_ylabel("seconds per step (median)")
    ax_rate.legend(fontsize=8)
    ax_time.legend(fontsize=8)
    fig.suptitle(runs[0][1]["device"], fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_kernels(runs, path, top=7):
    bars = [(f"{s['name']}\n{label}" if len(runs) > 1 else s["name"], s)
            for label, bench in runs for s in bench["scenes"]]
    totals = {}
    for _, s in bars:
        for k in s["kernels"]:
            totals[k["kernel"]] = totals.get(k["kernel"], 0) + k["share"]
    named = [k for k, _ in sorted(totals.items(), key=lambda kv: -kv[1])[:top]]
    fig, ax = plt.subplots(figsize=(max(6, 1.2 * len(bars)), 4.5))
    bottom = [0.0] * len(bars)
    for kernel in named + ["other"]:
        heights = []
        for _, s in bars:
            shares = {k["kernel"]: k["share"] for k in s["kernels"]}
            heights.append(sum(v for k, v in shares.items() if k not in named)
                           if kernel == "other" else shares.get(kernel, 0))
        ax.bar(range(len(bars)), heights, bottom=bottom, label=kernel)
        bottom = [b + h for b, h in zip(bottom, heights)]
    ax.set_xticks(range(len(bars)))
    ax.set_xticklabels([b[0] for b in bars], fontsize=8)
    ax.set_ylabel("share of device time")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1, 1))
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="+")
    ap.add_argument("--out")
    ap.add_argument("--label", nargs="+")
    args = ap.parse_args()
    labels = args.label or [os.path.splitext(os.path.basename(f))[0] for f in args.files]
    if len(labels) != len(args.files):
        sys.exit("bench_plot: give one --label per file")
    runs = []
    for label, path in zip(labels, args.files):
        with open(path) as f:
            runs.append((label, json.load(f)))
    out = args.out or os.path.dirname(os.path.abspath(args.files[0]))
    os.makedirs(out, exist_ok=True)
    plot_throughput(runs, os.path.join(out, "bench_throughput.png"))
    plot_kernels(runs, os.path.join(out, "bench_kernels.png"))
    header = ["file", "scene", "particles", "neighbours", "ms per step", "particle-steps/s",
              "pair interactions/s", "bytes/particle", "top kernel (share)"]
    rows = []
    for label, bench in runs:
        for s in bench["scenes"]:
            top = max(s["kernels"], key=lambda k: k["share"])
            rows.append([label, s["name"], s["particles"], f"{s['neighbours_mean']:.1f}",
                         f"{1e3 * s['median_seconds_per_step']:.2f}",
                         f"{s['particle_steps_per_s']:.3g}",
                         f"{s['pair_interactions_per_s']:.3g}",
                         f"{s['bytes_per_particle']:.0f}",
                         f"{top['kernel']} ({100 * top['share']:.0f}%)"])
    write_table(out, "bench_summary", header, rows)
    print(f"bench_plot: wrote bench_throughput.png, bench_kernels.png, bench_summary.md in {out}")


if __name__ == "__main__":
    main()

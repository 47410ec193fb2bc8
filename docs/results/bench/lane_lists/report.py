#!/usr/bin/python3
"""The interleaved benchmarks of the lane lists (docs/performance.md, "The
lane lists"): per round, the median time per step and passes 1 and 2 of each
build, with the mean CPU steal vmstat saw during it (this machine is a VM
whose neighbours take up to half its time; a round with steal above 5% is
not comparable), and the ratio old / list.

  FOLDER/{list,walk,old}_ROUND.json  sph bench --json of: the lists (this
                                     build), the same build with
                                     SPH_BUILD_OPTIONS=-DSPH_LANE_CELL_WALK,
                                     the build before (fc8a593; in
                                     taylor3d-200k_vs_8c0dbd5/, 8c0dbd5,
                                     before the material fast path too)
  FOLDER/vm_{...}_ROUND.log          vmstat 1 during that run

usage: report.py FOLDER [--max-steal 5]
"""
import argparse
import glob
import json
import os
import statistics


def load(folder, build, rnd):
    scene = json.load(open(os.path.join(folder, f"{build}_{rnd}.json")))["scenes"][0]
    ms = {k["kernel"]: k["s_per_step"] * 1e3 for k in scene["kernels"]}
    steal = []
    for line in open(os.path.join(folder, f"vm_{build}_{rnd}.log")):
        p = line.split()
        if len(p) > 16 and p[0].isdigit():
            steal.append(int(p[16]))
    pass1 = ms.get("pass1_velocity_gradient", ms.get("tl_deformation"))
    pass2 = ms.get("pass2_momentum_energy", ms.get("tl_momentum"))
    return (statistics.median(scene["seconds_per_step"]) * 1e3, pass1, pass2,
            statistics.mean(steal[1:] or [0]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folder")
    ap.add_argument("--max-steal", type=float, default=5.0)
    a = ap.parse_args()
    rounds = sorted({f.rsplit("_", 1)[1][:-5] for f in glob.glob(os.path.join(a.folder, "list_*.json"))},
                    key=int)
    builds = [b for b in ("list", "walk", "old") if glob.glob(os.path.join(a.folder, f"{b}_*.json"))]
    print("round  " + " | ".join(f"{b}: step pass1 pass2 steal" for b in builds) + " | old/list")
    kept = []
    for r in rounds:
        rows = {b: load(a.folder, b, r) for b in builds}
        clean = all(v[3] <= a.max_steal for v in rows.values())
        ratio = rows["old"][0] / rows["list"][0]
        if clean:
            kept.append(ratio)
        print(f"{r:>5}  " + " | ".join(f"{v[0]:6.1f} {v[1]:5.1f} {v[2]:5.1f} {v[3]:3.0f}%"
                                        for v in rows.values())
              + f" | {ratio:.3f}" + ("" if clean else "  (steal: left out)"))
    if kept:
        print(f"old / list over the {len(kept)} rounds with steal <= {a.max_steal:g}%: median "
              f"{statistics.median(kept):.3f}, range {min(kept):.3f}-{max(kept):.3f}")


if __name__ == "__main__":
    main()

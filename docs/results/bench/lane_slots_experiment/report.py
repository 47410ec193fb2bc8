#!/usr/bin/python3
"""Lane blocks without ghosts against the build before (docs/performance.md,
"Lane blocks without ghosts"): per scene and round, the median time per
step, passes 1 and 2 and the lists' build (ms per step) of each build, the
particle-steps/s, and base / slots.

  FOLDER/{SCENE}_{base,slots}_{ROUND}.json  sph bench --json (run.sh)

usage: report.py FOLDER [OTHER]   (OTHER: the second build's name, default slots)
"""
import glob
import json
import os
import statistics
import sys


def load(path):
    scene = json.load(open(path))["scenes"][0]
    ms = {k["kernel"]: k["s_per_step"] * 1e3 for k in scene["kernels"]}
    step = statistics.median(scene["seconds_per_step"]) * 1e3
    return (step, ms.get("pass1_velocity_gradient", 0), ms.get("pass2_momentum_energy", 0),
            ms.get("lane_list_build", 0), scene["particle_steps_per_s"] / 1e6)


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "."
    other = sys.argv[2] if len(sys.argv) > 2 else "slots"
    names = sorted(glob.glob(os.path.join(folder, "*_base_*.json")))
    print(f"scene round | base: step pass1 pass2 build (ms) Mps | {other}: same | base/{other} step")
    for base in names:
        scene, _, rnd = os.path.basename(base)[:-5].rsplit("_", 2)
        slots = base.replace("_base_", f"_{other}_")
        b, s = load(base), load(slots)
        print(f"{scene} {rnd} | " + " ".join(f"{v:6.1f}" for v in b[:4]) + f" {b[4]:.2f} | "
              + " ".join(f"{v:6.1f}" for v in s[:4]) + f" {s[4]:.2f} | {b[0] / s[0]:.3f}")


if __name__ == "__main__":
    main()

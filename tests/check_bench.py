#!/usr/bin/python3
"""Smoke test of `sph bench --quick` and `sph run --profile`: both run, and
every figure they report is finite and positive. It asserts no speed.

usage: check_bench.py SPH BENCH_JSON RUN_CASE RUN_FOLDER
"""
import json
import math
import os
import subprocess
import sys


def positive(value):
    return isinstance(value, (int, float)) and math.isfinite(value) and value > 0


def check_kernels(where, kernels, failures):
    if not kernels:
        failures.append(f"{where}: no kernel rows")
    for k in kernels:
        for key in ("calls", "device_s", "s_per_call"):
            if not positive(k.get(key)):
                failures.append(f"{where}: kernel {k.get('kernel')} {key} = {k.get(key)}")
    share = sum(k["share"] for k in kernels)
    if abs(share - 1) > 1e-3:
        failures.append(f"{where}: kernel shares add up to {share}")


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    sph, bench_json, case, folder = sys.argv[1:]
    failures = []
    proc = subprocess.run([sph, "bench", "--quick", "--json", bench_json], capture_output=True,
                          text=True)
    sys.stdout.write(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        failures.append(f"sph bench --quick exited {proc.returncode}")
    else:
        with open(bench_json) as f:
            bench = json.load(f)
        for key in ("ceiling_gb_per_s", "ceiling_gflop_per_s"):
            if not positive(bench.get(key)):
                failures.append(f"bench {key} = {bench.get(key)}")
        if len(bench["scenes"]) < 3:
            failures.append(f"{len(bench['scenes'])} scenes ran, expected 3 (the quick suite)")
        for scene in bench["scenes"]:
            for key in ("particles", "neighbours_mean", "median_seconds_per_step",
                        "particle_steps_per_s", "pair_interactions_per_s", "bytes_per_particle"):
                if not positive(scene.get(key)):
                    failures.append(f"{scene['name']}: {key} = {scene.get(key)}")
            steal = scene.get("cpu_steal_fraction", "absent")
            if steal is not None and not (isinstance(steal, (int, float)) and 0 <= steal <= 1):
                failures.append(f"{scene['name']}: cpu_steal_fraction = {steal}")
            check_kernels(scene["name"], scene["kernels"], failures)
            if sum(scene["memory_bytes_per_slot"].values()) != scene["bytes_per_slot"]:
                failures.append(f"{scene['name']}: the memory breakdown does not add up")
    proc = subprocess.run([sph, "run", case, "--out", folder, "--quiet", "--profile", "--set",
                           "numerics.dx=2e-3", "--set", "numerics.end_time=2e-5"],
                          capture_output=True, text=True)
    sys.stdout.write(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        failures.append(f"sph run --profile exited {proc.returncode}")
    elif "pass2_" not in proc.stdout:
        failures.append("sph run --profile printed no kernel table")
    else:
        with open(os.path.join(folder, "profile.json")) as f:
            profile = json.load(f)
        check_kernels("run --profile", profile["kernels"], failures)
        if not positive(profile.get("wall_s")) or profile["device_s"] > profile["wall_s"] * 1.05:
            failures.append(f"run --profile: device {profile['device_s']} s, wall "
                            f"{profile['wall_s']} s")
    for f in failures:
        print("FAIL: " + f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Strong scaling of one case over MPI ranks on this machine, and a model of
weak scaling to many ranks from what was measured (docs/scaling.md).

Each rank count runs `mpirun -np R sph run CASE --profile` with PoCL held to
one thread per rank and each rank bound to a core, so that R ranks use R
cores; the time per step is profile.json's time loop over its steps (set-up
and the first build are not in it). The halo figures are summary.json's.

The model: a rank holds N particles in a cube of side N^(1/3) dx (an
orthogonal bisection; today's slabs are its one-axis form) and exchanges a
shell w = support (1 + skin) thick with its 26 neighbours twice a step
(before each neighbour pass), plus three small reductions (log2 P
latencies each). Compute time per particle-step is the one-rank
measurement (or --compute-seconds, e.g. a GPU's); the bytes per halo
particle per step are the measured ones; the network is stated
(--bandwidth, --latency). No overlap of exchange and work is assumed.
Efficiency = compute / (compute + exchange). (The halo refreshes of
host/domain.c are point-to-point with the ranks that share a halo, as
modelled; the re-sort's migration, every few steps, goes through
MPI_Alltoall(v) over every rank and is not in the model.)

usage: scaling_study.py [--case CASE] [--set K=V ...] [--ranks 1 2] [--out DIR]
       [--per-rank N ...] [--model-ranks 8 64 512] [--bandwidth GB/s]
       [--latency us] [--gpu-memory GiB] [--compute-seconds S]"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import studylib  # noqa: E402

HALO_REFRESHES = 2  # per step: before pass 2 (every mirrored field), before pass 1
REDUCTIONS = 3  # per step: the step's figures, the interrupt flag, the drift bound's share


def run_ranks(a, ranks):
    folder = os.path.join(a.out, "ranks%d" % ranks)
    shutil.rmtree(folder, ignore_errors=True)
    mpirun = shutil.which("mpirun")
    if not mpirun:
        sys.exit("scaling_study: mpirun not found (Debian: openmpi-bin)")
    cmd = [mpirun, "--oversubscribe", "-np", str(ranks), "-x", "POCL_MAX_PTHREAD_COUNT=1"]
    cmd += ["--bind-to", "core", "--map-by", "core"] if a.bind else ["--bind-to", "none"]
    cmd += [studylib.SPH, "run", a.case, "--out", folder, "--quiet", "--profile"]
    for s in a.set:
        cmd += ["--set", s]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    print("$ " + " ".join(cmd), flush=True)
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        sys.stderr.write(proc.stdout[-3000:] + proc.stderr[-3000:])
        sys.exit("scaling_study: %d ranks exited with %d" % (ranks, proc.returncode))
    with open(os.path.join(folder, "profile.json")) as f:
        profile = json.load(f)
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    steps = profile["steps"]
    return {
        "ranks": ranks,
        "particles": summary["particles"],
        "steps": steps,
        "ms_per_step": 1e3 * profile["wall_s"] / steps,
        "halo_particles_per_rank": summary.get("halo_particles_per_rank", 0.0),
        "halo_bytes_per_step_per_rank": summary.get("halo_bytes_per_step_per_rank", 0.0),
        "bytes_per_particle": summary["bytes_per_particle"],
        "migrated_particles": summary.get("migrated_particles", 0),
    }


def model(a, t_particle, bytes_per_halo_particle, bytes_per_particle, support_over_dx):
    """Weak-scaling efficiency per (particles per rank, ranks)."""
    w = support_over_dx  # shell thickness in spacings
    rows = []
    for n in a.per_rank:
        side = n ** (1.0 / 3.0)
        halo = (side + 2 * w) ** 3 - n  # a cube's shell, all 26 neighbours
        compute = n * t_particle
        for p in a.model_ranks:
            neighbours = min(26, p - 1)
            shell = halo if p > 1 else 0.0
            volume = shell * bytes_per_halo_particle
            exchange = HALO_REFRESHES * (neighbours * a.latency * 1e-6) + volume / (
                a.bandwidth * 1e9)
            exchange += REDUCTIONS * math.log2(max(p, 2)) * a.latency * 1e-6
            rows.append([n, p, "%.3g" % halo, "%.3g" % (volume / 1e6),
                         "%.3g" % (1e3 * compute), "%.3g" % (1e3 * exchange),
                         "%.3f" % (compute / (compute + exchange))])
    gib = a.gpu_memory * 2 ** 30
    largest = gib / (bytes_per_particle * 1.25)  # room for halo and migration
    return rows, largest


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--case", default=os.path.join(studylib.ROOT, "cases", "taylor_3d_4340.yaml"))
    p.add_argument("--set", action="append", default=None,
                   help="case overrides (default: the 200k bar of sph bench, 20 steps)")
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--out", default="runs/scaling_study")
    p.add_argument("--no-bind", dest="bind", action="store_false",
                   help="do not bind ranks to cores (more ranks than cores)")
    p.add_argument("--per-rank", type=float, nargs="+", default=[1e5, 1e6, 1e7])
    p.add_argument("--model-ranks", type=int, nargs="+", default=[8, 64, 512])
    p.add_argument("--bandwidth", type=float, default=12.5,
                   help="GB/s per rank (default 12.5: 100 Gb/s InfiniBand)")
    p.add_argument("--latency", type=float, default=2.0, help="us per message (default 2)")
    p.add_argument("--gpu-memory", type=float, default=80.0, help="GiB (default 80: H100)")
    p.add_argument("--compute-seconds", type=float, default=None,
                   help="s per particle-step for the model (default: the one-rank measurement)")
    a = p.parse_args()
    if a.set is None:
        a.set = ["numerics.dx=1.29e-4", "numerics.h_over_dx=1.2", "numerics.end_time=2.3e-7",
                 "output.snapshot_interval=1e-3", "output.history_interval=1e-3"]
    os.makedirs(a.out, exist_ok=True)
    measured = [run_ranks(a, r) for r in a.ranks]
    base = measured[0]
    rows = []
    for m in measured:
        speedup = base["ms_per_step"] / m["ms_per_step"] * base["ranks"]
        halo = m["halo_particles_per_rank"]
        per_rank = m["particles"] / m["ranks"]
        rows.append([m["ranks"], m["particles"], m["steps"], "%.1f" % m["ms_per_step"],
                     "%.3f" % (m["particles"] / m["ms_per_step"] / 1e3), "%.2f" % speedup,
                     "%.2f" % (speedup / m["ranks"]), "%.0f" % halo,
                     "%.3f" % (halo / per_rank), "%.3g" % m["halo_bytes_per_step_per_rank"],
                     m["migrated_particles"]])
    studylib.write_table(a.out, "strong_scaling",
                         ["ranks", "particles", "steps", "ms/step", "M particle-steps/s",
                          "speed-up", "efficiency", "halo particles/rank",
                          "halo/particles per rank", "halo bytes/step/rank", "migrated"], rows)
    with_halo = [m for m in measured if m["halo_particles_per_rank"] > 0]
    if not with_halo:
        print("scaling_study: no run over several ranks: no halo to model")
        return
    m = with_halo[0]
    bytes_per_halo = m["halo_bytes_per_step_per_rank"] / m["halo_particles_per_rank"]
    t_particle = base["ms_per_step"] * 1e-3 * base["ranks"] / base["particles"]
    if a.compute_seconds:
        t_particle = a.compute_seconds
    # the support (1 + skin) in spacings from the case's h / dx (Wendland C2: 2h)
    h_over_dx = next((float(s.split("=")[1]) for s in a.set if s.startswith(
        "numerics.h_over_dx=")), 1.5)
    rows, largest = model(a, t_particle, bytes_per_halo, base["bytes_per_particle"],
                          2 * h_over_dx * 1.2)
    print("model inputs: %.3g s per particle-step (one core measured, or --compute-seconds), "
          "%.0f bytes per halo particle "
          "per step, %.4g GB/s, %.3g us, %d bytes per particle"
          % (t_particle, bytes_per_halo, a.bandwidth, a.latency, base["bytes_per_particle"]))
    studylib.write_table(a.out, "weak_scaling_model",
                         ["particles/rank", "ranks", "halo particles", "halo MB/step",
                          "compute ms/step", "exchange ms/step", "efficiency"], rows)
    print("largest case per %.0f GiB GPU: %.3g particles (at %d bytes each, 25%% room for "
          "halo and migration)" % (a.gpu_memory, largest, base["bytes_per_particle"]))
    with open(os.path.join(a.out, "scaling.json"), "w") as f:
        json.dump({"measured": measured, "seconds_per_particle_step": t_particle,
                   "bytes_per_halo_particle_per_step": bytes_per_halo,
                   "bandwidth_gb_s": a.bandwidth, "latency_us": a.latency,
                   "largest_per_gpu": largest}, f, indent=2)


if __name__ == "__main__":
    main()

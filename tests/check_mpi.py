#!/usr/bin/env python3
"""One case over several MPI processes against the same case as one process
(host/domain.c): the run completes on every rank count, particles migrate
between ranks (summary.json counts them) and none is lost or duplicated
(every snapshot holds each scene index exactly once, in the serial file's
order), the snapshots' positions and the figures agree
with the serial run to the tolerances given (float: the ranks add the same
terms in another order, so agreement is to rounding, amplified where the
physics is sensitive).

usage: check_mpi.py SPH CASE OUT --ranks 2 3 [--set K=V ...]
       [--summary KEY REL ...] [--history COLUMN REL ...] [--migration required|none|any]
       [--at-most KEY VALUE ...] [--positions REL]
Exit 77 (ctest: skipped) when mpirun is missing."""
import argparse
import csv
import glob
import json
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np


def run(command, env, log):
    with open(log, "w") as f:
        result = subprocess.run(command, env=env, stdout=f, stderr=subprocess.STDOUT)
    if result.returncode != 0:
        sys.stdout.write(open(log).read()[-4000:])
        sys.exit("FAIL: %s exited %d" % (" ".join(command), result.returncode))


def history(folder):
    rows = list(csv.DictReader(open(os.path.join(folder, "history.csv"))))
    if not rows:
        sys.exit("FAIL: %s/history.csv is empty" % folder)
    return rows


def check_snapshots(folder, serial, particles, tolerance):
    """Each snapshot holds every scene index once, in scene order (the
    serial file's layout, whoever wrote which rows), and its positions lie
    within `tolerance` of the body's extent of the serial run's."""
    files = sorted(glob.glob(os.path.join(folder, "snap_*.h5")))
    if len(files) < 2 or len(files) != len(glob.glob(os.path.join(serial, "snap_*.h5"))):
        sys.exit("FAIL: %s has %d snapshots" % (folder, len(files)))
    worst = 0.0
    for name in files:
        with h5py.File(name, "r") as f, \
                h5py.File(os.path.join(serial, os.path.basename(name)), "r") as g:
            ids = f["id"][...]
            if len(ids) != particles or not np.array_equal(ids, np.arange(particles)):
                sys.exit("FAIL: %s holds %d ids, not 0 .. %d in order"
                         % (name, len(ids), particles - 1))
            x, y = f["position"][...], g["position"][...]
            extent = np.max(np.ptp(y, axis=0))
            worst = max(worst, np.max(np.abs(x - y)) / extent)
    print("  snapshot positions: largest difference %.2e of the body's extent (limit %g)"
          % (worst, tolerance))
    if not worst <= tolerance:
        sys.exit("FAIL: %s: positions differ by %.2e of the extent" % (folder, worst))
    return len(files)


def relative(a, b):
    scale = max(abs(a), abs(b))
    return abs(a - b) / scale if scale > 0 else 0.0


def main():
    p = argparse.ArgumentParser()
    p.add_argument("sph")
    p.add_argument("case")
    p.add_argument("out")
    p.add_argument("--ranks", type=int, nargs="+", required=True)
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--summary", nargs=2, action="append", default=[],
                   metavar=("KEY", "REL"))
    p.add_argument("--history", nargs=2, action="append", default=[],
                   metavar=("COLUMN", "REL"))
    p.add_argument("--migration", choices=("required", "none", "any"), default="required",
                   help="particles must change rank (default), must not (the total "
                   "Lagrangian form keeps its reference ranks), or may")
    p.add_argument("--at-most", nargs=2, action="append", default=[],
                   metavar=("KEY", "VALUE"), help="a summary figure of every multi-rank "
                   "run must not exceed VALUE (e.g. the halo a decomposition makes)")
    p.add_argument("--positions", type=float, default=1e-5, metavar="REL",
                   help="snapshot positions within REL of the body's extent of the serial "
                   "run's (default 1e-5)")
    a = p.parse_args()
    mpirun = shutil.which("mpirun")
    if not mpirun:
        print("SKIPPED: mpirun not found (Debian: openmpi-bin)")
        sys.exit(77)
    sets = [x for s in a.set for x in ("--set", s)]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    shutil.rmtree(a.out, ignore_errors=True)
    os.makedirs(a.out)
    serial = os.path.join(a.out, "serial")
    run([a.sph, "run", a.case, "--out", serial, "--quiet"] + sets, env,
        os.path.join(a.out, "serial.log"))
    base = json.load(open(os.path.join(serial, "summary.json")))
    base_history = history(serial)
    particles = base["particles"]
    for n in a.ranks:
        folder = os.path.join(a.out, "ranks%d" % n)
        # one PoCL thread per rank: the ranks share this machine's cores
        run([mpirun, "--oversubscribe", "--bind-to", "none", "-np", str(n),
             "-x", "POCL_MAX_PTHREAD_COUNT=1", "-x", "POCL_CACHE_DIR", a.sph, "run", a.case,
             "--out", folder, "--quiet"] + sets, env, os.path.join(a.out, "ranks%d.log" % n))
        s = json.load(open(os.path.join(folder, "summary.json")))
        if s.get("processes") != n or s["status"] != base["status"]:
            sys.exit("FAIL: %d ranks: processes %s, status %s (serial %s)"
                     % (n, s.get("processes"), s["status"], base["status"]))
        if a.migration == "none" and s.get("migrated_particles", 0) != 0:
            sys.exit("FAIL: %d ranks: %d particles changed rank in the total Lagrangian form"
                     % (n, s["migrated_particles"]))
        if a.migration == "required" and not s.get("migrated_particles", 0) > 0:
            sys.exit("FAIL: %d ranks: no particle changed rank (the test must see migration)" % n)
        snapshots = check_snapshots(folder, serial, particles, a.positions)
        print("%d ranks: %d particles in each of %d snapshots, %d migrations, %d re-cuts"
              % (n, particles, snapshots, s["migrated_particles"], s["rebalances"]))
        for key, tolerance in a.summary:
            d = relative(base[key], s[key])
            print("  %s: serial %.9g, %d ranks %.9g, relative %.2e (limit %s)"
                  % (key, base[key], n, s[key], d, tolerance))
            if not d <= float(tolerance):
                sys.exit("FAIL: %s differs by %.2e relative on %d ranks" % (key, d, n))
        for key, limit in a.at_most:
            print("  %s: %.9g on %d ranks (at most %s)" % (key, s[key], n, limit))
            if not s[key] <= float(limit):
                sys.exit("FAIL: %s is %.9g on %d ranks, above %s" % (key, s[key], n, limit))
        rows = history(folder)
        if len(rows) != len(base_history):
            sys.exit("FAIL: %d history rows on %d ranks, %d serial"
                     % (len(rows), n, len(base_history)))
        for column, tolerance in a.history:
            x = np.array([float(r[column]) for r in base_history])
            y = np.array([float(r[column]) for r in rows])
            d = np.max(np.abs(x - y)) / max(np.max(np.abs(x)), 1e-300)
            print("  %s: largest difference over the history %.2e of its largest value "
                  "(limit %s)" % (column, d, tolerance))
            if not d <= float(tolerance):
                sys.exit("FAIL: %s differs by %.2e on %d ranks" % (column, d, n))
    print("PASS")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Checkpoints and `sph resume` (host/checkpoint.c) against a run that was
never interrupted.

usage: check_resume.py SPH CASE WORK_DIR [--raise-at-step N] [--set K=V ...]

1. reference: CASE run to its end with output.checkpoint_interval set, so
   the folder ends with a checkpoint part-way; it must be identical to the
   same run without checkpoints (they only read the device);
2. interrupted: the same run, sent SIGINT once its history has a fifth of
   its rows (or, with --raise-at-step, raising SIGINT itself after step N:
   SPH_RAISE_AT_STEP, for runs too short to catch from outside): it must exit 130 with status "interrupted" in summary.json and
   the resume command in the message; then `sph resume` must finish it with
   history.csv (and ballistics.csv) byte-identical to the reference and every
   dataset of every snapshot equal;
3. resume of the reference folder redoes the tail after its last
   checkpoint, again identically;
4. refusals: a folder without a checkpoint, and a case.resolved.yaml
   whose values were edited after the checkpoint, exit 1 with a message that says so and
   leave history.csv as it was.

With SPH_LAUNCHER set (e.g. "mpirun -np 2") every command runs through it:
a run over several processes, one checkpoint file per rank; the interrupt
must then come from --raise-at-step (every rank raises at the same step),
and the two-SIGINT check, which is about one process's signal handling, is
left out.
"""
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

LAUNCH = os.environ.get("SPH_LAUNCHER", "").split()


def fail(message):
    print("FAIL:", message)
    sys.exit(1)


def run(sph, args, expect):
    p = subprocess.run(LAUNCH + [sph] + args, capture_output=True, text=True)
    if p.returncode != expect:
        fail(f"{' '.join(args)}: exit {p.returncode}, expected {expect}\n{p.stderr[-2000:]}")
    return p


def rows(path):
    with open(path) as f:
        return sum(1 for _ in f)


def same_group(ga, gb):
    """The first difference between two HDF5 groups, recursively: names,
    attributes and every dataset's values; None when identical."""
    if set(ga.keys()) != set(gb.keys()):
        return f"{ga.name}: members {sorted(ga.keys())} against {sorted(gb.keys())}"
    if set(ga.attrs.keys()) != set(gb.attrs.keys()):
        return f"{ga.name}: other attributes"
    for key in ga.attrs:
        if not np.array_equal(np.asarray(ga.attrs[key]), np.asarray(gb.attrs[key])):
            return f"{ga.name}: attribute {key} differs"
    for key in ga:
        a, b = ga[key], gb[key]
        if isinstance(a, h5py.Group):
            problem = same_group(a, b)
            if problem:
                return problem
        elif not np.array_equal(a[()], b[()], equal_nan=True):
            return f"{a.name} differs"
    return None


def same_outputs(a, b, what):
    for name in ("history.csv", "ballistics.csv", "snapshots.xdmf"):
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if os.path.exists(pa) != os.path.exists(pb):
            fail(f"{what}: {name} in one folder only")
        if os.path.exists(pa) and open(pa, "rb").read() != open(pb, "rb").read():
            fail(f"{what}: {name} differs from the uninterrupted run")
    snaps = sorted(f for f in os.listdir(a) if f.startswith("snap_"))
    if snaps != sorted(f for f in os.listdir(b) if f.startswith("snap_")):
        fail(f"{what}: other snapshot files")
    for s in snaps:
        with h5py.File(os.path.join(a, s)) as fa, h5py.File(os.path.join(b, s)) as fb:
            problem = same_group(fa, fb)
            if problem:
                fail(f"{what}: {s}: {problem}")
    print(f"{what}: history, snapshots ({len(snaps)}) identical")


def main():
    sph, case, work = sys.argv[1], sys.argv[2], sys.argv[3]
    sets = sys.argv[4:]
    raise_at = None
    if sets[:1] == ["--raise-at-step"]:
        raise_at, sets = sets[1], sets[2:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    ref, cut = os.path.join(work, "reference"), os.path.join(work, "interrupted")
    run(sph, ["run", case, "--out", ref, "--quiet"] + sets, 0)
    total = rows(os.path.join(ref, "history.csv"))
    # checkpoints only read the device: the reference, which wrote them, is
    # the run without any
    plain = os.path.join(work, "no_checkpoints")
    run(sph, ["run", case, "--out", plain, "--quiet"] + sets +
        ["--set", "output.checkpoint_interval=0", "--set", "output.checkpoint_wall_interval=0"], 0)
    same_outputs(plain, ref, "with checkpoints against without")

    env = dict(os.environ)
    if raise_at:
        env["SPH_RAISE_AT_STEP"] = raise_at
    if LAUNCH and not raise_at:
        fail("SPH_LAUNCHER needs --raise-at-step (a signal to the launcher is its own)")
    p = subprocess.Popen(LAUNCH + [sph, "run", case, "--out", cut, "--quiet"] + sets, env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    history = os.path.join(cut, "history.csv")
    deadline = time.time() + 600
    while p.poll() is None and time.time() < deadline:
        if not raise_at and os.path.exists(history) and rows(history) > total // 5:
            p.send_signal(signal.SIGINT)
            break
        time.sleep(0.05)
    out, err = p.communicate()
    if p.returncode != 130:
        fail(f"interrupted run: exit {p.returncode}, expected 130\n{err[-2000:]}")
    summary = json.load(open(os.path.join(cut, "summary.json")))
    if summary["status"] != "interrupted" or "sph resume" not in summary["message"]:
        fail(f"interrupted run: summary status {summary['status']!r}, message "
             f"{summary['message']!r}")
    print(f"interrupted at step {summary['steps']} of the reference's "
          f"{json.load(open(os.path.join(ref, 'summary.json')))['steps']}: exit 130")
    run(sph, ["resume", cut, "--quiet"], 0)
    same_outputs(ref, cut, "interrupted and resumed")

    again = os.path.join(work, "again")
    shutil.copytree(ref, again)
    run(sph, ["resume", again, "--quiet"], 0)
    same_outputs(ref, again, "resumed from the last checkpoint")

    empty = os.path.join(work, "empty")
    os.makedirs(empty)
    p = run(sph, ["resume", empty], 1)
    if "no checkpoint" not in p.stderr:
        fail(f"resume without a checkpoint: {p.stderr!r}")
    # a comment changes nothing; a value does (the case is compared, not the text)
    resolved = os.path.join(again, "case.resolved.yaml")
    text = open(resolved).read()
    edited = re.sub(r"(\n\s*cfl: )([0-9.eE+-]+)", lambda m: m.group(1) + repr(float(m.group(2)) * 0.9),
                    text, count=1)
    if edited == text:
        fail("no cfl line to edit in the resolved case")
    open(resolved, "w").write("# a comment\n" + edited)
    before = open(os.path.join(again, "history.csv"), "rb").read()
    p = run(sph, ["resume", again], 1)
    if "is not the case" not in p.stderr:
        fail(f"resume of an edited case: {p.stderr!r}")
    if open(os.path.join(again, "history.csv"), "rb").read() != before:
        fail("a refused resume changed history.csv")
    print("refusals: no checkpoint, edited case: exit 1 with the reason")

    if LAUNCH:
        return
    # Ctrl-C pressed twice: the second signal ends the process at once (the
    # default action of SIGINT), and what was written before stays readable
    twice = os.path.join(work, "twice")
    env = dict(os.environ, SPH_RAISE_AT_STEP=str(max(1, summary["steps"] // 2)),
               SPH_RAISE_COUNT="2")
    p = subprocess.run([sph, "run", case, "--out", twice, "--quiet"] + sets, env=env,
                       capture_output=True, text=True, timeout=600)
    if p.returncode != -signal.SIGINT:
        fail(f"two SIGINTs: exit {p.returncode}, expected death by SIGINT\n{p.stderr[-2000:]}")
    if rows(os.path.join(twice, "history.csv")) < 2:
        fail("two SIGINTs: history.csv lost")
    print("a second SIGINT ends the run at once; history.csv kept")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Outputs under a file size limit (RLIMIT_FSIZE, as `ulimit -f` sets it):
the run must stop with exit 1 and a readable summary.json (status
output_error, a message naming the file), never crash or leave a truncated
snapshot, index or summary behind (every such file is written under a
temporary name and renamed).

usage: check_disk_full.py SPH CASE WORK_DIR LIMIT_BYTES WHAT [--set K=V ...]

WHAT is a text the summary's message must contain (the file that could not
be written). The case is first run for one step without a limit so the
kernel cache (which a cold PoCL writes while building) exists.
"""
import glob
import json
import os
import resource
import shutil
import subprocess
import sys

import h5py


def main():
    sph, case, work, limit, what = sys.argv[1:6]
    sets = sys.argv[6:]
    shutil.rmtree(work, ignore_errors=True)
    warm = subprocess.run([sph, "run", case, "--out", work + "-warm", "--quiet"] + sets +
                          ["--set", "numerics.end_time=1e-12"], capture_output=True, text=True)
    if warm.returncode != 0:
        print("FAIL: warm-up run:", warm.stderr[-1500:])
        return 1

    def cap():
        resource.setrlimit(resource.RLIMIT_FSIZE, (int(limit), int(limit)))

    p = subprocess.run([sph, "run", case, "--out", work, "--quiet"] + sets, capture_output=True,
                       text=True, preexec_fn=cap)
    problems = []
    if p.returncode != 1:
        problems.append(f"exit {p.returncode}, expected 1")
    try:
        summary = json.load(open(os.path.join(work, "summary.json")))
        if summary["status"] != "output_error" or what not in summary["message"]:
            problems.append(f"summary status {summary['status']!r}, message "
                            f"{summary['message']!r} (expected output_error, {what!r})")
    except (OSError, ValueError, KeyError) as e:
        problems.append(f"summary.json not readable: {e}")
    leftovers = glob.glob(os.path.join(work, ".*.tmp")) + glob.glob(os.path.join(work, "*.tmp"))
    if leftovers:
        problems.append(f"temporary files left: {leftovers}")
    for snap in glob.glob(os.path.join(work, "snap_*.h5")):
        try:
            with h5py.File(snap) as f:
                f["position"][()]
        except (OSError, KeyError) as e:
            problems.append(f"{snap} unreadable: {e}")
    if problems:
        print("FAIL:", "; ".join(problems), "\n", p.stderr[-1500:])
        return 1
    print(f"exit 1 under a {int(limit) // 1024} KiB file size limit: {summary['message']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

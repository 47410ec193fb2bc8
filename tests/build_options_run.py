"""One `sph run` with extra kernel build options (SPH_BUILD_OPTIONS, the
kernel developers' -D switches), for the tests that compare a build
variant with the default: check_reach.py, check_lane_lists.py."""
import os
import subprocess
import sys


def run_with_options(sph, case, out, sets, options, caller):
    """Runs `sph run CASE --out OUT --quiet SETS` with SPH_BUILD_OPTIONS set to
    `options`, echoes its output, and exits naming `caller` if it fails."""
    env = dict(os.environ, SPH_BUILD_OPTIONS=options)
    cmd = [sph, "run", case, "--out", out, "--quiet"] + sets
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    sys.stdout.write(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        sys.exit(f"{caller}: the run with '{options}' exited {proc.returncode}")

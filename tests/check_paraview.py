#!/usr/bin/python3
"""Opens a run's snapshots.xdmf the way a ParaView user does and checks what
the default reader shows.

    check_paraview.py SPH CASE OUT [--set K=V ...]

Runs `SPH run CASE --out OUT` with the --set options, then, in pvpython
(Debian's python3-paraview), opens OUT/snapshots.xdmf with OpenDataFile (no
reader chosen by hand) at the last time and checks:
- the particle block has one point AND one vertex cell per particle (a
  Polyvertex without connectivity gives points but no cells, and the Surface
  and Points views then draw nothing);
- mass, smoothing_length and id are there, ids 0..n-1;
- the stress tensor is in ParaView's Tensor6 order (XX, YY, ZZ, XY, YZ, XZ):
  the mean of its first three components is minus the pressure, particle by
  particle (in the old xx, xy, xz order it is not);
- snapshots.xdmf holds the particles alone (with the rigid bodies in the
  same file ParaView 5.11 draws no field in colour), and bodies.xdmf the
  projectile (when the case has one), a block whose points lie on the
  sphere of the case's diameter about the centre the snapshot records, and
  the walls, a block of one cell per wall;
- the snapshot times ParaView lists are the h5 files' time_s attributes.
Exits 77 (ctest's skip) with a message where pvpython is not installed.
"""
import json
import os
import shutil
import subprocess
import sys

READER = r"""
import json, sys
from paraview.simple import OpenDataFile, servermanager
reader = OpenDataFile(sys.argv[1])
times = list(reader.TimestepValues)
reader.UpdatePipeline(times[-1])
data = servermanager.Fetch(reader)
blocks = []
leaves = []
if data.IsA("vtkCompositeDataSet"):
    it = data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        leaves.append(it.GetCurrentDataObject())
        it.GoToNextItem()
else:
    leaves.append(data)
for b in leaves:
    pd = b.GetPointData()
    arrays = {}
    for i in range(pd.GetNumberOfArrays()):
        a = pd.GetArray(i)
        arrays[a.GetName()] = [[a.GetComponent(p, c) for c in range(a.GetNumberOfComponents())]
                               for p in range(a.GetNumberOfTuples())]
    points = [list(b.GetPoint(p)) for p in range(b.GetNumberOfPoints())]
    blocks.append({"points": points, "cells": b.GetNumberOfCells(), "arrays": arrays})
print(json.dumps({"reader": reader.GetXMLName(), "times": times, "blocks": blocks}))
"""


def fail(message):
    print("FAIL:", message)
    sys.exit(1)


def main():
    sph, case, out, sets = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    pvpython = shutil.which("pvpython")
    if not pvpython:
        print("SKIP: pvpython not found (Debian: apt-get install python3-paraview; "
              "tools/setup.sh test installs it)")
        sys.exit(77)
    shutil.rmtree(out, ignore_errors=True)
    run = subprocess.run([sph, "run", case, "--out", out, "--quiet", *sets])
    if run.returncode != 0:
        fail(f"sph run exited {run.returncode}")
    seen = read_in_paraview(pvpython, os.path.join(out, "snapshots.xdmf"))
    bodies = os.path.join(out, "bodies.xdmf")
    seen_bodies = read_in_paraview(pvpython, bodies) if os.path.exists(bodies) else None
    check(seen, seen_bodies, out)
    print("ok")


def read_in_paraview(pvpython, path):
    result = subprocess.run([pvpython, "-c", READER, path], capture_output=True, text=True,
                            timeout=300)
    lines = [l for l in result.stdout.splitlines() if l.startswith("{")]
    if result.returncode != 0 or not lines:
        fail(f"pvpython on {path} exited {result.returncode}: {result.stderr[-2000:]}")
    return json.loads(lines[-1])


def check(seen, seen_bodies, out):
    import h5py
    import numpy as np
    import yaml

    if seen["reader"] != "Xdmf3ReaderS":
        fail(f"ParaView picked {seen['reader']}, expected its default Xdmf3ReaderS")
    snapshots = sorted(f for f in os.listdir(out) if f.startswith("snap_") and f.endswith(".h5"))
    h5_times = [float(h5py.File(os.path.join(out, f), "r").attrs["time_s"][0]) for f in snapshots]
    if not np.allclose(seen["times"], h5_times, rtol=1e-6, atol=0):
        fail(f"ParaView lists times {seen['times']}, the snapshots say {h5_times}")
    summary = json.load(open(os.path.join(out, "summary.json")))
    n = summary["particles"]
    if len(seen["blocks"]) != 1:
        fail(f"snapshots.xdmf shows {len(seen['blocks'])} blocks; expected the particles alone")
    particles = seen["blocks"][0]
    if len(particles["points"]) != n or particles["cells"] != n:
        fail(f"particle block: {len(particles['points'])} points, {particles['cells']} cells; "
             f"expected {n} of each")
    arrays = particles["arrays"]
    for name in ("mass", "smoothing_length", "id", "stress", "pressure", "velocity"):
        if name not in arrays:
            fail(f"array {name} missing; ParaView shows {sorted(arrays)}")
    if sorted(int(v[0]) for v in arrays["id"]) != list(range(n)):
        fail("ids are not 0..n-1")
    stress, pressure = np.array(arrays["stress"]), np.array(arrays["pressure"])[:, 0]
    scale = max(np.abs(pressure).max(), 1.0)
    mismatch = np.abs(stress[:, :3].mean(axis=1) + pressure).max() / scale
    if stress.shape[1] != 6 or mismatch > 1e-6:
        fail(f"stress components 0-2 are not the normal stresses (XX, YY, ZZ): their mean "
             f"differs from -p by {mismatch:.3g} of max |p|")
    last = h5py.File(os.path.join(out, snapshots[-1]), "r")
    blocks = seen_bodies["blocks"] if seen_bodies else []
    resolved = yaml.safe_load(open(os.path.join(out, "case.resolved.yaml")))
    projectile = resolved.get("projectile") or {}
    if projectile.get("diameter"):
        if not blocks:
            fail("a run with a projectile has no projectile block (bodies.xdmf)")
        centre = last.attrs["projectile_centre_m"]
        surface = np.array(blocks.pop(0)["points"])
        radius = np.linalg.norm(surface - centre, axis=1)
        if len(surface) < 8 or np.abs(radius - 0.5 * projectile["diameter"]).max() > \
                1e-6 * projectile["diameter"]:
            fail("the projectile block is not the sphere about the recorded centre")
    walls = resolved.get("walls") or []
    shown = blocks[0]["cells"] if blocks else 0
    if shown != len(walls):
        fail(f"{len(walls)} walls in the case, {shown} wall cells shown")
    print(f"{n} particles and cells, {len(seen['times'])} times, stress order checked "
          f"(mismatch {mismatch:.2g}), projectile {'yes' if projectile.get('diameter') else 'no'}, "
          f"{len(walls)} wall(s)")


if __name__ == "__main__":
    main()

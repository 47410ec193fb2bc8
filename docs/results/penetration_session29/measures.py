#!/usr/bin/python3
"""The numbers of docs/validation_penetration.md's session-29 section
("The no-slip contact in the gel shots"), read from run folders.

usage: measures.py depth TIMES_NS RUN [RUN ...]
           depth and speed of the sphere at each time (ns), one row per run
       measures.py resistance RUN [RUN ...]
           the SEBS shot's resistance F / (pi d^2 / 4) in 30 m/s speed
           windows against the modified Clift-Gauvin fit's (eta 4.5e-2 Pa s,
           R 25 MPa: REFERENCES.md 3), and that fit's drag part
       measures.py contact TIMES_NS RUN [RUN ...]
           particles in contact and the holding force (mN), 50 ns windows
       measures.py slip RUN [RUN ...]
           per snapshot while the sphere moves faster than 50 m/s: the
           particles inside the contact's penalty layer (centre within
           R - dx_i/2 of the sphere's: the ones no_slip sticks) and the
           mean tangential speed, over the sphere's, of the face just
           outside it (R - dx_i/2 to R + dx_i/2)
       measures.py cap RUN [RUN ...]
           in every other snapshot after the first, the particles ahead of
           the sphere's centre within R + dx_i/2 of it, and how many of
           them were there in the first snapshot after impact (the stuck
           nose cap of the no-slip contact), and how many have failed

RUN is a folder written by `sph run` (ballistics.csv, case.resolved.yaml).
"""
import csv
import math
import os
import sys

import glob

import h5py
import numpy as np
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                                "tools"))
from penetration_models import clift_gauvin_cd  # noqa: E402


def ballistics(run):
    with open(os.path.join(run, "ballistics.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def depth(times, runs):
    print("run | " + " | ".join(f"{t:g} ns: um / m/s" for t in times))
    for run in runs:
        b = ballistics(run)
        cells = [f"{np.interp(t * 1e-9, b['time_s'], b['penetration_m']) * 1e6:.1f} / "
                 f"{np.interp(t * 1e-9, b['time_s'], b['velocity_m_per_s']):.0f}"
                 if t * 1e-9 <= b["time_s"][-1] else "-" for t in times]
        print(f"{run} | " + " | ".join(cells))


def resistance(runs, eta=4.5e-2, strength=25e6):
    for run in runs:
        with open(os.path.join(run, "case.resolved.yaml")) as f:
            case = yaml.safe_load(f)
        rho = float(case["materials"][0]["density"])
        d = float(case["projectile"]["diameter"])
        area = math.pi * d * d / 4
        b = ballistics(run)
        print(f"{run}\nv (m/s) | Re | SPH F/A (MPa) | Clift-Gauvin (MPa) | its drag part (MPa)")
        for v in (600, 500, 400, 300, 200, 150, 100, 50):
            window = np.abs(b["velocity_m_per_s"] - v) < 15
            if not window.any():
                continue
            re = rho * v * d / eta
            drag = 0.5 * clift_gauvin_cd(re) * rho * v * v
            print(f"{v} | {re:.0f} | {b['decelerating_force_N'][window].mean() / area / 1e6:.1f} | "
                  f"{(drag + strength) / 1e6:.1f} | {drag / 1e6:.1f}")


def contact(times, runs):
    print("run | " + " | ".join(f"{t:g} ns: particles / mN" for t in times))
    for run in runs:
        b = ballistics(run)
        cells = []
        for t in times:
            window = np.abs(b["time_s"] - t * 1e-9) < 25e-9
            cells.append(f"{b['contact_particles'][window].mean():.1f} / "
                         f"{b['decelerating_force_N'][window].mean() * 1e3:.2f}"
                         if window.any() else "-")
        print(f"{run} | " + " | ".join(cells))


def cap(runs):
    """Front particles near the sphere per snapshot (in brackets: those
    still there from the first snapshot after impact, and the failed)."""
    for run in runs:
        with open(os.path.join(run, "case.resolved.yaml")) as f:
            case = yaml.safe_load(f)
        dim = case["dimension"]
        radius = 0.5 * float(case["projectile"]["diameter"])
        axis = np.array(case["projectile"]["velocity"], dtype=float)[:dim]
        axis /= np.linalg.norm(axis)
        first, cells = None, []
        for path in sorted(glob.glob(os.path.join(run, "snap_*.h5")))[1::2]:
            with h5py.File(path) as s:
                x = s["position"][:][:, :dim]
                level = (s["flags"][:] >> 8) & 15  # include/sph_shared.h: SPH_LEVEL_OF
                ids = s["id"][:]
                failed = (s["flags"][:] & 8) != 0  # SPH_FLAG_DAMAGED
                centre = s.attrs["projectile_centre_m"][:dim]
            d = x - centre
            near = np.linalg.norm(d, axis=1) < radius + 0.5 * float(case["numerics"]["dx"]) * 2.0**level
            ahead = near & (d @ axis > 0)
            front = set(ids[ahead].tolist())
            first = front if first is None else first
            cells.append(f"{len(front)} ({len(front & first)}, {failed[ahead].sum()} failed)")
        print(f"{run} | " + " | ".join(cells))


def slip(runs):
    for run in runs:
        with open(os.path.join(run, "case.resolved.yaml")) as f:
            case = yaml.safe_load(f)
        dim = case["dimension"]
        radius = 0.5 * float(case["projectile"]["diameter"])
        print(f"{run}\nt (ns) | sphere speed (m/s) | inside the penalty layer | face slip / speed")
        for path in sorted(glob.glob(os.path.join(run, "snap_*.h5")))[1:]:
            with h5py.File(path) as s:
                x = s["position"][:][:, :dim]
                v = s["velocity"][:][:, :dim]
                level = (s["flags"][:] >> 8) & 15
                centre = s.attrs["projectile_centre_m"][:dim]
                sphere = s.attrs["projectile_velocity_m_per_s"][:dim]
                time = float(s.attrs["time_s"][0])
            speed = np.linalg.norm(sphere)
            if speed < 50:
                continue
            d = x - centre
            r = np.linalg.norm(d, axis=1)
            half = 0.5 * float(case["numerics"]["dx"]) * 2.0**level
            normal = d / r[:, None]
            relative = v - sphere
            tangential = relative - np.sum(relative * normal, axis=1)[:, None] * normal
            face = (r >= radius - half) & (r < radius + half)
            slip_face = np.linalg.norm(tangential[face], axis=1).mean() / speed
            print(f"{time * 1e9:.0f} | {speed:.0f} | {(r < radius - half).sum()} | {slip_face:.2f}")


def main():
    if len(sys.argv) < 3 or sys.argv[1] not in ("depth", "resistance", "contact", "cap", "slip"):
        sys.exit(__doc__)
    if sys.argv[1] == "resistance":
        resistance(sys.argv[2:])
    elif sys.argv[1] == "cap":
        cap(sys.argv[2:])
    elif sys.argv[1] == "slip":
        slip(sys.argv[2:])
    else:
        times = [float(t) for t in sys.argv[2].split(",")]
        (depth if sys.argv[1] == "depth" else contact)(times, sys.argv[3:])


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The hoop stretch of the gel around the shot line in a 3-D quarter run,
as the corrected SPH gradient sees it, against v_r / r (the hoop rate of
flow around the axis, which the axisymmetric form uses exactly): the
gelatin and SEBS counterpart of docs/results/taylor_session37/
rim_kinematics.py (docs/validation_penetration.md, session 37).

For the gel particles (not failed: those carry no hoop stress) within
`--shell` sphere radii of the sphere's centre and off the axis by at least
two spacings, at one snapshot: D_tt of pass 1's corrected gradient (L = G
B^-1, G = sum V_j (v_j - v_i) (x) grad W, B = sum V_j (x_j - x_i) (x) grad
W, Wendland C2 with each particle's h and the pair's mean h, mirror
images across the case's symmetry planes) against v_r / r, binned by the
polar angle from the shot's direction. The shot line is the axis of the
case's two symmetry planes' intersection (the quarter model: planes x = 0
and z = 0, the axis y).

Usage: wall_hoop_rate.py RUN SNAPSHOT_INDEX [--shell 1.5]
"""
import argparse

import h5py
import numpy as np
import yaml
from scipy.spatial import cKDTree

FLAG_DAMAGED, FLAG_FIXED = 8, 1


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("run")
    p.add_argument("snapshot", type=int)
    p.add_argument("--shell", type=float, default=1.5, help="sphere radii from the centre")
    a = p.parse_args()
    case = yaml.safe_load(open(f"{a.run}/case.resolved.yaml"))
    planes = ["xyz".index(s["axis"]) for s in case["symmetry"]]
    axis = ({0, 1, 2} - set(planes)).pop()
    radius = 0.5 * float(case["projectile"]["diameter"])
    dx = float(case["numerics"]["dx"])
    f = h5py.File(f"{a.run}/snap_{a.snapshot:05d}.h5", "r")
    x, v = f["position"][...].astype(float), f["velocity"][...].astype(float)
    h, flags = f["smoothing_length"][...].astype(float), f["flags"][...]
    vol = f["mass"][...] / f["density"][...]
    centre = f.attrs["projectile_centre_m"].astype(float)
    shot = -np.sign(f.attrs["projectile_velocity_m_per_s"][axis])  # + along the flight
    images = [np.ones(3)]
    for k in planes:
        images += [m * np.where(np.arange(3) == k, -1.0, 1.0) for m in images]
    X = np.vstack([x * m for m in images])
    V = np.vstack([v * m for m in images])
    H, VOL = np.concatenate([h] * len(images)), np.concatenate([vol] * len(images))
    tree = cKDTree(X)
    radial = x.copy()
    radial[:, axis] = 0
    r = np.linalg.norm(radial, axis=1)
    d = np.linalg.norm(x - centre, axis=1)
    pick = np.flatnonzero((d < a.shell * radius) & (r > 2 * dx) & ((flags & (FLAG_DAMAGED | FLAG_FIXED)) == 0))
    rows = []
    for i in pick:
        js = [j for j in tree.query_ball_point(x[i], 2 * (h[i] + H.max()) / 2) if j != i]
        js = np.array(js)
        hij = 0.5 * (h[i] + H[js])
        xij = x[i] - X[js]
        q = np.linalg.norm(xij, axis=1) / hij
        keep = q < 2
        js, xij, q, hij = js[keep], xij[keep], q[keep], hij[keep]
        grad = (-(1 - q / 2) ** 3 / hij ** 5)[:, None] * xij  # Wendland C2 dW/dr / r, constant left out
        g = ((V[js] - v[i]) * VOL[js, None]).T @ grad
        b = ((X[js] - x[i]) * VOL[js, None]).T @ grad
        dmat = g @ np.linalg.inv(b)
        dmat = 0.5 * (dmat + dmat.T)
        e_r = radial[i] / r[i]
        e_t = np.cross(np.eye(3)[axis], e_r)
        vr = v[i] @ e_r
        polar = np.degrees(np.arccos(np.clip(shot * (x[i] - centre)[axis] / d[i], -1, 1)))
        rows.append((polar, vr / r[i], e_t @ dmat @ e_t))
    rows = np.array(rows)
    print(f"{a.run} snapshot {a.snapshot} (t = {f.attrs['time_s'][0]:.3g} s): {len(rows)} intact gel "
          f"particles within {a.shell} radii of the sphere's centre")
    print("polar angle from the flight direction (deg)   n   mean v_r/r (1/s)   mean D_tt (1/s)   ratio")
    for lo in range(0, 180, 30):
        m = (rows[:, 0] >= lo) & (rows[:, 0] < lo + 30)
        if m.sum() < 3:
            continue
        vr_r, dtt = rows[m, 1].mean(), rows[m, 2].mean()
        print(f"{lo:3d}-{lo + 30:3d} {m.sum():6d} {vr_r:14.4g} {dtt:16.4g} {dtt / vr_r if vr_r else np.nan:9.3f}")


if __name__ == "__main__":
    main()

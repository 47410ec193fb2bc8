#!/usr/bin/env python3
"""How the Taylor rod's impact-face layer stretches around the axis
(docs/validation_taylor.md, "Where the 3-D face's hoop stretch goes",
session 37).

For the particles that started in the lowest layer, at one snapshot:
  - the stress in cylindrical components (sigma_rr, sigma_tt hoop,
    sigma_zz), the radial speed and the plastic strain, binned by radius;
  - 3-D runs only: the hoop strain rate D_tt that the corrected SPH
    gradient gives (pass 1's formula: L = G B^-1, G = sum V_j (v_j - v_i)
    (x) grad W, B = sum V_j (x_j - x_i) (x) grad W, Wendland C2, each
    particle's own h, mirror images across the x, y and z = 0 planes of
    the quarter model with its held face) against v_r / r, the hoop rate
    a smooth radial flow has (the axisymmetric form uses it exactly);
  - 3-D runs only: the rms angle between a rim particle's velocity and its
    position about the axis (outer 30% by radius): 0 in a radial flow;
  - 3-D runs only: the spacing of the two lowest layers (median z) and the
    face layer's nearest neighbour in its own plane, over the initial
    spacing dx.
The kernel's constant cancels in G B^-1, so it is left out.

Usage: rim_kinematics.py RUN SNAPSHOT_INDEX [--axisymmetric]
"""
import argparse

import h5py
import numpy as np
from scipy.spatial import cKDTree


def load(run, k):
    f = h5py.File(f"{run}/snap_{k:05d}.h5", "r")
    s = {n: f[n][...] for n in ("position", "displacement", "velocity", "stress",
                                "plastic_strain", "mass", "density", "smoothing_length")}
    if "smoothing_metric" in f:  # numerics.smoothing: tensor (session 38)
        s["smoothing_metric"] = f["smoothing_metric"][...]
    return s


def metric_of(row):
    """The 3 x 3 metric G = h0^2 M of a snapshot row XX YY ZZ XY YZ XZ."""
    xx, yy, zz, xy, yz, xz = row
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def cylindrical(s, axisymmetric):
    x, v, st = s["position"], s["velocity"], s["stress"]  # stress: XX YY ZZ XY YZ XZ
    if axisymmetric:  # (r, z, hoop)
        return x[:, 0], x[:, 1], v[:, 0], st[:, 0], st[:, 2], st[:, 1]
    r = np.hypot(x[:, 0], x[:, 1])
    c, n = x[:, 0] / np.maximum(r, 1e-30), x[:, 1] / np.maximum(r, 1e-30)
    vr = v[:, 0] * c + v[:, 1] * n
    srr = st[:, 0] * c * c + 2 * st[:, 3] * c * n + st[:, 1] * n * n
    stt = st[:, 0] * n * n - 2 * st[:, 3] * c * n + st[:, 1] * c * c
    return r, x[:, 2], vr, srr, stt, st[:, 2]


def face_layer(s, axisymmetric):
    z0 = (s["position"] - s["displacement"])[:, 1 if axisymmetric else 2]
    return np.abs(z0 - z0.min()) < 1e-3 * np.ptp(z0) / max(len(np.unique(np.round(z0, 9))), 1)


def sph_hoop_rate(s, face):
    """D_tt of the corrected SPH gradient for each face particle, 3-D quarter."""
    x, v, h = s["position"], s["velocity"], s["smoothing_length"]
    vol = s["mass"] / s["density"]
    images = [np.array([a, b, c]) for a in (1, -1) for b in (1, -1) for c in (1, -1)]
    X = np.vstack([x * m for m in images])
    V = np.vstack([v * m for m in images])
    VOL = np.concatenate([vol] * len(images))
    tree = cKDTree(X)
    rates = []
    metric = s.get("smoothing_metric")
    for i in np.flatnonzero(face):
        # with a tensor smoothing length each particle's own ellipsoid
        # (kernels/tensor_smoothing.cl): q = |H_i x| and the same weights
        # (dW/dr / r of q); with CSPH the metric cancels but for them
        reach = 2 * h[i] * (2.5 if metric is not None else 1.0)
        js = [j for j in tree.query_ball_point(x[i], reach) if j != i]
        xij = x[i] - X[js]
        if metric is not None:
            y = xij / h[i]
            q = np.sqrt(np.einsum("ja,ab,jb->j", y, metric_of(metric[i]), y))
        else:
            q = np.linalg.norm(xij, axis=1) / h[i]
        # Wendland C2: dW/dr / r, constant left out
        grad = (-np.maximum(1 - q / 2, 0) ** 3)[:, None] * xij
        g = ((V[js] - v[i]) * VOL[js, None]).T @ grad
        b = ((X[js] - x[i]) * VOL[js, None]).T @ grad
        d = 0.5 * (g @ np.linalg.inv(b) + (g @ np.linalg.inv(b)).T)
        r = np.hypot(x[i, 0], x[i, 1])
        e_t = np.array([-x[i, 1] / r, x[i, 0] / r, 0.0])
        rates.append(e_t @ d @ e_t)
    return np.array(rates)


def layer_spacing(s, face, rf):
    x, z0 = s["position"], (s["position"] - s["displacement"])[:, 2]
    levels = np.unique(np.round(z0, 9))
    dx = levels[1] - levels[0]
    second = np.abs(z0 - levels[1]) < 1e-3 * dx
    p = x[face]
    mirrored = np.vstack([p * [a, b, 1] for a in (1, -1) for b in (1, -1)])
    d, _ = cKDTree(mirrored).query(p, 2)
    near, outer = d[:, 1] / dx, rf > np.percentile(rf, 70)
    print(f"layers 0 to 1: {(np.median(x[second, 2]) - np.median(p[:, 2])) / dx:.2f} dx apart; "
          f"nearest in-plane neighbour {np.median(near[~outer]):.2f} dx (inner 70%), "
          f"{np.median(near[outer]):.2f} dx (rim)")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("run")
    p.add_argument("snapshot", type=int)
    p.add_argument("--axisymmetric", action="store_true")
    p.add_argument("--bins", type=int, default=6)
    a = p.parse_args()
    s = load(a.run, a.snapshot)
    face = face_layer(s, a.axisymmetric)
    r, _, vr, srr, stt, szz = cylindrical(s, a.axisymmetric)
    ep = s["plastic_strain"]
    print(f"{a.run} snapshot {a.snapshot}: {face.sum()} face particles, "
          f"largest radius {r[face].max() * 1e3:.3f} mm")
    dtt = None if a.axisymmetric else sph_hoop_rate(s, face)
    rf, order = r[face], np.argsort(r[face])
    edges = np.linspace(0, rf.max() * (1 + 1e-9), a.bins + 1)
    which = np.digitize(rf, edges)
    head = "r (mm)        n  v_r (m/s)  s_rr   s_tt   s_zz (MPa)  eps_p"
    print(head + ("   v_r/r  D_tt (1/s)" if dtt is not None else ""))
    for k in range(1, a.bins + 1):
        m = which == k
        if not m.any():
            continue
        line = (f"{edges[k-1]*1e3:5.2f}-{edges[k]*1e3:5.2f} {m.sum():4d} {vr[face][m].mean():8.1f} "
                f"{srr[face][m].mean()/1e6:7.0f}{stt[face][m].mean()/1e6:7.0f}"
                f"{szz[face][m].mean()/1e6:7.0f}      {ep[face][m].mean():5.2f}")
        if dtt is not None:
            line += f" {np.mean(vr[face][m] / rf[m]):8.0f} {dtt[m].mean():8.0f}"
        print(line)
    if not a.axisymmetric:
        x, v = s["position"][face], s["velocity"][face]
        outer = rf > np.percentile(rf, 70)
        dphi = np.degrees(np.arctan2(v[:, 1], v[:, 0]) - np.arctan2(x[:, 1], x[:, 0]))
        layer_spacing(s, face, rf)
        print(f"rim (outer 30%): rms angle between velocity and radius {np.sqrt(np.mean(dphi[outer]**2)):.1f} deg; "
              f"mean D_tt / (v_r / r) {np.mean(dtt[outer]) / np.mean(vr[face][outer] / rf[outer]):.3f}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Session 27's measurements on run folders (docs/validation_penetration.md,
"The 3-D and axisymmetric resistances at low speed, and the axis").

usage: measures.py resistance RUN...  mean contact force over pi a^2 (MPa),
                                      100-200, 200-400 and 400-700 ns, and the
                                      artificial viscosity's work over the
                                      internal energy at the end
       measures.py depth RUN...       force over pi a^2 (MPa) per micrometre
                                      of penetration
       measures.py hertz RUN...       force (N) against Hertz's (4/3) E*
                                      R^(1/2) delta^(3/2), delta from first
                                      contact (an elastic gel)
       measures.py wall RUN           the gel 20-120 degrees from the nose by
                                      distance from the sphere's centre
       measures.py axis RUN           the gel that started within 0.3 a of
                                      the shot axis: where it is now
       measures.py rear RUN           the gel over the sphere's rear and the
                                      contact springs' push, rear and front
       measures.py taylor RUN         a Taylor bar's plastic strain ring by
                                      ring in its two lowest layers
       measures.py wave RUN           axis_plane_wave.yaml: rings 1-3 and 10

`wall`: for an elastic gel moving in meridional planes about the shot axis
(y) the hoop axis does not rotate, so the hoop deviatoric stress over 2G is
the hoop strain the stress update integrated, and ln(r / r0) the hoop
strain the particle underwent (r its distance from the axis). Printed per
band: both, their ratio, von Mises over 3G, the fraction of the initial
neighbours within 2h still neighbours, and the CSPH moment matrix's
determinant sum_j V_j x_ji (x) grad W_ij (Wendland C2; kernels/common.cl
falls back to no correction below 1/1024 in 3-D). 3-D quarter models are
mirrored across x = 0 and z = 0, the axisymmetric form across the axis.
The last snapshot unless SNAP (an index) follows RUN.
"""
import glob
import os
import sys

import h5py
import numpy as np
import yaml
from scipy.spatial import cKDTree

PAIRS = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)]
CONTACT_INSET = 0.5  # spacings inside the sphere the contact layer is held at (projectile.cl)


def snapshots(run):
    return sorted(glob.glob(os.path.join(run, "snap_*.h5")))


def load(run, index=-1):
    """The resolved case and one snapshot's fields, rows in id order."""
    with open(os.path.join(run, "case.resolved.yaml")) as f:
        case = yaml.safe_load(f)
    paths = snapshots(run)
    with h5py.File(paths[0]) as first, h5py.File(paths[index]) as snap:
        order = np.argsort(snap["id"][:])
        d = {k: snap[k][:][order] for k in ("position", "velocity", "stress", "mass", "density",
                                            "von_mises_stress", "plastic_strain")}
        d["x0"] = first["position"][:][np.argsort(first["id"][:])]
        d["dim"] = int(snap.attrs["dimension"][0])
        d["time"] = float(snap.attrs["time_s"][0])
        d["centre"] = snap.attrs.get("projectile_centre_m")
        d["path"] = paths[index]
    d["case"] = case
    d["dx"] = case["numerics"]["dx"]
    d["h"] = case["numerics"]["h_over_dx"] * d["dx"]
    if "projectile" in case:
        d["a"] = case["projectile"]["diameter"] / 2
    return d


def axis_distance(x, dim):
    return x[:, 0] if dim == 2 else np.hypot(x[:, 0], x[:, 2])


def tensor(stress):
    t = np.zeros((len(stress), 3, 3))
    for k, (i, j) in enumerate(PAIRS):
        t[:, i, j] = t[:, j, i] = stress[:, k]
    return t


def hoop_deviator(d):
    """The hoop component of the deviatoric stress about the y axis."""
    stress, x = d["stress"], d["position"]
    trace = stress[:, 0] + stress[:, 1] + stress[:, 2]
    if d["dim"] == 2:
        return stress[:, 2] - trace / 3
    r = np.hypot(x[:, 0], x[:, 2])
    hoop = np.stack([-x[:, 2], np.zeros(len(x)), x[:, 0]], 1) / r[:, None]
    return np.einsum("ni,nij,nj->n", hoop, tensor(stress), hoop) - trace / 3


def mirrored(y, dim):
    signs = [[1, 1, 1], [-1, 1, 1]] if dim == 2 else \
        [[1, 1, 1], [-1, 1, 1], [1, 1, -1], [-1, 1, -1]]
    return np.concatenate([y * s for s in signs])


def about_sphere(d):
    """Distance from the axis, from the centre (in a) and polar angle from the nose."""
    r = axis_distance(d["position"], d["dim"])
    along = d["position"][:, 1] - d["centre"][1]
    return r, np.hypot(r, along) / d["a"], np.degrees(np.arctan2(r, -along)), along / d["a"]


def shear_modulus(case):
    material = case["materials"][0]
    return material["youngs_modulus"] / (2 * (1 + material["poisson_ratio"]))


def moment_determinant(d, tree, points, volumes, i):
    """det sum_j V_j x_ji (x) grad_i W_ij, Wendland C2 (support 2h)."""
    h, x = d["h"], d["position"][i]
    idx = np.array(tree.query_ball_point(x, 2 * h))
    dist = x - points[idx]
    q = np.linalg.norm(dist, axis=1) / h
    keep = q > 0
    dist, q, vol = dist[keep], q[keep], volumes[idx][keep]
    norm = 21 / (16 * np.pi * h**3) if d["dim"] == 3 else 7 / (4 * np.pi * h**2)
    grad = (norm / h * (-5 * q * (1 - q / 2) ** 3) / (q * h))[:, None] * dist
    moment = np.einsum("j,ja,jb->ab", vol, -dist, grad)[: d["dim"], : d["dim"]]
    return np.linalg.det(moment)


def wall(run, index=-1):
    d = load(run, index)
    dim, g = d["dim"], shear_modulus(d["case"])
    r, distance, polar, _ = about_sphere(d)
    r0 = axis_distance(d["x0"], dim)
    strain = hoop_deviator(d) / (2 * g)
    count = len(r)
    before, now = cKDTree(mirrored(d["x0"], dim)), cKDTree(mirrored(d["position"], dim))
    # the axisymmetric mass is per radian: the plane sums take m / r (common.cl)
    volume = d["mass"] / d["density"] / (np.maximum(r, 1e-30) if dim == 2 else 1)
    points, volumes = mirrored(d["position"], dim), np.tile(volume, 4 if dim == 3 else 2)
    print(f"{d['path']}: t = {d['time']:.4g} s, a = {d['a']:.4g} m, G = {g:.4g} Pa")
    print("band (a)  particles  stretch  integrated  ratio  von_mises/3G  neighbours_kept  "
          "det_median  det_min")
    for low, high in [(0.8, 1.1), (1.1, 1.4), (1.4, 1.8), (1.8, 2.4)]:
        band = np.where((distance >= low) & (distance < high) & (polar >= 20) & (polar < 120) &
                        (r0 > 0))[0]
        if len(band) == 0:
            continue
        stretch = np.log(r[band] / r0[band])
        kept = []
        for i in band:
            old = {j % count for j in before.query_ball_point(d["x0"][i], 2 * d["h"])} - {i}
            new = {j % count for j in now.query_ball_point(d["position"][i], 2 * d["h"])} - {i}
            kept.append(len(old & new) / max(len(old), 1))
        dets = [moment_determinant(d, now, points, volumes, i) for i in band]
        print(f"{low:.1f}-{high:.1f}  {len(band):9d}  {stretch.mean():7.3f}  "
              f"{strain[band].mean():10.3f}  {strain[band].mean() / stretch.mean():5.2f}  "
              f"{d['von_mises_stress'][band].mean() / (3 * g):12.2f}  {np.mean(kept):15.2f}  "
              f"{np.median(dets):10.3f}  {np.min(dets):7.2e}")


def axis(run, index=-1):
    d = load(run, index)
    r, _, _, along = about_sphere(d)
    r0 = axis_distance(d["x0"], d["dim"])
    start = np.where((r0 < 0.3 * d["a"]) & (d["x0"][:, 1] > d["centre"][1] - 2 * d["a"]))[0]
    print(f"{d['path']}: t = {d['time']:.4g} s; gel that started within 0.3 a of the axis, "
          "above 2 a below the sphere's centre (along: + behind the centre, - ahead)")
    print("y0 (um)  r0/a  r/a  along/a  von_mises (MPa)  plastic_strain")
    for i in start[np.argsort(-d["x0"][start, 1])]:
        print(f"{d['x0'][i, 1] * 1e6:7.2f}  {r0[i] / d['a']:4.2f}  {r[i] / d['a']:4.2f}  "
              f"{along[i]:7.2f}  {d['von_mises_stress'][i] / 1e6:15.1f}  "
              f"{d['plastic_strain'][i]:14.2f}")


def contact_push(d):
    """The contact springs' push along the shot, front and rear: overlap with
    the contact layer times mass (the spring constant is common)."""
    x = d["position"] - d["centre"]
    gap = np.linalg.norm(x, axis=1)
    overlap = d["a"] - CONTACT_INSET * d["dx"] - gap
    push = np.where(overlap > 0, d["mass"] * overlap * (-x[:, 1] / gap), 0.0)
    return push[x[:, 1] < 0].sum(), push[x[:, 1] > 0].sum()


def rear(run, index=-1):
    d = load(run, index)
    r, distance, polar, along = about_sphere(d)
    x = d["position"] - d["centre"]
    normal = x / np.linalg.norm(x, axis=1)[:, None]
    radial = np.einsum("ni,nij,nj->n", normal, tensor(d["stress"]), normal)
    volume = d["mass"] / d["density"]
    print(f"{d['path']}: t = {d['time']:.4g} s")
    for low, high in [(0.0, 0.5), (0.5, 1.0), (1.0, 1.5)]:
        slab = (along >= low) & (along < high)
        if slab.any():
            print(f"  {low}-{high} a behind the centre: nearest gel {r[slab].min() / d['a']:.2f} a "
                  "from the axis")
    for low, high in [(0.9, 1.1), (1.1, 1.3)]:
        shell = (distance >= low) & (distance < high) & (polar >= 90) & (polar < 135)
        if shell.any():
            mean = np.sum(radial[shell] * volume[shell]) / volume[shell].sum()
            print(f"  {low}-{high} a, 90-135 degrees: radial stress {mean / 1e6:.1f} MPa "
                  f"({shell.sum()} particles)")
    for k in range(1, len(snapshots(run))):
        s = load(run, k)
        front, back = contact_push(s)
        if front > 0:
            print(f"  t = {s['time']:.4g} s: rear push / front push {back / front:+.2f}")


def taylor(run, index=-1):
    d = load(run, index)
    x0, strain = d["x0"], d["plastic_strain"]
    for layer in range(2):
        rows = np.where((x0[:, 1] > layer * d["dx"]) & (x0[:, 1] < (layer + 1) * d["dx"]))[0]
        rows = rows[np.argsort(x0[rows, 0])][:6]
        print(f"{d['path']}: layer {layer + 1} from the face, rings 1-6: "
              + " ".join(f"{v:.2f}" for v in strain[rows]))


def wave(run, index=-1):
    d = load(run, index)
    x0, dx = d["x0"], d["dx"]
    print(f"{d['path']}: t = {d['time']:.4g} s; v_z (m/s) / sigma_zz (MPa)")
    for height in (0.005, 0.015, 0.025):
        cells = []
        for ring in (0, 1, 2, 9):
            pick = ((np.abs(x0[:, 0] - (ring + 0.5) * dx) < 0.1 * dx) &
                    (np.abs(x0[:, 1] - height) < 1.1 * dx))
            cells.append(f"ring {ring + 1}: {d['velocity'][pick, 1].mean():+.3f} / "
                         f"{d['stress'][pick, 1].mean() / 1e6:+.2f}")
        print(f"  z {height * 1e3:.0f} mm  " + "  ".join(cells))


def ballistics(run):
    """The resolved case and ballistics.csv of a projectile run."""
    with open(os.path.join(run, "case.resolved.yaml")) as f:
        case = yaml.safe_load(f)
    return case, np.genfromtxt(os.path.join(run, "ballistics.csv"), delimiter=",", names=True)


def resistance(runs):
    for run in runs:
        case, b = ballistics(run)
        a = case["projectile"]["diameter"] / 2
        cells = []
        for low, high in [(100e-9, 200e-9), (200e-9, 400e-9), (400e-9, 700e-9)]:
            pick = (b["time_s"] >= low) & (b["time_s"] <= high)
            force = b["decelerating_force_N"][pick]
            cells.append(f"{force.mean() / (np.pi * a * a) / 1e6:7.2f}" if pick.any() else "      -")
        h = np.genfromtxt(os.path.join(run, "history.csv"), delimiter=",", names=True)
        heat = h["artificial_viscosity_work_J"][-1] / h["internal_energy_J"][-1]
        print(f"{run}: " + " ".join(cells) + f"   viscosity work / internal energy {heat:.2f}")


def depth(runs):
    data = []
    for run in runs:
        case, b = ballistics(run)
        a = case["projectile"]["diameter"] / 2
        data.append((b["penetration_m"] * 1e6, b["decelerating_force_N"] / (np.pi * a * a) / 1e6))
    print("depth_um " + " ".join(f"{run:>14s}" for run in runs))
    for centre in np.arange(1.0, 21.0):
        cells = []
        for pen, stress in data:
            pick = (pen > centre - 0.5) & (pen <= centre + 0.5)
            cells.append(f"{stress[pick].mean():14.2f}" if pick.any() else " " * 14)
        print(f"{centre:8.1f} " + " ".join(cells))


def hertz(runs):
    for run in runs:
        case, b = ballistics(run)
        material = case["materials"][0]
        modulus = material["youngs_modulus"] / (1 - material["poisson_ratio"] ** 2)
        radius = case["projectile"]["diameter"] / 2
        force, pen = b["decelerating_force_N"], b["penetration_m"]
        first = np.argmax(force > 0)
        print(f"{run}: first contact {pen[first] * 1e6:.3f} um deep")
        for delta in np.array([0.25, 0.5, 1, 1.5, 2, 2.5, 3]) * 1e-6:
            i = np.argmin(np.abs(pen - pen[first] - delta))
            mean = force[max(i - 5, 0):i + 6].mean()  # 11 history rows
            model = 4 / 3 * modulus * np.sqrt(radius) * delta**1.5
            print(f"  delta {delta * 1e6:.2f} um: {mean:.4e} N, Hertz {model:.4e} N, "
                  f"ratio {mean / model:.3f}")


def main():
    commands = {"wall": wall, "axis": axis, "rear": rear, "taylor": taylor, "wave": wave}
    many = {"resistance": resistance, "depth": depth, "hertz": hertz}
    if len(sys.argv) >= 3 and sys.argv[1] in many:
        many[sys.argv[1]](sys.argv[2:])
    elif len(sys.argv) in (3, 4) and sys.argv[1] in commands:
        commands[sys.argv[1]](sys.argv[2], int(sys.argv[3]) if len(sys.argv) == 4 else -1)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()

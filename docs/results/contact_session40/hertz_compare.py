#!/usr/bin/env python3
"""Head-on collision of two identical elastic spheres (hertz_spheres_axi.yaml)
against Hertz's quasi-static contact, m* d2(delta)/dt2 = -k delta^(3/2),
k = 4/3 E* sqrt(R*), m* = m / 2, R* = R / 2, E* = E / (2 (1 - nu^2))
(Johnson 1985, Contact Mechanics, sec. 4.2 and 11.4):

    /usr/bin/python3 docs/results/contact_session40/hertz_compare.py RUN... [--plot OUT.png]

Per run, from the snapshots: the approach delta (the two spheres' centres
of mass closing, from their start) and the closing velocity, against the
Hertz solution integrated with RK4: the largest approach, the rebound
speed over the impact speed (Hertz: 1), the closing velocity's largest
and rms difference from Hertz's over Hertz's contact time, and from
history.csv the energy balance and the viscosity's work over the impact
energy at the end."""
import csv
import glob
import math
import os
import sys

import h5py
import numpy as np

E, NU, RHO, R, V_REL = 200e9, 0.3, 7850.0, 5e-3, 100.0


def hertz(step=1e-9):
    """time, approach and closing velocity until the spheres part"""
    mass = RHO * 4 / 3 * math.pi * R**3 / 2
    k = 4 / 3 * E / (2 * (1 - NU**2)) * math.sqrt(R / 2)

    def accel(d):
        return -k * max(d, 0.0) ** 1.5 / mass

    t, d, v, rows = 0.0, 0.0, V_REL, [(0.0, 0.0, V_REL)]
    while not (d < 0 and v < 0):
        k1 = (v, accel(d))
        k2 = (v + 0.5 * step * k1[1], accel(d + 0.5 * step * k1[0]))
        k3 = (v + 0.5 * step * k2[1], accel(d + 0.5 * step * k2[0]))
        k4 = (v + step * k3[1], accel(d + step * k3[0]))
        d += step * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]) / 6
        v += step * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]) / 6
        t += step
        rows.append((t, d, v))
    return np.array(rows)


def sph(run):
    """time, approach and closing velocity of a run"""
    rows = []
    for path in sorted(glob.glob(os.path.join(run, "snap_*.h5"))):
        with h5py.File(path, "r") as f:
            x, v, m = np.array(f["position"]), np.array(f["velocity"]), np.array(f["mass"])
            lower = (x - np.array(f["displacement"]))[:, 1] < 0
            time = float(f.attrs["time_s"][0])

        def mean(a, s):
            return np.sum(m[s] * a[s, 1]) / m[s].sum()

        rows.append((time, mean(x, ~lower) - mean(x, lower), mean(v, lower) - mean(v, ~lower)))
    rows = np.array(rows)
    rows[:, 1] = rows[0, 1] - rows[:, 1]
    return rows


def main():
    args = sys.argv[1:]
    plot = args.pop(args.index("--plot") + 1) if "--plot" in args else None
    runs = [a for a in args if a != "--plot"]
    ref = hertz()
    contact = ref[-1, 0]
    print("Hertz: largest approach %.1f um, contact time %.2f us" %
          (ref[:, 1].max() * 1e6, contact * 1e6))
    print("| run | largest approach (um) | against Hertz | rebound / impact speed |"
          " closing velocity: largest / rms difference over v_rel | energy balance |"
          " viscosity's work / KE0 |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    series = []
    for run in runs:
        s = sph(run)
        during = s[:, 0] <= contact
        dv = s[during, 2] - np.interp(s[during, 0], ref[:, 0], ref[:, 2])
        with open(os.path.join(run, "history.csv")) as f:
            rows = list(csv.DictReader(f))
        energy0 = float(rows[0]["kinetic_energy_J"])
        print("| %s | %.1f | %+.1f%% | %.3f | %.3f / %.3f | %+.2f%% | %.3f |" % (
            os.path.basename(run.rstrip("/")), s[:, 1].max() * 1e6,
            100 * (s[:, 1].max() / ref[:, 1].max() - 1), -s[-1, 2] / V_REL,
            np.abs(dv).max() / V_REL, np.sqrt(np.mean(dv**2)) / V_REL,
            100 * float(rows[-1]["energy_error"]),
            float(rows[-1]["artificial_viscosity_work_J"]) / energy0))
        series.append((run, s))
    if plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4))
        a.plot(ref[:, 0] * 1e6, ref[:, 1] * 1e6, "k-", lw=2, label="Hertz")
        b.plot(ref[:, 0] * 1e6, ref[:, 2], "k-", lw=2, label="Hertz")
        for run, s in series:
            name = os.path.basename(run.rstrip("/"))
            a.plot(s[:, 0] * 1e6, s[:, 1] * 1e6, label=name)
            b.plot(s[:, 0] * 1e6, s[:, 2], label=name)
        a.set(xlabel="t (us)", ylabel="approach (um)")
        b.set(xlabel="t (us)", ylabel="closing velocity (m/s)")
        a.legend()
        fig.tight_layout()
        fig.savefig(plot, dpi=80)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""The physical viscosity (materials[].viscosity) against hand-computed flows.

usage: check_viscous_flow.py SPH WORKDIR

A block of a soft viscous solid (rho0 = 1000 kg/m^3, E = 30 Pa, nu = 0.3,
so G = 11.54 Pa; eta = 1 Pa s) starts with a linear velocity field
(bodies[].velocity_gradient) and runs 5 ms, 28 steps at the viscous time
step limit. Away from its free faces (further than 10 dx: the disturbance
they send in travels c t = 1 mm by wave and sqrt(eta t / rho) = 2.2 mm by
diffusion) the flow stays homogeneous, so the stress is, for a constant
strain rate D (trace 0: no pressure),

    sigma = 2 eta D + 2 G D t   (Newtonian part plus Hooke's, Jaumann terms
                                 of order G (D t)^2, below 2e-4 Pa here)

and the internal energy per mass, from the stress power sigma : D,

    e = (2 eta D:D t + G D:D t^2) / rho0.

Flows: simple shear v_x = y in plane strain (both formulations) and in 3-D (sigma_xy = 1.0577
Pa, e = 5.1442e-6 J/kg), and in the axisymmetric form the isochoric
expansion v_r = r, v_z = -2 z, whose hoop rate v_r / r carries a third of
the dissipation (sigma_rr = sigma_hoop = 2.1154 Pa, sigma_zz = -4.2308 Pa,
e = 6.1731e-5 J/kg). Tolerances: 1% of the largest stress component per
component, 1% on the energy (measured: 0.3% and 0.1%).
"""
import os
import subprocess
import sys

import h5py
import numpy as np

RHO, E, NU, ETA, T_END, DX = 1000.0, 30.0, 0.3, 1.0, 5.0e-3, 1.0e-3
G = E / (2 * (1 + NU))

CASE = """name: viscous_{name}
dimension: {dim}
{plane}
materials:
  - name: goo
    density: {rho}
    youngs_modulus: {E}
    poisson_ratio: {nu}
    viscosity: {eta}
bodies:
  - name: block
    material: goo
    min: {lo}
    max: {hi}
    velocity: {velocity}
    velocity_gradient: {gradient}
numerics:
  dx: {dx}
  formulation: {formulation}
  h_over_dx: 1.2
  artificial_viscosity: {{alpha: 0, beta: 0}}
  xsph: 0
  csph: true
  end_time: {t}
output:
  snapshot_interval: {t}
  history_interval: 5.0e-4
"""

# name, dimension, plane line, box, velocity, gradient (row-major), and the
# strain rate D in the snapshot's axes (x, y, z; axisymmetric: r, z, hoop)
FLOWS = [
    ("shear_plane_strain", 2, "plane: strain", [0, 0], [0.04, 0.04], [0, 0],
     [0, 1, 0, 0, 0, 0, 0, 0, 0], [[0, 0.5, 0], [0.5, 0, 0], [0, 0, 0]]),
    ("shear_total_lagrangian", 2, "plane: strain", [0, 0], [0.04, 0.04], [0, 0],
     [0, 1, 0, 0, 0, 0, 0, 0, 0], [[0, 0.5, 0], [0.5, 0, 0], [0, 0, 0]]),
    ("shear_3d", 3, "", [0, 0, 0], [0.024, 0.024, 0.024], [0, 0, 0],
     [0, 1, 0, 0, 0, 0, 0, 0, 0], [[0, 0.5, 0], [0.5, 0, 0], [0, 0, 0]]),
    # the gradient acts about the box centre (r = 0.02 m): the velocity
    # puts the expansion's centre on the axis, v_r = r
    ("expansion_axisymmetric", 2, "plane: axisymmetric", [0, -0.02], [0.04, 0.02], [0.02, 0],
     [1, 0, 0, 0, -2, 0, 0, 0, 0], [[1, 0, 0], [0, -2, 0], [0, 0, 1]]),
]

# the snapshot's stress columns: XX, YY, ZZ, XY, YZ, XZ
PAIRS = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)]


def check_flow(sph, work, flow):
    name, dim, plane, lo, hi, velocity, gradient, rate = flow
    folder = os.path.join(work, name)
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "case.yaml")
    with open(path, "w") as f:
        f.write(CASE.format(name=name, dim=dim, plane=plane, rho=RHO, E=E, nu=NU, eta=ETA,
                            lo=lo, hi=hi, velocity=velocity, gradient=gradient, dx=DX, t=T_END,
                            formulation="total_lagrangian" if "total" in name
                            else "updated_lagrangian"))
    out = os.path.join(folder, "run")
    proc = subprocess.run([sph, "run", path, "--out", out, "--quiet"], capture_output=True,
                          text=True)
    if proc.returncode != 0:
        return [f"{name}: sph exited {proc.returncode}: {proc.stderr.strip()}"]
    with h5py.File(os.path.join(out, "snap_00001.h5")) as snap:
        time = float(snap.attrs["time_s"][0])
        x0 = snap["position"][:] - snap["displacement"][:]
        stress, energy = snap["stress"][:], snap["internal_energy"][:]
    margin = 10 * DX
    inner = np.ones(len(x0), dtype=bool)
    for a in range(dim):
        inner &= (x0[:, a] > lo[a] + margin) & (x0[:, a] < hi[a] - margin)
    d = np.array(rate, dtype=float)
    want = 2 * ETA * d + 2 * G * d * time
    want_energy = (2 * ETA * np.sum(d * d) * time + G * np.sum(d * d) * time**2) / RHO
    scale = np.abs(want).max()
    failures = []
    for column, (a, b) in enumerate(PAIRS):
        got = stress[inner, column]
        error = np.abs(got - want[a, b]).max() / scale
        print(f"{name}: sigma_{a}{b} {got.min():.5g} to {got.max():.5g} Pa, expected "
              f"{want[a, b]:.5g} (largest error {error:.2e} of {scale:.4g} Pa; "
              f"{inner.sum()} particles)")
        if error > 0.01:
            failures.append(f"{name}: sigma_{a}{b} off by {error:.3g} of {scale:.4g} Pa")
    error = np.abs(energy[inner] - want_energy).max() / want_energy
    print(f"{name}: e {energy[inner].min():.6g} to {energy[inner].max():.6g} J/kg, expected "
          f"{want_energy:.6g} (largest error {error:.2e})")
    if error > 0.01:
        failures.append(f"{name}: internal energy off by {error:.3g}")
    return failures


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sph, work = sys.argv[1], sys.argv[2]
    failures = []
    for flow in FLOWS:
        failures += check_flow(sph, work, flow)
    for failure in failures:
        print("FAIL:", failure)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

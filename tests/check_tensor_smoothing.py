#!/usr/bin/python3
"""The tensor smoothing length (numerics.smoothing: tensor,
kernels/tensor_smoothing.cl) against hand-computed homogeneous flows.

usage: check_tensor_smoothing.py SPH WORKDIR

Each particle's kernel is an ellipsoid with the metric G = h0^2 M, carried
with the material: for a flow whose deformation gradient is F, G = (F
F^T)^-1 while its semi-axes stay within [1/2.5, 2.5] h0, and clamped to
those bounds beyond. The blocks are the nearly stress-free solids of
tests/check_homogeneous_flow.py (rho0 = 1000 kg/m^3, E = 3e-3 Pa, nu =
0.3): their waves cross 1.7 mm per second, so the interior keeps the
imposed linear velocity field v = L0 (x - centre) and F = I + L0 t exactly
(a particle moves at its initial velocity). The interior is 8 dx from
every face of the 20 dx cube, beyond the search reach of 2.5 supports (6
dx) and the faces' waves (2.6 mm).

- large shear (v_x = y, gamma = 1.5 at 1.5 s, cfl 0.1): the metric, and
  the stress against the hypoelastic solution with the Jaumann rate
  (sigma_xy = G sin gamma, sigma_xx = -sigma_yy = G (1 - cos gamma), Dienes
  1979), as for the isotropic kernel in check_homogeneous_flow.py: the
  passes' corrected velocity gradient must stay exact for a linear field
  with kernels sheared to an aspect ratio of 3.5;
- stretch and squash with shear (L0 = [[0.8, 0.4, 0], [0, 0, 0], [0, 0,
  -0.35]] 1/s, 1 s): G's eigenvalues reach 0.29 and 2.37;
- a stretch beyond the bound (v_x = 2 x, 1 s: F_xx = 3, G_xx = 1/9) is held
  at G_xx = 1/2.5^2 = 0.16.
Tolerances: the metric to 1% of its largest component, the stress to 1% of
the largest (the isotropic kernel's tolerance); measured: see the output.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_homogeneous_flow import (CASE, DX, ELASTIC, PAIRS, compare,  # noqa: E402
                                    jaumann_shear, main, run_case)

AXIS_MAX = 2.5  # include/sph_shared.h SPH_TENSOR_AXIS_MAX
BOX = 0.020  # m: 20 dx
MARGIN = 8 * DX  # the interior: beyond the reach (6 dx) and the faces' waves (2.6 mm)

# name, velocity gradient L0 (1/s, row-major), end time (s), cfl, stress expectation
FLOWS = [
    ("large_shear", [0, 1, 0, 0, 0, 0, 0, 0, 0], 1.5, 0.1, jaumann_shear(0, 1)),
    ("stretch_squash_shear", [0.8, 0.4, 0, 0, 0, 0, 0, 0, -0.35], 1.0, 0.3, None),
    ("stretch_beyond_bound", [2, 0, 0, 0, 0, 0, 0, 0, 0], 1.0, 0.3, None),
]


def expected_metric(gradient, time):
    """(F F^T)^-1 with F = I + L0 t, each eigenvalue clamped to the bounds."""
    f = np.eye(3) + np.array(gradient, dtype=float).reshape(3, 3) * time
    g = np.linalg.inv(f @ f.T)
    values, vectors = np.linalg.eigh(g)
    values = np.clip(values, 1 / AXIS_MAX**2, AXIS_MAX**2)
    return vectors @ np.diag(values) @ vectors.T


def run(sph, work, name, gradient, end, cfl):
    l0 = np.array(gradient, dtype=float).reshape(3, 3)
    velocity = list(-l0 @ np.full(3, BOX / 2))  # the flow's fixed point at the box centre
    text = CASE.format(name=name, dim=3, plane="", material=ELASTIC, lo=[0, 0, 0], hi=[BOX] * 3,
                       velocity=velocity, gradient=gradient, dx=DX, t=end,
                       formulation="updated_lagrangian",
                       cfl_line=f"  cfl: {cfl}\n  smoothing: tensor\n")
    result = run_case(sph, work, name, text, ("stress", "smoothing_metric"))
    if isinstance(result, str):
        return result
    time, x0, fields = result
    inner = np.all((x0 > MARGIN) & (x0 < BOX - MARGIN), axis=1)
    return time, inner, fields


def check(sph, work, flow):
    name, gradient, end, cfl, expect = flow
    result = run(sph, work, name, gradient, end, cfl)
    if isinstance(result, str):
        return [result]
    time, inner, fields = result
    print(f"{name}: t = {time:.4g} s, {inner.sum()} interior particles")
    metric = expected_metric(gradient, time)
    failures = []
    scale = np.abs(metric).max()
    for column, (a, b) in enumerate(PAIRS):
        failures += compare(name, f"G_{a}{b}", fields["smoothing_metric"][inner, column],
                            metric[a, b], scale, 0.01)
    if expect is not None:
        sigma = expect(time)[0]
        scale = np.abs(sigma).max()
        for column, (a, b) in enumerate(PAIRS):
            failures += compare(name, f"sigma_{a}{b} (Pa)", fields["stress"][inner, column],
                                sigma[a, b], scale, 0.01)
    return failures


if __name__ == "__main__":
    main(FLOWS, check, __doc__)

#!/usr/bin/env python3
"""Tip deflection of a clamped cantilever under a tip load of fixed direction,
from Reissner's geometrically exact plane beam (E. Reissner, 1972, "On
one-dimensional finite-strain beam theory: the plane problem", ZAMP 23):
large rotation with axial extension and shear, linear section laws
N = EA eps, Q = kappa G A gamma, M = EI k.

It is the independent reference for the SPH beam (docs/validation_beam.md):
the elastica (inextensible, no shear; REFERENCES.md 1) is its limit for
EA, GA -> infinity, and linear Timoshenko theory its limit for F -> 0.

usage: tools/reissner_beam.py [--force N] [--length m] [--height m]
                              [--thickness m] [--youngs Pa] [--poisson nu]
                              [--shear-factor kappa] [--no-shear-extension]
Prints the tip deflection, its horizontal shortening and the tip rotation.
"""
import argparse
import math
import sys


def integrate(moment0, force, length, ea, gas, ei, steps):
    """RK4 along the reference arc length s from the clamp. State: x, y,
    theta, M. The section force is the tip load (0, -force) everywhere, so
    N = n.t, Q = n.n with t = (cos th, sin th), n = (-sin th, cos th), and
    M(s) = -force (x_tip - x(s)) gives dM/ds = force dx/ds."""

    def rates(state):
        x, y, theta, moment = state
        c, s = math.cos(theta), math.sin(theta)
        axial = -force * s  # n . t with n = (0, -force)
        shear = -force * c  # n . normal
        eps, gamma = axial / ea, shear / gas
        dx = (1 + eps) * c - gamma * s
        dy = (1 + eps) * s + gamma * c
        return (dx, dy, moment / ei, force * dx)

    h = length / steps
    state = (0.0, 0.0, 0.0, moment0)
    for _ in range(steps):
        k1 = rates(state)
        k2 = rates(tuple(v + 0.5 * h * k for v, k in zip(state, k1)))
        k3 = rates(tuple(v + 0.5 * h * k for v, k in zip(state, k2)))
        k4 = rates(tuple(v + h * k for v, k in zip(state, k3)))
        state = tuple(v + h / 6 * (a + 2 * b + 2 * c + d)
                      for v, a, b, c, d in zip(state, k1, k2, k3, k4))
    return state


def solve(force, length, ea, gas, ei, steps=4000):
    """Shooting on the clamp moment M(0) so that M(L) = 0 (free tip)."""
    if force == 0:
        return (length, 0.0, 0.0)
    lo, hi = -force * length * 1.5, 0.0  # M(0) = -F x_tip, 0 < x_tip < 1.5 L
    f_lo = integrate(lo, force, length, ea, gas, ei, steps)[3]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        f_mid = integrate(mid, force, length, ea, gas, ei, steps)[3]
        if (f_mid < 0) == (f_lo < 0):
            lo, f_lo = mid, f_mid
        else:
            hi = mid
        if hi - lo < 1e-13 * force * length:
            break
    x, y, theta, _ = integrate(0.5 * (lo + hi), force, length, ea, gas, ei, steps)
    return (x, y, theta)


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--force", type=float, default=1750.0, help="tip load, N (default 1750)")
    p.add_argument("--length", type=float, default=0.1, help="m (default 0.1)")
    p.add_argument("--height", type=float, default=0.01, help="in-plane height, m (default 0.01)")
    p.add_argument("--thickness", type=float, default=1e-3, help="m (default 0.001)")
    p.add_argument("--youngs", type=float, default=210e9, help="Pa (default 210e9)")
    p.add_argument("--poisson", type=float, default=0.3, help="(default 0.3)")
    p.add_argument("--shear-factor", type=float, default=5.0 / 6.0,
                   help="Timoshenko shear coefficient (default 5/6, rectangle)")
    p.add_argument("--no-shear-extension", action="store_true",
                   help="the elastica: inextensible, no shear")
    a = p.parse_args(argv)
    area = a.height * a.thickness
    ei = a.youngs * a.thickness * a.height ** 3 / 12
    shear_modulus = a.youngs / (2 * (1 + a.poisson))
    ea, gas = a.youngs * area, a.shear_factor * shear_modulus * area
    if a.no_shear_extension:
        ea = gas = 1e30
    x, y, theta = solve(a.force, a.length, ea, gas, ei)
    print("load parameter F L^2/(E I) = %.4f" % (a.force * a.length ** 2 / ei))
    print("tip deflection %.6g m (%.5f L), shortening %.6g m, tip rotation %.5f rad"
          % (-y, -y / a.length, a.length - x, -theta))
    linear = a.force * a.length ** 3 / (3 * ei) + (0 if a.no_shear_extension
                                                   else a.force * a.length / gas)
    print("linear Timoshenko: %.6g m" % linear)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

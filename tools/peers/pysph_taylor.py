"""PySPH side of tools/peer_bench.py: the 3-D Taylor bar stepped a fixed
number of times with PySPH's own solid-mechanics equations.

Run by peer_bench.py with the Python of a virtual environment that has
PySPH (it is not meant to be run with the system Python):

    VENV/bin/python tools/peers/pysph_taylor.py --dx 2.6e-4 --steps 300 \
        --dt 1.50e-8 --warmup 20 --threads 2 --out DIR

PySPH ships no 3-D elastic-plastic model (pysph.sph.solid_mech.hvi's
VonMisesPlasticity2D takes J2 from the in-plane components only, and
ElasticSolidsScheme uses the 2-D velocity gradient), so this runs the
closest 3-D scheme it has: Gray, Monaghan & Swift's elastic SPH, equation by
equation from pysph.sph.solid_mech.basic (linear EOS p = c0^2 (rho - rho0),
3-D velocity gradient, Jaumann-rate Hooke's law, momentum with stress,
Monaghan viscosity, continuity, energy, XSPH), Wendland C2 ("WendlandQuintic"
in PySPH) at h = 1.2 dx (support 2h, the same 56-neighbour lattice stencil as
impact-sph), predictor-corrector (PEC: one evaluation of the equations per
step), a fixed time step. The anvil is a reflecting plane through the
lowest layer's centres (impact-sph's wall at z = 0 acts on centres closer
than dx/2, so all three codes touch it from the first step), applied with
numpy after each step (elastic, frictionless). Same lattice as impact-sph:
spacing dx, centred in the cylinder's bounding box, points with r <= R.

It writes DIR/pysph_result.json: particles, steps timed, wall seconds over
them (perf_counter between the end of the warm-up step and the end of the
last step), neighbours per particle (from PySPH's own neighbour search at the
start), and the settings.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

# The bar and the lattice as peer_bench.py defines them (standard library
# only, so this venv's Python imports it too).
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from peer_bench import DENSITY, H_OVER_DX, LENGTH, POISSON, RADIUS, SPEED, YOUNG  # noqa: E402
from peer_bench import lattice_axis  # noqa: E402


def lattice(dx):
    """Positions of impact-sph's fill (host/scene.c) of the full cylinder:
    points centred in the bounding box (peer_bench.lattice_axis), kept where
    x^2 + y^2 <= R^2."""
    def axis(lo, hi):
        start, n = lattice_axis(lo, hi, dx)
        return start + dx * np.arange(n)
    x1 = axis(-RADIUS, RADIUS)
    z1 = axis(0.0, LENGTH)
    x, y, z = np.meshgrid(x1, x1, z1, indexing="ij")
    keep = (x * x + y * y) <= RADIUS * RADIUS
    return x[keep], y[keep], z[keep]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dx", type=float, required=True)
    ap.add_argument("--dt", type=float, required=True, help="time step (peer_bench.time_step)")
    ap.add_argument("--steps", type=int, required=True, help="timed steps")
    ap.add_argument("--warmup", type=int, default=20, help="untimed steps first")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()

    os.environ["OMP_NUM_THREADS"] = str(args.threads)
    from compyle.config import get_config
    get_config().use_openmp = args.threads > 1

    from pysph.base.kernels import WendlandQuintic
    from pysph.base.nnps import LinkedListNNPS
    from pysph.solver.application import Application
    from pysph.solver.solver import Solver
    from pysph.sph.equation import Group
    from pysph.sph.integrator import PECIntegrator
    from pysph.sph.integrator_step import SolidMechStep
    from pysph.sph.basic_equations import (ContinuityEquation, MonaghanArtificialViscosity,
                                           XSPHCorrection, VelocityGradient3D)
    from pysph.sph.solid_mech.basic import (IsothermalEOS, MomentumEquationWithStress,
                                            HookesDeviatoricStressRate, EnergyEquationWithStress,
                                            get_particle_array_elastic_dynamics)

    dx, h, dt = args.dx, H_OVER_DX * args.dx, args.dt
    total = args.warmup + args.steps
    marks = {}
    # impact-sph's anvil (z = 0) pushes on centres closer than dx/2, i.e. on
    # the lowest layer from the first step; here a reflecting plane through
    # that layer's centres.
    z_wall = float(lattice(dx)[2].min())

    class TaylorBar(Application):
        def _configure_global_config(self):
            # PySPH's command line leaves OpenMP off unless told otherwise
            # (its global config is reset while the options are processed),
            # so set it here, just before the equations are generated.
            super()._configure_global_config()
            get_config().use_openmp = args.threads > 1

        def create_particles(self):
            x, y, z = lattice(dx)
            pa = get_particle_array_elastic_dynamics(
                name="bar", x=x, y=y, z=z, h=np.full_like(x, h),
                m=np.full_like(x, DENSITY * dx ** 3), rho=np.full_like(x, DENSITY),
                w=np.full_like(x, -SPEED),
                # no wdeltap: PySPH's default (-1) skips the artificial-stress
                # term of the momentum equation, which a positive value
                # evaluates per pair even with no stress to weigh
                constants=dict(E=YOUNG, nu=POISSON, rho_ref=DENSITY))
            pa.rho0[:] = DENSITY
            return [pa]

        def create_solver(self):
            integrator = PECIntegrator(bar=SolidMechStep())
            solver = Solver(kernel=WendlandQuintic(dim=3), dim=3, integrator=integrator,
                            dt=dt, tf=dt * (total + 10), max_steps=total,
                            pfreq=10 ** 9, adaptive_timestep=False)
            return solver

        def create_equations(self):
            src = ["bar"]
            return [
                Group(equations=[
                    IsothermalEOS("bar", sources=None),
                    VelocityGradient3D("bar", sources=src),
                ]),
                Group(equations=[
                    ContinuityEquation("bar", sources=src),
                    MomentumEquationWithStress("bar", sources=src),
                    MonaghanArtificialViscosity("bar", sources=src, alpha=1.5, beta=1.5),
                    HookesDeviatoricStressRate("bar", sources=None),
                    EnergyEquationWithStress("bar", sources=src, alpha=1.5, beta=1.5, eta=0.01),
                    XSPHCorrection("bar", sources=src, eps=0.1),
                ]),
            ]

        def post_step(self, solver):
            pa = self.particles[0]
            low = pa.z < z_wall  # the anvil: reflect through the lowest layer
            if low.any():
                pa.z[low] = 2.0 * z_wall - pa.z[low]
                pa.w[low] = np.abs(pa.w[low])
            if solver.count == args.warmup:
                marks["start"] = time.perf_counter()
            if solver.count == total:
                marks["end"] = time.perf_counter()

    os.makedirs(args.out, exist_ok=True)
    app = TaylorBar(fname="taylor_bar")
    t0 = time.perf_counter()
    app.run(["--disable-output", "-d", os.path.join(args.out, "pysph_output"), "-q"])
    wall_all = time.perf_counter() - t0
    pa = app.particles[0]

    # Neighbours per particle on the initial lattice (PySPH's own search;
    # the count includes the particle itself, which is taken off).
    x, y, z = lattice(dx)
    from pysph.base.utils import get_particle_array
    probe = get_particle_array(name="p", x=x, y=y, z=z, h=np.full_like(x, h))
    nnps = LinkedListNNPS(dim=3, particles=[probe], radius_scale=2.0)
    from cyarray.carray import UIntArray
    nbrs = UIntArray()
    counts = []
    for i in range(len(x)):
        nnps.get_nearest_particles(0, 0, int(i), nbrs)
        counts.append(nbrs.length - 1)

    steps = total - args.warmup if "end" in marks and "start" in marks else 0
    wall = marks["end"] - marks["start"] if steps else float("nan")
    result = {
        "code": "PySPH",
        "particles": int(pa.get_number_of_particles()),
        "steps": steps,
        "warmup_steps": args.warmup,
        "wall_time_s": wall,
        "wall_time_whole_run_s": wall_all,
        "particle_steps_per_s": pa.get_number_of_particles() * steps / wall if steps else None,
        "neighbours_mean": float(np.mean(counts)),
        "neighbours_max": int(np.max(counts)),
        "dt_s": dt,
        "threads": args.threads,
        "openmp": bool(get_config().use_openmp),
        "finite": bool(np.isfinite(pa.x).all() and np.isfinite(pa.w).all()),
    }
    with open(os.path.join(args.out, "pysph_result.json"), "w") as f:
        json.dump(result, f, indent=2)
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())

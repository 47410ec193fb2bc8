#!/usr/bin/env python3
"""tools/reissner_beam.py against the closed forms it must reduce to: the
elastica tip deflections of REFERENCES.md 1 (0.30172 L at F L^2/EI = 1,
0.81061 L at 10, tabulated to 5 digits) and linear Timoshenko theory at a
small load (F L^2/EI = 1e-4, where the geometric nonlinearity is ~1e-8)."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import reissner_beam  # noqa: E402

L, EI = 0.1, 210e9 * 1e-3 * 1e-6 / 12
EA, GAS = 210e9 * 1e-5, 5 / 6 * 210e9 / 2.6 * 1e-5
failures = 0


def expect(name, got, want, tol):
    global failures
    ok = abs(got - want) <= tol * abs(want)
    print(f"{'ok ' if ok else 'FAIL'} {name}: {got:.7g} (expected {want:.7g} within {tol:g})")
    failures += not ok


for load_parameter, want in ((1.0, 0.30172), (10.0, 0.81061)):
    force = load_parameter * EI / L ** 2
    _, y, _ = reissner_beam.solve(force, L, 1e30, 1e30, EI)
    expect(f"elastica F L^2/EI = {load_parameter:g}", -y / L, want, 2e-5)

force = 1e-4 * EI / L ** 2
_, y, _ = reissner_beam.solve(force, L, EA, GAS, EI)
expect("linear Timoshenko limit", -y, force * L ** 3 / (3 * EI) + force * L / GAS, 1e-6)
sys.exit(1 if failures else 0)

#!/usr/bin/env python3
"""The tables of run.sh's runs (docs/validation_taylor.md, "The hourglass
coefficient in the total Lagrangian form"):

    /usr/bin/python3 docs/results/hourglass_session42/table.py OUT > runs.md

Taylor rows: summary.json's length, footprint radius, peak plastic strain,
energy balance and the viscosity's and hourglass springs' work over KE0.
Rings rows: stability_session40/rings_table.py's (pieces, moving apart).
Beam rows: the tip's mean deflection over the reference window against
the reference (summary.json)."""
import glob
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "stability_session40"))
from rings_table import row as rings_row  # noqa: E402


def summary(run):
    with open(os.path.join(run, "summary.json")) as f:
        return json.load(f)


def parse(run):
    """(kind, alpha, the rest) from run.sh's folder names."""
    kind, alpha, rest = os.path.basename(run).split("_", 2)
    return kind, float(alpha[1:]), rest


def taylor(runs):
    print("| dx (mm) | hourglass alpha | length (mm) | footprint radius (mm) | peak eps_p |"
          " energy balance | viscosity's work / KE0 | hourglass work / KE0 | healthy |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for run in sorted(runs, key=lambda r: (-float(parse(r)[2]), parse(r)[1])):
        s, (_, alpha, dx) = summary(run), parse(run)
        print("| %g | %g | %.3f | %.3f | %.2f | %.2f%% | %.3f | %.4f | %s |" % (
            1e3 * float(dx), alpha, 1e3 * s["final_length_m"], 1e3 * s["footprint_radius_m"],
            s["max_plastic_strain"], 100 * s["energy_drift"],
            s["artificial_viscosity_work_fraction"], s["hourglass_work_fraction"],
            "yes" if s["healthy"] else "no: " + s.get("unhealthy_reason", s["status"])))


def beam(runs):
    print("| load (N) | dx (mm) | hourglass alpha | mean tip deflection (mm) | reference (mm) |"
          " e_av | hourglass work / largest energy |")
    print("| --- | --- | --- | --- | --- | --- | --- |")

    def key(run):
        load, dx = parse(run)[2].split("_")
        return int(load), -float(dx), parse(run)[1]

    for run in sorted(runs, key=key):
        s, alpha, (load, dx) = summary(run), parse(run)[1], key(run)[:2]
        print("| %d | %g | %g | %.3f | %.4g | %+.2f%% | %.4f |" % (
            load, -1e3 * dx, alpha, -1e3 * s["tip_deflection_mean_m"], -1e3 * s["reference_m"],
            100 * s["e_av"], s["hourglass_work_fraction"]))


def main():
    out = sys.argv[1]
    runs = [r for r in glob.glob(os.path.join(out, "*"))
            if os.path.exists(os.path.join(r, "summary.json"))]
    by_kind = {}
    for run in runs:
        by_kind.setdefault(parse(run)[0], []).append(run)
    if "taylor" in by_kind:
        print("3-D 4340 quarter bar, total Lagrangian, 100 us\n")
        taylor(by_kind["taylor"])
    if "rings" in by_kind:
        print("\nRubber rings (total Lagrangian, two parts), 1.5 ms\n")
        print("| hourglass alpha | dx (mm) | pieces at 1.5 ms | first torn (ms) |"
              " moving apart (m/s) | energy balance | viscosity's work / KE0 |")
        print("| --- | --- | --- | --- | --- | --- | --- |")
        for run in sorted(by_kind["rings"], key=lambda r: (-float(parse(r)[2]), parse(r)[1])):
            print("| %g |" % parse(run)[1] + rings_row(run).split("|", 2)[2])
    if "beam" in by_kind:
        print("\nCantilever beam, total Lagrangian, 3.5 ms\n")
        beam(by_kind["beam"])


if __name__ == "__main__":
    main()

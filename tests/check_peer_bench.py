#!/usr/bin/env python3
"""tools/peer_bench.py end to end with no peer (ours only, both
formulations, --particles 1500: 1620 on the bar's lattice): its two runs per
formulation are long enough (20 and 20 + 200 steps) for the timing to be
the difference of the two, as in the real benchmark, and the report holds a
rate for each.

    check_peer_bench.py SPH RESULTS"""
import json
import math
import os
import subprocess
import sys

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "peer_bench.py")
STEPS = 200


def main():
    sph, results = sys.argv[1:3]
    subprocess.run([sys.executable, TOOL, "--particles", "1500", "--steps", str(STEPS), "--warmup", "20",
                    "--peers", "--sph", sph, "--results", results, "--work",
                    os.path.join(results, "work")], check=True)
    with open(os.path.join(results, "peers.json")) as f:
        rows = json.load(f)["results"]
    assert os.path.exists(os.path.join(results, "peers.md"))
    ours = [r for r in rows if r["code"] == "impact-sph"]
    assert len(ours) == 2 and not any(r.get("skipped") for r in ours), ours
    for r in ours:
        assert r["timing"].startswith("(wall_B - wall_A)"), r["timing"]
        assert abs(r["steps"] - STEPS) <= 2, r["steps"]  # end time (steps - 1/2) dt
        rate = r["particle_steps_per_s"]
        assert math.isfinite(rate) and rate > 0, rate
        print("check_peer_bench: %s %d steps, %.3g particle-steps/s" %
              (r["variant"], r["steps"], rate))
    return 0


if __name__ == "__main__":
    sys.exit(main())

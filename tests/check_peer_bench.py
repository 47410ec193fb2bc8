#!/usr/bin/env python3
"""tools/peer_bench.py end to end with no peer (ours only, both
formulations, --particles 1500: 1620 on the bar's lattice): its two runs per
formulation are long enough (20 and 20 + 200 steps) for the timing to be
the difference of the two, as in the real benchmark, and the report holds a
rate for each. Which of the two timings the tool takes depends on the
machine's load (CI runs tests side by side), so the choice itself is
checked on made-up summaries, and the end-to-end run is held to the steps
of whichever timing its report names.

    check_peer_bench.py SPH RESULTS"""
import json
import math
import os
import subprocess
import sys

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "peer_bench.py")
STEPS = 200


def check_timing_rule():
    sys.path.insert(0, os.path.dirname(TOOL))
    import peer_bench
    a = dict(steps=21, wall_time_s=0.10)
    steps, wall, how = peer_bench.ours_timing(a, dict(steps=221, wall_time_s=0.60))
    assert (steps, round(wall, 9)) == (200, 0.5) and how.startswith("(wall_B - wall_A)"), how
    # B - A within 5% of B: start-up noise, so the whole of B.
    steps, wall, how = peer_bench.ours_timing(a, dict(steps=221, wall_time_s=0.104))
    assert (steps, wall) == (221, 0.104) and how.startswith("whole run"), how
    steps, wall, how = peer_bench.ours_timing(a, dict(steps=21, wall_time_s=0.3))
    assert steps == 21 and how.startswith("whole run"), how


def main():
    check_timing_rule()
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
        # end time (steps - 1/2) dt, so each run's count within 2
        if r["timing"].startswith("(wall_B - wall_A)"):
            assert abs(r["steps"] - STEPS) <= 2, r["steps"]
        else:
            assert r["timing"].startswith("whole run"), r["timing"]
            assert abs(r["steps"] - (STEPS + 20)) <= 2, r["steps"]
            print("check_peer_bench: %s timed over the whole run (load)" % r["variant"])
        rate = r["particle_steps_per_s"]
        assert math.isfinite(rate) and rate > 0, rate
        print("check_peer_bench: %s %d steps, %.3g particle-steps/s" %
              (r["variant"], r["steps"], rate))
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""The lane passes' candidate lists (kernels/lanes.cl, lane_list_build)
against the cell walk they replace: a case run as built and with
numerics.lane_lists false (the passes walk the cells around each lane
block, -DSPH_LANE_CELL_WALK) must write the same history.csv and
ballistics.csv to the byte. A list holds the walk's candidates that some
lane could reach before the next sort, in the walk's order, and a candidate
no lane reaches adds exactly zero, so the sums are the walk's bit for bit; a
list that missed a neighbour, or a list left stale after a sort, changes the
history.

Fails unless both runs ran the lanes, only the first built lists
(summary.json lane_list_candidates_per_block), and the first re-sorted at
least MIN_SORTS times (grid_sorts: the lists were rebuilt while particles
moved).

--room N builds the lists with room for N entries per block in private
memory (-DSPH_LANE_LIST_ROOM=N, default 1024), so that blocks with more
take the build's second walk, which writes straight into the list. Every
build's second walk also runs at a run's first sort, when the list is still
empty.

usage: check_lane_lists.py SPH CASE OUT_FOLDER MIN_SORTS [--room N] [sph --set arguments ...]
"""
import filecmp
import json
import os
import sys

from build_options_run import run_with_options


def run(sph, case, out, sets, lists, options=""):
    run_with_options(sph, case, out, sets + ["--set", f"numerics.lane_lists={lists}"], options,
                     "check_lane_lists")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    if summary.get("neighbour_lanes") != 8:
        sys.exit(f"FAIL: the run with lane_lists {lists} ran {summary.get('neighbour_lanes')} "
                 "particles per work-item, not the lanes")
    if ("lane_list_candidates_per_block" in summary) != (lists == "true"):
        sys.exit(f"FAIL: the run with lane_lists {lists} did not do as the key says "
                 "(lane_list_candidates_per_block in summary.json)")
    return summary


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    sph, case, out, min_sorts = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    sets = sys.argv[5:]
    options = ""
    if sets[:1] == ["--room"]:
        options = f"-DSPH_LANE_LIST_ROOM={int(sets[1])}"
        sets = sets[2:]
    lists = run(sph, case, os.path.join(out, "lists"), sets, "true", options)
    run(sph, case, os.path.join(out, "walk"), sets, "false")
    sorts = lists.get("grid_sorts", 0)
    if sorts < min_sorts:
        sys.exit(f"FAIL: the run sorted its grid {sorts} times, fewer than {min_sorts}: "
                 "the lists were not rebuilt as particles moved")
    compared = 0
    for name in ("history.csv", "ballistics.csv"):
        a, b = os.path.join(out, "lists", name), os.path.join(out, "walk", name)
        if not os.path.exists(a) and not os.path.exists(b):
            continue
        if not filecmp.cmp(a, b, shallow=False):
            sys.exit(f"FAIL: {name} differs between the lists and the cell walk")
        compared += 1
    print(f"check_lane_lists: {compared} file(s) identical; {sorts} sorts, "
          f"{lists.get('lane_list_candidates_per_block', 0):.1f} candidates per lane block")


if __name__ == "__main__":
    main()

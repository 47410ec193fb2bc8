#!/usr/bin/python3
"""How much of the lane passes' arithmetic is masked, by geometry alone.

kernels/lanes.cl gives a work-item SPH_LANES particles that are consecutive
in the cell-sorted order, walks the cells around their box and evaluates a
candidate for every lane once any lane reaches it. This script counts, on a
cylinder lattice like the bench's Taylor bar, per particle:

  tested     candidates in the cells walked (one vector distance test each)
  evaluated  lanes x candidates some lane reaches (the vector arithmetic)
  neighbours the pairs within the support (the useful arithmetic)

for the order the solver sorts in (cell, then slot) and, for comparison,
with the particles of each cell in Z-order (Morton) of sub-cells, the
reordering docs/performance.md considered to shrink each block.

    python3 tools/lane_occupancy.py [--radius 12] [--length 40] [--lanes 8]
"""
import argparse
import json
import sys

import numpy as np
from scipy.spatial import cKDTree

H_OVER_DX = 1.2
SUPPORT = 2.0 * H_OVER_DX  # Wendland C2: 2 h, in units of dx
SKIN = 0.2  # host/solver.h SPH_GRID_SKIN: cells are support (1 + skin) wide


def cylinder_lattice(radius, length):
    """Unit-spacing lattice points inside a cylinder along z, x fastest (host/scene.c's order)."""
    g = np.arange(-radius, radius) + 0.5
    z, y, x = np.meshgrid(np.arange(length) + 0.5, g, g, indexing="ij")
    p = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    return p[p[:, 0] ** 2 + p[:, 1] ** 2 <= radius * radius]


def morton(sub, levels):
    """Interleaved bits of integer sub-cell coordinates (x lowest)."""
    code = np.zeros(len(sub), dtype=np.int64)
    for bit in range(levels):
        for axis in range(3):
            code |= ((sub[:, axis] >> bit) & 1) << (3 * bit + axis)
    return code


def occupancy(points, cells, order, lanes):
    """Per-particle tested, evaluated and useful counts for blocks of `lanes` in `order`."""
    n = len(points)
    tree = cKDTree(points)
    neighbours = sum(len(v) - 1 for v in tree.query_ball_point(points, SUPPORT - 1e-9))
    tested = evaluated = 0
    for first in range(0, n, lanes):
        block = order[first:first + lanes]
        lo, hi = cells[block].min(axis=0) - 1, cells[block].max(axis=0) + 1
        inside = np.all((cells >= lo) & (cells <= hi), axis=1)
        candidates = points[inside]
        tested += len(candidates)
        d2 = ((candidates[:, None, :] - points[block][None, :, :]) ** 2).sum(axis=-1)
        reached = np.any((d2 < SUPPORT * SUPPORT) & (d2 > 0), axis=1)
        evaluated += lanes * int(reached.sum())
    return {"tested": tested / n, "evaluated": evaluated / n, "neighbours": neighbours / n}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--radius", type=int, default=12, help="bar radius, in dx (default 12)")
    ap.add_argument("--length", type=int, default=40, help="bar length, in dx (default 40)")
    ap.add_argument("--lanes", type=int, default=8, help="particles per work-item (default 8)")
    ap.add_argument("--json", help="write the counts here too")
    args = ap.parse_args(argv)
    points = cylinder_lattice(args.radius, args.length)
    cell_size = SUPPORT * (1.0 + SKIN)
    origin = points.min(axis=0) - 1e-6
    cells = np.floor((points - origin) / cell_size).astype(np.int64)
    dims = cells.max(axis=0) + 1
    key = (cells[:, 2] * dims[1] + cells[:, 1]) * dims[0] + cells[:, 0]
    slot = np.arange(len(points))
    rows = {"cell, slot (the solver's order)": np.lexsort((slot, key))}
    for levels in (1, 2):
        sub = np.floor((points - origin) / cell_size * 2 ** levels).astype(np.int64)
        sub -= cells * 2 ** levels
        rows[f"cell, Z-order of {2 ** levels}^3 sub-cells"] = np.lexsort(
            (slot, morton(sub, levels), key))
    print(f"{len(points)} particles, h = {H_OVER_DX} dx, cells {cell_size:.2f} dx, "
          f"{args.lanes} lanes")
    print(f"{'order':40s} {'tested':>8s} {'evaluated':>10s} {'neighbours':>11s} {'waste':>6s}")
    results = {}
    for name, order in rows.items():
        r = occupancy(points, cells, order, args.lanes)
        results[name] = r
        print(f"{name:40s} {r['tested']:8.1f} {r['evaluated']:10.1f} {r['neighbours']:11.1f} "
              f"{r['evaluated'] / r['neighbours']:6.2f}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"particles": len(points), "lanes": args.lanes, "orders": results}, f,
                      indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/bin/sh
# The rubber rings as shipped (total Lagrangian form, the one numerics
# block, two parts) at dx = 2, 1, 0.5 and 0.25 mm (session 41).
# usage: run_rings.sh SPH OUT
#   then /usr/bin/python3 docs/results/stability_session40/rings_table.py OUT > rings_tl.md
# 0.25 mm: 70,416 particles, 17,276 steps, 362 s on two cores; 0.125 mm:
# 281,472 particles, 34,637 steps, 1955 s.
set -e
sph=$1 out=$2
case=$(dirname "$0")/../../../cases/rubber_rings_2d.yaml
mkdir -p "$out"
for dx in 2e-3 1e-3 0.5e-3 0.25e-3 0.125e-3; do
    "$sph" run "$case" --quiet --out "$out/T_$dx" --set numerics.dx=$dx
done

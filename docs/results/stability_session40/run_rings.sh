#!/bin/sh
# The rubber rings as two parts (session 40): six numerics at dx = 2, 1 and
# 0.5 mm (F also at 0.25 mm), and the shipped numerics as one part at 1 mm.
# usage: run_rings.sh SPH OUT   (then rings_table.py OUT > rings_parts.md)
# A: as shipped (constant alpha = beta = 1, artificial stress 0.3 with the
#    relative weight, CSPH, h = 1.2 dx); B, C: A at h = 1.5 and 2.0 dx;
# D: Monaghan's published (lattice) weight, h = 1.5 dx; E: the lattice
#    weight without CSPH (Gray, Monaghan & Swift's form) at h = 1.2 dx; F: E
#    at h = 1.5 dx.
set -e
sph=$1 out=$2
case=$(dirname "$0")/../../../cases/rubber_rings_2d.yaml
lat="--set numerics.artificial_stress.weight=lattice"
# the case as it was shipped then (since session 41 it runs the total
# Lagrangian form with the one numerics block)
then="--set numerics.formulation=updated_lagrangian
      --set numerics.artificial_viscosity.scheme=monaghan
      --set numerics.artificial_viscosity.alpha=1.0 --set numerics.artificial_viscosity.beta=1.0
      --set numerics.xsph=0.5 --set numerics.artificial_stress.epsilon=0.3"
mkdir -p "$out"
run() { name=$1; shift; "$sph" run "$case" --quiet --out "$out/$name" $then "$@"; }
for dx in 2e-3 1e-3 0.5e-3; do
    run A_$dx --set numerics.dx=$dx
    run B_$dx --set numerics.dx=$dx --set numerics.h_over_dx=1.5
    run C_$dx --set numerics.dx=$dx --set numerics.h_over_dx=2.0
    run D_$dx --set numerics.dx=$dx $lat --set numerics.h_over_dx=1.5
    run E_$dx --set numerics.dx=$dx $lat --set numerics.csph=false
    run F_$dx --set numerics.dx=$dx $lat --set numerics.csph=false --set numerics.h_over_dx=1.5
done
run A_one_part_1e-3 --set numerics.dx=1e-3 --set bodies.right.part=0
run F_0.25e-3 --set numerics.dx=0.25e-3 $lat --set numerics.csph=false --set numerics.h_over_dx=1.5

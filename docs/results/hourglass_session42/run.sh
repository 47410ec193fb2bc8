#!/bin/sh
# The total Lagrangian hourglass coefficient against the shipped and study
# cases (session 42, docs/validation_taylor.md, "The hourglass coefficient").
# usage: run.sh SPH OUT [part...]   parts: taylor rings beam (default all)
#   then /usr/bin/python3 docs/results/hourglass_session42/table.py OUT
set -e
sph=$1 out=$2
shift 2
parts=${*:-taylor rings beam}
cases=$(dirname "$0")/../../../cases
mkdir -p "$out"
run() { # name case sets...
    name=$1 case=$2
    shift 2
    [ -f "$out/$name/summary.json" ] && return 0
    "$sph" run "$cases/$case" --quiet --out "$out/$name" "$@" || true
}
for part in $parts; do
    case $part in
    taylor) # the 3-D 4340 quarter bar, 100 us
        for a in 0.01 0.03 0.1 0.3 1 10; do
            run "taylor_a${a}_3.5e-4" taylor_3d_4340.yaml --set numerics.formulation=total_lagrangian \
                --set numerics.dx=3.5e-4 --set numerics.hourglass=$a
        done
        for dx in 5e-4 2.5e-4 1.8e-4; do
            for a in 0.1 10; do
                run "taylor_a${a}_$dx" taylor_3d_4340.yaml --set numerics.formulation=total_lagrangian \
                    --set numerics.dx=$dx --set numerics.hourglass=$a
            done
        done ;;
    rings)
        for dx in 2e-3 1e-3 0.5e-3; do
            for a in 0 0.01 0.03 0.1 1 10; do
                [ $dx = 0.5e-3 ] && [ $a != 0.1 ] && [ $a != 10 ] && continue
                run "rings_a${a}_$dx" rubber_rings_2d.yaml --set numerics.dx=$dx --set numerics.hourglass=$a
            done
        done ;;
    beam) # 1.75 and 17.5 kN at the shipped 0.5 mm, 1.75 kN at 1 and 2 mm
        for a in 0.1 10; do
            run "beam_a${a}_1750_5e-4" beam_2d_static.yaml --set numerics.hourglass=$a
            run "beam_a${a}_17500_5e-4" beam_2d_static.yaml --set numerics.hourglass=$a \
                --set "groups.tip.load.force=[0,-17500]" --set reference.value=-82.25e-3
            for dx in 1e-3 2e-3; do
                run "beam_a${a}_1750_$dx" beam_2d_static.yaml --set numerics.hourglass=$a \
                    --set numerics.dx=$dx
            done
        done
        for dx in 5e-4 1e-3 2e-3; do # 175 N and 17.5 kN (175 N at 0.5 mm: 0.1 only)
            for a in 0.1 10; do
                [ $dx != 5e-4 ] || [ $a = 0.1 ] &&
                    run "beam_a${a}_175_$dx" beam_2d_static.yaml --set numerics.hourglass=$a \
                        --set numerics.dx=$dx --set "groups.tip.load.force=[0,-175]" \
                        --set reference.value=-3.3555e-3
                [ $dx = 5e-4 ] ||
                    run "beam_a${a}_17500_$dx" beam_2d_static.yaml --set numerics.hourglass=$a \
                        --set numerics.dx=$dx --set "groups.tip.load.force=[0,-17500]" \
                        --set reference.value=-82.25e-3
            done
        done
        for a in 0 0.01 1; do # the plateau at 1 mm
            run "beam_a${a}_1750_1e-3" beam_2d_static.yaml --set numerics.hourglass=$a \
                --set numerics.dx=1e-3
        done ;;
    esac
done

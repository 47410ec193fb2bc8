#!/bin/bash
# usage: ab2.sh OUTDIR ROUNDS BIN_A BIN_B SCENE_ARGS...
out=$1; rounds=$2; A=$3; B=$4; shift 4
mkdir -p $out
GPID=$(pgrep -f "sph run cases/gelatin_silica_3d" | head -1)
[ -n "$GPID" ] && kill -STOP $GPID
for r in $(seq 1 $rounds); do
  $A bench "$@" --json $out/base_$r.json > $out/base_$r.log 2>&1
  $B bench "$@" --json $out/exp_$r.json > $out/exp_$r.log 2>&1
done
[ -n "$GPID" ] && kill -CONT $GPID
for f in $out/*.log; do echo "$(basename $f): $(grep -o '[0-9.]* ms/step' $f | head -1) $(grep -E '^(pass[12]|lane_list_build|grid_neighbour_reach|grid_coarser_spread)' $f | awk '{print $1, $4}' | tr '\n' ' ')"; done

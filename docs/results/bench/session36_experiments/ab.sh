#!/bin/bash
# usage: ab.sh OUTDIR ROUNDS SCENE_ARGS... ; A = base, B = SPH_BUILD_OPTIONS=$EXP_OPTS
out=$1; rounds=$2; shift 2
mkdir -p $out
GPID=$(pgrep -f "sph run cases/gelatin_silica_3d" | head -1)
[ -n "$GPID" ] && kill -STOP $GPID
for r in $(seq 1 $rounds); do
  /tmp/exp/build/sph bench "$@" --json $out/base_$r.json > $out/base_$r.log 2>&1
  SPH_BUILD_OPTIONS="$EXP_OPTS" /tmp/exp/build/sph bench "$@" --json $out/exp_$r.json > $out/exp_$r.log 2>&1
done
[ -n "$GPID" ] && kill -CONT $GPID
for f in $out/*.log; do echo "$f: $(grep -o '[0-9.]* ms/step' $f) $(grep -E '^pass[12]' $f | awk '{print $1, $4}' | tr '\n' ' ')"; done

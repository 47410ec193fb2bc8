#!/bin/bash
# -cl-denorms-are-zero (SPH_BUILD_OPTIONS: PoCL then sets the CPU's
# flush-to-zero and denormals-are-zero flags) against the build as it is
# (e1bea75), the same binary, alternating, vmstat 5 beside;
# ../lane_slots_experiment/report.py prints the table when pointed here
# with base/ftz in place of base/slots (docs/performance.md, "The graded
# passes' rate per pair").
cd /tmp/ftz
vmstat 5 > vmstat.log &
VM=$!
for r in 1 2 3 4; do
  for b in base ftz; do
    o=""; [ $b = ftz ] && o="-cl-denorms-are-zero"
    for s in "gelatin3d-120k g120k --steps 10 --repeats 3 --warmup 2" \
             "gelatin3d-1m g1m --large --steps 5 --repeats 3 --warmup 1" \
             "taylor3d-200k t200k --steps 10 --repeats 3 --warmup 2"; do
      set -- $s
      scene=$1 prefix=$2
      shift 2
      SPH_BUILD_OPTIONS="$o" /work/main/build/sph bench --only $scene "$@" \
        --json ${prefix}_${b}_$r.json > ${prefix}_${b}_$r.txt 2>&1
    done
  done
done
kill $VM

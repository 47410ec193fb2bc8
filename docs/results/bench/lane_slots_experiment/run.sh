#!/bin/bash
# Lane blocks without ghosts (lane_slots.patch applied to the working tree,
# "slots") against bfd9dcd (a worktree at /tmp/base, "base"), alternating,
# vmstat 5 beside; report.py prints the table (docs/performance.md,
# "The graded passes' rate per pair").
cd /tmp/slots
vmstat 5 > vmstat.log &
VM=$!
# rounds SCENE PREFIX COUNT BENCH-OPTIONS...
rounds() {
  local scene=$1 prefix=$2 count=$3
  shift 3
  for r in $(seq 1 "$count"); do
    for b in base slots; do
      bin=/tmp/base/build/sph; [ $b = slots ] && bin=/work/main/build/sph
      echo "$(date +%T) $scene $b $r" >> order.log
      $bin bench --only "$scene" "$@" --json ${prefix}_${b}_$r.json > ${prefix}_${b}_$r.txt 2>&1
    done
  done
}
rounds gelatin3d-120k g120k 3 --steps 10 --repeats 3 --warmup 2
rounds taylor3d-200k t200k 2 --steps 10 --repeats 3 --warmup 2
rounds gelatin3d-1m g1m 2 --large --steps 5 --repeats 3 --warmup 1
echo "$(date +%T) done" >> order.log
kill $VM

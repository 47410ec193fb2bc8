#!/bin/bash
# lane blocks without ghosts: HEAD (bfd9dcd worktree, "base") against the
# working tree ("slots"), alternating, vmstat 5 beside
cd /tmp/slots
vmstat 5 > vmstat.log &
VM=$!
for r in 1 2 3; do
  for b in base slots; do
    bin=/tmp/base/build/sph; [ $b = slots ] && bin=/work/main/build/sph
    echo "$(date +%T) gelatin3d-120k $b $r" >> order.log
    $bin bench --only gelatin3d-120k --steps 10 --repeats 3 --warmup 2 --json g120k_${b}_$r.json > g120k_${b}_$r.txt 2>&1
  done
done
for r in 1 2; do
  for b in base slots; do
    bin=/tmp/base/build/sph; [ $b = slots ] && bin=/work/main/build/sph
    echo "$(date +%T) taylor3d-200k $b $r" >> order.log
    $bin bench --only taylor3d-200k --steps 10 --repeats 3 --warmup 2 --json t200k_${b}_$r.json > t200k_${b}_$r.txt 2>&1
  done
done
for r in 1 2; do
  for b in base slots; do
    bin=/tmp/base/build/sph; [ $b = slots ] && bin=/work/main/build/sph
    echo "$(date +%T) gelatin3d-1m $b $r" >> order.log
    $bin bench --large --only gelatin3d-1m --steps 5 --repeats 3 --warmup 1 --json g1m_${b}_$r.json > g1m_${b}_$r.txt 2>&1
  done
done
echo "$(date +%T) done" >> order.log
kill $VM

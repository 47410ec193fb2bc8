#!/bin/bash
# interleaved A/B: this build (new, 8835f8d) against d549cda (old)
cd /work/main
vmstat 5 > /tmp/ab2/vmstat.log &
VM=$!
for r in 1 2 3; do
  for b in new old; do
    bin=./build/sph; [ $b = old ] && bin=/tmp/wt_head/build/sph
    $bin bench --only gelatin3d-120k --steps 10 --repeats 3 --warmup 2 --json /tmp/ab2/g120k_${b}_$r.json > /tmp/ab2/g120k_${b}_$r.log 2>&1
  done
done
for r in 1 2; do
  for b in new old; do
    bin=./build/sph; [ $b = old ] && bin=/tmp/wt_head/build/sph
    $bin bench --large --only gelatin3d-1m --steps 5 --repeats 3 --warmup 1 --json /tmp/ab2/g1m_${b}_$r.json > /tmp/ab2/g1m_${b}_$r.log 2>&1
  done
done
kill $VM
echo done

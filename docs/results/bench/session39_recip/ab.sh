#!/bin/sh
# alternating rounds: base (/work/main: 1 / h) against native_recip(h) (/tmp/wt_base)
for r in 1 2 3; do
  (cd /work/main && ./build/sph bench --large --only gelatin3d-1m --steps 5 --repeats 2 --warmup 1 --json /tmp/b39/recip/base_$r.json > /tmp/b39/recip/base_$r.txt 2>&1)
  (cd /tmp/wt_base && ./build/sph bench --large --only gelatin3d-1m --steps 5 --repeats 2 --warmup 1 --json /tmp/b39/recip/recip_$r.json > /tmp/b39/recip/recip_$r.txt 2>&1)
done

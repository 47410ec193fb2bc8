#!/bin/bash
# interleaved rounds: base (4b4adef) and new (HEAD) on the 1M gel scene and the 200k bar
cd /tmp/bench35
for r in 1 2 3; do
  for v in base new; do
    if [ $v = base ]; then root=/tmp/base; else root=/work/main; fi
    (cd $root && ./build/sph bench --large --only gelatin3d-1m --steps 5 --repeats 3 --warmup 1 --json /tmp/bench35/gel1m_${v}_$r.json > /tmp/bench35/gel1m_${v}_$r.txt 2>&1)
    (cd $root && ./build/sph bench --only taylor3d-200k --steps 10 --repeats 3 --warmup 2 --json /tmp/bench35/bar200k_${v}_$r.json > /tmp/bench35/bar200k_${v}_$r.txt 2>&1)
  done
done
# Rounds 4-6 (gel1m only) were run afterwards in the order new, base:
#   for r in 4 5 6; do for v in new base; do ... gelatin3d-1m as above; done; done
# Table: /usr/bin/python3 ../lane_slots_experiment/report.py . new
# base = /tmp/base at 4b4adef, new = the session-35 tree (the CSPH floor and
# the pass 1 / pass 2 products); the d/dx 12 run and the stability study
# were stopped (SIGSTOP) while these ran.

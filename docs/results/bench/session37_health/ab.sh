#!/bin/bash
# The health indicators before (1580cd7) and after (session 37) they went
# through the lane loop: the shipped 3-D gelatin case to 40 ns with its
# shipped history interval (end_time 360 ns / 1000 = 0.36 ns), profiled,
# old and new one after the other, twice (docs/performance.md, "The health
# indicators through the lanes"). OLD_TREE and NEW_TREE: built checkouts.
# Usage: OLD_TREE=... NEW_TREE=... ab.sh [OUT]
O=${1:-/tmp/health_ab}; mkdir -p "$O"
for round in 1 2; do
for v in old new; do
  if [ $v = old ]; then cd "${OLD_TREE:?}"; else cd "${NEW_TREE:?}"; fi
  /usr/bin/time -f "%e s wall" ./build/sph run cases/gelatin_silica_3d.yaml --quiet --profile --out "$O/${v}_$round" \
    --set numerics.end_time=40e-9 --set output.history_interval=0.36e-9 > "$O/${v}_$round.txt" 2>&1
done; done

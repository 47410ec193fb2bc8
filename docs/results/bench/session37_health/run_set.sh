#!/bin/bash
# Eight short runs whose history.csv compare.py sets side by side.
# usage: run_set.sh SPH_BIN OUTDIR  (run from the checkout SPH_BIN was built from: its kernels)
B=$1; O=$2; mkdir -p $O
$B run cases/gelatin_silica_3d.yaml --quiet --out $O/gel3d --set numerics.dx=1.23e-6 --set numerics.end_time=20e-9 > $O/gel3d.log 2>&1
$B run cases/gelatin_silica.yaml --quiet --out $O/gelaxi --set numerics.dx=1.23e-6 --set numerics.end_time=40e-9 > $O/gelaxi.log 2>&1
$B run cases/taylor_3d_4340.yaml --quiet --out $O/t4340 --set numerics.dx=1e-3 --set numerics.end_time=10e-6 > $O/t4340.log 2>&1
$B run cases/beam_2d.yaml --quiet --out $O/beam --set numerics.end_time=2e-3 > $O/beam.log 2>&1
$B run cases/beam_2d_static.yaml --quiet --out $O/beamtl --set numerics.end_time=2e-3 > $O/beamtl.log 2>&1
$B run cases/sebs_steel_oblique_3d.yaml --quiet --out $O/sebsobl --set numerics.end_time=30e-9 > $O/sebsobl.log 2>&1
$B run cases/rubber_rings_2d.yaml --quiet --out $O/rings --set numerics.end_time=2e-3 > $O/rings.log 2>&1
$B run cases/taylor_3d_copper.yaml --quiet --out $O/cu3d --set numerics.end_time=10e-6 > $O/cu3d.log 2>&1
echo done > $O/DONE

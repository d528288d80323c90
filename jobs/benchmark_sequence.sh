#!/usr/bin/env bash
# A depth-camera sequence against Open3D 0.16's ScalableTSDFVolume: the bunny scaled
# to 1.5 m, filmed along one orbit by a 640x480 depth camera (noise 0.5 voxel at the orbit's
# distance, growing with the square of the range, 0.5 % outliers), written as a TUM folder
# (16-bit PNG frames, groundtruth.txt). Both read the same PNG frames and poses; rangefuse on
# 2 ranks (prism and robust), Open3D in one process (it does not use MPI). Prints time read to
# mesh, peak memory and accuracy against the true mesh.
# Each tool runs twice and its faster run is kept (as in benchmark_speed.sh: a first touch of
# memory the guest has not used lately costs far more than a second).
# Usage: bash jobs/benchmark_sequence.sh [FRAMES WIDTH HEIGHT VOXEL]  (default 300 640 480 0.01)
# SEQ_DIR=folder keeps the generated sequence there (and reuses it when it exists).
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
frames=${1:-300} width=${2:-640} height=${3:-480} voxel=${4:-0.01}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/rangefuse
seq=${SEQ_DIR:-$tmp/seq}
[[ -f $seq/depth.txt ]] ||
  $bin scan --mesh tests/data/bunny/bun_zipper.ply --scale 10 --views "$frames" --width "$width" \
    --height "$height" --voxel "$voxel" --noise 0.5 --depth-noise --outliers 0.005 --path orbit \
    --format tum --out "$seq"
echo "$frames frames ${width}x${height}, voxel $voxel, $(du -sm "$seq/depth" | cut -f1) MB of PNG"

accuracy() {  # mesh -> "chamfer | accuracy mean | p99 | F-score", lengths in voxels
  $bin eval --mesh "$1" --reference "$seq/truth.ply" --voxel "$voxel" --json |
    /usr/bin/python3 -c '
import json, sys
j, v = json.load(sys.stdin), float(sys.argv[1])
a = j["accuracy"]
print("%.3f | %.3f | %.2f | %.4f" % (j["chamfer"] / v, a["mean"] / v, a["p99"] / v, j["fscore"]))
' "$voxel"
}

echo "| tool | seconds read to mesh | peak memory (MiB) | Chamfer (voxel) | accuracy mean | accuracy p99 | F-score |"
echo "|---|---|---|---|---|---|---|"
for method in prism robust; do
  seconds=
  for run in 1 2; do
    start=$(date +%s.%N)
    mpirun -np 2 --bind-to none $bin fuse --scans "$seq" --voxel "$voxel" --method $method \
      --out "$tmp/$method.ply" >"$tmp/$method.log.$run"
    took=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }')
    if [[ -z $seconds ]] || awk -v a="$took" -v b="$seconds" 'BEGIN { exit !(a < b) }'; then
      seconds=$took
      mv "$tmp/$method.log.$run" "$tmp/$method.log"
    fi
  done
  memory=$(grep "peak memory per rank" "$tmp/$method.log" | sed 's/.*(MiB) \([0-9 /]*\) (.*/\1/')
  echo "| rangefuse $method, 2 ranks | $seconds | $memory | $(accuracy "$tmp/$method.ply") |"
done
o3d=$(/usr/bin/python3 jobs/open3d_sequence.py "$seq" "$voxel" "$tmp/o3d.ply" 2>/dev/null)
again=$(/usr/bin/python3 jobs/open3d_sequence.py "$seq" "$voxel" "$tmp/o3d.ply" 2>/dev/null)
if awk -v a="$(echo "$again" | sed 's/.*total \([0-9.]*\) s.*/\1/')" \
  -v b="$(echo "$o3d" | sed 's/.*total \([0-9.]*\) s.*/\1/')" 'BEGIN { exit !(a < b) }'; then
  o3d=$again
fi
seconds=$(echo "$o3d" | sed 's/.*total \([0-9.]*\) s.*/\1/')
memory=$(echo "$o3d" | sed 's/.*peak memory \([0-9]*\) MiB.*/\1/')
echo "| Open3D ScalableTSDFVolume, 1 process | $seconds | $memory | $(accuracy "$tmp/o3d.ply") |"
echo "$o3d"
grep -E "\] (read|field|mesh) " "$tmp/prism.log"

#!/usr/bin/env bash
# Lays the real 7-Scenes kitchen recording (../shared/data/7scenes-kitchen, research use only:
# never copied into the repository) out as a Redwood folder that `rangefuse fuse --scans` reads:
# OUT/depth/NNNNNN.png as links to the frames, OUT/camera_intrinsic.json from its K, and, unless
# NOPOSES=1, OUT/trajectory.log from its camera-to-world poses (KinectFusion's, not truth).
# With STEP > 1 the folder holds every STEP-th of those frames (held-out frame benchmarks).
# Usage: bash jobs/kitchen_as_redwood.sh OUT [FRAMES (default 1000)] [FIRST (default 0)] [STEP (1)]
set -euo pipefail
out=$1
frames=${2:-1000}
first=${3:-0}
step=${4:-1}
src=${KITCHEN:-$(cd "$(dirname "$0")/../.." && pwd)/shared/data/7scenes-kitchen}
[[ -f $src/camera-intrinsics.txt ]] || { echo "no kitchen recording at $src (set KITCHEN)" >&2; exit 1; }
mkdir -p "$out/depth"
read -r fx _ cx < <(sed -n 1p "$src/camera-intrinsics.txt")
read -r _ fy cy < <(sed -n 2p "$src/camera-intrinsics.txt")
cat >"$out/camera_intrinsic.json" <<EOF
{"width": 640, "height": 480, "intrinsic_matrix": [$fx, 0, 0, 0, $fy, 0, $cx, $cy, 1]}
EOF
rm -f "$out/trajectory.log"
for ((k = 0; k * step < frames; k++)); do
  name=$(printf 'frame-%06d' $((first + k * step)))
  ln -sf "$src/$name.depth.png" "$out/depth/$(printf %06d "$k").png"
  if [[ ${NOPOSES:-0} != 1 ]]; then
    echo "$k $k $((k + 1))" >>"$out/trajectory.log"
    cat "$src/$name.pose.txt" >>"$out/trajectory.log"
  fi
done
echo "$out: $frames kitchen frames from $first, every $step, as a Redwood folder"

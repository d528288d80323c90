#!/usr/bin/env bash
# Depth streams without poses: rangefuse tracks every frame against its field and
# fuses it; Open3D 0.16 tracks frame to frame (point-to-plane ICP, coarse to fine) and fuses
# with ScalableTSDFVolume, in the same run. Sequences: the bunny scaled to 1.5 m along an orbit
# and along a hand-held path with fast turns, 640 x 480, Kinect-like noise (0.5 voxel at the
# path's distance, growing with the square of the range), 0.5 % outliers; written as TUM
# folders whose groundtruth.txt is kept aside. Prints, per sequence and tool: ATE and RPE
# against the truth, seconds read to mesh (best of two), frames/s, peak memory, and the mesh's
# Chamfer distance to the true surface; and rangefuse at the true poses (no tracking), the
# Chamfer tracking should come within 10 % of; and the tracked poses refined afterwards by
# --register simultaneous (one run). A third sequence follows the hand-held path around a
# synthetic desk (--shape desk: table top, legs, monitor, keyboard, book, ball, ring), and a
# fourth walks through a synthetic room (8 x 6 x 3 m, desk, cabinet, ball) with the same camera
# and noise: tracked with --skip-lost, one run each.
# Usage: bash jobs/benchmark_tracking.sh [FRAMES WIDTH HEIGHT VOXEL]  (default 300 640 480 0.01)
# SEQ_ROOT=folder keeps the generated sequences there (and reuses them); SEQUENCES="orbit desk"
# runs only those (default: orbit handheld desk). The walk is asked for by name (SEQUENCES=
# "orbit handheld desk walk"): Open3D takes 10-20 minutes on it and both trackers lose it.
# FUSE_ARGS: options added to every rangefuse command (e.g. "--merge-cells 1.5"); PEERS=0
# leaves Open3D out and REFINE=0 the refined run (to set rangefuse's options against each
# other); SENSOR=kinect renders the sequences with the synthetic Kinect checked against real
# frames (docs/sensor.md) instead of the Gaussian noise, kept as kinect-NAME in SEQ_ROOT.
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
frames=${1:-300} width=${2:-640} height=${3:-480} voxel=${4:-0.01}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/rangefuse
root=${SEQ_ROOT:-$tmp}

chamfer() {  # mesh truth.ply -> Chamfer in voxels; for the room, whose truth holds much no
  # camera sees, the mean distance from the mesh to the truth (marked "acc.")
  $bin eval --mesh "$1" --reference "$2" --voxel "$voxel" --json |
    python3 -c '
import json, sys
j, v = json.load(sys.stdin), float(sys.argv[1])
print("%.3f" % (j["chamfer"] / v) if sys.argv[2] != "walk" else "acc. %.3f" % (j["accuracy"]["mean"] / v))
' "$voxel" "$path"
}
ate() {  # trajectory truth -> "ATE mm | RPE mm/s"
  $bin eval --trajectory "$1" --reference "$2" --json |
    python3 -c 'import json, sys; j = json.load(sys.stdin); print("%.2f | %.2f" % (1e3 * j["ate_rmse"], 1e3 * j["rpe_translation_rmse_per_s"]))'
}
best() {  # best of two timed runs of a command; prints seconds, keeps the faster log in $tmp/log
  local seconds=
  for run in 1 2; do
    local start took
    start=$(date +%s.%N)
    "$@" >"$tmp/log.$run" 2>&1
    took=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }')
    if [[ -z $seconds ]] || awk -v a="$took" -v b="$seconds" 'BEGIN { exit !(a < b) }'; then
      seconds=$took
      mv "$tmp/log.$run" "$tmp/log"
    fi
  done
  echo "$seconds"
}

echo "| sequence | tool | ATE (mm) | RPE (mm/s) | seconds read to mesh | frames/s | peak memory (MiB) | Chamfer (voxel) |"
echo "|---|---|---|---|---|---|---|---|"
once() {  # one timed run; prints seconds, keeps the log in $tmp/log
  local start
  start=$(date +%s.%N)
  "$@" >"$tmp/log" 2>&1 || true
  awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }'
}
noise=(--noise 0.5 --depth-noise --outliers 0.005)
[[ ${SENSOR:-} == kinect ]] && noise=(--sensor kinect)
for name in ${SEQUENCES:-orbit handheld desk}; do
  seq=$root/${SENSOR:+$SENSOR-}$name path=$name
  shape=(--mesh tests/data/bunny/bun_zipper.ply --scale 10)
  [[ $name == walk ]] && shape=(--shape room)
  [[ $name == desk ]] && shape=(--shape desk) path=handheld
  [[ -f $seq/groundtruth.txt ]] ||
    $bin scan "${shape[@]}" --views "$frames" \
      --width "$width" --height "$height" --voxel "$voxel" "${noise[@]}" --path "$path" \
      --format tum --out "$seq" >/dev/null
  timed=best skip=()
  [[ $path == walk ]] && timed=once skip=(--skip-lost)
  stream=$tmp/$path-stream
  mkdir -p "$stream"
  cp -r "$seq/depth" "$seq/depth.txt" "$seq/camera_intrinsic.json" "$stream/"
  first=$(awk '!/^#/ { print $2 "," $3 "," $4 "," $5 "," $6 "," $7 "," $8; exit }' "$seq/groundtruth.txt")
  rm -f "$tmp/track.ply" "$tmp/track.txt"
  seconds=$($timed mpirun -np 2 --bind-to none $bin fuse --scans "$stream" --voxel "$voxel" \
    --first-pose "$first" "${skip[@]}" --out "$tmp/track.ply" --trajectory-out "$tmp/track.txt" \
    ${FUSE_ARGS:-})
  memory=$(grep "peak memory per rank" "$tmp/log" | sed 's/.*(MiB) \([0-9 /]*\) (.*/\1/' || true)
  mv "$tmp/log" "$tmp/track.log"
  fps=$(awk -v n="$frames" -v s="$seconds" 'BEGIN { printf "%.1f", n / s }')
  if [[ -s $tmp/track.txt ]]; then
    echo "| $name | rangefuse, 2 ranks | $(ate "$tmp/track.txt" "$seq/groundtruth.txt") | $seconds | $fps | $memory | $(chamfer "$tmp/track.ply" "$seq/truth.ply") |"
  else  # the run stopped (30 frames lost in a row): its own message says where
    echo "| $name | rangefuse, 2 ranks | failed after $seconds s: $(grep -o 'frame [0-9]*: tracking lost[^:]*' "$tmp/track.log" | head -n 1) | | | | | |"
  fi
  seconds=$($timed mpirun -np 2 --bind-to none $bin fuse --scans "$seq" --voxel "$voxel" \
    --out "$tmp/true.ply" ${FUSE_ARGS:-})
  echo "| $name | rangefuse at the true poses | | | $seconds | | | $(chamfer "$tmp/true.ply" "$seq/truth.ply") |"
  if [[ $path != walk && ${REFINE:-1} != 0 ]]; then
    seconds=$(once mpirun -np 2 --bind-to none $bin fuse --scans "$stream" --voxel "$voxel" \
      --first-pose "$first" --register simultaneous --out "$tmp/refined.ply" \
      --trajectory-out "$tmp/refined.txt" ${FUSE_ARGS:-})
    memory=$(grep "peak memory per rank" "$tmp/log" | sed 's/.*(MiB) \([0-9 /]*\) (.*/\1/')
    echo "| $name | rangefuse, refined by --register simultaneous | $(ate "$tmp/refined.txt" "$seq/groundtruth.txt") | $seconds | | $memory | $(chamfer "$tmp/refined.ply" "$seq/truth.ply") |"
  fi
  if [[ ${PEERS:-1} != 0 ]]; then
    o3d=$(/usr/bin/python3 jobs/open3d_track.py "$stream" "$voxel" "$tmp/o3d.ply" "$tmp/o3d.txt" "$first" 2>/dev/null)
    seconds=$(echo "$o3d" | sed 's/.*total \([0-9.]*\) s.*/\1/')
    memory=$(echo "$o3d" | sed 's/.*peak memory \([0-9]*\) MiB.*/\1/')
    fps=$(awk -v n="$frames" -v s="$seconds" 'BEGIN { printf "%.1f", n / s }')
    echo "| $name | Open3D frame-to-frame ICP + TSDF, 1 process | $(ate "$tmp/o3d.txt" "$seq/groundtruth.txt") | $seconds | $fps | $memory | $(chamfer "$tmp/o3d.ply" "$seq/truth.ply") |"
  fi
  grep -E "\] (track|mesh|done) " "$tmp/track.log" || true
done

#!/usr/bin/env bash
# Tracking on the synthetic Kinect (`scan --sensor kinect`, docs/sensor.md) beside the clean
# sensor (Gaussian noise growing with depth^2) and Open3D 0.16's frame-to-frame ICP on the same
# frames, in the same run: the bunny scaled to 1.5 m, 240 frames of 320 x 240, 1 cm voxels, 2
# ranks, from the true first pose. Each Kinect stream is tracked with every fault, and without
# the time faults (rolling shutter, 10 ms offset) to show what they cost.
# Usage: bash jobs/benchmark_sensor_tracking.sh [PATHS ("fastturns handheld")] [BIN]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${2:-build/rangefuse}")
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source jobs/trajectory_ate.sh
echo "| path | sensor | rangefuse ATE | lost | frames/s | Open3D ICP ATE |"
echo "|---|---|---|---|---|---|"
for path in ${1:-fastturns handheld}; do
  for sensor in "kinect" "kinect without shutter,offset" "clean"; do
    case $sensor in
      kinect) args=(--sensor kinect) ;;
      clean) args=(--noise 0.5 --depth-noise) ;;
      *) args=(--sensor kinect --sensor-without shutter,offset) ;;
    esac
    rm -rf "$tmp/s" "$tmp/stream"
    "$bin" scan --mesh tests/data/bunny/bun_zipper.ply --scale 10 --views 240 --width 320 \
      --height 240 --voxel 0.01 --path "$path" "${args[@]}" --format tum --out "$tmp/s" >/dev/null
    mkdir "$tmp/stream"
    cp -r "$tmp/s/depth" "$tmp/s/depth.txt" "$tmp/s/camera_intrinsic.json" "$tmp/stream/"
    first=$(awk '!/^#/ { print $2 "," $3 "," $4 "," $5 "," $6 "," $7 "," $8; exit }' \
      "$tmp/s/groundtruth.txt")
    start=$(date +%s.%N)
    mpirun -np 2 "$bin" fuse --scans "$tmp/stream" --voxel 0.01 --first-pose "$first" \
      --out "$tmp/m.ply" --trajectory-out "$tmp/t.txt" >"$tmp/log" 2>&1
    fps=$(echo "240 / ($(date +%s.%N) - $start)" | bc -l)
    o3d=""
    if [[ $sensor == kinect ]]; then
      /usr/bin/python3 jobs/open3d_track.py "$tmp/stream" 0.01 "$tmp/o.ply" "$tmp/o.txt" "$first" \
        >/dev/null 2>&1
      o3d=$(ate "$tmp/o.txt" "$tmp/s/groundtruth.txt")
    fi
    printf "| %s | %s | %s | %d | %.1f | %s |\n" "$path" "$sensor" \
      "$(ate "$tmp/t.txt" "$tmp/s/groundtruth.txt")" "$(grep -c ' LOST ' "$tmp/log" || true)" \
      "$fps" "$o3d"
  done
done

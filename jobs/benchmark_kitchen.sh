#!/usr/bin/env bash
# Tracking on real Kinect v1 frames: the 7-Scenes kitchen (../shared/data/7scenes-kitchen, read
# in place through links, never copied), its poses hidden, tracked by rangefuse with default
# options on 2 ranks and by Open3D 0.16's frame-to-frame ICP (jobs/open3d_track.py) on the same
# frames, in the same run; both compared with the set's KinectFusion poses (a reference that
# agrees to about 1 cm at best, not truth).
# Sets: dev (frames 0-299, looked at while developing) and judge (frames 500-899, held out:
# its settings were fixed before it was first run).
# Usage: [FUSE_ARGS="--close-loops"] bash jobs/benchmark_kitchen.sh [SETS ("dev judge")] [BIN]
# (FUSE_ARGS: options added to rangefuse's command; BIN: build/rangefuse)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${2:-build/rangefuse}")
kitchen=${KITCHEN:-$(pwd)/../shared/data/7scenes-kitchen}
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source jobs/trajectory_ate.sh
echo "| set | frames | rangefuse ATE | frames/s | lost | peak MiB/rank | updates max/mean | Open3D ICP ATE | Open3D frames/s |"
echo "|---|---|---|---|---|---|---|---|---|"
for set in ${1:-dev judge}; do
  case $set in dev) first=0 count=300 ;; judge) first=500 count=400 ;; *) exit 2 ;; esac
  # rangefuse reads the 7-Scenes layout itself: depth images and intrinsics, no pose files.
  mkdir -p "$tmp/$set"
  ln -s "$kitchen/camera-intrinsics.txt" "$tmp/$set/"
  for ((k = first; k < first + count; k++)); do
    ln -s "$kitchen/$(printf 'frame-%06d' $k).depth.png" "$tmp/$set/"
  done
  bash jobs/kitchen_as_redwood.sh "$tmp/$set-ref" "$count" "$first" >/dev/null
  NOPOSES=1 bash jobs/kitchen_as_redwood.sh "$tmp/$set-o3d" "$count" "$first" >/dev/null
  start=$(date +%s.%N)
  /usr/bin/time -f %M -o "$tmp/mem" mpirun -np 2 "$bin" fuse --scans "$tmp/$set" --voxel 0.01 \
    --trajectory-out "$tmp/$set.txt" --out "$tmp/$set.ply" ${FUSE_ARGS:-} >"$tmp/$set.log" 2>&1
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  # The reference is a .log (frame k at k / 30 s); our times are the frame numbers / 30.
  python3 - "$tmp/$set.txt" "$first" <<'PY'
import sys
path, first = sys.argv[1], int(sys.argv[2])
lines = open(path).read().splitlines()
with open(path, "w") as out:
    for line in lines:
        if line.startswith("#"):
            out.write(line + "\n")
            continue
        t, rest = line.split(" ", 1)
        out.write("%.6f %s\n" % (float(t) - first / 30, rest))
PY
  peak=$(grep -o 'peak memory per rank (MiB) [0-9]* / [0-9]*' "$tmp/$set.log" | grep -o '[0-9]* / [0-9]*')
  lost=$(grep -c ' LOST ' "$tmp/$set.log" || true)
  # The ranks' balance: the track line's voxel updates per rank, max/mean.
  balance=$(grep -o 'voxels updated per rank [0-9 /]* (max/mean [0-9.]*' "$tmp/$set.log" |
    grep -o '[0-9.]*$' || echo -)
  o3d_start=$(date +%s.%N)
  /usr/bin/python3 jobs/open3d_track.py "$tmp/$set-o3d" 0.01 "$tmp/o3d.ply" "$tmp/o3d.txt" >/dev/null 2>&1
  o3d_seconds=$(echo "$(date +%s.%N) - $o3d_start" | bc)
  printf "| %s | %d from %d | %s | %.1f | %d | %s | %s | %s | %.1f |\n" "$set" "$count" "$first" \
    "$(ate "$tmp/$set.txt" "$tmp/$set-ref/trajectory.log")" "$(echo "$count / $seconds" | bc -l)" \
    "$lost" "$peak" "$balance" "$(ate "$tmp/o3d.txt" "$tmp/$set-ref/trajectory.log")" \
    "$(echo "$count / $o3d_seconds" | bc -l)"
done

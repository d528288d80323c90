#!/usr/bin/env bash
# Robust fusion on depth-camera frames, where a pixel without a return is a measurement the
# camera did not make (docs/robust.md, Lines of sight): surface kept against the prism field.
# - room: the synthetic Kinect (docs/sensor.md, without its time faults: the poses are true)
#   carried through the room, read as a TUM folder; dev set seed 11, 100 frames; judge set
#   seed 23, 300 frames (settings fixed before it was first run). Each mesh against the true
#   room (the whole room: what no frame saw counts as missing for every tool), beside Open3D
#   0.16's ScalableTSDFVolume on the same frames.
# - kitchen: real Kinect v1 frames with their reference poses (../shared/data/7scenes-kitchen,
#   read in place through links, never copied), dev every 3rd of frames 0-299, judge every 4th
#   of 500-899; no true surface, so the robust mesh is judged against the prism mesh: recall
#   at one voxel is the share of the prism field's surface robust fusion kept.
# Usage: bash jobs/benchmark_robust_depth.sh [SETS ("room-dev room-judge kitchen-dev
# kitchen-judge")] [BIN (build/rangefuse)]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${2:-build/rangefuse}")
kitchen=${KITCHEN:-$(pwd)/../shared/data/7scenes-kitchen}
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
figures() {  # MESH REFERENCE -> "recall | precision | Chamfer (voxel) | spurious"
  "$bin" eval --mesh "$1" --reference "$2" --voxel 0.01 --json | /usr/bin/python3 -c '
import json, sys
j = json.load(sys.stdin)
print("%.4f | %.4f | %.2f | %.4f %%" % (j["recall"], j["precision"], j["chamfer"] / 0.01,
                                       100 * j["spurious_area_fraction"]))'
}
fuse() {  # FOLDER METHOD OUT
  mpirun -np 2 "$bin" fuse --scans "$1" --voxel 0.01 --method "$2" --out "$3" >"$3.log" 2>&1
  grep -o 'removed [0-9]*' "$3.log" | sed 's/removed //' || echo "-"
}
echo "| set | tool | recall at 1 voxel | precision | Chamfer (voxel) | spurious area | voxels removed |"
echo "|---|---|---|---|---|---|---|"
for set in ${1:-room-dev room-judge kitchen-dev kitchen-judge}; do
  dir=$tmp/$set
  case $set in
    room-*)
      [[ $set == room-dev ]] && seed=11 views=100 || seed=23 views=300
      "$bin" scan --shape room --path walk --views $views --width 640 --height 480 --voxel 0.01 \
        --sensor kinect --sensor-without shutter,offset --seed $seed --format tum --out "$dir" \
        >/dev/null
      ref=$dir/truth.ply ;;
    kitchen-*)
      [[ $set == kitchen-dev ]] && range="0 3 299" || range="500 4 899"
      mkdir -p "$dir"
      ln -s "$kitchen/camera-intrinsics.txt" "$dir/"
      for k in $(seq $range); do
        for part in depth.png pose.txt; do ln -s "$kitchen/$(printf 'frame-%06d' "$k").$part" "$dir/"; done
      done
      ref=$tmp/$set-prism.ply ;;
  esac
  removed=$(fuse "$dir" prism "$tmp/$set-prism.ply")
  [[ $set == room-* ]] && echo "| $set | prism | $(figures "$tmp/$set-prism.ply" "$ref") | $removed |"
  removed=$(fuse "$dir" robust "$tmp/$set-robust.ply")
  echo "| $set | robust | $(figures "$tmp/$set-robust.ply" "$ref") | $removed |"
  if [[ $set == room-* ]]; then
    /usr/bin/python3 jobs/open3d_sequence.py "$dir" 0.01 "$tmp/o3d.ply" >/dev/null 2>&1
    echo "| $set | Open3D ScalableTSDFVolume | $(figures "$tmp/o3d.ply" "$ref") | - |"
  fi
done

#!/usr/bin/env bash
# A real depth stream has no true surface: the frames left out of a fusion judge it. Each set
# is a span of the 7-Scenes kitchen (../shared/data/7scenes-kitchen, real Kinect v1 depth at
# KinectFusion's poses, read in place through links, never copied); its even frames are fused
# at 1 cm and every tenth odd frame that does not repeat the frame before it (the recording's
# dropped frames) is judged by jobs/heldout_depth.py: the distance of its pixels, placed by
# their pose, to the mesh. Kinect noise is in every figure alike, so the figures rank meshes
# rather than measure their error. Tools: rangefuse prism at its defaults and with
# --merge-cells 1.5 (larger triangles, docs/benchmarks.md), and Open3D 0.16's
# ScalableTSDFVolume (voxel as ours, truncation 4 voxels), on 2 cores each; seconds are the
# best of two runs (rangefuse's mpirun job; Open3D's read, integrate and extract).
# - kitchen-dev: frames 0-399; kitchen-judge: frames 500-899. Settings (frames, judged pixels
#   every 4th row and column, 5 cm reach, 4 M mesh samples) fixed before the judge set was
#   first run.
# Usage: bash jobs/benchmark_heldout.sh [SETS ("kitchen-dev kitchen-judge")] [BIN]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${2:-build/rangefuse}")
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

seconds() {  # COMMAND... -> wall seconds, best of two runs
  local start took best=
  for run in 1 2; do
    start=$(date +%s.%N)
    "$@" >"$tmp/log" 2>&1 || { cat "$tmp/log" >&2; return 1; }
    took=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }')
    [[ -z $best ]] || awk -v a="$took" -v b="$best" 'BEGIN { exit !(a < b) }' && best=$took
  done
  echo "$best"
}
judged() {  # ALL-FRAMES-FOLDER -> comma-separated odd frames, every tenth, not repeats
  local list="" a b
  for ((f = 1; f < 400; f += 10)); do
    a=$(readlink -f "$1/depth/$(printf %06d $f).png")
    b=$(readlink -f "$1/depth/$(printf %06d $((f - 1))).png")
    cmp -s "$a" "$b" || list="$list,$f"
  done
  echo "${list#,}"
}
# MESH ALL-FRAMES-FOLDER FRAMES -> "pixels | median | mean | within 1 cm | within reach"
figures() {
  /usr/bin/python3 jobs/heldout_depth.py "$1" "$2" "$3" | sed -E \
    's/median ([0-9.]+) mm \| mean ([0-9.]+) mm \| within 1 cm ([0-9.]+) \| within reach ([0-9.]+) \| pixels ([0-9]+)/\5 | \1 | \2 | \3 | \4/'
}

echo "| set | tool | seconds read to mesh | judged pixels | median distance (mm) | mean (mm) | within 1 cm | within 5 cm |"
echo "|---|---|---|---|---|---|---|---|"
for set in ${1:-kitchen-dev kitchen-judge}; do
  [[ $set == kitchen-dev ]] && first=0 || first=500
  all=$tmp/$set-all fused=$tmp/$set-even
  bash jobs/kitchen_as_redwood.sh "$all" 400 $first >/dev/null
  bash jobs/kitchen_as_redwood.sh "$fused" 400 $first 2 >/dev/null
  frames=$(judged "$all")
  for tool in default merge-1.5 open3d; do
    case $tool in
      default | merge-1.5)
        flag=()
        [[ $tool == merge-1.5 ]] && flag=(--merge-cells 1.5)
        s=$(seconds mpirun -np 2 --bind-to none "$bin" fuse --scans "$fused" --voxel 0.01 \
          --colour none "${flag[@]}" --out "$tmp/mesh.ply")
        name="rangefuse prism, 2 ranks${flag:+, ${flag[*]}}" ;;
      open3d)
        s=
        for run in 1 2; do  # best of two, as for rangefuse
          /usr/bin/python3 jobs/open3d_sequence.py "$fused" 0.01 "$tmp/mesh.ply" 4 >"$tmp/o3d" 2>&1
          took=$(sed -n 's/.*total \([0-9.]*\) s.*/\1/p' "$tmp/o3d")
          [[ -z $s ]] || awk -v a="$took" -v b="$s" 'BEGIN { exit !(a < b) }' && s=$took
        done
        name="Open3D ScalableTSDFVolume" ;;
    esac
    echo "| $set | $name | $s | $(figures "$tmp/mesh.ply" "$all" "$frames") |"
  done
done

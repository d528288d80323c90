#!/usr/bin/env bash
# What --preview costs: the same fusion with and without it, on 2 ranks, median of 3 runs each,
# on the bunny (an object, orbit view), three scanner stations in a room and a depth camera
# walking through it (both seen from the first sensor). The share is the extra wall time over
# the run without a preview.
# Usage: bash jobs/benchmark_preview.sh [BUILD_DIR]  (default build/)
set -euo pipefail
cd "$(dirname "$0")/.."
source jobs/mpi_env.sh
bin=$(realpath "${1:-build}")/rangefuse
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$bin" scan --shape room --path stations --views 3 --width 720 --height 320 --voxel 0.02 \
  --noise 0.3 --format ptx --out "$tmp/room" >/dev/null
"$bin" scan --shape room --path walk --views 120 --width 320 --height 240 --voxel 0.02 \
  --noise 0.3 --depth-noise --format tum --out "$tmp/walk" >/dev/null

median3() {  # COMMAND...: the median wall time of three runs, seconds
  local times=()
  for _ in 1 2 3; do
    local start end
    start=$(date +%s.%N)
    "$@" >/dev/null
    end=$(date +%s.%N)
    times+=("$(echo "$end - $start" | bc)")
  done
  printf '%s\n' "${times[@]}" | sort -g | sed -n 2p
}

echo "| scene | view | fuse without (s) | with --preview (s) | preview share |"
echo "|---|---|---|---|---|"
case_row() {  # NAME VIEW SCANS VOXEL
  local fuse=(mpirun -np 2 "$bin" fuse --scans "$3" --voxel "$4" --out "$tmp/mesh.ply")
  local without with
  without=$(median3 "${fuse[@]}")
  with=$(median3 "${fuse[@]}" --preview "$tmp/preview.png")
  printf '| %s | %s | %.2f | %.2f | %.0f %% |\n' "$1" "$2" "$without" "$with" \
    "$(echo "100 * ($with - $without) / $without" | bc -l)"
}
case_row "bunny, 10 scans, 1 mm" "orbit, 512 x 512" tests/data/bunny/bun.conf 0.001
case_row "room, 3 stations, 2 cm" "first station, 640 x 480" "$tmp/room/stations.ptx" 0.02
case_row "room, 120 depth frames, 2 cm" "first camera, 640 x 480" "$tmp/walk" 0.02

#!/usr/bin/env bash
# Terrestrial laser scans: the synthetic room scanned from STATIONS tripods, each a
# full turn of COLS x ROWS points (noise 0.3 voxel), written as one ASCII Leica PTX file (or,
# with FORMAT=e57, one ASTM E57 file of double coordinates). Times `rangefuse perturb` (it
# indexes the file and reads every scan's grid, nothing else of note: the reading speed), then
# fuses on 2 ranks at VOXEL and measures the mesh against the room.
# Usage: [FORMAT=ptx|e57] [BANDS="4000000 0"] [METHOD=prism|robust|...]
#        bash jobs/benchmark_ptx.sh [STATIONS COLS ROWS VOXEL]  (default 3 3000 1500 0.01)
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
stations=${1:-3} cols=${2:-3000} rows=${3:-1500} voxel=${4:-0.01}
tmp=$(mktemp -d -p "${TMPDIR:-/tmp}")
trap 'rm -rf "$tmp"' EXIT
bin=build/rangefuse
format=${FORMAT:-ptx}
start=$(date +%s.%N)
$bin scan --shape room --path stations --views "$stations" --width "$cols" --height "$rows" \
  --voxel "$voxel" --noise 0.3 --format "$format" --out "$tmp/room" --max-grid-cells 1000000000
echo "scan written in $(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.1f", e - s }') s"
bytes=$(stat -c %s "$tmp/room/stations.$format")
start=$(date +%s.%N)
$bin perturb --scans "$tmp/room/stations.$format" --voxel "$voxel" --rot-deg 0 --trans-vox 0 \
  --out "$tmp/p.conf" --max-grid-cells 1000000000 >/dev/null
seconds=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }')
echo "$format: $stations stations, $((stations * cols * rows)) points, $((bytes / 1000000)) MB:" \
  "index and read $seconds s, $(awk -v b="$bytes" -v s="$seconds" 'BEGIN { printf "%.0f", b / 1e6 / s }') MB/s (perturb, one process)"
# Each fuse runs once per --band-cells value of BANDS: the default splits stations past 4 M
# cells into bands of columns read by any rank; 0 reads every station whole on one rank.
for band in ${BANDS:-4000000 0}; do
  echo "== fuse --method ${METHOD:-prism} with --band-cells $band"
  start=$(date +%s.%N)
  mpirun -np 2 --bind-to none $bin fuse --scans "$tmp/room/stations.$format" --voxel "$voxel" \
    --method "${METHOD:-prism}" --band-cells "$band" --out "$tmp/m.ply" --max-grid-cells 1000000000 >"$tmp/log"
  seconds=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }')
  grep -E "\] (read|field|mesh|write|done) " "$tmp/log"
  echo "fuse, 2 ranks, read to write: $seconds s"
  echo "against the whole room:"
  $bin eval --mesh "$tmp/m.ply" --reference "$tmp/room/truth.ply" --voxel "$voxel" |
    grep -E "accuracy|completeness|chamfer|F-score"
  echo "against the surface the stations saw (within about one voxel of their triangulated scans):"
  $bin eval --mesh "$tmp/m.ply" --reference "$tmp/room/truth.ply" --voxel "$voxel" \
    --seen "$tmp/room/truth.conf" --max-grid-cells 1000000000 |
    grep -E "seen|completeness|chamfer|F-score"
done

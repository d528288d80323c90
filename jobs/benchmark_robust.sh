#!/usr/bin/env bash
# Robust fusion: outliers, one-scan patches and noise, on synthetic sets with known
# truth. For each set: the prism field, robust fusion, robust with free space off (agreement
# alone) and with agreement off (free space alone), all on 2 ranks, beside Open3D 0.16's TSDF
# on the same scans in the same run. Whole-process wall time (Open3D's includes its Python
# loading, as a user's script would), Chamfer and spurious area against the truth mesh, the
# share of each patch's area the mesh keeps, and peak memory per rank.
# Usage: bash jobs/benchmark_robust.sh [--consensus]   (consensus adds minutes a set)
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
bin=$PWD/build/rangefuse
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
methods=("prism" "robust" "robust --free-margin inf" "robust --min-views 1000")
[[ ${1:-} == --consensus ]] && methods+=("consensus")

now() { date +%s.%N; }
# judge MESH SET: "chamfer | spurious % | patch kept" against the set's truth and patches.
judge() {
  local e c s p
  e=$($bin eval --mesh "$1" --reference "$2/truth.ply" --voxel 1)
  c=$(echo "$e" | awk '/^chamfer/ { print substr($3, 2) }')
  s=$(echo "$e" | awk '/^spurious/ { print $NF }')
  p=$($bin eval --mesh "$2/patches.ply" --reference "$1" --voxel 1 | awk '/F-score/ { print $5 }')
  echo "$c | $s | $p"
}

echo "| set | method | wall (s) | / Open3D wall | Chamfer (voxel) | spurious area | patch area kept | peak MiB per rank |"
echo "|---|---|---|---|---|---|---|---|"
# set NAME SCAN-OPTIONS...
set_row() {
  local name=$1 dir=$tmp/$1
  shift
  $bin scan "$@" --voxel 1 --out "$dir" >/dev/null
  local t0 t1 o3d
  t0=$(now)
  /usr/bin/python3 jobs/open3d_tsdf.py "$dir" 1 "$tmp/o3d.ply" >/dev/null
  t1=$(now)
  o3d=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')
  for m in "${methods[@]}"; do
    t0=$(now)
    # shellcheck disable=SC2086
    mpirun -np 2 "$bin" fuse --scans "$dir/truth.conf" --voxel 1 --method $m \
      --out "$tmp/m.ply" >"$tmp/log"
    t1=$(now)
    local wall peak
    wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')
    peak=$(grep "] done " "$tmp/log" | sed 's/.*(MiB) \([0-9]*\).*/\1/')
    echo "| $name | $m | $wall | $(awk -v a="$wall" -v b="$o3d" 'BEGIN { printf "%.2f", a / b }') | $(judge "$tmp/m.ply" "$dir") | $peak |"
  done
  echo "| $name | Open3D TSDF | $o3d | 1 | $(judge "$tmp/o3d.ply" "$dir") | |"
}
set_row "composite, 24 views, noise 0.5, 1 % outliers, 2 patches" --shape composite --views 24 \
  --noise 0.5 --outliers 0.01 --patches 2 --seed 11
set_row "composite, 18 views, noise 1, 2 % outliers, 3 patches" --shape composite --views 18 \
  --noise 1 --outliers 0.02 --patches 3 --seed 12
set_row "torus, 18 views, noise 1, 2 % outliers, 3 patches" --shape torus --views 18 --noise 1 \
  --outliers 0.02 --patches 3 --seed 13
for v in 6 12; do
  set_row "composite, $v views, noise 0.5, 1 % outliers, 2 patches" --shape composite \
    --views "$v" --noise 0.5 --outliers 0.01 --patches 2 --seed 14
done

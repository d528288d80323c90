#!/usr/bin/env bash
# How the consensus cost grows with the number of views: the composite shape scanned from
# 6, 12 and 24 views (160x120, noise 0.5 voxel), fused on 1 rank; time per evaluated point.
# Usage: bash jobs/benchmark_views.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/rangefuse
echo "| views | method | field (s) | evaluated points | voxels | us per point |"
echo "|---|---|---|---|---|---|"
for views in 6 12 24; do
  $bin scan --shape composite --views $views --width 160 --height 120 --voxel 1 --noise 0.5 \
    --out "$tmp/s$views" >/dev/null
  for method in consensus naive; do
    mpirun -np 1 $bin fuse --scans "$tmp/s$views/truth.conf" --voxel 1 --method $method \
      --out "$tmp/m.ply" >"$tmp/log"
    line=$(grep '] field ' "$tmp/log")
    seconds=$(echo "$line" | sed 's/.*(\([0-9.]*\)s)$/\1/')
    points=$(echo "$line" | sed 's/.*per rank \([0-9]*\),.*/\1/')
    voxels=$(echo "$line" | sed 's/.*voxels \([0-9]*\) .*/\1/')
    echo "| $views | $method | $seconds | $points | $voxels | $(awk "BEGIN { printf \"%.1f\", 1e6 * $seconds / $points }") |"
  done
done

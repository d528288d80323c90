#!/usr/bin/env bash
# Benchmark: the bunny fuse at two voxel sizes on 1 and 2 ranks, in one run, with wall
# time, peak memory per rank, accuracy against bun_zipper.ply and the 2-vs-1 speed-up.
# Usage: bash jobs/benchmark.sh [repeats]   (prints a Markdown table; best of `repeats`)
set -euo pipefail
cd "$(dirname "$0")/.."
repeats=${1:-3}
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
data=tests/data/bunny

calc() { awk "BEGIN { printf \"$1\", $2 }"; }

echo "| voxel (mm) | ranks | mpirun wall (s) | job (s) | field (s) | bricks | peak MiB per rank | accuracy mean (mm) | completeness mean (mm) | speed-up 2 vs 1 (job / wall) |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for voxel in 0.001 0.0005; do
  declare -A best=() job=()
  for ranks in 1 2; do
    best[$ranks]=999
    for ((i = 0; i < repeats; i++)); do
      start=$(date +%s.%N)
      mpirun -np "$ranks" build/rangefuse fuse --scans $data/bun.conf --voxel $voxel \
        --out "$tmp/m$ranks.ply" >"$tmp/log"
      wall=$(calc %.3f "$(date +%s.%N) - $start")
      if [[ $(calc %d "$wall < ${best[$ranks]}") == 1 ]]; then
        best[$ranks]=$wall
        cp "$tmp/log" "$tmp/best$ranks.log"
      fi
    done
    build/rangefuse eval --mesh "$tmp/m$ranks.ply" --reference $data/bun_zipper.ply \
      --voxel $voxel >"$tmp/eval"
    acc=$(awk '/^accuracy/ {printf "%.4f", $3 * 1000}' "$tmp/eval")
    comp=$(awk '/^completeness/ {printf "%.4f", $3 * 1000}' "$tmp/eval")
    field=$(grep '] field ' "$tmp/best$ranks.log" | sed 's/.*(\(.*\)s)$/\1/')
    bricks=$(grep '] bricks ' "$tmp/best$ranks.log" | awk '{print $4}')
    mem=$(grep '] done ' "$tmp/best$ranks.log" | sed 's/.*(MiB) \(.*\) (.*/\1/')
    job[$ranks]=$(grep '] done ' "$tmp/best$ranks.log" | sed 's/^\[ *\([0-9.]*\)s\].*/\1/')
    speedup=""
    [[ $ranks == 2 ]] && speedup="$(calc %.2f "${job[1]} / ${job[2]}") / $(calc %.2f "${best[1]} / ${best[2]}")"
    printf "| %s | %s | %.2f | %s | %s | %s | %s | %s | %s | %s |\n" "$(calc %g "$voxel * 1000")" \
      "$ranks" "${best[$ranks]}" "${job[$ranks]}" "$field" "$bricks" "$mem" "$acc" "$comp" "$speedup"
  done
done
echo
echo "mpirun wall = the whole command including MPI start-up; job = rangefuse's own elapsed time"
echo "(read, triangulate, fields, mesh, write); best of $repeats runs; $(nproc) cores."

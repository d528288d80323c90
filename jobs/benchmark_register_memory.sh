#!/usr/bin/env bash
# Peak memory per rank of a registering run: synthetic bunny scans perturbed by up to
# 5 deg / 5 voxels, `fuse --register both` on 1, 2, 4 ... ranks. Prints a Markdown table.
# Usage: bash jobs/benchmark_register_memory.sh [VIEWS] [WIDTH] [HEIGHT] [RANKS...]
#        (defaults: 24 320 240 1 2 4)
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
views=${1:-24} width=${2:-320} height=${3:-240}
shift $(($# < 3 ? $# : 3))
ranks=("${@:-1 2 4}")
[[ $# -eq 0 ]] && ranks=(1 2 4)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=$PWD/build/rangefuse
$bin scan --mesh tests/data/bunny/bun_zipper.ply --views "$views" --width "$width" \
  --height "$height" --voxel 0.001 --noise 0.5 --rot-deg 5 --trans-vox 5 --out "$tmp/set" >/dev/null
echo "$views views, ${width}x$height, voxel 1 mm, --register both"
echo
echo "| ranks | peak memory per rank (MiB) | all ranks (MiB) | wall (s) | register (s) | ms a fit |"
echo "|---|---|---|---|---|---|"
for n in "${ranks[@]}"; do
  start=$(date +%s.%N)
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/set/perturbed.conf" --voxel 0.001 \
    --register both --out "$tmp/mesh$n.ply" --poses-out "$tmp/poses$n.conf" >"$tmp/log$n"
  wall=$(echo "$(date +%s.%N) - $start" | bc)
  peaks=$(grep -o 'peak memory per rank (MiB) [0-9 /]*' "$tmp/log$n" | sed 's/.*(MiB) //')
  total=$(echo "$peaks" | tr '/' '\n' | awk '{ s += $1 } END { print s }')
  reg=$(grep '] register ' "$tmp/log$n" | sed 's/.*(\([0-9.]*\)s)$/\1/' |
    awk '{ s += $1 } END { printf "%.2f", s }')
  fit=$(grep '] register .* fits;' "$tmp/log$n" | sed 's/.*(\([0-9.]*\) ms a fit).*/\1/')
  printf "| %s | %s | %s | %.1f | %s | %s |\n" "$n" "$peaks" "$total" "$wall" "$reg" "$fit"
  [[ $n == "${ranks[0]}" ]] || cmp -s "$tmp/poses${ranks[0]}.conf" "$tmp/poses$n.conf" ||
    echo "poses on $n ranks differ from ${ranks[0]} rank(s)" >&2
done

#!/usr/bin/env bash
# Two ranks against one, by rangefuse's own clock (`wall_seconds` of `fuse --report`): the
# issue's scale-out measure, on the real bunny at 0.5 mm and the 48 x 1024² re-scan (the set of
# benchmark_memory.sh and benchmark_speed.sh, made once in the cache). Each rank count is run
# three times, alternated, and its best run is kept; default binding (one thread a rank).
# Usage: bash jobs/benchmark_speedup.sh [BIN]   (BIN: build/rangefuse; CACHE: where the
# 48-view set is kept)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${1:-build/rangefuse}")
cache=${CACHE:-/tmp/rangefuse-bench}
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

s48=$cache/bunny-48x1024
if [[ ! -f $s48/truth.conf ]]; then
  $bin scan --mesh tests/data/bunny/bun_zipper.ply --views 48 --width 1024 --height 1024 \
    --voxel 0.0005 --noise 0.3 --out "$s48" >/dev/null
fi

# field REPORT KEY: wall seconds, or the max/mean of the ranks' voxel updates.
field() {
  python3 -c 'import json, sys
r = json.load(open(sys.argv[1]))
if sys.argv[2] == "wall":
    print(r["wall_seconds"])
else:
    n = [p["voxels_updated"] for p in r["per_rank"]]
    print("%.3f" % (max(n) * len(n) / sum(n)))' "$1" "$2"
}
# best A B: the smaller of two numbers (A empty: B).
best() { awk -v a="$1" -v b="$2" 'BEGIN { print (a == "" || b + 0 < a + 0) ? b : a }'; }

echo "| set | 1 rank (s) | 2 ranks (s) | speed-up | voxel updates max/mean at 2 ranks |"
echo "|---|---|---|---|---|"
for entry in "real bunny, 10 scans, 0.5 mm:tests/data/bunny/bun.conf" \
  "48 x 1024², 0.5 mm:$s48/truth.conf"; do
  name=${entry%%:*} conf=${entry#*:}
  one= two=
  for run in 1 2 3; do
    for n in 1 2; do
      mpirun -np $n "$bin" fuse --scans "$conf" --voxel 0.0005 --out "$tmp/mesh.ply" \
        --report "$tmp/r$n.json" >/dev/null 2>&1
    done
    one=$(best "$one" "$(field "$tmp/r1.json" wall)")
    two=$(best "$two" "$(field "$tmp/r2.json" wall)")
  done
  printf "| %s | %.2f | %.2f | %.2f | %s |\n" "$name" "$one" "$two" \
    "$(awk -v a="$one" -v b="$two" 'BEGIN { print a / b }')" "$(field "$tmp/r2.json" balance)"
done

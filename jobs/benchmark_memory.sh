#!/usr/bin/env bash
# Peak memory per rank and wall time of one streamed prism fuse on 1, 2, 4 and 8 ranks (more
# ranks than cores are oversubscribed), with the bytes routed per input triangle and what the
# largest rank's peak was made of (the run report's memory_at_peak_mib); then, in the
# same run, Open3D's ScalableTSDFVolume on the same scans when python3-open3d is installed
# (jobs/open3d_tsdf.py). The scan set is made once by the synthetic scanner and kept in the
# cache folder.
# Usage: bash jobs/benchmark_memory.sh [VIEWS] [SIZE] [RANKS...]   (defaults: 48 1024 1 2 4 8)
# Environment: CACHE (default /tmp/rangefuse-bench), SCAN_MEMORY (MiB, default: the option's).
set -euo pipefail
cd "$(dirname "$0")/.."
views=${1:-48} size=${2:-1024}
shift $(($# > 2 ? 2 : $#)) || true
ranks=("$@")
((${#ranks[@]})) || ranks=(1 2 4 8)
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
bin=build/rangefuse
cache=${CACHE:-/tmp/rangefuse-bench}
set_dir=$cache/bunny-${views}x${size}
if [[ ! -f $set_dir/truth.conf ]]; then
  $bin scan --mesh tests/data/bunny/bun_zipper.ply --views "$views" --width "$size" \
    --height "$size" --voxel 0.0005 --noise 0.3 --out "$set_dir" >/dev/null
fi
extra=()
[[ -n ${SCAN_MEMORY:-} ]] && extra=(--scan-memory "$SCAN_MEMORY")
log=$(mktemp)
reports=$(mktemp -d)
trap 'rm -rf "$log" "$reports" "$cache/mesh.ply" "$cache/open3d.ply"' EXIT
echo "| ranks | peak memory per rank (MiB) | all ranks (MiB) | wall (s) | routed per input triangle |"
echo "|---|---|---|---|---|"
for n in "${ranks[@]}"; do
  mpirun -np "$n" $bin fuse --scans "$set_dir/truth.conf" --voxel 0.0005 "${extra[@]}" \
    --out "$cache/mesh.ply" --report "$reports/$n.json" >"$log"
  mem=$(grep "] done " "$log" | sed 's/.*(MiB) \(.*\) (.*/\1/')
  total=$(echo "$mem" | tr '/' '\n' | awk '{s += $1} END {print s}')
  wall=$(grep "] done " "$log" | sed 's/^\[ *\([0-9.]*\)s\].*/\1/')
  routed=$(grep "routed" "$log" | sed 's/.*routed \(.*\) per input triangle.*/\1/')
  echo "| $n | $mem | $total | $wall | $routed |"
done
echo
echo "What the largest rank's peak was made of (MiB; 'other': allocator slack and transient copies):"
echo
python3 - "$reports" "${ranks[@]}" <<'PY'
import json, sys
folder, counts = sys.argv[1], sys.argv[2:]
parts = ["process", "kept_scans", "routed_scans", "field", "integrator", "brick_list",
         "sight_maps", "other"]
print("| ranks | peak (rank) | " + " | ".join(p.replace("_", " ") for p in parts) + " |")
print("|---" * (len(parts) + 2) + "|")
for n in counts:
    ranks = json.load(open(f"{folder}/{n}.json"))["per_rank"]
    top = max(ranks, key=lambda r: r["peak_memory_mib"])
    at = top["memory_at_peak_mib"]
    print(f"| {n} | {top['peak_memory_mib']} ({top['rank']}) | " +
          " | ".join(f"{at[p]:.1f}" for p in parts) + " |")
PY
if /usr/bin/python3 -c "import open3d" 2>/dev/null; then  # Debian's python, not a pyenv one
  /usr/bin/python3 jobs/open3d_tsdf.py "$set_dir" 0.0005 "$cache/open3d.ply"
fi

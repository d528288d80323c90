#!/usr/bin/env bash
# Weak scaling: the same work on every rank, 1 to 16 ranks (more ranks than cores are
# oversubscribed, so wall times say little here; memory and traffic per rank are the figures).
# Each rank brings one copy of the bunny seen by VIEWS scans of 1024 x 1024 (the 48-view set's
# views spread around it), the copies side by side SPACING m apart (default 1: each copy's
# scanner positions apart from the others'; at 0.25 they interleave with the neighbours'), so
# the field, the scans and the mesh all grow with the rank count. Prints, per rank count, the input points, the largest
# rank's peak memory and what it was made of, MPI bytes and calls per rank (largest), the
# balance of voxel updates and the wall time.
# Usage: bash jobs/benchmark_weak_scaling.sh [VIEWS] [RANKS...]   (defaults: 6  1 2 4 8 16)
#   bash jobs/benchmark_weak_scaling.sh 18 8   fuses 144 scans (151 M points) on 8 ranks
# Environment: CACHE (default /tmp/rangefuse-bench), where the 48-view set is made once.
set -euo pipefail
cd "$(dirname "$0")/.."
views=${1:-6} spacing=${SPACING:-1}
shift $(($# > 0 ? 1 : 0)) || true
ranks=("$@")
((${#ranks[@]})) || ranks=(1 2 4 8 16)
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
bin=build/rangefuse
cache=${CACHE:-/tmp/rangefuse-bench}
set_dir=$cache/bunny-48x1024
if [[ ! -f $set_dir/truth.conf ]]; then
  $bin scan --mesh tests/data/bunny/bun_zipper.ply --views 48 --width 1024 --height 1024 \
    --voxel 0.0005 --noise 0.3 --out "$set_dir" >/dev/null
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# copies COUNT: a scan list of COUNT bunnies, each seen by the same VIEWS views, shifted in x.
copies() {
  awk -v copies="$1" -v views="$views" -v dir="$set_dir" -v spacing="$spacing" '
    { line[NR - 1] = $0 }
    END {
      step = int(48 / views); if (step < 1) step = 1
      for (c = 0; c < copies; ++c)
        for (v = 0; v < views; ++v) {
          split(line[(v * step) % 48], f, " ")
          printf "%s %s/%s %.17g %s %s", f[1], dir, f[2], f[3] + spacing * c, f[4], f[5]
          for (k = 6; k <= 9; ++k) printf " %s", f[k]
          printf "\n"
        }
    }' "$set_dir/truth.conf"
}

echo "| ranks | scans | input points (M) | peak per rank, largest (MiB) | / 1 rank | its peak: process / kept scans / routed / field / integrator / brick list / other | MPI sent / received per rank, largest (MiB) | MPI calls per rank, largest | voxel updates max/mean | wall (s) |"
echo "|---|---|---|---|---|---|---|---|---|---|"
first=""
for n in "${ranks[@]}"; do
  copies "$n" >"$work/scans.conf"
  mpirun -np "$n" $bin fuse --scans "$work/scans.conf" --voxel 0.0005 --out "$work/mesh.ply" \
    --report "$work/report.json" >"$work/log" 2>&1 || { cat "$work/log"; exit 1; }
  row=$(python3 - "$work/report.json" "$n" "${first:-0}" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
n, first = int(sys.argv[2]), float(sys.argv[3])
ranks = r["per_rank"]
top = max(ranks, key=lambda e: e["peak_memory_mib"])
m = top["memory_at_peak_mib"]
parts = " / ".join("%.0f" % m[k] for k in ["process", "kept_scans", "routed_scans", "field",
                                           "integrator", "brick_list", "other"])
mib = 1024.0 * 1024.0
sent = max(e["mpi"]["bytes_sent"] for e in ranks) / mib
received = max(e["mpi"]["bytes_received"] for e in ranks) / mib
calls = max(e["mpi"]["calls"] for e in ranks)
updates = [e["voxels_updated"] for e in ranks]
balance = max(updates) * len(updates) / max(1, sum(updates))
peak = top["peak_memory_mib"]
ratio = "%.2f" % (peak / first) if first > 0 else "1"
points = r["inputs"]["scan_count"] * 1024 * 1024 / 1e6
print("| %d | %d | %.0f | %d | %s | %s | %.0f / %.0f | %d | %.3f | %.1f |" % (
    n, r["inputs"]["scan_count"], points, peak, ratio, parts, sent, received, calls, balance,
    r["wall_seconds"]))
PY
)
  echo "$row"
  [[ -n $first ]] || first=$(echo "$row" | awk -F'|' '{print $5}' | tr -d ' ')
done

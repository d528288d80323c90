#!/usr/bin/env bash
# Where a fuse's time goes: `perf record` over the whole mpirun job (every rank), then the
# samples' shares by stage and their largest symbols (jobs/profile_shares.py), as the tables
# of docs/benchmarks.md, "Where a depth stream's time goes", give them. Needs Debian's
# linux-perf, and perf_event_paranoid low enough to sample (as root, any).
# Usage: bash jobs/profile_stream.sh SCANS [VOXEL (0.01)] [RANKS (2)] [FUSE OPTIONS...]
#   e.g. bash jobs/profile_stream.sh ROOM-DEV 0.01 2 --colour none
set -euo pipefail
cd "$(dirname "$0")/.."
scans=${1:?usage: profile_stream.sh SCANS [VOXEL] [RANKS] [FUSE OPTIONS...]}
voxel=${2:-0.01}
ranks=${3:-2}
shift $(($# < 3 ? $# : 3))
bin=$(realpath "${BIN:-build/rangefuse}")
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
perf record -F 999 -o "$tmp/perf.data" -- mpirun -np "$ranks" "$bin" fuse --scans "$scans" \
  --voxel "$voxel" "$@" --out "$tmp/mesh.ply" --report "$tmp/report.json" 2>&1 |
  grep -E "\] (read|field|track) " || true
python3 - "$tmp/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
ranks = r["per_rank"]
updates = sum(p["voxels_updated"] for p in ranks)
prisms = sum(p["prisms"] for p in ranks)
print("\n%.2f s by rangefuse's clock; %.1f M voxel updates (%.1f a prism); %.0f ns an update "
      "a core, end to end" % (r["wall_seconds"], updates / 1e6, updates / max(prisms, 1),
                              r["wall_seconds"] * len(ranks) / max(updates, 1) * 1e9))
per = lambda f: " / ".join(f(p) for p in ranks)
print("seconds a rank: read %s; field %s (adding %s, planning %s, routing %s); mesh %s; write %s"
      % (per(lambda p: "%.2f" % p["stage_seconds"]["read"]),
         per(lambda p: "%.2f" % p["stage_seconds"]["field"]),
         per(lambda p: "%.2f" % p["adding_seconds"]), per(lambda p: "%.2f" % p["planning_seconds"]),
         per(lambda p: "%.2f" % p["routing_seconds"]),
         per(lambda p: "%.2f" % p["stage_seconds"]["mesh"]),
         per(lambda p: "%.2f" % p["stage_seconds"].get("write", 0))))
print("prisms a rank %s; voxel updates a rank %s" % (per(lambda p: "%.2f M" % (p["prisms"] / 1e6)),
                                                     per(lambda p: "%.1f M" % (p["voxels_updated"] / 1e6))))
PY
echo
python3 jobs/profile_shares.py "$tmp/perf.data"

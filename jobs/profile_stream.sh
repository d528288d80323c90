#!/usr/bin/env bash
# Where a fuse's time goes: `perf record` over the whole mpirun job (every rank), then the
# samples' shares by stage and their largest symbols (jobs/profile_shares.py), as the tables
# of docs/benchmarks.md, "Where a depth stream's time goes", give them: for frames at known
# poses (read, field) or tracked ones (a folder without poses: track). Needs Debian's
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
seconds = lambda get: per(lambda p: "%.2f" % get(p))  # each rank's, from its report
# A posed stream reads, then builds the field; a tracked one tracks (reads, fits and adds,
# frame by frame): print the stages the run had, in the pipeline's order.
order = ["read", "field", "track", "mesh", "write"]
stages = sorted((s for s in ranks[0]["stage_seconds"] if s not in ("open", "done")),
                key=lambda s: order.index(s) if s in order else len(order))
parts = []
for s in stages:
    line = "%s %s" % (s, seconds(lambda p: p["stage_seconds"][s]))
    if s == "field":
        line += " (%s)" % ", ".join("%s %s" % (k, seconds(lambda p: p[k + "_seconds"]))
                                    for k in ("adding", "planning", "routing"))
    if s == "track":  # the report's "reading" is the wait for the next frame to be read
        names = {"reading": "waiting for the frame"}
        line += " (%s)" % ", ".join("%s %s" % (names.get(k, k),
                                               seconds(lambda p: p["tracking_seconds"][k]))
                                    for k in ranks[0]["tracking_seconds"])
    parts.append(line)
print("seconds a rank: " + "; ".join(parts))
print("prisms a rank %s; voxel updates a rank %s" % (per(lambda p: "%.2f M" % (p["prisms"] / 1e6)),
                                                     per(lambda p: "%.1f M" % (p["voxels_updated"] / 1e6))))
PY
echo
python3 jobs/profile_shares.py "$tmp/perf.data"

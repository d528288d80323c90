#!/usr/bin/env bash
# Issue 56's figures on a real recording (the 7-Scenes kitchen, jobs/kitchen_as_redwood.sh):
# its poses written back as TUM and compared with its own .log by `eval` (every pose, ATE 0),
# `info` against the first pose file, a tracked run's report figures, and the refusals of a
# forced --scan-format and of a voxel in the wrong unit. Prints what it measured.
# Usage: bash jobs/measure_outputs_real.sh [FRAMES (default 200)]
set -euo pipefail
cd "$(dirname "$0")/.."
source jobs/mpi_env.sh
frames=${1:-200}
bin=build/rangefuse
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bash jobs/kitchen_as_redwood.sh "$tmp/k" "$frames" >/dev/null

echo "== posed: the recording's poses out as TUM, compared with its .log"
mpirun -np 2 $bin fuse --scans "$tmp/k" --voxel 0.02 --track off --quiet --out "$tmp/k.ply" \
  --trajectory-out "$tmp/k.txt" --checkpoint "$tmp/k.h5"
$bin eval --trajectory "$tmp/k.txt" --reference "$tmp/k/trajectory.log"
$bin eval --trajectory "$tmp/k/trajectory.log" --reference "$tmp/k.txt" | grep -E "matched|ATE"

echo "== info: the first frame's pose, then the recording's pose file"
$bin info "$tmp/k.h5" >"$tmp/info.txt"
grep -m1 "depth/000000.png" "$tmp/info.txt"
head -3 "$tmp/k/trajectory.log" | tail -2

echo "== tracked ($frames frames, 2 cm, 2 ranks): the report's tracking figures"
mpirun -np 2 $bin fuse --scans "$tmp/k" --voxel 0.02 --track on --skip-lost --quiet \
  --out "$tmp/t.ply" --trajectory-out "$tmp/t.txt" --report "$tmp/t.json"
python3 - "$tmp/t.json" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
t = r["tracking"]
print("frames %d, fused %d, lost %d, recovered %d; inliers min %.3f median %.3f; "
      "RMS residual median %.4f m, max %.4f m; prisms %d" % (
          t["frames"], t["fused"], t["lost"], t["recovered"], t["inliers"]["min"],
          t["inliers"]["median"], t["rms_residual"]["median"], t["rms_residual"]["max"],
          sum(p["prisms"] for p in r["per_rank"])))
for f in t["lost_frames"][:5]:
    print("  lost %s: %s" % (f["name"], f["why"]))
EOF
$bin eval --trajectory "$tmp/t.txt" --reference "$tmp/k/trajectory.log" | grep -E "matched|ATE|RPE"

echo "== refusals and warnings"
# Each run's output to a file first: mpirun killed by a closed pipe reports a segfault of its own.
mpirun -np 2 $bin fuse --scans "$tmp/k" --voxel 0.02 --scan-format tum --out "$tmp/x.ply" \
  >"$tmp/format.txt" 2>&1 || true
grep -m1 "error" "$tmp/format.txt"
mpirun -np 2 $bin fuse --scans "$tmp/k" --voxel 10 --track on --skip-lost --out "$tmp/x.ply" \
  >"$tmp/voxel.txt" 2>&1 || true
grep -m1 "did you mean" "$tmp/voxel.txt"

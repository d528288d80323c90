#!/usr/bin/env bash
# Loop closure on a synthetic loop seen by the synthetic Kinect (scan --sensor kinect: depth
# steps, holes, shadows, rolling shutter, a time offset): one turn around the bunny scaled to
# 1.5 m, 300 frames of 320 x 240, tracked without poses. Closing loops at least halves the ATE
# tracking alone leaves, places every frame, and gives the same trajectory and mesh bytes on 2
# and 3 ranks.
set -euo pipefail
bin=$1 data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" scan --mesh "$data/bunny/bun_zipper.ply" --scale 10 --views 300 --width 320 \
  --height 240 --voxel 0.01 --path orbit --sensor kinect --format tum --out "$tmp/truth" >/dev/null
mkdir "$tmp/stream"
cp -r "$tmp/truth/depth" "$tmp/truth/depth.txt" "$tmp/truth/camera_intrinsic.json" "$tmp/stream/"
first=$(awk '!/^#/ { print $2 "," $3 "," $4 "," $5 "," $6 "," $7 "," $8; exit }' \
  "$tmp/truth/groundtruth.txt")
ate() {
  "$bin" eval --trajectory "$1" --reference "$tmp/truth/groundtruth.txt" --json |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["ate_rmse"])'
}
mpirun -np 2 "$bin" fuse --scans "$tmp/stream" --voxel 0.01 --first-pose "$first" \
  --out "$tmp/open.ply" --trajectory-out "$tmp/open.txt" >"$tmp/open.log"
for n in 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/stream" --voxel 0.01 \
    --first-pose "$first" --close-loops --report "$tmp/closed$n.json" --out "$tmp/closed$n.ply" \
    --trajectory-out "$tmp/closed$n.txt" >"$tmp/closed$n.log"
done
cmp "$tmp/closed2.txt" "$tmp/closed3.txt" && cmp "$tmp/closed2.ply" "$tmp/closed3.ply"
echo "loop closure: 2 and 3 ranks give identical trajectories and meshes"
open=$(ate "$tmp/open.txt") closed=$(ate "$tmp/closed2.txt")
echo "loop closure: ATE $closed m closing loops, $open m without (bound: half)"
python3 -c "import sys; sys.exit(0 if $closed <= 0.5 * $open else 1)" ||
  fail "closing loops left ATE $closed m, more than half of $open m"
python3 - "$tmp/closed2.json" <<'PY' || fail "loops not closed, or frames not placed"
import json, sys
t = json.load(open(sys.argv[1]))["tracking"]
print("loop closure: %d key frames, %d loops measured, %d closed, %d of %d frames fused"
      % (t["loops"]["key_frames"], t["loops"]["measured"], t["loops"]["closed"], t["fused"],
         t["frames"]))
sys.exit(0 if t["loops"]["closed"] >= 1 and t["fused"] >= 0.95 * t["frames"] else 1)
PY

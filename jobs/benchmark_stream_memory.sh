#!/usr/bin/env bash
# Memory of a depth stream tracked through the Python module, frame after frame: the process's
# peak resident memory after 25, 50, 100 and FRAMES frames (640x480, the bunny scaled to 1.5 m
# along an orbit, 1 cm), tracked with the prism method (the tracking field is the
# mesh: only the last fused frame's images are kept) and with robust (every frame kept, to be
# fused again at the end). Usage: bash jobs/benchmark_stream_memory.sh [FRAMES]  (default 200)
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
frames=${1:-200}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export PYTHONPATH=$PWD/build/python
build/rangefuse scan --mesh tests/data/bunny/bun_zipper.ply --scale 10 --views "$frames" \
  --width 640 --height 480 --voxel 0.01 --noise 0.5 --depth-noise --path orbit \
  --format tum --out "$tmp/seq" >/dev/null
rm "$tmp/seq/groundtruth.txt"  # a stream without a trajectory

cat >"$tmp/track.py" <<'PY'
import resource, sys, rangefuse
checkpoints = {25, 50, 100, int(sys.argv[3])}
fusion = rangefuse.Fusion(voxel=0.01, method=sys.argv[2])
peaks = []
for n, (depth, _, K, scale, _, time) in enumerate(rangefuse.read_frames(sys.argv[1]), 1):
    fusion.track(rangefuse.read_depth(depth), K, depth_scale=scale, time=time)
    if n in checkpoints:
        peaks.append(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
print(" | ".join("%.0f" % p for p in peaks))
PY

echo "| method | peak MiB after 25 | 50 | 100 | $frames frames |"
echo "|---|---|---|---|---|"
for method in prism robust; do
  echo "| $method | $(/usr/bin/python3 "$tmp/track.py" "$tmp/seq" "$method" "$frames") |"
done

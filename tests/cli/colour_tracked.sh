#!/usr/bin/env bash
# Colour on a tracked stream: a painted bunny filmed along an orbit, given without its
# trajectory and tracked against the field it builds. Its colour images are fused as the same
# frames at their true poses fuse them (eval's colour error within 2/255), on 2 and 3 ranks to
# the same bytes.
set -euo pipefail
bin=$1
data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" scan --mesh "$data/bun_zipper.ply" --scale 10 --views 300 \
  --path orbit --width 160 --height 120 --voxel 0.01 --noise 0.3 --texture 0.0973 --format tum \
  --out "$tmp/stream" >/dev/null
mpirun -np 2 "$bin" fuse --scans "$tmp/stream" --voxel 0.01 --track off --out "$tmp/posed.ply" \
  >/dev/null
# One awk, not grep | head: under pipefail, head closing the pipe early fails the grep.
first=$(awk '!/^#/ { print $2","$3","$4","$5","$6","$7","$8; exit }' "$tmp/stream/groundtruth.txt")
rm "$tmp/stream/groundtruth.txt"
for n in 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/stream" --voxel 0.01 \
    --first-pose "$first" --out "$tmp/tracked$n.ply" >/dev/null
done
cmp "$tmp/tracked2.ply" "$tmp/tracked3.ply"
colour_error() {  # mesh -> eval's mean colour error against the stream's truth
  "$bin" eval --mesh "$1" --reference "$tmp/stream/truth.ply" --voxel 0.01 --json |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["colour"]["error"]["mean"])'
}
tracked=$(colour_error "$tmp/tracked2.ply") posed=$(colour_error "$tmp/posed.ply")
awk -v t="$tracked" -v p="$posed" 'BEGIN { exit !(t <= p + 2) }' ||
  fail "tracked stream colour error $tracked against $posed at the true poses"
echo "tracked stream: colour error $tracked/255 (at true poses $posed), 2 and 3 ranks identical"


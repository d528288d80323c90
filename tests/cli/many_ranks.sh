#!/usr/bin/env bash
# The fused mesh is byte-identical on 1, 4, 8 and 16 ranks (oversubscribed), on small data:
# prism and robust fields, registration, a depth-camera sequence, and bunny copies side by
# side whose scans are read where they lie (no scan bytes cross ranks). determinism.sh covers
# 2 and 3 ranks.
set -euo pipefail
bin=$1 data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ranks=(1 4 8 16)

# same NAME FILE...: every rank count's FILE equals the one rank's.
same() {
  local name=$1
  shift
  for file in "$@"; do
    for n in "${ranks[@]:1}"; do cmp "$tmp/${file%.*}-1.${file##*.}" "$tmp/${file%.*}-$n.${file##*.}"; done
  done
  echo "$name: ${ranks[*]} ranks give identical results"
}

for method in prism robust; do
  for n in "${ranks[@]}"; do
    mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$data/bunny/bun.conf" --voxel 0.002 \
      --method $method --out "$tmp/$method-$n.ply" >"$tmp/log"
  done
  same "bunny, $method" "$method.ply"
done

"$bin" scan --shape composite --views 6 --width 100 --height 80 --voxel 1 --rot-deg 2 \
  --trans-vox 2 --out "$tmp/synth" >/dev/null
for n in "${ranks[@]}"; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/synth/perturbed.conf" --voxel 1 \
    --register both --max-iterations 3 --max-rounds 2 --out "$tmp/reg-$n.ply" \
    --poses-out "$tmp/poses-$n.conf" >"$tmp/log"
done
same "registration (poses and mesh)" reg.ply poses.conf

"$bin" scan --shape composite --views 10 --width 120 --height 90 --voxel 0.01 --scale 0.01 \
  --path orbit --noise 0.5 --depth-noise --format tum --out "$tmp/tum" >/dev/null
for n in "${ranks[@]}"; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/tum" --voxel 0.01 \
    --out "$tmp/tum-$n.ply" >"$tmp/log"
done
same "depth sequence (TUM)" tum.ply

# Four copies of two bunny scans, 1 m apart: on 4 ranks each copy is read by the rank that
# owns it, so almost no scan bytes cross ranks, and the mesh is still the one rank's.
head -3 "$data/bunny/bun.conf" | grep '^bmesh' | head -2 >"$tmp/two"
awk -v dir="$(cd "$data/bunny" && pwd)" '{ for (c = 0; c < 4; ++c)
  printf "%s %s/%s %.17g %s %s %s %s %s %s\n", $1, dir, $2, $3 + c, $4, $5, $6, $7, $8, $9 }' \
  "$tmp/two" >"$tmp/copies.conf"
for n in 1 4; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/copies.conf" --voxel 0.002 \
    --out "$tmp/copies-$n.ply" --report "$tmp/copies-$n.json" >"$tmp/log"
done
cmp "$tmp/copies-1.ply" "$tmp/copies-4.ply"
python3 - "$tmp/copies-4.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
routed = sum(e["routed_bytes_sent"] for e in r["per_rank"])
triangles = r["inputs"]["scan_triangles"]
print("copies on 4 ranks: %.2f routed bytes an input triangle" % (routed / triangles))
assert routed < 0.05 * 30 * triangles, "scans should be read by the rank that owns them"
PY

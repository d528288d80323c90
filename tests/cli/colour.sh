#!/usr/bin/env bash
# Colour fused beside the distance: range grids painted with checks of a known colour, fused on
# 1, 2 and 3 ranks to the same bytes; the mesh's colours against the checks' colour at each
# vertex (exact away from the check edges), by prism and robust fusion; sequences with PNG and
# JPEG colour images; a room walk's joined flat blocks; PTX r g b and intensity; a checkpoint
# resumed to the same coloured mesh;
# --colour none gives the bytes of the same scans without colour, and reads no colour image;
# colour asked of scans that have none, or of a method that cannot fuse it, refused by name.
# Tracked streams: colour_tracked.sh.
set -euo pipefail
bin=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" scan --shape sphere --views 12 --voxel 1 --noise 0.3 --texture 20 --out "$tmp/painted" \
  >/dev/null
"$bin" scan --shape sphere --views 12 --voxel 1 --noise 0.3 --out "$tmp/plain" >/dev/null
for n in 1 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/painted/truth.conf" --voxel 1 \
    --out "$tmp/mesh$n.ply" >"$tmp/log$n"
done
cmp "$tmp/mesh1.ply" "$tmp/mesh2.ply" && cmp "$tmp/mesh1.ply" "$tmp/mesh3.ply"
echo "painted sphere: 1, 2 and 3 ranks give identical coloured meshes"

# The mesh's colour against the checks' colour at each vertex, by distance from the nearest
# check edge: five voxels or more away, every vertex to 1/255 (8-bit rounding and the fused
# mean's last units; JPEG's own error is larger); two to five voxels away, within 1/255 on
# average (prisms interpolate across a triangle, and grazing views reach a little farther);
# nearer, the two colours may blend. Where a scene has fewer views of a spot (patches hid it from
# some), grazing views weigh more and blend farther. Given the sphere's radius (about the
# origin), vertices more than 3 voxels off it are stray geometry, not colour: counted apart.
check_colours() {  # mesh.ply, check side, voxel [2-5 voxel mean limit (1)] [5+ voxel limit (1)]
  #                  [sphere radius]
  python3 - "$@" <<'PY'
import math, struct, sys
side, voxel = float(sys.argv[2]), float(sys.argv[3])
near_limit = float(sys.argv[4]) if len(sys.argv) > 4 else 1.0
far_limit = float(sys.argv[5]) if len(sys.argv) > 5 else 1.0
radius = float(sys.argv[6]) if len(sys.argv) > 6 else None
stray = 0
data = open(sys.argv[1], "rb").read()
head, body = data.split(b"end_header\n", 1)
lines = head.decode().splitlines()
n = int(next(l for l in lines if l.startswith("element vertex")).split()[2])
assert "property uchar red" in lines, "no colour in the mesh"
a, b = (0.85, 0.35, 0.15), (0.15, 0.45, 0.80)
far, near = [], []
for i in range(n):
    x, y, z, _, _, _, r, g, bl = struct.unpack_from("<6f3B", body, 27 * i)
    if radius is not None and abs(math.sqrt(x * x + y * y + z * z) - radius) > 3 * voxel:
        stray += 1
        continue
    u = [c / side + 0.382 for c in (x, y, z)]  # check edges lie 0.382 of a side off round
    edge = min(abs(w - round(w)) * side for w in u) / voxel
    want = a if sum(math.floor(w) for w in u) % 2 == 0 else b
    err = max(abs(got - 255 * w) for got, w in zip((r, g, bl), want))
    (far if edge >= 5 else near if edge >= 2 else []).append(err)
mean = sum(near) / len(near)
print(f"{len(far)} vertices 5+ voxels from a check edge: worst error {max(far):.2f}/255; "
      f"{len(near)} at 2-5 voxels: mean error {mean:.2f}/255"
      + (f"; {stray} stray vertices off the sphere not judged" if radius else ""))
sys.exit(0 if len(far) > 5000 and max(far) <= far_limit and mean <= near_limit else 1)
PY
}
check_colours "$tmp/mesh1.ply" 20 1

# Robust fusion keeps the colour of what stands: magenta patches seen by one scan each, and 2 %
# outliers, leave no trace in the colour (prism fusion keeps the patches, and fails the check).
"$bin" scan --shape sphere --views 12 --voxel 1 --noise 0.3 --outliers 0.02 --patches 6 \
  --texture 20 --out "$tmp/patched" >/dev/null
for n in 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/patched/truth.conf" --voxel 1 \
    --method robust --out "$tmp/robust$n.ply" >/dev/null
done
cmp "$tmp/robust2.ply" "$tmp/robust3.ply"
check_colours "$tmp/robust2.ply" 20 1 2 1 50
mpirun -np 2 "$bin" fuse --scans "$tmp/patched/truth.conf" --voxel 1 --out "$tmp/kept.ply" \
  >/dev/null
if check_colours "$tmp/kept.ply" 20 1 2 >/dev/null; then fail "prism fusion hid the patches"; fi
echo "robust fusion: no patch colour on the mesh, 2 and 3 ranks identical"

# Depth sequences with colour images (TUM rgb.txt and rgb/, Redwood color/), at their poses.
for format in tum redwood; do
  "$bin" scan --shape sphere --views 12 --voxel 0.01 --noise 0.3 --texture 0.2 --scale 0.01 \
    --format "$format" --out "$tmp/$format" >/dev/null
  for n in 2 3; do
    mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/$format" --voxel 0.01 --track off \
      --out "$tmp/$format$n.ply" >/dev/null
  done
  cmp "$tmp/${format}2.ply" "$tmp/${format}3.ply"
  check_colours "$tmp/${format}2.ply" 0.2 0.01
done
echo "TUM and Redwood colour images: on the mesh, 2 and 3 ranks identical"
# A room walk with colour images: its flat blocks are joined as without colour, and their feet
# take the colours of the cells they cover (a blend of the joined corners' colours would double
# the error); 1, 2 and 3 ranks give the same bytes.
"$bin" scan --shape room --path walk --views 30 --width 320 --height 240 --voxel 0.02 \
  --sensor kinect --sensor-without shutter,offset --texture 0.25 --format tum --out "$tmp/room" \
  >/dev/null
for n in 1 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/room" --voxel 0.02 --track off \
    --out "$tmp/room$n.ply" >"$tmp/room$n.log"
done
cmp "$tmp/room1.ply" "$tmp/room2.ply" && cmp "$tmp/room1.ply" "$tmp/room3.ply"
mpirun -np 2 "$bin" fuse --scans "$tmp/room" --voxel 0.02 --track off --join-flat 0 \
  --out "$tmp/room-fine.ply" >"$tmp/room-fine.log"
triangles() { grep -o 'scans, [0-9]* triangles' "$1" | grep -o '[0-9]*' | tail -n 1; }
joined=$(triangles "$tmp/room2.log") fine=$(triangles "$tmp/room-fine.log")
((joined * 10 < fine * 7)) || fail "coloured frames joined too few blocks: $joined of $fine"
colour_error() {  # mesh: mean colour error and edge contrast against the painted room
  "$bin" eval --mesh "$1" --reference "$tmp/room/truth.ply" --voxel 0.02 --json |
    python3 -c '
import json, sys
c = json.load(sys.stdin)["colour"]
print("%.3f %.3f" % (c["error"]["mean"], c["edge_contrast"]))'
}
read -r err contrast < <(colour_error "$tmp/room2.ply")
read -r fine_err fine_contrast < <(colour_error "$tmp/room-fine.ply")
python3 -c "import sys
sys.exit(0 if $err <= 1.1 * $fine_err and $contrast >= 0.95 * $fine_contrast else 1)" ||
  fail "joined blocks' colour: error $err, contrast $contrast; without joins $fine_err, $fine_contrast"
echo "room walk: $joined triangles against $fine unjoined, colour error $err against $fine_err," \
  "1, 2 and 3 ranks identical"
# --colour none does not decode colour images: a broken one is refused only when colour is
# fused, and the mesh without colour is the intact folder's.
mpirun -np 2 "$bin" fuse --scans "$tmp/tum" --voxel 0.01 --track off --colour none \
  --out "$tmp/tum-none.ply" >/dev/null
broken=$(ls "$tmp"/tum/rgb/*.png | head -n 1)
head -c 100 "$broken" >"$tmp/part.png" && mv "$tmp/part.png" "$broken"
mpirun -np 2 "$bin" fuse --scans "$tmp/tum" --voxel 0.01 --track off --colour none \
  --out "$tmp/tum-broken.ply" >/dev/null
cmp "$tmp/tum-none.ply" "$tmp/tum-broken.ply"
if mpirun -np 2 "$bin" fuse --scans "$tmp/tum" --voxel 0.01 --track off \
  --out "$tmp/tum-x.ply" >"$tmp/err.log" 2>&1; then fail "a broken colour image was read"; fi
grep -q "$(basename "$broken")" "$tmp/err.log" || fail "no file named: $(cat "$tmp/err.log")"
echo "--colour none: colour images left unread"
# The recorder's color/*.jpg: JPEG at quality 95 stays within the same limits.
"$bin" scan --shape sphere --views 12 --voxel 0.01 --noise 0.3 --texture 0.2 --scale 0.01 \
  --format redwood --jpeg --out "$tmp/jpeg" >/dev/null
[[ -f $tmp/jpeg/color/000000.jpg ]] || fail "scan --jpeg wrote no JPEG"
mpirun -np 2 "$bin" fuse --scans "$tmp/jpeg" --voxel 0.01 --track off --out "$tmp/jpeg.ply" \
  >/dev/null
check_colours "$tmp/jpeg.ply" 0.2 0.01 1.5 4
echo "JPEG colour images: on the mesh"

# The colours go into the checkpoint: resumed on 3 ranks, the same mesh.
mpirun -np 2 "$bin" fuse --scans "$tmp/painted/truth.conf" --voxel 1 --checkpoint "$tmp/run.h5" \
  --out "$tmp/checkpointed.ply" >/dev/null
mpirun --oversubscribe -np 3 "$bin" fuse --resume "$tmp/run.h5" --out "$tmp/resumed.ply" >/dev/null
cmp "$tmp/mesh1.ply" "$tmp/checkpointed.ply" && cmp "$tmp/mesh1.ply" "$tmp/resumed.ply"
echo "checkpoint written on 2 ranks, resumed on 3: the same coloured mesh"

mpirun -np 2 "$bin" fuse --scans "$tmp/painted/truth.conf" --voxel 1 --colour none \
  --out "$tmp/none.ply" >/dev/null
mpirun -np 2 "$bin" fuse --scans "$tmp/plain/truth.conf" --voxel 1 --out "$tmp/plain.ply" \
  >/dev/null
cmp "$tmp/none.ply" "$tmp/plain.ply"
echo "--colour none: the bytes of the same scans without colour"

# Stations in a PTX file: r g b on the point lines when painted, else the intensity.
"$bin" scan --shape room --path stations --views 2 --width 360 --height 120 --voxel 0.05 \
  --texture 0.5 --format ptx --out "$tmp/ptx" >/dev/null
"$bin" scan --shape room --path stations --views 2 --width 360 --height 120 --voxel 0.05 \
  --format ptx --out "$tmp/grey" >/dev/null
for n in 2 3; do
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$tmp/ptx/stations.ptx" --voxel 0.05 \
    --out "$tmp/ptx$n.ply" >/dev/null
done
cmp "$tmp/ptx2.ply" "$tmp/ptx3.ply"
head -c 400 "$tmp/ptx2.ply" | grep -aq "property uchar red" || fail "PTX r g b did not reach the mesh"
mpirun -np 2 "$bin" fuse --scans "$tmp/grey/stations.ptx" --voxel 0.05 --out "$tmp/grey.ply" \
  >/dev/null
head -c 400 "$tmp/grey.ply" | grep -aq "property float intensity" ||
  fail "PTX intensity did not reach the mesh"
echo "PTX stations: r g b (2 and 3 ranks identical), or intensity, on the mesh"

expect_error() {  # expected message, then the command
  local want=$1
  shift
  if "$@" >"$tmp/err.log" 2>&1; then fail "accepted: $*"; fi
  grep -q -- "$want" "$tmp/err.log" || fail "expected '$want', got: $(cat "$tmp/err.log")"
}
expect_error "scan_000.ply: carries no colour" \
  mpirun -np 2 "$bin" fuse --scans "$tmp/plain/truth.conf" --voxel 1 --colour rgb \
  --out "$tmp/x.ply"
expect_error "needs --method prism or robust" \
  mpirun -np 2 "$bin" fuse --scans "$tmp/painted/truth.conf" --voxel 1 --colour rgb \
  --method consensus --out "$tmp/x.ply"
[[ ! -e $tmp/x.ply ]] || fail "a refused run left a mesh"
echo "colour asked of scans without it, or of another method: refused by name"

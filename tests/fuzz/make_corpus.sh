#!/usr/bin/env bash
# Seed corpus for the fuzz targets, from the real files in the repository and small synthetic
# scans in every encoding. Usage: make_corpus.sh RANGEFUSE_BINARY OUT_DIR
set -euo pipefail
tool=$1
out=$2
repo=$(cd "$(dirname "$0")/../.." && pwd)
data=$repo/tests/data/bunny
mkdir -p "$out"/{range_grid_ply,mesh_ply,conf,fuse_ini,checkpoint,ptx,e57,depth_png,depth_sequence,colour_image}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# A real Stanford header over a small body: keeps the seeds short, so the fuzzer stays fast.
crop_range_grid() {  # SCAN COLS ROWS
  awk -v c="$2" -v r="$3" '
    /^obj_info num_cols/ { print "obj_info num_cols " c; next }
    /^obj_info num_rows/ { print "obj_info num_rows " r; next }
    /^element vertex/ { print "element vertex " c * r; next }
    /^element range_grid/ { print "element range_grid " c * r; next }
    body == 0 { print }
    /^end_header/ { body = 1; n = 0; next }
    body == 1 && n < c * r { print; n++; next }
    body == 1 && n >= c * r { exit }' "$1"
  for ((i = 0; i < $2 * $3; i++)); do
    if ((i % 3 == 1)); then echo 0; else echo "1 $i"; fi
  done
}
crop_range_grid "$data/bun000.ply" 4 3 >"$out/range_grid_ply/bun000_crop.ply"
crop_range_grid "$data/top2.ply" 2 2 >"$out/range_grid_ply/top2_crop.ply"

for enc in ascii big-endian little-endian; do
  flag=--$enc
  [[ $enc == little-endian ]] && flag=
  "$tool" scan --shape sphere --views 2 --width 6 --height 5 --voxel 0.2 --patches 1 \
    --rot-deg 2 $flag --out "$tmp/$enc" >/dev/null
  cp "$tmp/$enc/scan_000.ply" "$out/range_grid_ply/sphere_$enc.ply"
done
cp "$tmp/ascii/perturbed.conf" "$out/conf/synthetic.conf"
cp "$tmp/ascii/patch_0.ply" "$out/mesh_ply/patch_binary.ply"

# The reference mesh's header over its first vertices and faces (indices kept in range).
awk '/^element vertex/ { print "element vertex 6"; next }
     /^element face/ { print "element face 2"; next }
     body == 0 { print }
     /^end_header/ { body = 1; next }
     body == 1 && v < 6 { print; v++; next }
     body == 1 { print "3 0 1 2"; print "4 2 3 4 5"; exit }' "$data/bun_zipper.ply" \
  >"$out/mesh_ply/bun_zipper_crop.ply"

cp "$data/bun.conf" "$out/conf/bun.conf"
printf '# comment\r\ncamera 0 0 0 0 0 0 1\r\nmesh a.ply 0 0 0 0 0 0 1\r\nbmesh b.ply 1 2 3 0 0 0 1\r\n' \
  >"$out/conf/crlf.conf"

cp "$repo"/jobs/*.ini "$out/fuse_ini/"
printf 'scans = a.conf\nvoxel = 0.5\nmethod = consensus\nquorum = 1.5\nregister = both\nmax-voxels = 1000\n' \
  >"$out/fuse_ini/consensus.ini"

# Sensor files: a two-station PTX, a depth frame, and sequence folders as the depth_sequence
# entry takes them (a layout byte, then the folder's text files separated by NULs; its two
# frames are named as a two-frame TUM sequence names them).
"$tool" scan --shape room --path stations --views 2 --width 8 --height 4 --voxel 0.5 \
  --format ptx --out "$tmp/ptx" >/dev/null
cp "$tmp/ptx/stations.ptx" "$out/ptx/two_stations.ptx"
# E57 as the e57 entry takes it: a byte (even: logical bytes, re-paged by the entry; odd: the
# file as it is), then the bytes.
"$tool" scan --shape room --path stations --views 2 --width 8 --height 4 --voxel 0.5 \
  --format e57 --out "$tmp/e57" >/dev/null
{ printf '\x01'; cat "$tmp/e57/stations.e57"; } >"$out/e57/two_stations_paged.e57"
python3 - "$tmp/e57/stations.e57" "$out/e57/two_stations_logical.e57" <<'PY'
import sys
data = open(sys.argv[1], "rb").read()
logical = b"".join(data[at:at + 1020] for at in range(0, len(data), 1024))
open(sys.argv[2], "wb").write(b"\x00" + logical)
PY
# Colour: PTX x y z i r g b lines, range grids with red green blue, a painted truth mesh, and
# colour images as the colour_image entry takes them (a byte picking JPEG or PNG, then the file).
"$tool" scan --shape room --path stations --views 2 --width 8 --height 4 --voxel 0.5 \
  --texture 1 --format ptx --out "$tmp/ptxc" >/dev/null
cp "$tmp/ptxc/stations.ptx" "$out/ptx/two_stations_rgb.ptx"
"$tool" scan --shape sphere --views 1 --width 6 --height 5 --voxel 0.2 --texture 0.5 --ascii \
  --out "$tmp/painted" >/dev/null
cp "$tmp/painted/scan_000.ply" "$out/range_grid_ply/sphere_rgb_ascii.ply"
"$tool" scan --shape sphere --path orbit --views 1 --width 4 --height 3 --voxel 0.2 \
  --texture 0.5 --format redwood --out "$tmp/colour" >/dev/null
{ printf '\x01'; cat "$tmp/colour/color/"*.png; } >"$out/colour_image/frame.png"
"$tool" scan --shape sphere --path orbit --views 1 --width 4 --height 3 --voxel 0.2 \
  --texture 0.5 --format redwood --jpeg --out "$tmp/jpeg" >/dev/null
{ printf '\x00'; cat "$tmp/jpeg/color/"*.jpg; } >"$out/colour_image/frame.jpg"
"$tool" scan --shape sphere --path orbit --views 2 --width 4 --height 3 --voxel 0.2 \
  --format tum --out "$tmp/tum" >/dev/null
"$tool" scan --shape sphere --path orbit --views 2 --width 4 --height 3 --voxel 0.2 \
  --format redwood --out "$tmp/redwood" >/dev/null
cp "$(find "$tmp/tum/depth" -name '*.png' | sort | head -1)" "$out/depth_png/frame.png"
{ printf '\x00'; cat "$tmp/tum/depth.txt"; printf '\x00'; cat "$tmp/tum/groundtruth.txt"
  printf '\x00'; cat "$tmp/tum/camera_intrinsic.json"; } >"$out/depth_sequence/tum"
{ printf '\x01'; cat "$tmp/redwood/trajectory.log"; printf '\x00'
  cat "$tmp/redwood/camera_intrinsic.json"; } >"$out/depth_sequence/redwood"

# Checkpoint seeds are choice bytes (see FuzzCheckpoint.cpp): flags first, then values.
printf '\x00\x00\x00\x40' >"$out/checkpoint/field"
printf '\x00\x00\x00\x00' >"$out/checkpoint/meta_only"
printf '\x00\x00\x00\x44\x01\x02\x03' >"$out/checkpoint/no_version"
printf '\x00\x00\x20\x40\x05\x01\x07' >"$out/checkpoint/wrong_cols"
echo "seed corpus in $out: $(find "$out" -type f | wc -l) files"

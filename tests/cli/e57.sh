#!/usr/bin/env bash
# E57 stations end to end: the same stations written as PTX and as E57 fuse to the same mesh
# bytes, on 1, 2 and 3 ranks, whole or read in bands; a .conf naming FILE.e57#K reads back
# what --poses-out wrote; a damaged page stops every rank with the page named.
set -euo pipefail
bin=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

for format in ptx e57; do
  "$bin" scan --shape room --path stations --views 3 --width 360 --height 160 --voxel 0.05 \
    --noise 0.3 --format "$format" --out "$tmp/$format" >/dev/null
done
fuse() {  # RANKS SCANS OUT [OPTIONS...]
  local n=$1 scans=$2 out=$3
  shift 3
  mpirun --oversubscribe -np "$n" "$bin" fuse --scans "$scans" --voxel 0.05 --out "$out" "$@" \
    >"$out.log"
}
fuse 2 "$tmp/ptx/stations.ptx" "$tmp/ptx.ply"
for n in 1 2 3; do
  fuse "$n" "$tmp/e57/stations.e57" "$tmp/e57-$n.ply"
  cmp "$tmp/ptx.ply" "$tmp/e57-$n.ply" || fail "E57 on $n ranks differs from PTX"
done
echo "stations: E57 on 1, 2 and 3 ranks gives the PTX mesh's bytes"

# Bands: each station of 57600 cells read in bands of at most 20000.
fuse 2 "$tmp/ptx/stations.ptx" "$tmp/ptx-bands.ply" --band-cells 20000
fuse 3 "$tmp/e57/stations.e57" "$tmp/e57-bands.ply" --band-cells 20000
cmp "$tmp/ptx-bands.ply" "$tmp/e57-bands.ply" || fail "E57 bands differ from PTX bands"
# Bands take their rules from a sample of columns, so their mesh is the whole station's to
# rounding, not to the bit: every sample within a voxel, Chamfer under a hundredth of one.
"$bin" eval --mesh "$tmp/e57-bands.ply" --reference "$tmp/ptx.ply" --voxel 0.05 >"$tmp/bands.eval"
grep -q "F-score 1.0000" "$tmp/bands.eval" && grep -qE "^chamfer .*\(0\.00[0-9] voxels\)" "$tmp/bands.eval" ||
  fail "bands against the whole station: $(cat "$tmp/bands.eval")"
echo "bands: E57 read in bands gives the PTX bands' mesh, the whole station's within 0.01 voxel"

# The same stations without row and column indices: projected on an angular grid (with a
# warning a station), the mesh of the structured stations within a voxel nearly everywhere.
"$bin" scan --shape room --path stations --views 3 --width 360 --height 160 --voxel 0.05 \
  --noise 0.3 --format e57 --e57-loose --e57-coordinates single --out "$tmp/loose" >/dev/null
fuse 2 "$tmp/loose/stations.e57" "$tmp/loose.ply" 2>"$tmp/loose.err"
[[ $(grep -c "no row and column indices; gridded by spherical projection" "$tmp/loose.err") -eq 3 ]] ||
  fail "loose stations: $(cat "$tmp/loose.err")"
"$bin" eval --mesh "$tmp/loose.ply" --reference "$tmp/ptx.ply" --voxel 0.05 >"$tmp/loose.eval"
python3 - "$tmp/loose.eval" <<'PY' || fail "loose stations: $(cat "$tmp/loose.eval")"
import re, sys
f = float(re.search(r"F-score ([0-9.]+)", open(sys.argv[1]).read()).group(1))
sys.exit(f < 0.98)
PY
echo "stations without indices: $(grep F-score "$tmp/loose.eval")"

# A .conf naming the file's scans, and --poses-out writing that form.
fuse 2 "$tmp/e57/truth.conf" "$tmp/conf.ply" --poses-out "$tmp/poses.conf"
cmp "$tmp/ptx.ply" "$tmp/conf.ply" || fail "truth.conf naming stations.e57#K differs"
grep -q "stations.e57#2" "$tmp/poses.conf" || fail "poses.conf: $(cat "$tmp/poses.conf")"
fuse 2 "$tmp/poses.conf" "$tmp/again.ply"
cmp "$tmp/ptx.ply" "$tmp/again.ply" || fail "the written poses read back differently"
echo "a .conf naming FILE.e57#K: the same mesh; --poses-out writes and reads back that form"

# A damaged page: every rank stops within seconds, one message naming the page.
python3 - "$tmp/e57/stations.e57" "$tmp/damaged.e57" <<'PY'
import sys
data = bytearray(open(sys.argv[1], "rb").read())
data[3 * 1024 + 100] ^= 0x01
open(sys.argv[2], "wb").write(data)
PY
if timeout 60 mpirun -np 2 "$bin" fuse --scans "$tmp/damaged.e57" --voxel 0.05 \
  --out "$tmp/damaged.ply" 2>"$tmp/damaged.err"; then fail "a damaged page was read"; fi
[[ $(grep -c "rangefuse: error" "$tmp/damaged.err") -eq 1 ]] || fail "$(cat "$tmp/damaged.err")"
grep -q "damaged.e57: page 3 (bytes 3072-4095): checksum mismatch" "$tmp/damaged.err" ||
  fail "$(cat "$tmp/damaged.err")"
[[ ! -e $tmp/damaged.ply ]] || fail "output left behind"
echo "a damaged page: $(grep error "$tmp/damaged.err")"

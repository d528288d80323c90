#!/usr/bin/env bash
# Every bad input: non-zero exit on all ranks within the time limit, one message naming the
# file, and no output under the final name.
set -uo pipefail
bin=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0

header() {  # $1 = format, $2 = vertex count
  printf 'ply\nformat %s 1.0\nobj_info num_cols 2\nobj_info num_rows 2\nelement vertex %s\n' "$1" "$2"
  printf 'property float x\nproperty float y\nproperty float z\n'
  printf 'element range_grid 4\nproperty list uchar int vertex_indices\nend_header\n'
}
body='0 0 1\n1 0 1\n0 1 1\n1 0\n1 1\n0\n1 2\n'

make_case() {  # $1 = name, $2 = scan file content (printf format)
  mkdir -p "$tmp/$1"
  printf "$2" >"$tmp/$1/scan.ply"
  printf 'bmesh scan.ply 0 0 0 0 0 0 1\n' >"$tmp/$1/scans.conf"
}

# expect NAME EXPECTED-TEXT-IN-MESSAGE [fuse options...]
expect() {
  local name=$1 text=$2
  shift 2
  run_case "$name" "$text" fuse --out "$tmp/$name.out.ply" "$@"
}

# run_case NAME EXPECTED-TEXT COMMAND [options...]: the output checked is $tmp/NAME.out.*
run_case() {
  local name=$1 text=$2
  shift 2
  local out="$tmp/$name.out.ply"
  [[ $1 == scan ]] && out="$tmp/$name.out.dir"
  [[ $1 == render ]] && out="$tmp/$name.out.png"
  timeout 60 mpirun -np 2 "$bin" "$@" >"$tmp/$name.stdout" 2>"$tmp/$name.stderr"
  local rc=$?
  local errors
  errors=$(grep -c 'rangefuse: error' "$tmp/$name.stderr")
  if [[ $rc -eq 0 || $rc -eq 124 ]]; then
    echo "FAIL $name: exit code $rc"; failures=$((failures + 1))
  elif [[ $errors -ne 1 ]] || ! grep 'rangefuse: error' "$tmp/$name.stderr" | grep -q -- "$text"; then
    echo "FAIL $name: expected one error mentioning '$text', got:"; cat "$tmp/$name.stderr"
    failures=$((failures + 1))
  elif [[ -e $out || -e $out.tmp ]]; then
    echo "FAIL $name: output file left behind"; failures=$((failures + 1))
  else
    echo "ok   $name: $(grep 'rangefuse: error' "$tmp/$name.stderr")"
  fi
}

make_case truncated "$(header ascii 3)\n0 0 1\n1 0 1\n0 1 1\n1 0\n"
expect truncated "truncated" --scans "$tmp/truncated/scans.conf" --voxel 0.1
# Leica PTX: a scan cut short, a point line with two numbers, a .conf naming a missing scan.
ptx_header='2\n2\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n'
printf "${ptx_header}0 0 1 1\n1 0 1 1\n0 1 1 1\n" >"$tmp/short.ptx"
expect ptx_short "short.ptx:11: scan 1 has fewer than 4 point lines" --scans "$tmp/short.ptx" --voxel 0.1
printf "${ptx_header}0 0 1 1\n1 0 1 1\n0 1\n1 1 1 1\n" >"$tmp/line.ptx"
expect ptx_line "line.ptx:13: expected 'x y z intensity" --scans "$tmp/line.ptx" --voxel 0.1
printf "${ptx_header}0 0 1 1\n1 0 1 1\n0 1 1 1\n1 1 1 1\n" >"$tmp/one.ptx"
printf 'bmesh one.ptx#2 0 0 0 0 0 0 1\n' >"$tmp/ptx2.conf"
expect ptx_index "holds only 1 scans" --scans "$tmp/ptx2.conf" --voxel 0.1
# Depth-image sequences: a missing frame, timestamps out of order, a corrupt PNG, counts that
# disagree, a camera missing (each found on one rank or the other, never a hang).
"$bin" scan --shape sphere --views 3 --width 40 --height 30 --voxel 1 --scale 0.01 --path orbit \
  --format tum --out "$tmp/tum" >/dev/null
cp -r "$tmp/tum" "$tmp/tum_missing" && rm "$tmp/tum_missing/depth/1000.033333.png"
expect tum_missing "depth.txt: line 4: depth/1000.033333.png does not exist" \
  --scans "$tmp/tum_missing" --voxel 0.01
cp -r "$tmp/tum" "$tmp/tum_order" && sed -i 's/^1000.066667 /999.5 /' "$tmp/tum_order/depth.txt"
expect tum_order "depth.txt: line 5: timestamps out of order" --scans "$tmp/tum_order" --voxel 0.01
cp -r "$tmp/tum" "$tmp/tum_png" && head -c 100 "$tmp/tum/depth/1000.066667.png" \
  >"$tmp/tum_png/depth/1000.066667.png"
expect tum_png "1000.066667.png: corrupt or truncated PNG" --scans "$tmp/tum_png" --voxel 0.01
cp -r "$tmp/tum" "$tmp/tum_camera" && rm "$tmp/tum_camera/camera_intrinsic.json"
expect tum_camera "no camera intrinsics" --scans "$tmp/tum_camera" --voxel 0.01
expect tum_intrinsics "--intrinsics: 'a,b' is not fx,fy,cx,cy" --scans "$tmp/tum" --voxel 0.01 \
  --intrinsics a,b
"$bin" scan --shape sphere --views 3 --width 40 --height 30 --voxel 1 --scale 0.01 --path orbit \
  --format redwood --out "$tmp/rw" >/dev/null
rm "$tmp/rw/depth/000002.png"
expect redwood_count "trajectory.log: 3 poses but" --scans "$tmp/rw" --voxel 0.01
make_case extra "$(header ascii 3)\n${body}1 1\n"
expect extra "do not match" --scans "$tmp/extra/scans.conf" --voxel 0.1
make_case format "$(header binary_middle_endian 3)\n$body"
expect format "unknown format" --scans "$tmp/format/scans.conf" --voxel 0.1
make_case nan "$(header ascii 3)\n0 0 1\nnan 0 1\n0 1 1\n1 0\n1 1\n0\n1 2\n"
expect nan "NaN" --scans "$tmp/nan/scans.conf" --voxel 0.1
make_case range "$(header ascii 3)\n0 0 1\n1 0 1\n0 1 1\n1 0\n1 1\n0\n1 9\n"
expect range "out of range" --scans "$tmp/range/scans.conf" --voxel 0.1
make_case count "$(header ascii 4)\n$body"
expect count "scan.ply" --scans "$tmp/count/scans.conf" --voxel 0.1
mkdir -p "$tmp/missing" && printf 'bmesh gone.ply 0 0 0 0 0 0 1\n' >"$tmp/missing/scans.conf"
expect missing "gone.ply: cannot open" --scans "$tmp/missing/scans.conf" --voxel 0.1
printf 'bmesh scan.ply 0 0 0 0 0 0\n' >"$tmp/truncated/short.conf"
expect conf-line "short.conf: line 1" --scans "$tmp/truncated/short.conf" --voxel 0.1
expect no-conf "nothing.conf: cannot open" --scans "$tmp/nothing.conf" --voxel 0.1
expect voxel "--voxel" --scans "$tmp/extra/scans.conf" --voxel -1
expect option "unrecognised option" --scans "$tmp/extra/scans.conf" --voxel 1 --frobnicate 3

# Memory bounds: refused before allocating, naming the limit and the option that raises it.
make_case huge-grid "$(header ascii 3 | sed 's/num_cols 2/num_cols 1000000/; s/num_rows 2/num_rows 1000000/')\n$body"
expect huge-grid "scan.ply: grid num_cols x num_rows = 1e+12 exceeds the limit 100000000 (raise it with --max-grid-cells)" \
  --scans "$tmp/huge-grid/scans.conf" --voxel 0.1
make_case huge-count "$(header ascii 3000000000)\n$body"
expect huge-count "scan.ply: element 'vertex' count 3e+09 exceeds the limit 200000000 (raise it with --max-elements)" \
  --scans "$tmp/huge-count/scans.conf" --voxel 0.1
"$bin" scan --shape sphere --views 2 --width 16 --height 12 --voxel 0.1 --out "$tmp/sphere" >/dev/null
expect huge-field "exceeds the limit 1000 (raise it with --max-voxels)" \
  --scans "$tmp/sphere/truth.conf" --voxel 0.1 --max-voxels 1000
run_case scan-grid "exceeds the limit 100000000 (raise it with --max-grid-cells)" scan --shape sphere \
  --voxel 1 --width 1000000 --height 1000000 --out "$tmp/scan-grid.out.dir"
run_case eval-samples "--samples 1e+12 exceeds the limit 200000000 (raise it with --max-elements)" \
  eval --mesh a.ply --reference b.ply --voxel 1 --samples 1000000000000

# Bad output paths are refused before any scan is read: no "read" line with good scans, and
# with missing scans the message is about the output.
run_case out-folder "$tmp/no/such/mesh.ply: cannot write the mesh there: folder '$tmp/no/such' does not exist" \
  fuse --scans "$tmp/sphere/truth.conf" --voxel 0.1 --out "$tmp/no/such/mesh.ply"
grep -q '\] read ' "$tmp/out-folder.stdout" && { echo "FAIL out-folder: scans were read"; failures=$((failures + 1)); }
run_case out-checkpoint "ck.h5: cannot write the checkpoint there" fuse --scans "$tmp/missing/scans.conf" \
  --voxel 0.1 --out "$tmp/out-checkpoint.out.ply" --checkpoint "$tmp/no/ck.h5"
run_case out-is-folder "cannot write the report there: it is a folder" fuse --scans "$tmp/missing/scans.conf" \
  --voxel 0.1 --out "$tmp/out-is-folder.out.ply" --report "$tmp"
run_case out-twice "(the mesh) and the preview" fuse --scans "$tmp/missing/scans.conf" \
  --voxel 0.1 --out "$tmp/out-twice.out.ply" --preview "$tmp/out-twice.out.ply"

run_case scan-mesh "nothing.ply: cannot open" scan --mesh "$tmp/nothing.ply" --voxel 1 --out "$tmp/scan-mesh.out.dir"
run_case scan-views "--views" scan --shape sphere --views 0 --voxel 1 --out "$tmp/scan-views.out.dir"
run_case scan-noise "--noise" scan --shape sphere --noise -1 --voxel 1 --out "$tmp/scan-noise.out.dir"
run_case scan-shape "--shape" scan --shape cube --voxel 1 --out "$tmp/scan-shape.out.dir"
# Depth frames whose depths overflow 16-bit PNG counts, or whose depth steps are coarser than a
# quarter voxel: refused before a folder is made, with the scale that fits.
run_case scan-tum-overflow "16-bit PNGs hold 13.107 .*--scale 0.01) and the voxel with it (--voxel 0.01)" \
  scan --shape sphere --views 2 --width 40 --height 30 --voxel 1 --format tum \
  --out "$tmp/scan-tum-overflow.out.dir"
run_case scan-depth-steps "under four of its depth steps" scan --shape sphere --views 2 \
  --width 40 --height 30 --voxel 0.001 --scale 0.001 --format redwood \
  --out "$tmp/scan-depth-steps.out.dir"
run_case eval-missing "gone.ply: cannot open" eval --mesh "$tmp/gone.ply" --reference "$tmp/gone.ply" --voxel 1
run_case eval-mix "either --mesh" eval --mesh a.ply --poses b.conf --voxel 1
run_case render-slice "--slice" render --scans "$tmp/nothing.conf" --voxel 1 --slice w=3 --out "$tmp/render-slice.out.png"
run_case render-scans "nothing.conf: cannot open" render --scans "$tmp/nothing.conf" --voxel 1 --out "$tmp/render-scans.out.png"

# Unit slips: a missing voxel says it is missing; a voxel in the wrong units names the likely one.
bunny=$(dirname "$0")/../data/bunny/bun.conf
expect voxel-missing "--voxel is required: the voxel size in the scans' units" --scans "$bunny"
expect voxel-tiny "--max-voxels" --scans "$bunny" --voxel 1e-6
grep -q "warning: --voxel 1e-06 gives .* did you mean 0.001?" "$tmp/voxel-tiny.stderr" ||
  { echo "FAIL voxel-tiny: no unit-slip warning"; cat "$tmp/voxel-tiny.stderr"; failures=$((failures + 1)); }
if mpirun -np 2 "$bin" fuse --scans "$bunny" --voxel 1 --out "$tmp/slip.ply" >/dev/null 2>"$tmp/slip.stderr" &&
  grep -q "warning: --voxel 1 gives 0.15.* voxels across the scans, .* did you mean 0.001?" "$tmp/slip.stderr"; then
  echo "ok   voxel-slip: $(grep warning "$tmp/slip.stderr")"
else
  echo "FAIL voxel-slip: no unit-slip warning"; cat "$tmp/slip.stderr"; failures=$((failures + 1))
fi
# E57: a file cut short, a damaged page, a .conf naming a scan the file does not hold.
"$bin" scan --shape room --path stations --views 2 --width 60 --height 30 --voxel 0.2 \
  --format e57 --out "$tmp/e57" >/dev/null
head -c -100 "$tmp/e57/stations.e57" >"$tmp/cut.e57"
expect e57-cut "cut.e57: .* not a whole number of 1024-byte E57 pages" --scans "$tmp/cut.e57" \
  --voxel 0.2
python3 -c "
import sys
b = bytearray(open(sys.argv[1], 'rb').read()); b[1024 + 9] ^= 4
open(sys.argv[2], 'wb').write(b)" "$tmp/e57/stations.e57" "$tmp/crc.e57"
expect e57-crc "crc.e57: page 1 (bytes 1024-2047): checksum mismatch" --scans "$tmp/crc.e57" \
  --voxel 0.2
printf 'bmesh stations.e57#3 0 0 0 0 0 0 1\n' >"$tmp/e57/three.conf"
expect e57-missing-scan "stations.e57 holds only 2 scans" --scans "$tmp/e57/three.conf" \
  --voxel 0.2

# Inputs given to the wrong option: recognised by their content, the message says what --scans
# or --config expects.
expect scans-ply "bun000.ply: is a PLY file, not a scan list: --scans takes a scan list" \
  --scans "$(dirname "$bunny")/bun000.ply" --voxel 0.001
expect scans-folder "holds $(dirname "$bunny")/bun.conf: give --scans one of those" \
  --scans "$(dirname "$bunny")" --voxel 0.001
# An E57 file under another name is read as E57, by its signature.
printf 'ASTM-E57\0\0\0\0\0\0\0\0' >"$tmp/station.dat"
expect scans-e57 "station.dat: 16 bytes is not a whole number of 1024-byte E57 pages" \
  --scans "$tmp/station.dat" --voxel 0.001
expect config-conf "bun.conf: the options configuration file contains an invalid line" --config "$bunny"
grep -q "a scan list goes to --scans" "$tmp/config-conf.stderr" ||
  { echo "FAIL config-conf: no hint"; failures=$((failures + 1)); }

[[ $failures -eq 0 ]] && echo "all bad-input cases passed" || { echo "$failures case(s) failed"; exit 1; }

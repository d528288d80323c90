#!/usr/bin/env bash
# Speed on dense scans: one rank, compute by stage (read / field / mesh) and the cost
# of a voxel update, beside Open3D 0.16's ScalableTSDFVolume on the same scans in the same run
# (depth conversion / integrate / extract; its Python loading left out), with the Chamfer
# distance of both meshes to bun_zipper.ply. Sets: the bunny mesh re-scanned, 24 x 320x240 at
# 1 mm and 48 x 1024x1024 at 0.5 mm (kept in the cache folder), and the real bunny at 0.5 mm
# (its Cyberware grids have no pinhole: open3d_tsdf.py sees each from a far pinhole).
# Usage: bash jobs/benchmark_speed.sh [EXTRA FUSE OPTIONS...]   e.g. --merge-cells 0, --threads 1
# (rangefuse runs as one process without mpirun, so it may use every core, as Open3D does).
# Each tool runs twice on each set and its faster run is kept: on a virtual machine a process's
# first touch of memory the guest has not used lately costs far more than on one it has (the
# real bunny's field: 0.74 s cold, 0.41 s warm), and which tool ran first would get the cost.
# Environment: CACHE (default /tmp/rangefuse-bench); EXTRA_SETS="PATH:VOXEL ..." adds sets, each
# a folder `rangefuse scan` wrote or a Stanford .conf, fused at VOXEL (scan sets the benchmark
# does not hold, e.g. `rangefuse scan --mesh tests/data/bunny/bun_zipper.ply --views 16 --width
# 640 --height 480 --voxel 0.001 --noise 0.5 --out /tmp/s16`, then EXTRA_SETS=/tmp/s16:0.001).
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
bin=$PWD/build/rangefuse
reference=tests/data/bunny/bun_zipper.ply
cache=${CACHE:-/tmp/rangefuse-bench}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# make_set VIEWS WIDTH HEIGHT VOXEL NOISE: the scan folder (made once).
make_set() {
  local dir=$cache/bunny-$1x$2x$3-n$5
  [[ $1 == 48 && $2 == 1024 ]] && dir=$cache/bunny-48x1024  # benchmark_memory.sh's set
  if [[ ! -f $dir/truth.conf ]]; then
    $bin scan --mesh "$reference" --views "$1" --width "$2" --height "$3" --voxel "$4" \
      --noise "$5" --out "$dir" >/dev/null
  fi
  echo "$dir"
}
# stage REPORT NAME: a stage's seconds from a run report (the log rounds to 10 ms);
# stage REPORT wall: the whole run's.
stage() {
  python3 -c 'import json, sys
r = json.load(open(sys.argv[1]))
print(r["wall_seconds"] if sys.argv[2] == "wall" else r["per_rank"][0]["stage_seconds"][sys.argv[2]])' "$1" "$2"
}
# faster_open3d SET VOXEL: the line of the faster of two Open3D runs (by its compute seconds).
faster_open3d() {
  local a b
  a=$(/usr/bin/python3 jobs/open3d_tsdf.py "$1" "$2" "$tmp/o3d.ply")
  b=$(/usr/bin/python3 jobs/open3d_tsdf.py "$1" "$2" "$tmp/o3d.ply")
  awk -v a="$a" -v b="$b" 'BEGIN {
    ca = a; sub(/.*compute /, "", ca); cb = b; sub(/.*compute /, "", cb)
    print (cb + 0 < ca + 0) ? b : a }'
}
chamfer() { $bin eval --mesh "$1" --reference "$reference" --voxel "$2" | awk '/^chamfer/ { print substr($3, 2) }'; }

echo "| input | triangles | rangefuse read / field / mesh (s) | read to write (s) | ns a voxel update | peak MiB | Chamfer (voxel) | Open3D depth conversion / integrate / extract (s) | Open3D peak MiB | Open3D Chamfer | (field + mesh) / (integrate + extract) | read to write / Open3D compute |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
# run NAME CONF VOXEL [SET_DIR]
run() {
  local name=$1 conf=$2 voxel=$3 set=${4:-} log=$tmp/log rep=$tmp/report.json again=$tmp/report2.json
  $bin fuse --scans "$conf" --voxel "$voxel" --out "$tmp/ours.ply" --report "$rep" "${extra[@]}" >"$log"
  $bin fuse --scans "$conf" --voxel "$voxel" --out "$tmp/ours.ply" --report "$again" \
    "${extra[@]}" >"$log.2"
  if awk -v a="$(stage "$again" wall)" -v b="$(stage "$rep" wall)" 'BEGIN { exit !(a < b) }'; then
    mv "$log.2" "$log"
    mv "$again" "$rep"
  fi
  local r f m tri updates ns total peak
  r=$(stage "$rep" read) f=$(stage "$rep" field) m=$(stage "$rep" mesh)
  tri=$(grep "] read " "$log" | sed 's/.*scans, \([0-9]*\) triangles.*/\1/')
  updates=$(grep "] field " "$log" | grep -v "scans added" | sed 's/.*voxels updated per rank \([0-9]*\).*/\1/')
  ns=$(awk -v f="$f" -v u="$updates" 'BEGIN { printf "%.0f", 1e9 * f / u }')
  total=$(stage "$rep" wall)
  peak=$(grep "] done " "$log" | sed 's/.*(MiB) \([0-9]*\).*/\1/')
  local o3d="—" o3dc="—" o3dm="—" ratio="—" whole="—"
  if [[ -n $set ]] && /usr/bin/python3 -c "import open3d" 2>/dev/null; then
    local line
    line=$(faster_open3d "$set" "$voxel")
    local c i e
    c=$(echo "$line" | sed 's/.*depth conversion \([0-9.]*\) s.*/\1/')
    i=$(echo "$line" | sed 's/.*integrate \([0-9.]*\) s.*/\1/')
    e=$(echo "$line" | sed 's/.*extract \([0-9.]*\) s.*/\1/')
    o3dm=$(echo "$line" | sed 's/.*peak memory \([0-9]*\) MiB.*/\1/')
    o3d="$c / $i / $e" o3dc=$(chamfer "$tmp/o3d.ply" "$voxel")
    ratio=$(awk -v a="$f" -v b="$m" -v c="$i" -v d="$e" 'BEGIN { printf "%.2f", (a + b) / (c + d) }')
    whole=$(awk -v t="$total" -v a="$c" -v b="$i" -v d="$e" 'BEGIN { printf "%.2f", t / (a + b + d) }')
  fi
  r=$(printf %.3f "$r") f=$(printf %.3f "$f") m=$(printf %.3f "$m") total=$(printf %.2f "$total")
  echo "| $name | $tri | $r / $f / $m | $total | $ns | $peak | $(chamfer "$tmp/ours.ply" "$voxel") | $o3d | $o3dm | $o3dc | $ratio | $whole |"
}
extra=("$@")
s24=$(make_set 24 320 240 0.001 0.5)
run "synthetic bunny, 24 x 320x240, 1 mm" "$s24/truth.conf" 0.001 "$s24"
run "real bunny, 10 scans, 0.5 mm" tests/data/bunny/bun.conf 0.0005 tests/data/bunny/bun.conf
s48=$(make_set 48 1024 1024 0.0005 0.3)
run "bunny re-scanned, 48 x 1024x1024, 0.5 mm" "$s48/truth.conf" 0.0005 "$s48"
# Sets of the caller's: a folder `rangefuse scan` wrote (its truth.conf) or a Stanford .conf.
for entry in ${EXTRA_SETS:-}; do
  set_path=${entry%:*} set_voxel=${entry##*:}
  set_conf=$set_path
  [[ -d $set_path ]] && set_conf=$set_path/truth.conf
  run "$(basename "$set_path"), $set_voxel" "$set_conf" "$set_voxel" "$set_path"
done

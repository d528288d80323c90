#!/usr/bin/env bash
# Closing holes: `fuse --fill-holes` beside Open3D's screened Poisson reconstruction
# (create_from_point_cloud_poisson, depth 9, untrimmed and with the lowest 5 % density trimmed),
# in the same run, on the real bunny (10 scans, 1 mm) and a synthetic sphere six views saw
# (radius 50, voxel 1). Per mesh: open edges (0: closed), faces, the share of the area farther
# than 3 voxels from every input point (invented), the share rangefuse marks filled, accuracy
# against the reference (eval: Chamfer, F at 1 voxel, spurious area beyond 3 voxels) and seconds.
# Usage: bash jobs/benchmark_fill.sh [OUT_DIR]  (default /tmp/rangefuse-fill)
set -euo pipefail
cd "$(dirname "$0")/.."
source jobs/mpi_env.sh
out=${1:-/tmp/rangefuse-fill}
mkdir -p "$out"
R=build/rangefuse
PY=/usr/bin/python3
"$R" scan --shape sphere --views 6 --width 160 --height 120 --voxel 1 --out "$out/sphere" >/dev/null
"$R" eval --help >/dev/null
row() {  # NAME METHOD MESH SET VOXEL REFERENCE SECONDS
  local closure acc
  closure=$($PY jobs/mesh_closure.py "$3" "$4" "$5")
  acc=$("$R" eval --mesh "$3" --reference "$6" --voxel "$5" 2>&1 |
    awk '/^chamfer/ {c=$3; gsub(/[(]/, "", c)} /F-score/ {f=$NF} /spurious/ {s=$NF} END {print c, f, s}')
  echo "| $1 | $2 | $closure | $acc | $7 |"
}
timed() {  # seconds of a command, its output discarded
  local t0 t1
  t0=$(date +%s.%N)
  "$@" >/dev/null 2>&1
  t1=$(date +%s.%N)
  echo "$t1 - $t0" | bc
}
echo "| set | mesh | closure | Chamfer (voxels), F, spurious | seconds |"
echo "|---|---|---|---|---|"
for set in bunny sphere; do
  if [ $set = bunny ]; then
    scans=tests/data/bunny/bun.conf voxel=0.001 ref=tests/data/bunny/bun_zipper.ply
  else
    scans=$out/sphere/truth.conf voxel=1 ref=$out/sphere/truth.ply
  fi
  poissonSet=$scans
  [ $set = sphere ] && poissonSet=$out/sphere
  s=$(timed mpirun -np 2 "$R" fuse --scans "$scans" --voxel $voxel --out "$out/$set-open.ply")
  row $set "rangefuse prism, 2 ranks" "$out/$set-open.ply" "$scans" $voxel "$ref" "$s"
  s=$(timed mpirun -np 2 "$R" fuse --scans "$scans" --voxel $voxel --fill-holes \
    --out "$out/$set-filled.ply")
  row $set "rangefuse prism --fill-holes, 2 ranks" "$out/$set-filled.ply" "$scans" $voxel "$ref" "$s"
  for trim in 0 0.05; do
    s=$(timed $PY jobs/open3d_poisson.py "$poissonSet" "$out/$set-poisson-$trim.ply" 9 $trim)
    row $set "Open3D Poisson depth 9, trim $trim" "$out/$set-poisson-$trim.ply" "$scans" $voxel \
      "$ref" "$s"
  done
done

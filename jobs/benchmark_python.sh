#!/usr/bin/env bash
# The Python module's cost over the command on the same inputs, read to mesh, in one process
# and on 2 ranks (mpirun, mpi4py): the real bunny at 1 mm, and a depth sequence (the bunny
# scaled to 1.5 m, filmed along an orbit by a 640x480 camera, 1 cm), read into numpy arrays and
# added (arrays) or added by their list (add_scans: the library reads the files, each rank its
# share). Each run N times (default 5), alternating, and the fastest kept; prints seconds and
# the module's ratios to the command.
# Usage: bash jobs/benchmark_python.sh [RUNS [FRAMES]]  (default 5 100)
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
runs=${1:-5} frames=${2:-100}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/rangefuse
export PYTHONPATH=$PWD/build/python
build/rangefuse scan --mesh tests/data/bunny/bun_zipper.ply --scale 10 --views "$frames" \
  --width 640 --height 480 --voxel 0.01 --noise 0.5 --depth-noise --outliers 0.005 --path orbit \
  --format tum --out "$tmp/seq" >/dev/null

cat >"$tmp/conf.py" <<'PY'
import os, sys, rangefuse
from concurrent.futures import ThreadPoolExecutor
comm = None
if sys.argv[3] == "mpi":
    from mpi4py import MPI
    comm = MPI.COMM_WORLD
fusion = rangefuse.Fusion(voxel=float(sys.argv[2]), comm=comm)
scans = rangefuse.read_conf(sys.argv[1])
with ThreadPoolExecutor(os.cpu_count()) as pool:  # the readers release the GIL
    for (path, pose), (points, colours) in zip(scans, pool.map(rangefuse.read_grid, [s[0] for s in scans])):
        fusion.add_grid(points, pose, colours=colours)
vertices, faces, colours = fusion.mesh()
PY
cat >"$tmp/frames.py" <<'PY'
import os, sys, rangefuse
from concurrent.futures import ThreadPoolExecutor
comm = None
if sys.argv[3] == "mpi":
    from mpi4py import MPI
    comm = MPI.COMM_WORLD
fusion = rangefuse.Fusion(voxel=float(sys.argv[2]), comm=comm)
frames = rangefuse.read_frames(sys.argv[1])
with ThreadPoolExecutor(os.cpu_count()) as pool:  # the readers release the GIL
    for (_, _, K, scale, pose, _), depth in zip(frames, pool.map(rangefuse.read_depth, [f[0] for f in frames])):
        fusion.add_depth(depth, K, pose, depth_scale=scale)
vertices, faces, colours = fusion.mesh()
PY

# The same inputs added by their list: each rank reads only its share of the files.
cat >"$tmp/list.py" <<'PY'
import sys, rangefuse
comm = None
if sys.argv[3] == "mpi":
    from mpi4py import MPI
    comm = MPI.COMM_WORLD
fusion = rangefuse.Fusion(voxel=float(sys.argv[2]), comm=comm)
fusion.add_scans(sys.argv[1])
vertices, faces, colours = fusion.mesh()
PY

seconds() {  # COMMAND... -> wall seconds
  local start end
  start=$(date +%s.%N)
  "$@" >/dev/null
  end=$(date +%s.%N)
  echo "$end - $start" | bc
}
fastest() { sort -g | head -1; }

row() {  # LABEL RANKS SCANS VOXEL SCRIPT
  local label=$1 ranks=$2 scans=$3 voxel=$4 script=$5 c=() p=() l=() i
  local launch=() mode=alone
  if ((ranks > 1)); then launch=(mpirun -np "$ranks"); mode=mpi; fi
  for ((i = 0; i < runs; i++)); do
    c+=("$(seconds "${launch[@]}" $bin fuse --scans "$scans" --voxel "$voxel" --out "$tmp/c.ply" --quiet)")
    p+=("$(seconds "${launch[@]}" /usr/bin/python3 "$script" "$scans" "$voxel" "$mode")")
    l+=("$(seconds "${launch[@]}" /usr/bin/python3 "$tmp/list.py" "$scans" "$voxel" "$mode")")
  done
  local cs ps ls
  cs=$(printf '%s\n' "${c[@]}" | fastest)
  ps=$(printf '%s\n' "${p[@]}" | fastest)
  ls=$(printf '%s\n' "${l[@]}" | fastest)
  printf '| %s | %d | %.2f | %.2f | %.3f | %.2f | %.3f | %.3f |\n' "$label" "$ranks" "$cs" \
    "$ps" "$(echo "$ps / $cs" | bc -l)" "$ls" "$(echo "$ls / $cs" | bc -l)" \
    "$(echo "($ls - $start) / $cs" | bc -l)"
}

# What any Python program pays before it calls the module: the interpreter and numpy.
start=$(for ((i = 0; i < runs; i++)); do seconds /usr/bin/python3 -c "import numpy"; done | fastest)
echo "Python and numpy start in $start s (fastest of $runs)."
echo
echo "| input | ranks | command (s) | arrays (s) | arrays / command | add_scans (s) | add_scans / command | less Python's start |"
echo "|---|---|---|---|---|---|---|---|"
row "real bunny, 10 scans, 1 mm" 1 tests/data/bunny/bun.conf 0.001 "$tmp/conf.py"
row "real bunny, 10 scans, 1 mm" 2 tests/data/bunny/bun.conf 0.001 "$tmp/conf.py"
row "bunny orbit, $frames frames 640x480, 1 cm" 1 "$tmp/seq" 0.01 "$tmp/frames.py"
row "bunny orbit, $frames frames 640x480, 1 cm" 2 "$tmp/seq" 0.01 "$tmp/frames.py"

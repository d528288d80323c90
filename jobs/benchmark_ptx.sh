#!/usr/bin/env bash
# PTX reading speed (issue 18): writes a synthetic station (a full turn of COLS x ROWS points
# on a room-sized sphere, ASCII as Leica exports it), then times `rangefuse perturb`, which
# indexes the file and reads every scan's grid (nothing else of note), and `rangefuse fuse`'s
# read stage on one rank. Usage: bash jobs/benchmark_ptx.sh [COLS ROWS]  (default 3000 1500)
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cols=${1:-3000}
rows=${2:-1500}
/usr/bin/python3 - "$tmp/station.ptx" "$cols" "$rows" <<'PY'
import sys
import numpy as np
path, cols, rows = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
az = 2 * np.pi * np.arange(cols) / cols
el = np.pi * (np.arange(rows) + 0.5) / rows - np.pi / 2
A, E = np.meshgrid(az, el, indexing="ij")  # column-major: all rows of a column together
r = 5 + 0.002 * np.sin(7 * A) * np.cos(5 * E)
pts = np.stack([r * np.cos(E) * np.cos(A), r * np.cos(E) * np.sin(A), r * np.sin(E),
                np.full(A.shape, 0.5)], axis=-1).reshape(-1, 4)
with open(path, "w") as f:
    f.write(f"{cols}\n{rows}\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n")
    np.savetxt(f, pts, fmt="%.6f")
PY
bytes=$(stat -c %s "$tmp/station.ptx")
start=$(date +%s.%N)
build/rangefuse perturb --scans "$tmp/station.ptx" --voxel 0.01 --rot-deg 0 --trans-vox 0 \
  --out "$tmp/p.conf" >/dev/null
seconds=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }')
echo "PTX $((cols * rows)) points, $(awk -v b="$bytes" 'BEGIN { printf "%.0f", b / 1e6 }') MB:" \
  "index and read $seconds s, $(awk -v b="$bytes" -v s="$seconds" 'BEGIN { printf "%.0f", b / 1e6 / s }') MB/s (perturb)"
mpirun -np 1 build/rangefuse fuse --scans "$tmp/station.ptx" --voxel 0.01 --out "$tmp/m.ply" |
  grep -E "\] (read|write) "

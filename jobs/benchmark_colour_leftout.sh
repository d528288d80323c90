#!/usr/bin/env bash
# Colour judged against frames left out of the fusion, rangefuse beside Open3D 0.16's RGB8
# ScalableTSDFVolume: every EVERY-th frame of a TUM RGB-D folder with poses is left out, both
# fuse the rest (rangefuse prism on 2 ranks at the given poses, Open3D with truncation 4
# voxels), and jobs/colour_leftout.py projects each mesh's vertices into every left-out frame's
# colour image where that frame's depth saw them, and compares colours, overall and at the
# image's edges. Works on real recordings in TUM layout (with camera_intrinsic.json); without
# a folder, on a synthetic Kinect room (seed 11, 100 frames of 640 x 480, checks of 0.237 m,
# colour misregistered with depth by a pixel), the development set.
# Usage: bash jobs/benchmark_colour_leftout.sh [TUM_FOLDER [VOXEL [EVERY]]]
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
voxel=${2:-0.01} every=${3:-10}
tmp=$(mktemp -d -p "${TMPDIR:-/tmp}")
trap 'rm -rf "$tmp"' EXIT
root=$PWD
bin=$root/build/rangefuse
seq=${1:-}
if [[ -z $seq ]]; then
  seq=$tmp/room
  "$bin" scan --shape room --path walk --views 100 --width 640 --height 480 --voxel 0.01 \
    --sensor kinect --sensor-without shutter,offset --seed 11 --texture 0.237 \
    --colour-shift 1 --format tum --out "$seq" >/dev/null
  echo "synthetic Kinect room, seed 11, 100 frames, colour shifted by a pixel"
fi
/usr/bin/python3 jobs/colour_leftout.py split "$seq" "$every" "$tmp/fused"
mpirun -np 2 "$bin" fuse --scans "$tmp/fused" --voxel "$voxel" --track off --colour rgb \
  --out "$tmp/rangefuse.ply" >/dev/null
/usr/bin/python3 jobs/open3d_sequence.py "$tmp/fused" "$voxel" "$tmp/open3d.ply" 4 rgb >/dev/null
(cd "$tmp" && /usr/bin/python3 "$root/jobs/colour_leftout.py" judge "$seq" "$voxel" "$every" \
  rangefuse.ply open3d.ply)

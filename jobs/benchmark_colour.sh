#!/usr/bin/env bash
# Colour beside Open3D 0.16's RGB8 ScalableTSDFVolume: the bunny scaled to 1.5 m and
# painted with checks (sides not a multiple of the voxel, so no edge lies on the lattice),
# filmed along one orbit by a 640x480 depth camera with colour images (depth noise 0.5 voxel,
# 0.5 % outliers), as a TUM folder. Both read the same PNG frames, colour images and poses.
# rangefuse runs on 2 ranks with colour (prism and robust) and without (--colour none), Open3D
# with RGB8 and without colour. Then a room scanned from painted PTX stations, which Open3D's
# pinhole volume cannot take: rangefuse alone, with and without colour. `rangefuse eval`
# measures colour error at the mesh vertices against the painted truth (mean absolute
# difference per channel, of 255) and edge contrast (the colour step kept across check edges, 1
# as sharp as the truth). Each run is made twice and the faster kept. The cost of colour is
# then measured apart, as the median over five pairs of runs with and without colour made one
# after the other (drift in the machine's speed between two separate series is larger than
# the effect).
# Usage: bash jobs/benchmark_colour.sh [FRAMES VOXEL CHECK]  (default 200 0.01 0.0973)
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
frames=${1:-200} voxel=${2:-0.01} check=${3:-0.0973}
tmp=$(mktemp -d -p "${TMPDIR:-/tmp}")
trap 'rm -rf "$tmp"' EXIT
bin=build/rangefuse
seq=$tmp/seq
$bin scan --mesh tests/data/bunny/bun_zipper.ply --scale 10 --views "$frames" --width 640 \
  --height 480 --voxel "$voxel" --noise 0.5 --depth-noise --outliers 0.005 --path orbit \
  --texture "$check" --format tum --out "$seq" >/dev/null
echo "$frames frames 640x480 with colour images, voxel $voxel, checks of $check"

quality() {  # mesh truth voxel -> "Chamfer | colour mean | p90 | edge contrast"
  $bin eval --mesh "$1" --reference "$2" --voxel "$3" --json | /usr/bin/python3 -c '
import json, sys
j, v = json.load(sys.stdin), float(sys.argv[1])
c = j["colour"]
if c is None:
    print("%.3f | | | " % (j["chamfer"] / v))
else:
    print("%.3f | %.2f | %.2f | %.3f" % (j["chamfer"] / v, c["error"]["mean"], c["error"]["p90"],
                                          c["edge_contrast"]))
' "$3"
}

# Runs fuse twice on 2 ranks; prints "seconds | field seconds | peak MiB" of the faster run.
fuse_row() {  # name, then fuse arguments
  local name=$1 best=
  shift
  for run in 1 2; do
    local start took
    start=$(date +%s.%N)
    mpirun -np 2 --bind-to none $bin fuse "$@" --out "$tmp/$name.ply" >"$tmp/$name.log.$run"
    took=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }')
    if [[ -z $best ]] || awk -v a="$took" -v b="$best" 'BEGIN { exit !(a < b) }'; then
      best=$took
      mv "$tmp/$name.log.$run" "$tmp/$name.log"
    fi
  done
  local field memory
  field=$(grep "\] field " "$tmp/$name.log" | sed 's/.*(\([0-9.]*\)s)$/\1/')
  memory=$(grep "peak memory per rank" "$tmp/$name.log" | sed 's/.*(MiB) \([0-9 /]*\) (.*/\1/')
  echo "$best | $field | $memory"
}

# Median over 5 alternating pairs of (field s, peak MiB of the larger rank) with colour / without.
colour_cost() {  # fuse arguments (without --colour)
  for pair in 1 2 3 4 5; do
    for colour in auto none; do
      mpirun -np 2 --bind-to none $bin fuse "$@" --colour $colour --out "$tmp/cost.ply" \
        >"$tmp/cost-$colour.log"
    done
    for colour in auto none; do
      field=$(grep "\] field " "$tmp/cost-$colour.log" | sed 's/.*(\([0-9.]*\)s)$/\1/')
      memory=$(grep "peak memory per rank" "$tmp/cost-$colour.log" |
        sed 's/.*(MiB) \([0-9 /]*\) (.*/\1/' | tr '/' '\n' | sort -n | tail -1)
      echo -n "$field $memory "
    done
    echo
  done | awk '{ printf "%.2f %.2f\n", $1 / $3, $2 / $4 }' >"$tmp/ratios"
  # Debian's awk (mawk) has no sort: the third of five sorted ratios is the median.
  echo "field time $(cut -d' ' -f1 "$tmp/ratios" | sort -n | sed -n 3p)x," \
    "peak memory $(cut -d' ' -f2 "$tmp/ratios" | sort -n | sed -n 3p)x (median of 5 pairs)"
}

echo
echo "| sequence | seconds read to mesh | field (s) | peak MiB | Chamfer (voxel) | colour error mean (of 255) | p90 | edge contrast |"
echo "|---|---|---|---|---|---|---|---|"
for method in prism robust; do
  for colour in auto none; do
    [[ $method == robust && $colour == none ]] && continue
    row=$(fuse_row "$method-$colour" --scans "$seq" --voxel "$voxel" --method $method \
      --colour $colour)
    echo "| rangefuse $method, colour $colour, 2 ranks | $row | $(quality "$tmp/$method-$colour.ply" "$seq/truth.ply" "$voxel") |"
  done
done
for colour in rgb none; do
  best= line=
  for run in 1 2; do
    out=$(/usr/bin/python3 jobs/open3d_sequence.py "$seq" "$voxel" "$tmp/o3d-$colour.ply" 4 \
      $colour 2>/dev/null)
    total=$(echo "$out" | sed 's/.*total \([0-9.]*\) s.*/\1/')
    if [[ -z $best ]] || awk -v a="$total" -v b="$best" 'BEGIN { exit !(a < b) }'; then
      best=$total line=$out
    fi
  done
  integrate=$(echo "$line" | sed 's/.*integrate \([0-9.]*\) s.*/\1/')
  memory=$(echo "$line" | sed 's/.*peak memory \([0-9]*\) MiB.*/\1/')
  name=$([[ $colour == rgb ]] && echo "RGB8" || echo "no colour")
  echo "| Open3D ScalableTSDFVolume $name, 1 process | $best | $integrate | $memory | $(quality "$tmp/o3d-$colour.ply" "$seq/truth.ply" "$voxel") |"
done
echo
echo "rangefuse prism with colour against without: $(colour_cost --scans "$seq" --voxel "$voxel")"

# Stations: a room 12 m across from 3 painted tripods, 2000 x 1000 points a turn.
room=$tmp/room
svoxel=$(awk -v v="$voxel" 'BEGIN { print 2 * v }')
$bin scan --shape room --path stations --views 3 --width 2000 --height 1000 --voxel "$svoxel" \
  --noise 0.3 --texture "$(awk -v c="$check" 'BEGIN { print 3 * c }')" --format ptx \
  --out "$room" --max-grid-cells 100000000 >/dev/null
echo
echo "| stations (3 x 2000 x 1000, PTX r g b, voxel $svoxel) | seconds read to mesh | field (s) | peak MiB | Chamfer (voxel) | colour error mean (of 255) | p90 | edge contrast |"
echo "|---|---|---|---|---|---|---|---|"
for colour in auto none; do
  row=$(fuse_row "room-$colour" --scans "$room/stations.ptx" --voxel "$svoxel" --colour $colour)
  echo "| rangefuse prism, colour $colour, 2 ranks | $row | $(quality "$tmp/room-$colour.ply" "$room/truth.ply" "$svoxel") |"
done
echo
echo "rangefuse prism with colour against without: $(colour_cost --scans "$room/stations.ptx" --voxel "$svoxel")"

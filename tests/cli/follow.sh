#!/usr/bin/env bash
# --follow: a depth stream tracked while its folder is still being written (frames copied in
# one by one, as a recorder would), ended by a STOP file or by --follow-timeout, gives the same
# trajectory and mesh bytes as the finished folder read afterwards on another rank count; an
# empty folder ends with a message once the timeout passes.
set -euo pipefail
bin=$1 data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" scan --mesh "$data/bunny/bun_zipper.ply" --scale 10 --views 240 --width 160 --height 120 \
  --voxel 0.01 --path handheld --noise 0.5 --depth-noise --format tum --out "$tmp/truth" >/dev/null
frames=($(grep -v '^#' "$tmp/truth/depth.txt" | cut -d' ' -f2))

record() {  # record FOLDER N: the first N frames written into FOLDER in the recorder layout
  local k
  for ((k = 0; k < $2; k++)); do
    cp "$tmp/truth/${frames[k]}" "$1/depth/.part.png"
    mv "$1/depth/.part.png" "$1/depth/$(printf %06d "$k").png"
    sleep 0.02
  done
}
follow_and_compare() {  # follow_and_compare NAME N HOW: HOW is stop or timeout
  local dir=$tmp/$1
  mkdir -p "$dir/depth"
  cp "$tmp/truth/camera_intrinsic.json" "$dir/"
  mpirun -np 2 "$bin" fuse --scans "$dir" --follow --follow-timeout 3 --depth-scale 5000 \
    --voxel 0.01 --out "$tmp/$1.ply" --trajectory-out "$tmp/$1.txt" >"$tmp/$1.log" &
  local run=$!
  record "$dir" "$2"
  [[ $3 == stop ]] && touch "$dir/STOP"
  wait "$run" || fail "$1: $(tail -3 "$tmp/$1.log")"
  grep -q "$2 of $2 frames tracked" "$tmp/$1.log" || fail "$1: $(grep 'track  ' "$tmp/$1.log")"
  rm -f "$dir/STOP"
  mpirun --oversubscribe -np 3 "$bin" fuse --scans "$dir" --depth-scale 5000 --voxel 0.01 \
    --out "$tmp/$1.after.ply" --trajectory-out "$tmp/$1.after.txt" >/dev/null
  cmp "$tmp/$1.ply" "$tmp/$1.after.ply" && cmp "$tmp/$1.txt" "$tmp/$1.after.txt" ||
    fail "$1: the followed stream differs from the finished folder"
  echo "followed while recorded ($2 frames, ended by $3): identical to the finished folder"
}
follow_and_compare stopped 120 stop
follow_and_compare timed 60 timeout

mkdir -p "$tmp/empty/depth"
cp "$tmp/truth/camera_intrinsic.json" "$tmp/empty/"
if mpirun -np 2 "$bin" fuse --scans "$tmp/empty" --follow --follow-timeout 1 --voxel 0.01 \
  --out "$tmp/x.ply" >"$tmp/empty.log" 2>&1; then
  fail "an empty followed folder gave a mesh"
fi
grep -q "empty: --follow: no frames appeared within --follow-timeout" "$tmp/empty.log" ||
  fail "$(cat "$tmp/empty.log")"
echo "empty folder: refused once the timeout passed"

#!/usr/bin/env bash
# No run overwrites what it reads: every output aliasing an input (scan list, a scan it names,
# a sequence's frames, the checkpoint resumed, the options file) or another output is refused
# before any work, naming both files, with the input byte for byte as it was; an existing
# checkpoint is replaced only with --overwrite; outputs are written in the format their name
# says or refused.
set -euo pipefail
bin=$1
data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# refused NAME FILE_KEPT TEXT... -- COMMAND...: the command exits non-zero, its message holds
# every TEXT, and FILE_KEPT is byte-identical afterwards.
refused() {
  local name=$1 kept=$2 texts=() before
  shift 2
  while [[ $1 != -- ]]; do texts+=("$1"); shift; done
  shift
  before=$(sha256sum "$kept" | cut -d' ' -f1)
  if "$@" >"$tmp/out.txt" 2>&1; then fail "$name: ran ($(tail -2 "$tmp/out.txt"))"; fi
  for t in "${texts[@]}"; do
    grep -qF -- "$t" "$tmp/out.txt" || fail "$name: message lacks '$t': $(cat "$tmp/out.txt")"
  done
  [[ $(sha256sum "$kept" | cut -d' ' -f1) == "$before" ]] || fail "$name: $kept changed"
  echo "ok   $name"
}

cp -r "$data/bunny" "$tmp/b"
fuse=(mpirun -np 2 "$bin" fuse --quiet)
bunny=("${fuse[@]}" --voxel 0.004)
"${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m.ply" --checkpoint "$tmp/c.h5"

# Outputs over inputs.
refused "--out over the checkpoint resumed" "$tmp/c.h5" "$tmp/c.h5" "checkpoint resumed" -- \
  "${bunny[@]}" --resume "$tmp/c.h5" --out "$tmp/c.h5"
refused "mesh --out over its checkpoint" "$tmp/c.h5" "$tmp/c.h5" "would overwrite" -- \
  mpirun -np 2 "$bin" mesh "$tmp/c.h5" --out "$tmp/./c.h5"
refused "--report over the scan list" "$tmp/b/bun.conf" "would overwrite '$tmp/b/bun.conf' (the scan list)" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m2.ply" --report "$tmp/b/bun.conf"
refused "--out over a raw scan" "$tmp/b/bun000.ply" "$tmp/b/bun000.ply" "scan list's file" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/b/bun000.ply"
ln -s "$tmp/b/bun045.ply" "$tmp/link.ply"
refused "--out through a symbolic link to a scan" "$tmp/b/bun045.ply" "$tmp/link.ply" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/link.ply"
ln "$tmp/b/bun090.ply" "$tmp/hard.ply"
refused "--poses-out over a hard link to a scan" "$tmp/b/bun090.ply" "$tmp/hard.ply" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m2.ply" --poses-out "$tmp/hard.ply"
mkdir -p "$tmp/d"
refused "--checkpoint over the XDMF mesh's data" "$tmp/c.h5" "given as both" "(the mesh data)" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/d/x.xdmf" --checkpoint "$tmp/d/../d/x.h5"
printf 'scans = %s\n' "$tmp/b/bun.conf" >"$tmp/run.ini"
refused "--report over the options file" "$tmp/run.ini" "options file" -- \
  "${bunny[@]}" --config "$tmp/run.ini" --out "$tmp/m2.ply" --report "$tmp/run.ini"
refused "perturb over its own list" "$tmp/b/bun.conf" "would overwrite" -- \
  "$bin" perturb --scans "$tmp/b/bun.conf" --voxel 0.001 --out "$tmp/b/bun.conf"
refused "render over the list" "$tmp/b/bun.conf" "would overwrite" -- \
  "$bin" render --scans "$tmp/b/bun.conf" --voxel 0.004 --out "$tmp/b/../b/bun.conf"
refused "eval --json-out over the reference" "$tmp/b/bun_zipper.ply" "(the reference)" -- \
  "$bin" eval --mesh "$tmp/m.ply" --reference "$tmp/b/bun_zipper.ply" --voxel 0.004 \
  --json-out "$tmp/b/./bun_zipper.ply"
cp "$tmp/b/bun_zipper.ply" "$tmp/d/truth.ply"
refused "scan --mesh inside --out" "$tmp/d/truth.ply" "inside --out" -- \
  "$bin" scan --mesh "$tmp/d/truth.ply" --voxel 0.004 --views 2 --out "$tmp/d"

# A depth sequence's frames, and a followed folder.
"$bin" scan --mesh "$data/bunny/bun_zipper.ply" --scale 10 --views 40 --width 80 --height 60 \
  --voxel 0.02 --path handheld --format redwood --out "$tmp/seq" >/dev/null
refused "--trajectory-out over the sequence's trajectory" "$tmp/seq/trajectory.log" "scan list's file" -- \
  "${fuse[@]}" --scans "$tmp/seq" --voxel 0.02 --out "$tmp/s.ply" --trajectory-out "$tmp/seq/trajectory.log"
refused "--preview inside a followed folder" "$tmp/seq/trajectory.log" "inside" "followed folder" -- \
  "${fuse[@]}" --scans "$tmp/seq" --voxel 0.02 --track on --follow --follow-timeout 1 \
  --out "$tmp/s.ply" --preview "$tmp/seq/depth/p.png"

# A checkpoint: resumed in place (updated by renames), else replaced only with --overwrite.
refused "an existing --checkpoint not resumed" "$tmp/c.h5" "exists" "--resume $tmp/c.h5" "--overwrite" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m2.ply" --checkpoint "$tmp/c.h5"
"${bunny[@]}" --resume "$tmp/c.h5" --checkpoint "$tmp/c.h5" --out "$tmp/m3.ply"
cmp -s "$tmp/m.ply" "$tmp/m3.ply" || fail "resumed in place: a different mesh"
"$bin" info "$tmp/c.h5" >/dev/null || fail "resumed in place: the checkpoint is no longer one"
"${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/m4.ply" --checkpoint "$tmp/c.h5" --overwrite
cmp -s "$tmp/m.ply" "$tmp/m4.ply" || fail "--overwrite: a different mesh"
echo "ok   a checkpoint resumed in place, and replaced with --overwrite"

# Formats by name.
refused "--out .obj" "$tmp/c.h5" "t.obj: the mesh is written as .ply or .xdmf" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/t.obj"
refused "--preview .jpg" "$tmp/c.h5" "the preview is written as .png" -- \
  "${bunny[@]}" --scans "$tmp/b/bun.conf" --out "$tmp/t.ply" --preview "$tmp/t.jpg"
refused "render --out .jpg" "$tmp/c.h5" "the picture is written as .png" -- \
  "$bin" render --checkpoint "$tmp/c.h5" --out "$tmp/t.jpg"
refused "mesh --out .obj" "$tmp/c.h5" "is written as .ply or .xdmf" -- \
  "$bin" mesh "$tmp/c.h5" --out "$tmp/t.obj"
[[ ! -e $tmp/t.obj && ! -e $tmp/t.jpg ]] || fail "a refused format was written"
mpirun -np 2 "$bin" mesh "$tmp/c.h5" --out "$tmp/x.xdmf" >/dev/null
head -c 5 "$tmp/x.xdmf" | grep -q '<?xml' || fail "mesh --out .xdmf is not XDMF"
[[ $(head -c 4 "$tmp/x.h5" | od -An -c | tr -d ' ') == '211HDF' ]] || fail "mesh --out .xdmf: no HDF5 data"
echo "ok   mesh --out .xdmf writes XDMF with its HDF5 data"
echo "all overwrite and format checks passed"

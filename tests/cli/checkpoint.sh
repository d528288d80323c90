#!/usr/bin/env bash
# Checkpoints: resume and mesh on another rank count give the same mesh byte for byte; a
# half-written temporary never shadows a good checkpoint; every bad file fails cleanly.
set -uo pipefail
bin=$1 data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

conf="$data/bunny/bun.conf"
mpirun -np 2 "$bin" fuse --scans "$conf" --voxel 0.002 --out "$tmp/direct.ply" \
  --checkpoint "$tmp/run.h5" >/dev/null || fail "fuse with --checkpoint"
mpirun -np 1 "$bin" fuse --scans "$conf" --voxel 0.002 --out "$tmp/one.ply" \
  --checkpoint "$tmp/one.h5" >/dev/null || fail "fuse on 1 rank"
mpirun -np 1 "$bin" fuse --resume "$tmp/run.h5" --out "$tmp/resumed1.ply" >/dev/null || fail "resume on 1 rank"
mpirun -np 2 "$bin" fuse --resume "$tmp/one.h5" --out "$tmp/resumed2.ply" >/dev/null || fail "resume on 2 ranks"
mpirun -np 3 "$bin" mesh "$tmp/run.h5" --out "$tmp/mesh3.ply" >/dev/null || fail "mesh on 3 ranks"
for f in one resumed1 resumed2 mesh3; do
  cmp -s "$tmp/direct.ply" "$tmp/$f.ply" && echo "ok   $f.ply identical to the uninterrupted mesh" || fail "$f.ply differs"
done
mpirun -np 3 "$bin" render --checkpoint "$tmp/run.h5" --width 64 --height 48 --out "$tmp/r.png" >/dev/null \
  && [[ $(head -c 8 "$tmp/r.png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] \
  && echo "ok   render from the checkpoint on 3 ranks wrote a PNG" || fail "render --checkpoint"
"$bin" info "$tmp/run.h5" | grep -q '^progress: *finished field' && echo "ok   info says the field is finished" || fail "info"

# A temporary left by a killed writer does not shadow the checkpoint.
head -c 1000 "$tmp/run.h5" >"$tmp/run.h5.tmp"
mpirun -np 1 "$bin" mesh "$tmp/run.h5" --out "$tmp/again.ply" >/dev/null && cmp -s "$tmp/again.ply" "$tmp/direct.ply" \
  && echo "ok   half-written run.h5.tmp ignored" || fail "temporary shadowed the checkpoint"

# bad CASE EXPECTED-TEXT COMMAND...: non-zero exit within 60 s and one error naming the cause.
bad() {
  local name=$1 text=$2
  shift 2
  timeout 60 mpirun -np 2 "$bin" "$@" >"$tmp/$name.out" 2>"$tmp/$name.err"
  local rc=$?
  if [[ $rc -eq 0 || $rc -eq 124 ]]; then fail "$name: exit code $rc"; return; fi
  local errors
  errors=$(grep -c 'rangefuse: error' "$tmp/$name.err")
  if [[ $errors -ne 1 ]] || ! grep 'rangefuse: error' "$tmp/$name.err" | grep -q -- "$text"; then
    fail "$name: expected one error mentioning '$text'"; cat "$tmp/$name.err"; return
  fi
  echo "ok   $name: $(grep 'rangefuse: error' "$tmp/$name.err")"
}
head -c 5000 "$tmp/run.h5" >"$tmp/truncated.h5"
bad truncated "truncated" mesh "$tmp/truncated.h5" --out "$tmp/x.ply"
printf 'not hdf5 at all\n' >"$tmp/garbage.h5"
bad garbage "not an HDF5 file" info "$tmp/garbage.h5"
cp "$tmp/run.h5" "$tmp/corrupt.h5"
printf '\xde\xad\xbe\xef%.0s' $(seq 1 4000) | dd of="$tmp/corrupt.h5" bs=1 seek=2000 conv=notrunc status=none
bad corrupt "damaged: the metadata" mesh "$tmp/corrupt.h5" --out "$tmp/x.ply"
bad missing "cannot open checkpoint" fuse --resume "$tmp/none.h5" --out "$tmp/x.ply"
bad params "--voxel" fuse --resume "$tmp/run.h5" --voxel 0.003 --out "$tmp/x.ply"
mkdir -p "$tmp/changed" && cp "$data"/bunny/*.ply "$data/bunny/bun.conf" "$tmp/changed/" && rm "$tmp/changed/bun_zipper.ply"
mpirun -np 2 "$bin" fuse --scans "$tmp/changed/bun.conf" --voxel 0.002 --out "$tmp/c.ply" --checkpoint "$tmp/changed.h5" >/dev/null
echo "comment touched" >>"$tmp/changed/top2.ply"
bad hash "top2.ply" fuse --resume "$tmp/changed.h5" --out "$tmp/x.ply"
rm "$tmp/changed/chin.ply"
bad input-gone "chin.ply" fuse --resume "$tmp/changed.h5" --out "$tmp/x.ply"
[[ -e "$tmp/x.ply" ]] && fail "an output was written by a failed run"

[[ $failures -eq 0 ]] && echo "all checkpoint cases passed" || { echo "$failures case(s) failed"; exit 1; }

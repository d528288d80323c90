#!/usr/bin/env bash
# Storage faults on 2 ranks: a full file system ends the run on every rank with one message
# (no hang), leaves no temporary file or lock, and a failed checkpoint write leaves the previous
# checkpoint as it was and resumable. Needs root to mount small tmpfs file systems; exits 77
# (skipped) where that is not allowed. The bunny at 2 mm gives a checkpoint of about 6 MB and a
# mesh of about 1 MB: "small" holds neither, "big" holds one checkpoint but not two (a write
# keeps the previous checkpoint until the new one is complete). A run takes seconds in release
# but over a minute under the sanitizers beside other tests, so a hang is a run past 180 s.
set -uo pipefail
bin=$1 data=$2
tmp=$(mktemp -d)
small=$tmp/small big=$tmp/big
mkdir -p "$small" "$big"
cleanup() {
  umount "$small" 2>/dev/null
  umount "$big" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
if ! mount -t tmpfs -o size=512k tmpfs "$small" 2>/dev/null ||
  ! mount -t tmpfs -o size=10m tmpfs "$big" 2>/dev/null; then
  echo "skipped: cannot mount tmpfs here (needs root)"
  exit 77
fi
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
run() {  # run NAME fuse-options...: 2 ranks, 180 s limit; sets rc, leaves NAME.stderr
  local name=$1
  shift
  timeout 180 mpirun -np 2 "$bin" fuse --scans "$data/bun.conf" --voxel 0.002 "$@" \
    >"$tmp/$name.stdout" 2>"$tmp/$name.stderr"
  rc=$?
}
no_leftovers() {  # no_leftovers FOLDER: no temporary or lock files
  local left
  left=$(ls -A "$1" | grep -E '\.tmp' || true)
  [[ -z $left ]] || fail "$2: left behind: $left"
}

# A checkpoint on a full file system: exit 1 on every rank, the cause and the sizes named.
run ck-full --out "$tmp/a.ply" --checkpoint "$small/ck.h5"
[[ $rc -eq 1 ]] || fail "ck-full: exit code $rc (124 = hung)"
grep -q "ck.h5: checkpoint not written: .*MiB are free there" "$tmp/ck-full.stderr" ||
  { fail "ck-full: message"; cat "$tmp/ck-full.stderr"; }
[[ ! -e $small/ck.h5 ]] || fail "ck-full: a checkpoint under the final name"
no_leftovers "$small" ck-full
[[ ! -e $tmp/a.ply ]] || fail "ck-full: a mesh was written after the failed checkpoint"

# The mesh on a full file system: exit 1, no partial file.
run mesh-full --out "$small/mesh.ply"
[[ $rc -eq 1 ]] || fail "mesh-full: exit code $rc"
grep -q "mesh.ply: short write" "$tmp/mesh-full.stderr" || { fail "mesh-full: message"; cat "$tmp/mesh-full.stderr"; }
[[ ! -e $small/mesh.ply ]] || fail "mesh-full: partial mesh under the final name"
no_leftovers "$small" mesh-full

# The last good checkpoint survives a failed write and resumes to the same mesh.
run good --out "$tmp/good.ply" --checkpoint "$big/ck.h5"
[[ $rc -eq 0 ]] || { fail "good: exit code $rc"; cat "$tmp/good.stderr"; }
before=$(md5sum <"$big/ck.h5")
run again --out "$tmp/again.ply" --checkpoint "$big/ck.h5" # no room for a second copy
[[ $rc -eq 1 ]] || fail "again: exit code $rc (the file system should have been full)"
[[ $(md5sum <"$big/ck.h5") == "$before" ]] || fail "again: the previous checkpoint changed"
no_leftovers "$big" again
run resume --out "$tmp/resumed.ply" --resume "$big/ck.h5"
[[ $rc -eq 0 ]] || { fail "resume: exit code $rc"; cat "$tmp/resume.stderr"; }
cmp -s "$tmp/good.ply" "$tmp/resumed.ply" || fail "resume: the mesh differs from the run that wrote the checkpoint"

[[ $failures -eq 0 ]] && echo "all storage-fault cases passed" || { echo "$failures case(s) failed"; exit 1; }

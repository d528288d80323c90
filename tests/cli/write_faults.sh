#!/usr/bin/env bash
# A failed write of each output (checkpoint, mesh, preview, poses, report), injected with
# RANGEFUSE_FAULT=write:throw@RANK#N on 1, 2 and 3 ranks, on rank 0 and on the last rank for
# the outputs every rank writes: a non-zero exit on every rank (no hang), one message, no
# temporary or lock file, nothing under the failed output's name, and the previous checkpoint
# unchanged and resumable into the same mesh.
set -uo pipefail
bin=$1 data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

# fuse RANKS DIR [options]: every output into DIR
fuse() {
  local n=$1 dir=$2
  shift 2
  mkdir -p "$dir"
  timeout 60 mpirun -np "$n" "$bin" fuse --scans "$data/bun.conf" --voxel 0.002 --out "$dir/mesh.ply" \
    --preview "$dir/preview.png" --poses-out "$dir/poses.conf" --report "$dir/report.json" "$@" \
    >"$dir/stdout" 2>"$dir/stderr"
}

# The order of writes on a rank: 5 checkpoint datasets (meta, codes, work, sums, digests), the
# mesh, then on rank 0 the preview, the poses and the report.
declare -A nth=([checkpoint]=4 [mesh]=6 [preview]=7 [poses]=8 [report]=9)
declare -A file=([checkpoint]=ck.h5 [mesh]=mesh.ply [preview]=preview.png [poses]=poses.conf
  [report]=report.json)

for n in 1 2 3; do
  good=$tmp/good$n
  fuse "$n" "$good" --checkpoint "$good/ck.h5" || fail "$n ranks: the fault-free run failed"
  for writer in checkpoint mesh preview poses report; do
    ranks=(0)
    [[ $writer == checkpoint || $writer == mesh ]] && ((n > 1)) && ranks+=($((n - 1)))
    for r in "${ranks[@]}"; do
      case=$tmp/$writer-$n-$r
      mkdir -p "$case"
      cp "$good/ck.h5" "$case/ck.h5"  # the previous checkpoint
      RANGEFUSE_FAULT="write:throw@$r#${nth[$writer]}" fuse "$n" "$case" --checkpoint "$case/ck.h5" \
        --overwrite
      rc=$?
      name="$writer failing on rank $r of $n"
      [[ $rc -ne 0 && $rc -ne 124 ]] || fail "$name: exit code $rc (124 = hung)"
      [[ $(grep -c 'rangefuse: error' "$case/stderr") -eq 1 ]] &&
        grep 'rangefuse: error' "$case/stderr" | grep -q 'injected fault' ||
        { fail "$name: expected one error naming the fault"; cat "$case/stderr"; }
      left=$(ls -A "$case" | grep -E '\.tmp' || true)
      [[ -z $left ]] || fail "$name: left behind: $left"
      [[ $writer == checkpoint || ! -e $case/${file[$writer]} ]] || fail "$name: ${file[$writer]} exists"
      [[ $writer != checkpoint ]] || cmp -s "$good/ck.h5" "$case/ck.h5" ||
        fail "$name: the previous checkpoint changed"
    done
  done
  # The checkpoint that survived a failed write resumes into the same mesh.
  resumed=$tmp/resumed$n
  mkdir -p "$resumed"
  timeout 60 mpirun -np "$n" "$bin" fuse --resume "$tmp/checkpoint-$n-0/ck.h5" --out "$resumed/mesh.ply" \
    >/dev/null 2>"$resumed/stderr" || { fail "$n ranks: resume failed"; cat "$resumed/stderr"; }
  cmp -s "$good/mesh.ply" "$resumed/mesh.ply" || fail "$n ranks: the resumed mesh differs"
done

# The XDMF mesh: a failed write of any of its datasets (geometry, topology, normals), on the
# first or the last rank, leaves neither the .xdmf nor the .h5 nor a temporary.
for n in 2; do
  for nth in 1 2 3; do
    for r in 0 $((n - 1)); do
      case=$tmp/xdmf-$n-$nth-$r
      mkdir -p "$case"
      RANGEFUSE_FAULT="write:throw@$r#$nth" timeout 60 mpirun -np "$n" "$bin" fuse \
        --scans "$data/bun.conf" --voxel 0.002 --out "$case/mesh.xdmf" >/dev/null 2>"$case/stderr"
      code=$?
      name="xdmf write $nth on rank $r of $n"
      ((code != 0 && code != 124)) || fail "$name: exit $code"
      [[ $(grep -c "rangefuse: error:" "$case/stderr") -eq 1 ]] || fail "$name: not one message"
      [[ -z $(ls "$case" | grep -v stderr) ]] || fail "$name: left $(ls "$case" | grep -v stderr)"
    done
  done
done

[[ $failures -eq 0 ]] && echo "all write-fault cases passed" || { echo "$failures case(s) failed"; exit 1; }

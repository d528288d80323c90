#!/usr/bin/env bash
# Injected faults on one of two ranks (RANGEFUSE_FAULT, see parallel/FaultInjection.h): the
# whole job must stop with a non-zero exit, the rank's message and no output, and the other
# rank must not hang. The bound (30 s from the fault) only tells a hang from a stop; the
# measured time from the fault to the end of mpirun is printed. A run may take minutes to reach
# a late fault under the sanitizers on a busy machine, so the outer timeout is generous.
set -uo pipefail
tool=$1
data=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

check_fault() {  # FAULT EXPECTED_MESSAGE [FUSE OPTIONS...]
  local out=$work/out.ply log=$work/log fault=$1 message=$2
  shift 2
  rm -f "$out"
  RANGEFUSE_FAULT=$fault timeout 300 mpirun -np 2 "$tool" fuse --scans "$data/bun.conf" \
    --voxel 0.002 --out "$out" "$@" >"$log" 2>&1
  local rc=$? end
  end=$(date +%s.%N)
  local start
  start=$(grep -o 'injecting fault .* at [0-9.]*' "$log" | grep -o '[0-9.]*$')
  local stop
  stop=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }')
  if ((rc == 0 || rc == 124)) || [[ -z $start ]] || ! grep -q "$message" "$log" ||
    [[ -e $out ]] || awk -v s="$stop" 'BEGIN { exit !(s > 30) }'; then
    echo "FAIL $fault $*: exit $rc, stopped after ${stop}s; log:"
    cat "$log"
    failures=$((failures + 1))
  else
    echo "ok   $fault $*: exit $rc, every rank stopped ${stop}s after the fault"
  fi
}

check_fault read:throw@1 "bun[0-9]*.ply: injected fault on rank 1"
check_fault read:throw@0 "bun[0-9]*.ply: injected fault on rank 0"
check_fault field:throw@1 "error on rank 1: field: injected fault on rank 1"
check_fault field:kill@1 "exited on signal 9"
check_fault field:kill@0 "exited on signal 9"
# Registration with no scan kept re-reads them for every field: a read failing then, at any
# step (the lattice, the brick plan, the routing of scans or of control points, the motion
# of a round), stops every rank.
reread=(--register both --max-iterations 3 --max-rounds 2 --scan-memory 0)
for n in 6 8 12 20 40; do
  check_fault "read:throw@1#$n" "injected fault on rank 1" "${reread[@]}"
done
exit $((failures > 0))

#!/usr/bin/env bash
# A run killed with SIGKILL at several moments, then resumed from its checkpoint (on another
# rank count), ends with the same poses and mesh, byte for byte, as a run never interrupted.
set -uo pipefail
bin=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
"$bin" scan --shape composite --views 8 --width 160 --height 120 --voxel 1 --rot-deg 3 \
  --trans-vox 3 --out "$tmp/s" >/dev/null
args=(--scans "$tmp/s/perturbed.conf" --voxel 1 --register both --max-rounds 3)
mpirun -np 2 "$bin" fuse "${args[@]}" --out "$tmp/ref.ply" --poses-out "$tmp/ref.conf" >/dev/null
start=$(date +%s.%N)
mpirun -np 2 "$bin" fuse "${args[@]}" --out "$tmp/timed.ply" >/dev/null
total=$(awk "BEGIN { print $(date +%s.%N) - $start }")
resumed=0
for fraction in 0.35 0.5 0.65 0.8 0.9; do
  rm -f "$tmp/ck.h5" "$tmp/out.ply" "$tmp/out.conf"
  # Its own process group, so that the kill reaches every rank and nothing else.
  setsid mpirun -np 2 "$bin" fuse "${args[@]}" --out "$tmp/out.ply" --checkpoint "$tmp/ck.h5" \
    >/dev/null 2>&1 &
  job=$!
  sleep "$(awk "BEGIN { print $total * $fraction }")"
  kill -KILL -- -"$job" 2>/dev/null
  wait "$job" 2>/dev/null
  sleep 0.2
  if [[ ! -e $tmp/ck.h5 ]]; then echo "skip $fraction: killed before the first checkpoint"; continue; fi
  stage=$("$bin" info "$tmp/ck.h5" | sed -n 's/^progress: *//p')
  mpirun -np 1 "$bin" fuse --resume "$tmp/ck.h5" --checkpoint "$tmp/ck.h5" --out "$tmp/out.ply" \
    --poses-out "$tmp/out.conf" >/dev/null
  if cmp -s "$tmp/out.ply" "$tmp/ref.ply" && cmp -s "$tmp/out.conf" "$tmp/ref.conf"; then
    echo "ok   killed at ${fraction} of the run (checkpoint: $stage), resumed on 1 rank: identical"
    resumed=$((resumed + 1))
  else
    echo "FAIL killed at ${fraction} (checkpoint: $stage): result differs"; failures=$((failures + 1))
  fi
done
# Killed right after a given registration checkpoint (RANGEFUSE_FAULT), not at a time: the
# middle of Algorithm 2's rounds, whatever the machine's speed.
for nth in 10 14; do
  rm -f "$tmp/ck.h5" "$tmp/out.ply" "$tmp/out.conf"
  RANGEFUSE_FAULT="checkpoint:kill@0#$nth" mpirun -np 2 -x RANGEFUSE_FAULT "$bin" fuse "${args[@]}" \
    --out "$tmp/out.ply" --checkpoint "$tmp/ck.h5" >/dev/null 2>&1
  stage=$("$bin" info "$tmp/ck.h5" | sed -n 's/^progress: *//p')
  mpirun -np 1 "$bin" fuse --resume "$tmp/ck.h5" --checkpoint "$tmp/ck.h5" --out "$tmp/out.ply" \
    --poses-out "$tmp/out.conf" >/dev/null
  if [[ $stage == *simultaneous* ]] && cmp -s "$tmp/out.ply" "$tmp/ref.ply" && cmp -s "$tmp/out.conf" "$tmp/ref.conf"; then
    echo "ok   killed after registration checkpoint $nth ($stage), resumed on 1 rank: identical"
    resumed=$((resumed + 1))
  else
    echo "FAIL killed after registration checkpoint $nth ($stage): result differs or not in Algorithm 2"
    failures=$((failures + 1))
  fi
done
if [[ $resumed -lt 2 ]]; then echo "FAIL only $resumed runs were killed after a checkpoint"; exit 1; fi
[[ $failures -eq 0 ]] && echo "all kill-and-resume cases passed ($resumed resumed)" || exit 1

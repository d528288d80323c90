#!/usr/bin/env bash
# Runs (or resumes) a checkpointed fuse job: if the config's checkpoint exists, continues from
# it, otherwise starts afresh. Used by the local, Slurm and PBS scripts; safe to rerun after a
# crash, a kill or a wall-time limit.
# Usage: bash jobs/run_resumable.sh [RANKS] [CONFIG.ini]
set -euo pipefail
cd "$(dirname "$0")/.."
ranks=${1:-2}
config=${2:-jobs/bunny_checkpointed.ini}
checkpoint=$(sed -n 's/^checkpoint *= *//p' "$config")
mkdir -p "$(dirname "$checkpoint")"
launcher=${MPIEXEC:-mpirun}
if [[ -n $checkpoint && -f $checkpoint ]]; then
  echo "resuming from $checkpoint"
  exec $launcher -np "$ranks" build/rangefuse fuse --config "$config" --resume "$checkpoint"
fi
exec $launcher -np "$ranks" build/rangefuse fuse --config "$config"

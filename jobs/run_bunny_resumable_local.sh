#!/usr/bin/env bash
# Local two-rank run of the checkpointed bunny job; rerun it after an interruption to resume.
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh
source jobs/mpi_env.sh
bash jobs/run_resumable.sh 2 jobs/bunny_checkpointed.ini

#!/usr/bin/env bash
# Set up, build and run the whole test suite (unit tests, 2-rank MPI tests, CLI tests).
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh
source jobs/mpi_env.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"

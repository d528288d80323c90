#!/usr/bin/env bash
# The main demo: set up, build, fuse the bundled bunny scans on 2 MPI ranks into
# out/bunny.ply, and compare it with the Stanford reconstruction.
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh
source jobs/mpi_env.sh
mkdir -p out
mpirun -np 2 build/rangefuse fuse --config jobs/bunny.ini
build/rangefuse eval --mesh out/bunny.ply --reference tests/data/bunny/bun_zipper.ply --voxel 0.001
echo "mesh written to out/bunny.ply"

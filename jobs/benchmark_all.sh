#!/usr/bin/env bash
# The headline benchmarks, one after another, each beside its peer in the same run: rerun
# before closing an issue that touches the pipeline, and compare with docs/benchmarks.md.
#   benchmark.sh           bunny and noisy sets: accuracy beside Open3D TSDF
#   benchmark_speed.sh     dense scans: seconds and memory beside Open3D
#   benchmark_sequence.sh  a depth-camera sequence at true poses beside ScalableTSDFVolume
#   benchmark_tracking.sh  depth streams without poses beside Open3D's frame-to-frame ICP
# Usage: bash jobs/benchmark_all.sh [OUT_DIR]  (each script's output in OUT_DIR/NAME.md;
# default benchmarks-out/). Takes about an hour on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-benchmarks-out}
mkdir -p "$out"
for name in benchmark benchmark_speed benchmark_sequence benchmark_tracking; do
  echo "== $name ($(date +%H:%M:%S))"
  bash "jobs/$name.sh" | tee "$out/$name.md"
done
echo "== done ($(date +%H:%M:%S)); tables in $out/"

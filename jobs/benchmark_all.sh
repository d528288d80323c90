#!/usr/bin/env bash
# The headline benchmarks, one after another, each beside its peer in the same run, then one
# table of the headline figures (jobs/summarize_benchmarks.py): rerun before closing an issue
# that touches the pipeline, and compare with docs/benchmarks.md.
#   benchmark.sh              bunny and noisy sets: accuracy, speed-up of 2 ranks against 1
#   benchmark_speed.sh        dense scans: seconds and accuracy beside Open3D TSDF
#   benchmark_memory.sh       the 48-view set: peak memory per rank on 1 and 4 ranks, and
#                             what each peak was made of
#   benchmark_speedup.sh      2 ranks against 1 by rangefuse's clock, best of 3: the real
#                             bunny and the 48-view set
#   benchmark_weak_scaling.sh the same work on every rank, 1 to 8 ranks
#   benchmark_sequence.sh     a depth-camera sequence at true poses beside ScalableTSDFVolume
#   benchmark_robust_depth.sh robust fusion on depth-camera frames: the synthetic Kinect room
#                             beside ScalableTSDFVolume, the real kitchen against prism
#   benchmark_tracking.sh     depth streams without poses beside Open3D's frame-to-frame ICP
#   benchmark_kitchen.sh      real Kinect frames (7-Scenes, read in place), poses hidden,
#                             beside Open3D's frame-to-frame ICP: the dev and held-out sets
#   benchmark_stream_speed.sh room walks and the real kitchen read to mesh beside
#                             ScalableTSDFVolume: seconds, ns an update, balance, memory
#   benchmark_heldout.sh      the real kitchen's fused surfaces judged by frames left out
# Usage: bash jobs/benchmark_all.sh [OUT_DIR]  (each script's output in OUT_DIR/NAME.md, the
# summary in OUT_DIR/summary.md; default benchmarks-out/). Takes about 35 minutes on two cores;
# SEQ_ROOT and SEQUENCES pass to benchmark_tracking.sh (SEQUENCES="orbit handheld desk walk"
# adds the walk through the room, which both trackers lose, and 10-40 minutes).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-benchmarks-out}
mkdir -p "$out"
run() {  # NAME [ARGS...]
  local name=$1
  shift
  echo "== $name $* ($(date +%H:%M:%S))"
  bash "jobs/$name.sh" "$@" | tee "$out/$name.md"
}
run benchmark
run benchmark_speed
run benchmark_memory 48 1024 1 4
run benchmark_speedup
run benchmark_weak_scaling 6 1 2 4 8
run benchmark_sequence
run benchmark_robust_depth
run benchmark_tracking
run benchmark_kitchen
run benchmark_stream_speed
run benchmark_heldout
echo "== summary ($(date +%H:%M:%S)); tables in $out/"
python3 jobs/summarize_benchmarks.py "$out" | tee "$out/summary.md"

#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (build-fuzz/), makes the seed corpus and runs each
# target for SECONDS (default 600). Crashing inputs land in tests/fuzz/regressions/TARGET/,
# which the test suite replays. Usage: jobs/fuzz.sh [SECONDS] [TARGET...]
# FUZZ_PARALLEL=N runs N targets at once (default 1).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(range_grid_ply mesh_ply conf fuse_ini checkpoint ptx e57 depth_png
  depth_sequence colour_image)

RANGEFUSE_EXTRA_PACKAGES="clang libclang-rt-14-dev" bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DRANGEFUSE_FUZZ=ON >/dev/null
cmake --build build-fuzz -j "$(nproc)" >/dev/null
corpus=build-fuzz/corpus
bash tests/fuzz/make_corpus.sh build/rangefuse "$corpus/seeds"

export ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
run_one() {
  local t=$1 found=tests/fuzz/regressions/$1
  mkdir -p "$corpus/$t" "$found"
  local extra=()
  # Checkpoint inputs are choice bytes: let them grow past the tiny seeds at once.
  [[ $t == checkpoint ]] && extra=(-max_len=512)
  # The working corpus grows in build-fuzz; the seeds stay as they are.
  build-fuzz/tests/fuzz/fuzz_"$t" "$corpus/$t" "$corpus/seeds/$t" -max_total_time="$seconds" \
    -rss_limit_mb=2048 -timeout=20 -artifact_prefix="$found/" -print_final_stats=1 "${extra[@]}" \
    >"build-fuzz/fuzz_$t.log" 2>&1 || true
  local runs
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "build-fuzz/fuzz_$t.log" | grep -o '[0-9]*$' || echo 0)
  printf '%-15s %6ss %12s executions  %s crash files in %s\n' "$t" "$seconds" "$runs" \
    "$(find "$found" -type f ! -name '.*' | wc -l)" "$found"
}
export -f run_one
export corpus seconds
printf '%s\n' "${targets[@]}" | xargs -P "${FUZZ_PARALLEL:-1}" -I{} bash -c 'run_one {}'

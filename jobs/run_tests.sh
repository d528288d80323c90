#!/usr/bin/env bash
# Set up, build and run the whole test suite (unit tests, 2-rank MPI tests, CLI tests), then
# build again under AddressSanitizer + UndefinedBehaviorSanitizer and run it once more, less
# the cases labelled slow (tests/CMakeLists.txt says which and why) and the MPI suite's
# end-to-end cases.
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh
source jobs/mpi_env.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"

echo "== sanitizer pass (ASan + UBSan) =="
# -O1 with line tables only (ASan's advice): 10 minutes to build on two cores, where -O2 -g took
# over 25 (GCC's variable tracking runs for minutes on each unity file).
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DRANGEFUSE_SANITIZE=ON -DCMAKE_UNITY_BUILD=ON -DRANGEFUSE_PYTHON=OFF >/dev/null
cmake --build build-asan -j "$(nproc)" >/dev/null
# Open MPI's own allocations outlive MPI_Finalize: leak reports would be about it, not us.
export ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -LE slow

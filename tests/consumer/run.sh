#!/usr/bin/env bash
# Installs the built rangefuse into a fresh prefix, builds this consumer project against it
# with find_package(rangefuse) alone, and runs it on one rank and on two.
# Usage: run.sh BUILD_DIR MPIEXEC
set -euo pipefail
build=$1 mpiexec=$2
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$here" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/build" >/dev/null
# Nothing of the source tree may be needed: the headers and library come from the prefix.
flags=$work/build/CMakeFiles/fuse_sphere.dir/flags.make
grep -q "$work/prefix/include" "$flags" || { echo "FAIL: the prefix's headers are not used" >&2; exit 1; }
if grep -q "$(cd "$here/../.." && pwd)/include" "$flags"; then
  echo "FAIL: the consumer compiled against the source tree's headers" >&2
  exit 1
fi
"$work/build/fuse_sphere"
"$mpiexec" -n 2 "$work/build/fuse_sphere"

#!/usr/bin/env bash
# Installs the built rangefuse into a fresh prefix, builds this consumer project against it
# with find_package(rangefuse) alone, and runs it on one rank and on two. With PYTHON and the
# module's folder under the prefix, it also imports the installed module and fuses with it: the
# prefix is not the configured one, so the module must find the library relative to itself.
# Usage: run.sh BUILD_DIR MPIEXEC [PYTHON PYTHON_DIR]
set -euo pipefail
build=$1 mpiexec=$2 python=${3:-} python_dir=${4:-}
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

if [[ -n $python ]]; then
  module=$work/prefix/$python_dir
  [[ -f $(echo "$module"/rangefuse*.so) ]] || { echo "FAIL: no module in $module" >&2; exit 1; }
  # Only the prefix: no build tree on the search paths.
  env -u LD_LIBRARY_PATH PYTHONPATH="$module" "$python" -c "
import os, rangefuse
assert os.path.dirname(rangefuse.__file__) == '$module', rangefuse.__file__
f = rangefuse.Fusion(voxel=0.01)
try:
    rangefuse.Fusion(voxel=0.01, min_views=0)
    raise SystemExit('FAIL: min_views=0 accepted')
except ValueError as e:
    assert 'min-views' in str(e) or 'min_views' in str(e), e
print('installed module imported from', os.path.dirname(rangefuse.__file__))
"
fi

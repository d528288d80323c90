#!/usr/bin/env bash
# The layer check (cmake/CheckLayers.cmake) passes on the source tree, and fails, naming the
# file and the include, on a copy of the layer list with a wrong-way include, a private header
# of another folder, or a layer naming one below it.
# Usage: layers.sh SOURCE_DIR
set -euo pipefail
source_dir=$1
check=$source_dir/cmake/CheckLayers.cmake
cmake -DROOT="$source_dir" -P "$check"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# A tree of its own: the real layer list, one file a folder.
fresh() {
  rm -rf "$work/t"
  mkdir -p "$work/t/docs" "$work/t/include/rangefuse/core" "$work/t/include/rangefuse/volume" \
    "$work/t/src/core" "$work/t/src/volume"
  cp "$source_dir/docs/architecture.md" "$work/t/docs/"
  echo '#pragma once' >"$work/t/include/rangefuse/core/A.h"
  printf '#pragma once\n#include "rangefuse/core/A.h"\n' >"$work/t/include/rangefuse/volume/B.h"
  printf '#include "rangefuse/volume/B.h"\n#include "Private.h"\n' >"$work/t/src/volume/B.cpp"
}
refused() {  # what the check must say
  if cmake -DROOT="$work/t" -P "$check" >"$work/out" 2>&1; then
    echo "FAIL: the check passed: $1" >&2
    exit 1
  fi
  grep -q "$2" "$work/out" || { cat "$work/out" >&2; echo "FAIL: no '$2' for $1" >&2; exit 1; }
}

fresh
cmake -DROOT="$work/t" -P "$check" >/dev/null
echo '#include "rangefuse/volume/B.h"' >"$work/t/src/core/A.cpp"
refused "core including volume" "src/core/A.cpp: includes rangefuse/volume/B.h, but core may not depend on volume"

fresh
echo '#include "volume/Private.h"' >"$work/t/src/core/A.cpp"
refused "another folder's private header" "src/core/A.cpp: includes volume/Private.h, a private header"

fresh
sed -i 's/^core:$/core: volume/' "$work/t/docs/architecture.md"
refused "a layer naming one below it" "layer core names volume"
echo "layers: the tree passes; wrong-way and private includes and a cycle are refused"

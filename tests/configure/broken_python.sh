#!/usr/bin/env bash
# A configure must not fail on a broken `python3` on PATH (a pyenv shim naming a version that is
# not installed): it builds the module for a Python that works, or skips the module with one
# status line when none does.
# Usage: broken_python.sh SOURCE_DIR
set -euo pipefail
source_dir=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/bin"
printf '#!/bin/sh\necho "pyenv: python3.6: command not found" >&2\nexit 127\n' >"$work/bin/python3"
chmod +x "$work/bin/python3"

PATH="$work/bin:$PATH" cmake -S "$source_dir" -B "$work/a" >"$work/a.log" 2>&1 ||
  { cat "$work/a.log" >&2; echo "FAIL: configure with a broken python3 on PATH failed" >&2; exit 1; }
if grep -q "PYTHON_EXECUTABLE:FILEPATH=$work/bin/python3" "$work/a/CMakeCache.txt"; then
  echo "FAIL: the module was set up for the broken python3" >&2
  exit 1
fi

PATH="$work/bin:$PATH" cmake -S "$source_dir" -B "$work/b" -DPYTHON_EXECUTABLE="$work/bin/python3" \
  >"$work/b.log" 2>&1 ||
  { cat "$work/b.log" >&2; echo "FAIL: configure naming a broken Python failed" >&2; exit 1; }
lines=$(grep -c "Python module skipped" "$work/b.log" || true)
[[ $lines == 1 ]] || { cat "$work/b.log" >&2; echo "FAIL: $lines skip lines, not 1" >&2; exit 1; }
if grep -q "rangefuse_python" "$work/b/Makefile"; then
  echo "FAIL: the module is still a target" >&2
  exit 1
fi
echo "broken python3: configured, module skipped when no Python works"

#!/usr/bin/env bash
# Every command the README shows, run as printed from a fresh folder holding only this build
# (as build/rangefuse) and the repository's tests/ and jobs/, in order (later commands read what
# earlier ones wrote); synthetic pictures at half the printed resolution. A command that exits
# non-zero or prints an error or a warning fails the test, naming the command.
set -euo pipefail
bin=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

mkdir "$tmp/build"
ln -s "$bin" "$tmp/build/rangefuse"
ln -s "$src/tests" "$tmp/tests"
ln -s "$src/jobs" "$tmp/jobs"
python3 "$src/tests/cli/readme_commands.py" "$src/README.md" --small >"$tmp/commands.txt"
count=$(wc -l <"$tmp/commands.txt")
[[ $count -ge 15 ]] || { echo "FAIL: only $count commands found in README.md" >&2; exit 1; }

cd "$tmp"
n=0
while IFS= read -r command; do
  n=$((n + 1))
  if ! bash -c "$command" >"$tmp/log" 2>&1 </dev/null || grep -qE "^rangefuse: (error|warning)" "$tmp/log"; then
    echo "FAIL: README command $n of $count: $command" >&2
    tail -5 "$tmp/log" >&2
    exit 1
  fi
  echo "ok $n/$count: $command"
done <"$tmp/commands.txt"

# Every preview the README writes frames its surface: at least 60 % of the width or height.
previews=$(grep -o -- "--preview [^ ]*" "$tmp/commands.txt" | cut -d' ' -f2 || true)
[[ -n $previews ]] || { echo "FAIL: no --preview among the README's commands" >&2; exit 1; }
for png in $previews; do
  read -r across down < <(python3 "$src/tests/cli/preview_bounds.py" "$png")
  python3 -c "import sys; sys.exit(not max($across, $down) >= 0.6)" ||
    { echo "FAIL: $png: the surface spans $across of the width, $down of the height" >&2; exit 1; }
  echo "preview $png: the surface spans $across of the width, $down of the height"
done

#!/usr/bin/env bash
# What a first run reads: each command's help in sections, essentials first, listing only the
# options the command uses; --version; --quiet prints nothing but warnings, the default a line
# a stage and a line a registration round, --verbose every fit; the last lines name every file
# written.
set -euo pipefail
bin=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# Sections in order: the first line of each heading ("Input:") in the help.
sections() { "$bin" "$1" --help | grep -E '^[A-Z][A-Za-z ()-]*:$' | grep -v '^Example:' | tr -d ':' | paste -sd '|'; }
[[ $(sections fuse) == "Input|Field|Output|Registration (--register)|Depth streams without poses (tracking)|Checkpoints|Resources|Input limits" ]] ||
  fail "fuse sections: $(sections fuse)"
[[ $(sections render) == "Input|Picture|Field|Resources|Input limits" ]] ||
  fail "render sections: $(sections render)"
[[ $(sections eval) == "Meshes|Poses and trajectories|Output|Reading scan lists|Input limits" ]] ||
  fail "eval sections: $(sections eval)"
echo "sections: fuse, render and eval in order"

# Only the options a command uses.
absent() {  # COMMAND OPTION...
  local command=$1 help
  shift
  help=$("$bin" "$command" --help | tr -s ' \n' ' ')  # wrapped lines joined
  for option in "$@"; do
    ! grep -q -- "$option\b" <<<"$help" || fail "$command --help lists $option"
  done
}
absent render --register-solve --follow --preview-every --poses-out --checkpoint-every
absent eval --scans --register --max-voxels "how to read --scans"
absent perturb --max-voxels --register
absent scan --max-voxels --scan-format
grep -q "how to read --seen, --poses and --reference-poses" <<<"$("$bin" eval --help | tr -s ' \n' ' ')" ||
  fail "eval's --scan-format does not say what it reads"
grep -q -- "--band-cells arg (=4000000)" <<<"$("$bin" fuse --help)" || fail "fuse --band-cells default"
grep -q -- "--normals arg (=true)" <<<"$("$bin" mesh --help)" || fail "mesh --normals default"
grep -q -- "--checkpoint" <<<"$("$bin" info --help)" || fail "info --help lists no option"
echo "each command lists only its options, defaults as written"

for command in "" fuse eval mesh info perturb render scan; do
  grep -qE "^rangefuse [0-9]+\.[0-9]+\.[0-9]+ \(HDF5 " <<<"$("$bin" $command --version)" ||
    fail "rangefuse $command --version"
done
echo "--version on every command"

# Output volume, on a registration run (24 scans, both algorithms).
"$bin" scan --shape sphere --views 12 --voxel 1 --noise 0.3 --rot-deg 2 --trans-vox 2 \
  --out "$tmp/set" >/dev/null
run() { mpirun -np 2 "$bin" fuse --scans "$tmp/set/perturbed.conf" --voxel 1 --register both \
  --out "$tmp/mesh.ply" --preview "$tmp/mesh.png" --report "$tmp/report.json" "$@"; }
run --quiet >"$tmp/quiet.out" 2>"$tmp/quiet.err"
# Warnings still go to stderr (a sphere holds no scan's turn: they are loose), nothing else.
[[ ! -s $tmp/quiet.out ]] || fail "--quiet printed: $(head -3 "$tmp/quiet.out")"
! grep -v "^rangefuse: warning: " "$tmp/quiet.err" || fail "--quiet printed more than warnings"
run >"$tmp/normal.out"
run --verbose >"$tmp/verbose.out"
fits=$(grep -oE "register +(both|incremental|simultaneous): [0-9]+ fits" "$tmp/normal.out" |
  grep -oE "[0-9]+ fits" | cut -d' ' -f1)
normal=$(grep -c '^\[register\]' "$tmp/normal.out" || true)
verbose=$(grep -c '^\[register\] .* it ' "$tmp/verbose.out" || true)
[[ $fits -gt 20 && $verbose -eq $fits && $normal -lt 10 ]] ||
  fail "$fits fits: $normal [register] lines by default, $verbose fit lines with --verbose"
echo "output: --quiet nothing, default $normal registration lines, --verbose one a fit ($fits)"
tail -3 "$tmp/normal.out" | grep -q "write .*mesh.ply, .*mesh.png" || fail "write line"
tail -1 "$tmp/normal.out" | grep -q "report .*report.json" || fail "report line"
if mpirun -np 2 "$bin" fuse --scans "$tmp/set/truth.conf" --voxel 1 --out "$tmp/x.ply" --quiet \
  --verbose 2>"$tmp/both.err"; then fail "--quiet --verbose accepted"; fi
grep -q "verbose cannot be given with --quiet" "$tmp/both.err" || fail "$(cat "$tmp/both.err")"
echo "the last lines name the mesh, the preview and the report"

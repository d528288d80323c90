#!/usr/bin/env bash
# Registration benchmark, 2 ranks: accuracy on the synthetic bunny (24 views,
# 320x240, noise 0.5 and 1 voxel, perturbation 0-5 deg / 0-5 voxels) and the real bunny
# (bun.conf perturbed the same way), then how the cost grows with the number of scans and
# of control points, with the simple method (a new field for every scan) beside it.
# Prints Markdown tables. Usage: bash jobs/benchmark_registration.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=$PWD/build/rangefuse
bunny=$PWD/tests/data/bunny

calc() { awk "BEGIN { printf \"$1\", $2 }"; }
# register CONF TAG ARGS...: fuse with registration on 2 ranks; leaves $tmp/TAG.{log,conf,ply}.
register() {
  local conf=$1 tag=$2
  shift 2
  mpirun -np 2 "$bin" fuse --scans "$conf" --voxel 0.001 --poses-out "$tmp/$tag.conf" \
    --out "$tmp/$tag.ply" "$@" >"$tmp/$tag.log"
}
# The stage's lines (the fits, then the check against the other scans) summed; the fits' line.
stage_seconds() {
  grep "] register " "$tmp/$1.log" | sed 's/.*(\([0-9.]*\)s)$/\1/' | awk '{ s += $1 } END { printf "%.2f", s }'
}
field_seconds() { grep "] register .* fits;" "$tmp/$1.log" | sed 's/.*fields \([0-9.]*\) s.*/\1/'; }
fit_ms() { grep "] register .* fits;" "$tmp/$1.log" | sed 's/.*(\([0-9.]*\) ms a fit).*/\1/'; }
fits() { grep -c ' corr ' "$tmp/$1.log"; }

echo "## Accuracy (--register both, 2 ranks)"
echo
echo "| data | register (s) | fits | median rotation (deg) | median translation (vox) | median displacement (vox) | worst scan displacement (vox) |"
echo "|---|---|---|---|---|---|---|"
for noise in 0.5 1; do
  $bin scan --mesh "$bunny/bun_zipper.ply" --views 24 --voxel 0.001 --noise $noise \
    --rot-deg 5 --trans-vox 5 --out "$tmp/s$noise" >/dev/null
  register "$tmp/s$noise/perturbed.conf" "s$noise" --register both
  $bin eval --poses "$tmp/s$noise.conf" --reference-poses "$tmp/s$noise/truth.conf" \
    --voxel 0.001 >"$tmp/eval"
  awk -v d="synthetic bunny, noise $noise voxel" -v s="$(stage_seconds s$noise)" \
    -v f="$(fits s$noise)" '$1 ~ /ply$/ && !p { if ($4 > w) w = $4 }
    /^median/ { r = $3; t = $6; m = $9; p = 1 }
    END { printf "| %s | %s | %s | %s | %s | %s | %.3f |\n", d, s, f, r, t, m, w }' "$tmp/eval"
done

# The real bunny: perturbed and refined poses written beside links to the scans they name.
mkdir -p "$tmp/real"
ln -s "$bunny"/*.ply "$tmp/real/"
$bin perturb --scans "$bunny/bun.conf" --voxel 0.001 --rot-deg 5 --trans-vox 5 \
  --out "$tmp/real/perturbed.conf" >/dev/null
mpirun -np 2 "$bin" fuse --scans "$bunny/bun.conf" --voxel 0.001 --out "$tmp/ref.ply" >/dev/null
register "$tmp/real/perturbed.conf" real/out --register both
$bin eval --poses "$tmp/real/out.conf" --reference-poses "$bunny/bun.conf" --voxel 0.001 >"$tmp/eval"
accuracy() {
  $bin eval --mesh "$1" --reference "$bunny/bun_zipper.ply" --voxel 0.001 |
    awk '/^accuracy/ { printf "%.4f", $3 * 1000 }'
}
awk -v s="$(stage_seconds real/out)" -v f="$(fits real/out)" '/^median/ { p = 1 } $1 ~ /ply$/ && !p {
    if ($2 > r) r = $2; if ($3 > t) t = $3 }
  END { printf "\nReal bunny (10 scans, 1 mm): register %s s, %s fits; worst scan against bun.conf: rotation %.3f deg, translation %.3f voxel (mm)\n", s, f, r, t }' "$tmp/eval"
echo "Mesh accuracy mean against bun_zipper.ply: registered $(accuracy "$tmp/real/out.ply") mm, from bun.conf $(accuracy "$tmp/ref.ply") mm"
consistency() {
  $bin eval --poses "$1" --consistency --voxel 0.001 | awk '/^point-to-plane/ { print substr($6, 2) }'
}
echo "Scans' agreement with one another (eval --consistency, point-to-plane RMS, voxels):" \
  "registered $(consistency "$tmp/real/out.conf"), bun.conf $(consistency "$bunny/bun.conf")," \
  "perturbed $(consistency "$tmp/real/perturbed.conf")"
echo

echo "## Cost against the number of scans (noise 0.5 voxel)"
echo
echo "Algorithm 1 (incremental) alone, then both; field = seconds building fields, fit = ms per fit."
echo
echo "| scans | field | incremental (s) | fields (s) | fields per scan (s) | fits | ms per fit | both (s) | fields (s) | fits | ms per fit |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for views in 6 12 24; do
  $bin scan --mesh "$bunny/bun_zipper.ply" --views $views --voxel 0.001 --noise 0.5 \
    --rot-deg 5 --trans-vox 5 --out "$tmp/v$views" >/dev/null
  for field in grow rebuild; do
    register "$tmp/v$views/perturbed.conf" inc --register incremental --register-field $field
    register "$tmp/v$views/perturbed.conf" both --register both --register-field $field
    echo "| $views | $field | $(stage_seconds inc) | $(field_seconds inc) |" \
      "$(calc %.3f "$(field_seconds inc) / $views") | $(fits inc) | $(fit_ms inc) |" \
      "$(stage_seconds both) | $(field_seconds both) | $(fits both) | $(fit_ms both) |"
  done
done
echo

echo "## Cost against the number of control points (12 scans, --register both)"
echo
echo "| control stride | correspondences per fit (mean) | register (s) | fields (s) | fits | ms per fit |"
echo "|---|---|---|---|---|---|"
for stride in 1 2 4 8; do
  register "$tmp/v12/perturbed.conf" st --register both --control-stride $stride
  points=$(grep ' corr ' "$tmp/st.log" | awk '{ s += $8; n++ } END { printf "%.0f", s / n }')
  echo "| $stride | $points | $(stage_seconds st) | $(field_seconds st) | $(fits st) | $(fit_ms st) |"
done

#!/usr/bin/env bash
# Registration accuracy, 2 ranks: the joint solve of Algorithm 2 (the default)
# against per-scan fits and against Open3D 0.16's multiway registration (pairwise
# point-to-plane ICP over every pair, then a pose graph: jobs/open3d_multiway.py) on the same
# perturbed synthetic sets, several seeds; then the real bunny, where only the published poses
# and the scans' agreement with one another can judge. Prints Markdown tables.
# Usage: bash jobs/benchmark_joint.sh [SEEDS...]   (default: 1 2 3)
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=$PWD/build/rangefuse
bunny=$PWD/tests/data/bunny
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2 3)

# poses_row CONF TRUTH: median | worst | common motion | median | worst, voxels (1 mm)
poses_row() {
  "$bin" eval --poses "$1" --reference-poses "$2" --voxel 0.001 | awk '
    /^median/ { poses = 1 }
    $1 ~ /ply$/ && !poses { if ($4 > w) w = $4 }
    /^median/ { m = $9 }
    /^common motion/ { c = $3; cm = $12; cw = $14 }
    END { printf "%.3f | %.3f | %.3f | %.3f | %.3f", m, w, c, cm, cw }'
}
# The registration stage's lines (the fits, then the check against the other scans), summed.
register_seconds() {
  grep "] register " "$1" | sed 's/.*(\([0-9.]*\)s)$/\1/' | awk '{ s += $1 } END { printf "%.2f", s }'
}

echo "## Synthetic bunny, perturbed by up to 5 deg and 5 voxels per axis (1 mm voxels)"
echo
echo "Point displacement per scan in voxels against the truth (the anchor's frame); then the best"
echo "common rigid motion of all scans and the displacements once it is removed."
echo
echo "| set | seed | method | register (s) | median | worst | common motion | median without it | worst without it |"
echo "|---|---|---|---|---|---|---|---|---|"
sets=("24 0.5 0.01 2" "18 1 0.02 3")
for set in "${sets[@]}"; do
  read -r views noise outliers patches <<<"$set"
  for seed in "${seeds[@]}"; do
    dir=$tmp/v${views}n${noise}s$seed
    "$bin" scan --mesh "$bunny/bun_zipper.ply" --views "$views" --voxel 0.001 --noise "$noise" \
      --outliers "$outliers" --patches "$patches" --rot-deg 5 --trans-vox 5 --seed "$seed" \
      --out "$dir" >/dev/null
    label="$views views, noise $noise, $outliers outliers, $patches patches"
    for solve in joint per-scan; do
      mpirun -np 2 "$bin" fuse --scans "$dir/perturbed.conf" --voxel 0.001 --register both \
        --register-solve $solve --poses-out "$dir/$solve.conf" --out "$dir/$solve.ply" >"$dir/$solve.log"
      echo "| $label | $seed | rangefuse $solve | $(register_seconds "$dir/$solve.log") |" \
        "$(poses_row "$dir/$solve.conf" "$dir/truth.conf") |"
    done
    o3d=$(/usr/bin/python3 jobs/open3d_multiway.py "$dir/perturbed.conf" 0.001 "$dir/o3d.conf" 2>/dev/null |
      sed 's/.*register \([0-9.]*\) s.*/\1/')
    echo "| $label | $seed | Open3D multiway | $o3d | $(poses_row "$dir/o3d.conf" "$dir/truth.conf") |"
  done
done
echo

echo "## Real bunny (10 Cyberware scans, 1 mm voxels), bun.conf perturbed by up to 5 deg / 5 voxels"
echo
mkdir -p "$tmp/real"
ln -s "$bunny"/*.ply "$tmp/real/"
"$bin" perturb --scans "$bunny/bun.conf" --voxel 0.001 --rot-deg 5 --trans-vox 5 \
  --out "$tmp/real/perturbed.conf" >/dev/null
consistency() {
  "$bin" eval --poses "$1" --consistency --voxel 0.001 | awk '
    /^point-to-plane/ { r = substr($6, 2); p = $9 }
    /^overlapping/ { o = $4 "/" $6 }
    END { printf "%s | %s | %s", r, p, o }'
}
chamfer() {
  "$bin" eval --mesh "$1" --reference "$bunny/bun_zipper.ply" --voxel 0.001 |
    awk '/^accuracy/ { printf "%.4f", $3 * 1000 }'
}
echo "| poses | wall (s) | register (s) | mesh to bun_zipper, mean (mm) | vs bun.conf: median / worst displacement (mm) | scans' RMS to each other (vox) | partners | overlapping pairs |"
echo "|---|---|---|---|---|---|---|---|"
mpirun -np 2 "$bin" fuse --scans "$bunny/bun.conf" --voxel 0.001 --out "$tmp/ref.ply" >/dev/null
echo "| bun.conf | | | $(chamfer "$tmp/ref.ply") | | $(consistency "$bunny/bun.conf") |"
for solve in joint per-scan; do
  start=$(date +%s.%N)
  mpirun -np 2 "$bin" fuse --scans "$tmp/real/perturbed.conf" --voxel 0.001 --register both \
    --register-solve $solve --poses-out "$tmp/real/$solve.conf" --out "$tmp/real/$solve.ply" \
    >"$tmp/real/$solve.log"
  wall=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { printf "%.2f", e - s }')
  vs=$("$bin" eval --poses "$tmp/real/$solve.conf" --reference-poses "$bunny/bun.conf" --voxel 0.001 |
    awk '/^median/ { m = $9; p = 1 } $1 ~ /ply$/ && !p { if ($4 > w) w = $4 } END { printf "%.3f / %.3f", m, w }')
  echo "| --register-solve $solve | $wall | $(register_seconds "$tmp/real/$solve.log") |" \
    "$(chamfer "$tmp/real/$solve.ply") | $vs | $(consistency "$tmp/real/$solve.conf") |"
done
# Where the joint solve goes from bun.conf itself: the same optimum as from the perturbed start?
cp "$bunny/bun.conf" "$tmp/real/start.conf"
mpirun -np 2 "$bin" fuse --scans "$tmp/real/start.conf" --voxel 0.001 --register simultaneous \
  --poses-out "$tmp/real/fromconf.conf" --out "$tmp/real/fromconf.ply" >/dev/null
echo
echo "Joint solve started at bun.conf against started at the perturbed poses (median / worst displacement, mm):" \
  "$("$bin" eval --poses "$tmp/real/fromconf.conf" --reference-poses "$tmp/real/joint.conf" --voxel 0.001 |
    awk '/^median/ { m = $9; p = 1 } $1 ~ /ply$/ && !p { if ($4 > w) w = $4 } END { printf "%.4f / %.4f", m, w }')"

#!/usr/bin/env bash
# Benchmark, in one run: the bunny fuse at two voxel sizes on 1 and 2 ranks, and the
# synthetic scanner's default set (composite shape, 24 views at 320x240, noise 0.5 voxel,
# 1% outliers, 2 patches). Prints a Markdown table with wall time, peak memory per rank,
# accuracy (from `rangefuse eval`) and the 2-vs-1-rank speed-up; best of `repeats` runs.
# Usage: bash jobs/benchmark.sh [repeats]
set -euo pipefail
cd "$(dirname "$0")/.."
repeats=${1:-3}
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=build/rangefuse

calc() { awk "BEGIN { printf \"$1\", $2 }"; }
field() { grep "] $1 " "$tmp/best.log" | sed "$2"; }

# bench DATASET METHOD CONF REFERENCE VOXEL UNIT-NAME UNIT-SCALE [REPEATS]: a row per rank count.
bench() {
  local dataset=$1 method=$2 conf=$3 ref=$4 voxel=$5 unit=$6 scale=$7 repeats=${8:-$repeats}
  local job1=""
  for ranks in 1 2; do
    local best=999 wall
    for ((i = 0; i < repeats; i++)); do
      local start
      start=$(date +%s.%N)
      mpirun -np "$ranks" $bin fuse --scans "$conf" --voxel "$voxel" --method "$method" \
        --out "$tmp/mesh.ply" >"$tmp/log"
      wall=$(calc %.3f "$(date +%s.%N) - $start")
      if [[ $(calc %d "$wall < $best") == 1 ]]; then best=$wall && cp "$tmp/log" "$tmp/best.log"; fi
    done
    $bin eval --mesh "$tmp/mesh.ply" --reference "$ref" --voxel "$voxel" >"$tmp/eval"
    local acc comp chamfer fscore spurious job mem speedup=""
    acc=$(awk -v s="$scale" '/^accuracy/ {printf "%.4f", $3 * s}' "$tmp/eval")
    comp=$(awk -v s="$scale" '/^completeness/ {printf "%.4f", $3 * s}' "$tmp/eval")
    chamfer=$(awk '/^chamfer/ {gsub("\\(", "", $3); printf "%.3f", $3}' "$tmp/eval")
    fscore=$(awk '/F-score/ {print $NF}' "$tmp/eval")
    spurious=$(awk '/^spurious/ {print $NF}' "$tmp/eval")
    job=$(field done 's/^\[ *\([0-9.]*\)s\].*/\1/')
    mem=$(field done 's/.*(MiB) \(.*\) (.*/\1/')
    [[ $ranks == 1 ]] && job1=$job
    [[ $ranks == 2 ]] && speedup=$(calc %.2f "$job1 / $job")
    printf "| %s | %s | %s | %s | %.2f | %s | %s | %s | %s | %s | %s | %s | %s |\n" "$dataset" "$method" \
      "$ranks" "$(calc %g "$voxel * $scale") $unit" "$best" "$job" "$mem" "$acc" "$comp" "$chamfer" \
      "$fscore" "$spurious" "$speedup"
  done
}

$bin scan --shape composite --views 24 --width 320 --height 240 --voxel 1 --noise 0.5 \
  --outliers 0.01 --patches 2 --rot-deg 5 --trans-vox 5 --seed 1 --out "$tmp/synth" >"$tmp/scan.log"

echo "| dataset | method | ranks | voxel | mpirun wall (s) | job (s) | peak MiB per rank | accuracy mean | completeness mean | chamfer (voxels) | F-score (1 voxel) | spurious area | speed-up 2 vs 1 (job) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
bench bunny prism tests/data/bunny/bun.conf tests/data/bunny/bun_zipper.ply 0.001 mm 1000
bench bunny prism tests/data/bunny/bun.conf tests/data/bunny/bun_zipper.ply 0.0005 mm 1000
bench bunny consensus tests/data/bunny/bun.conf tests/data/bunny/bun_zipper.ply 0.001 mm 1000 1
bench bunny naive tests/data/bunny/bun.conf tests/data/bunny/bun_zipper.ply 0.001 mm 1000 1
for method in prism consensus naive; do
  bench "synthetic composite" $method "$tmp/synth/truth.conf" "$tmp/synth/truth.ply" 1 units 1 1
done
echo
echo "Accuracy/completeness: mean distance (mm for the bunny, model units for the synthetic set);"
echo "mpirun wall = the whole command including MPI start-up; job = rangefuse's own elapsed time"
echo "(read, triangulate, fields, mesh, write). Best of $repeats runs; $(nproc) cores."
echo "Synthetic set: $(cat "$tmp/scan.log")"
echo
echo "Extraneous patches of the synthetic set: share of each patch's area within 1 voxel of the mesh"
for method in consensus naive; do
  mpirun -np 2 $bin fuse --scans "$tmp/synth/truth.conf" --voxel 1 --method $method --out "$tmp/p.ply" >/dev/null
  kept=""
  for k in 0 1; do
    kept+=" $($bin eval --mesh "$tmp/synth/patch_$k.ply" --reference "$tmp/p.ply" --voxel 1 --samples 20000 | awk '/precision/ {print $5}')"
  done
  echo "- $method:$kept"
done

echo
echo "Checkpoints, bunny 0.5 mm, 2 ranks (best of $repeats): write cost against the job, size, resume"
best_ck=999 best_job=0
for ((i = 0; i < repeats; i++)); do
  mpirun -np 2 $bin fuse --scans tests/data/bunny/bun.conf --voxel 0.0005 --out "$tmp/ck.ply" \
    --checkpoint "$tmp/ck.h5" --overwrite >"$tmp/cklog"
  ck=$(grep '] checkpoint ' "$tmp/cklog" | sed 's/.*(\([0-9.]*\)s)$/\1/')
  job=$(grep '] done ' "$tmp/cklog" | sed 's/^\[ *\([0-9.]*\)s\].*/\1/')
  if [[ $(calc %d "$ck < $best_ck") == 1 ]]; then best_ck=$ck best_job=$job; fi
done
bricks=$(grep '] field ' "$tmp/cklog" | sed 's/.*: \([0-9]*\) bricks.*/\1/')
size=$(stat -c %s "$tmp/ck.h5")
start=$(date +%s.%N)
mpirun -np 2 $bin fuse --resume "$tmp/ck.h5" --out "$tmp/resumed.ply" >/dev/null
resume=$(calc %.2f "$(date +%s.%N) - $start")
echo "- checkpoint write $best_ck s of a $best_job s job ($(calc %.1f "100 * $best_ck / $best_job") %);" \
  "$(calc %.1f "$size / 1048576") MiB for $bricks bricks ($(calc %.1f "$size / $bricks / 1024") KiB a brick)"
echo "- resume from it to the written mesh: $resume s (mpirun wall)"

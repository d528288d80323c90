#!/usr/bin/env bash
# Registration on sets whose scans may be held loosely: the composite shape (a torus, a sphere
# on its axis, a small sphere off it), 24 views, noise 0.5 voxel, 1 % outliers, 2 one-scan
# patches, poses perturbed by up to 5 degrees and 5 voxels, five seeds; `fuse --register both`
# on 2 ranks. Per seed: the median scan's displacement from its true pose, the worst of the
# scans held firmly, and each scan the run reported as held loosely (it saw no point of the
# small sphere: its turn about the z axis is free) with its displacement and how far it lies
# from the others' true surfaces against the same at its true pose (eval --poses).
# Usage: bash jobs/benchmark_loose.sh [SEEDS...]  (default 1 2 3 4 11)
set -euo pipefail
cd "$(dirname "$0")/.."
bash jobs/setup.sh >/dev/null
source jobs/mpi_env.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=$PWD/build/rangefuse
seeds=("$@")
[[ ${#seeds[@]} -gt 0 ]] || seeds=(1 2 3 4 11)

echo "| seed | median scan (voxel) | worst held scan (voxel) | loose scans: displacement (voxel), surface rms / at the true pose |"
echo "|---|---|---|---|"
for seed in "${seeds[@]}"; do
  set_dir=$tmp/s$seed
  "$bin" scan --shape composite --views 24 --noise 0.5 --outliers 0.01 --patches 2 \
    --rot-deg 5 --trans-vox 5 --seed "$seed" --voxel 1 --out "$set_dir" >/dev/null
  mpirun -np 2 "$bin" fuse --scans "$set_dir/perturbed.conf" --voxel 1 --register both \
    --poses-out "$set_dir/out.conf" --report "$set_dir/report.json" --out "$set_dir/mesh.ply" \
    >"$set_dir/log" 2>"$set_dir/err"
  "$bin" eval --poses "$set_dir/out.conf" --reference-poses "$set_dir/truth.conf" --voxel 1 \
    --json >"$set_dir/eval.json"
  /usr/bin/python3 - "$set_dir" "$seed" <<'PY'
import json, statistics, sys
folder, seed = sys.argv[1:3]
e = json.load(open(folder + "/eval.json"))
report = json.load(open(folder + "/report.json"))
loose = {s["scan"] for s in report["registration"]["scans"] if s["loose"]}
disp = [s["point_displacement_mean"] for s in e["scans"]]
held = [d for i, d in enumerate(disp) if i not in loose]
cells = ["%s %.2f, %.3f / %.3f" % (e["scans"][i]["name"], disp[i], e["surface"][i]["rms"],
                                   e["surface"][i]["reference_rms"]) for i in sorted(loose)]
print("| %s | %.3f | %.3f | %s |" % (seed, statistics.median(disp), max(held),
                                     "; ".join(cells) or "none"))
PY
done

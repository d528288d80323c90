#!/usr/bin/env bash
# The synthetic Kinect (`scan --sensor kinect`) against real Kinect v1 frames: noise and depth
# steps by depth, holes and mixed returns at depth edges (jobs/sensor_statistics.py), on the
# 7-Scenes kitchen (../shared/data/7scenes-kitchen, every 10th of frames 0-399, read in place)
# and on the synthetic room walked at 640 x 480.
# Usage: bash jobs/benchmark_sensor.sh [BIN (build/rangefuse)]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/rangefuse}
kitchen=${KITCHEN:-$(pwd)/../shared/data/7scenes-kitchen}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin" scan --shape room --views 20 --width 640 --height 480 --voxel 0.01 --path walk \
  --sensor kinect --format 7scenes --out "$tmp/room" >/dev/null
/usr/bin/python3 jobs/sensor_statistics.py "$kitchen" 10 0 400 --json >"$tmp/real.json"
/usr/bin/python3 jobs/sensor_statistics.py "$tmp/room" 1 --json >"$tmp/synthetic.json"
/usr/bin/python3 - "$tmp/real.json" "$tmp/synthetic.json" <<'PY'
import json, sys
real, syn = (json.load(open(p)) for p in sys.argv[1:3])
print("| | 7-Scenes kitchen (real Kinect v1) | synthetic room, --sensor kinect |")
print("|---|---|---|")
for key, what in (("holes_at_edges", "holes among pixels at depth edges"),
                  ("flying_at_edges", "mixed returns among pixels at depth edges")):
    print(f"| {what} | {100 * real[key]:.1f} % | {100 * syn[key]:.1f} % |")
by = {n["depth"]: n for n in syn["noise"]}
for n in real["noise"]:
    s = by.get(n["depth"])
    other = f"{s['sigma_mm']:.2f} mm, steps {s['step_mm']:.0f} mm" if s else "(no depths)"
    print(f"| noise at {n['depth']:.2f} m | {n['sigma_mm']:.2f} mm, steps {n['step_mm']:.0f} mm "
          f"| {other} |")
PY

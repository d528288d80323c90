#!/usr/bin/env bash
# Registration reports the scan it left out of line: a composite scene of 12 views with 1 %
# outliers and 2 one-scan patches, perturbed by up to 2 degrees and 2 voxels, registers with no
# such warning, every scan held firmly within 0.12 voxel of its true pose; the same set with
# one scan moved 25 and 20 voxels more gets one warning naming that scan, and the report marks
# it (and it alone) as a straggler, with its residual and overlap beside every other scan's. A scan that saw only
# the composite's torus and the sphere on its axis (not the small sphere off it) cannot be fixed
# in its turn about that axis: the clean set's report marks exactly those scans loose, each with
# a turn about the z axis through the axis, and warns once for each; a sphere's scans are all
# loose, and the warnings name five and count the rest. A scan turned 6 degrees off ends within
# 0.12 voxel of its true pose or is named.
set -euo pipefail
bin=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" scan --shape composite --views 12 --noise 0.5 --outliers 0.01 --patches 2 --rot-deg 2 \
  --trans-vox 2 --seed 5 --voxel 1 --out "$tmp/set" >/dev/null
mpirun --oversubscribe -np 2 "$bin" fuse --scans "$tmp/set/perturbed.conf" --voxel 1 \
  --register both --out "$tmp/clean.ply" --report "$tmp/clean.json" \
  --poses-out "$tmp/clean.conf" >"$tmp/clean.log" 2>"$tmp/clean.err"
grep -q "out of line" "$tmp/clean.err" && fail "a clean set warned: $(cat "$tmp/clean.err")"
echo "clean set: no scan out of line"
python3 "$(dirname "$0")/loose_scans.py" "$tmp/set" "$tmp/clean.json" "$tmp/clean.err"
# eval --poses: every registered scan, loose or not, lies on the others' true surfaces as
# closely as at its true pose, and keeps its partners; the perturbed start does not.
for poses in clean perturbed; do
  conf="$tmp/clean.conf"
  [[ $poses == perturbed ]] && conf="$tmp/set/perturbed.conf"
  "$bin" eval --poses "$conf" --reference-poses "$tmp/set/truth.conf" --voxel 1 --json \
    >"$tmp/$poses-eval.json"
done
python3 - "$tmp/clean-eval.json" "$tmp/perturbed-eval.json" "$tmp/clean.json" <<'PY'
import json, sys
clean, start = (json.load(open(p))["surface"] for p in sys.argv[1:3])
assert len(clean) == 12, clean
for s in clean:
    assert s["rms"] < 1.15 * s["reference_rms"], s
    assert s["partners"] > 0.95 * s["reference_partners"], s
assert max(s["rms"] / s["reference_rms"] for s in start) > 2, start
# Every scan held firmly ends within 0.12 voxel of its true pose, patches and outliers
# notwithstanding (the loose ones' turn about the axis is not in the data).
poses = json.load(open(sys.argv[1]))["scans"]
loose = {s["scan"] for s in json.load(open(sys.argv[3]))["registration"]["scans"] if s["loose"]}
held = [p["point_displacement_mean"] for i, p in enumerate(poses) if i not in loose]
assert len(held) >= 8 and max(held) < 0.12, held
print("held scans end within %.3f voxel of their true poses" % max(held))
print("registered scans on the true surfaces: surface rms / at the true pose up to %.3f"
      % max(s["rms"] / s["reference_rms"] for s in clean))
PY

# A sphere holds no turn of any scan: every scan but the anchor is loose; five are named.
"$bin" scan --shape sphere --views 10 --noise 0.3 --rot-deg 1 --trans-vox 1 --voxel 1 \
  --out "$tmp/sphere" >/dev/null
mpirun --oversubscribe -np 2 "$bin" fuse --scans "$tmp/sphere/perturbed.conf" --voxel 1 \
  --register simultaneous --out "$tmp/sphere.ply" >/dev/null 2>"$tmp/sphere.err"
[[ $(grep -c "is held loosely" "$tmp/sphere.err") == 5 ]] ||
  fail "expected five loose scans named: $(cat "$tmp/sphere.err")"
grep -q "registration: 4 more scans are held loosely" "$tmp/sphere.err" ||
  fail "expected the other four counted: $(cat "$tmp/sphere.err")"
echo "sphere: five loose scans named, four more counted"

awk 'NR == 6 { $3 += 25; $4 -= 20 } { print }' "$tmp/set/perturbed.conf" >"$tmp/set/moved.conf"
mpirun --oversubscribe -np 2 "$bin" fuse --scans "$tmp/set/moved.conf" --voxel 1 \
  --register both --out "$tmp/moved.ply" --report "$tmp/report.json" >"$tmp/moved.log" \
  2>"$tmp/moved.err"
[[ $(grep -c "out of line" "$tmp/moved.err") == 1 ]] ||
  fail "expected one warning: $(cat "$tmp/moved.err")"
grep -q "registration: scan_005.ply is out of line" "$tmp/moved.err" ||
  fail "the warning does not name scan_005.ply: $(cat "$tmp/moved.err")"
python3 - "$tmp/report.json" <<'PY'
import json, sys
scans = json.load(open(sys.argv[1]))["registration"]["scans"]
assert len(scans) == 12, scans
flagged = [s["scan"] for s in scans if s["straggler"]]
assert flagged == [5], flagged
moved = scans[5]
others = sorted(s["rms"] for s in scans if s["scan"] != 5)
assert moved["rms"] > 1.25 * others[len(others) // 2] or moved["overlap_share"] < 1 / 3, moved
print("moved scan: residual %.3f (median of the others %.3f), overlap %.0f %% of the median"
      % (moved["rms"], others[len(others) // 2], 100 * moved["overlap_share"]))
PY
# Scans turned 6 degrees more about an axis their overlap holds, through the composite's centre:
# each ends within 0.12 voxel of its true pose or is named out of line. scan_005 of seed 8 (the
# first axis) ended 20 voxels off with a residual like every other scan's, unnamed, until each
# of the scans registration moved most was fitted against the others' field alone.
"$bin" scan --shape composite --views 12 --noise 0.5 --outliers 0.01 --patches 2 --rot-deg 2 \
  --trans-vox 2 --seed 8 --voxel 1 --out "$tmp/turn" >/dev/null
turn() {  # in.conf out.conf scan axis_x axis_y axis_z: that scan turned 6 degrees about (8, 0, 16)
  python3 - "$@" <<'PY'
import math, sys
src, dst, k = sys.argv[1], sys.argv[2], int(sys.argv[3])
a = [float(x) for x in sys.argv[4:7]]
n = math.sqrt(sum(x * x for x in a))
h = math.radians(6) / 2
qa = tuple(x / n * math.sin(h) for x in a) + (math.cos(h),)
def mul(p, q):
    px, py, pz, pw = p; qx, qy, qz, qw = q
    return (pw * qx + px * qw + py * qz - pz * qy, pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw, pw * qw - px * qx - py * qy - pz * qz)
def turn(v):
    return mul(mul(qa, tuple(v) + (0,)), (-qa[0], -qa[1], -qa[2], qa[3]))[:3]
centre = (8.0, 0.0, 16.0)
rows = open(src).read().split("\n")
scan = 0
for i, line in enumerate(rows):
    if not line.startswith("bmesh"):
        continue
    if scan == k:
        f = line.split()
        t = turn([float(f[2 + j]) - centre[j] for j in range(3)])
        q = mul(qa, tuple(float(x) for x in f[5:9]))
        rows[i] = " ".join(f[:2] + ["%.17g" % (t[j] + centre[j]) for j in range(3)] +
                           ["%.17g" % x for x in q])
    scan += 1
open(dst, "w").write("\n".join(rows))
PY
}
for case in "5 -0.5826 0.1379 0.8010" "3 0.6639 0.7470 0.0342"; do
  read -r k ax ay az <<<"$case"
  name=$(printf 'scan_%03d.ply' "$k")
  turn "$tmp/turn/perturbed.conf" "$tmp/turn/turned$k.conf" "$k" "$ax" "$ay" "$az"
  mpirun --oversubscribe -np 2 "$bin" fuse --scans "$tmp/turn/turned$k.conf" --voxel 1 \
    --register both --poses-out "$tmp/turn/registered$k.conf" --out "$tmp/turn/mesh$k.ply" \
    --report "$tmp/turn/report$k.json" >"$tmp/turn/log$k" 2>"$tmp/turn/err$k"
  ends=$("$bin" eval --poses "$tmp/turn/registered$k.conf" --reference-poses \
    "$tmp/turn/truth.conf" --voxel 1 | awk -v n="$name" '$1 == n { print $4; exit }')
  if grep -q "registration: $name is out of line" "$tmp/turn/err$k"; then
    # The report marks it too, with the fit against the others when that fit named it.
    python3 - "$tmp/turn/report$k.json" "$k" "$tmp/turn/err$k" <<'PY'
import json, sys
scans = json.load(open(sys.argv[1]))["registration"]["scans"]
k = int(sys.argv[2])
assert [s["scan"] for s in scans if s["straggler"]] == [k], scans
if "alone it moves" in open(sys.argv[3]).read():
    assert scans[k]["others_motion"] > 0.12, scans[k]
PY
    echo "$name turned 6 degrees: named out of line (ends $ends voxel off)"
  else
    awk -v e="$ends" 'BEGIN { exit !(e < 0.12) }' ||
      fail "$name turned 6 degrees ends $ends voxel off, unnamed: $(cat "$tmp/turn/err$k")"
    echo "$name turned 6 degrees: brought within $ends voxel"
  fi
done
echo "stragglers: pass"
